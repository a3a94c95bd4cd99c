#include "gpu/shader_compiler.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace stsv::test {
namespace {

void writeFile(const fs::path& path, const std::string& text) {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
}

/// A fresh folder per test and process under the system temp dir, removed afterwards.
struct ScratchDirectory {
    fs::path path;
    explicit ScratchDirectory(const std::string& name)
        : path(fs::temp_directory_path() / ("stsv_gpu_test_" + name + "_" + std::to_string(getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~ScratchDirectory() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
    }
};

TEST(ShaderStage, FromExtension) {
    EXPECT_EQ(shaderStageFromPath("a/stsv.geom"), VK_SHADER_STAGE_GEOMETRY_BIT);
    EXPECT_EQ(shaderStageFromPath("x.vert"), VK_SHADER_STAGE_VERTEX_BIT);
    EXPECT_EQ(shaderStageFromPath("x.frag"), VK_SHADER_STAGE_FRAGMENT_BIT);
    EXPECT_EQ(shaderStageFromPath("x.comp"), VK_SHADER_STAGE_COMPUTE_BIT);
    EXPECT_EQ(shaderStageFromPath("x.mesh"), VK_SHADER_STAGE_MESH_BIT_EXT);
    EXPECT_EQ(shaderStageFromPath("x.task"), VK_SHADER_STAGE_TASK_BIT_EXT);
    EXPECT_THROW(shaderStageFromPath("x.glsl"), UsageError);
}

TEST(ShaderCompiler, ValidSourceGivesSpirv) {
    const std::vector<uint32_t> spirv =
        sharedCompiler().compileSource("#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
                                       VK_SHADER_STAGE_COMPUTE_BIT, "ok.comp");
    ASSERT_GE(spirv.size(), 5u);
    EXPECT_EQ(spirv[0], 0x07230203u) << "SPIR-V magic number";
    EXPECT_EQ(spirv[1], 0x00010600u) << "SPIR-V 1.6 for Vulkan 1.3";
}

TEST(ShaderCompiler, ErrorNamesFileAndLine) {
    const std::string source = "#version 450\n"
                               "layout(local_size_x = 1) in;\n"
                               "void main() {\n"
                               "    float x = undeclaredThing;\n"
                               "}\n";
    try {
        sharedCompiler().compileSource(source, VK_SHADER_STAGE_COMPUTE_BIT, "broken/bad_shader.comp");
        FAIL() << "no ShaderError";
    } catch (const ShaderError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("broken/bad_shader.comp:4"), std::string::npos) << what;
        EXPECT_NE(what.find("undeclaredThing"), std::string::npos) << what;
        EXPECT_EQ(e.file(), "broken/bad_shader.comp");
    }
}

TEST(ShaderCompiler, ErrorInIncludedHeaderNamesTheHeader) {
    const ScratchDirectory scratch("include_error");
    const fs::path& dir = scratch.path;
    writeFile(dir / "lib" / "broken.glsl", "// comment\nfloat f() { return missingSymbol; }\n");
    writeFile(dir / "main.frag", "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                                 "#include \"lib/broken.glsl\"\nlayout(location = 0) out vec4 o;\n"
                                 "void main() { o = vec4(f()); }\n");
    ShaderCompiler compiler(dir);
    try {
        compiler.compileFile("main.frag");
        FAIL() << "no ShaderError";
    } catch (const ShaderError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("broken.glsl:2"), std::string::npos) << what;
        EXPECT_NE(what.find("missingSymbol"), std::string::npos) << what;
    }
}

TEST(ShaderCompiler, FolderResolvesIncludesAgainstTheFileAndTheFolder) {
    const ScratchDirectory scratch("includes");
    const fs::path shaders = scratch.path / "shaders";
    // main.comp → "sub/a.glsl" (beside main), which → "b.glsl" (beside a) and "lib/c_dh.h" (from
    // the folder's top, as a family's shader includes a module header), which → "top_dh.h" (from
    // the top too, not beside c_dh.h). Nothing resolves against the folder above.
    writeFile(shaders / "sub" / "a.glsl", "#include \"b.glsl\"\n#include \"lib/c_dh.h\"\n"
                                          "uint fromA() { return fromB() + fromC(); }\n");
    writeFile(shaders / "sub" / "b.glsl", "uint fromB() { return 40u; }\n");
    writeFile(shaders / "lib" / "c_dh.h", "#include \"top_dh.h\"\nuint fromC() { return TOP; }\n");
    writeFile(shaders / "top_dh.h", "#define TOP 1u\n");
    writeFile(shaders / "main.comp", "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                                     "#include \"sub/a.glsl\"\nlayout(local_size_x = 1) in;\n"
                                     "layout(std430, binding = 0) buffer Out { uint value; };\n"
                                     "void main() { value = fromA() + VALUE_FROM_DEFINE; }\n");
    ShaderCompiler compiler(shaders);
    EXPECT_FALSE(compiler.compileFile("main.comp", {{"VALUE_FROM_DEFINE", "1u"}}).empty());
    // Without the define the shader does not compile: defines really reach the preprocessor.
    EXPECT_THROW(compiler.compileFile("main.comp"), ShaderError);
    // Nor without the header at the folder's top, though a copy lies in the folder above.
    writeFile(scratch.path / "lib" / "c_dh.h", "#include \"top_dh.h\"\nuint fromC() { return TOP; }\n");
    fs::remove(shaders / "lib" / "c_dh.h");
    EXPECT_THROW(compiler.compileFile("main.comp", {{"VALUE_FROM_DEFINE", "1u"}}), ShaderError);
}

TEST(ShaderCompiler, EmbeddedSetResolvesTheRepositoryHeaders) {
    // An in-memory shader including a module header, which includes core/dh.h from its own folder's
    // parent: both come from the embedded set, not from the disk.
    const std::string source = "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                               "#include \"volumes/stsv_dh.h\"\nlayout(local_size_x = 1) in;\n"
                               "layout(std430, binding = 0) buffer Out { uint value; };\n"
                               "void main() { value = WRAP_CLAMP; }\n";
    const ShaderCompiler embedded{ShaderCompiler()};
    ASSERT_TRUE(embedded.shaderDirectory().empty()) << "STSV_SHADER_DIR is set in the test environment";
    EXPECT_FALSE(embedded.compileSource(source, VK_SHADER_STAGE_COMPUTE_BIT, "in_memory.comp").empty());
}

TEST(ShaderCompiler, MissingIncludeIsAnError) {
    try {
        sharedCompiler().compileSource("#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                                       "#include \"no/such_header_dh.h\"\nvoid main() {}\n",
                                       VK_SHADER_STAGE_COMPUTE_BIT, "missing_include.comp");
        FAIL() << "no ShaderError";
    } catch (const ShaderError& e) {
        EXPECT_NE(std::string(e.what()).find("no/such_header_dh.h"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("embedded shader set"), std::string::npos) << e.what();
    }
}

TEST(ShaderCompiler, MissingFileIsAnInputError) {
    EXPECT_THROW(sharedCompiler().compileFile("does_not_exist.comp"), InputError);
    EXPECT_THROW(ShaderCompiler(fs::path(STSV_SOURCE_DIR)).compileFile("does_not_exist.comp"), InputError);
}

/// The files the build embeds, named by their paths from the repository's root: every file of the
/// families' shaders/ folders (render/shaders, volumes/shaders, ...), core/dh.h and every module's
/// *_dh.h (render's backends' too: render/vulkan/gpu_frame_dh.h, and each family's Vulkan side:
/// wedges/vulkan/gpu_wedges_dh.h).
std::map<std::string, fs::path> repositoryShaderSet() {
    const fs::path root = STSV_SOURCE_DIR;
    std::map<std::string, fs::path> files;
    auto add = [&](const fs::path& folder, bool onlyHeaders) {
        if (!fs::is_directory(folder)) return;
        for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
            const std::string name = entry.path().filename().string();
            if (entry.is_regular_file() && (!onlyHeaders || name.ends_with("_dh.h")))
                files[fs::relative(entry.path(), root).generic_string()] = entry.path();
        }
    };
    files["core/dh.h"] = root / "core" / "dh.h";
    for (const fs::directory_entry& folder : fs::directory_iterator(root)) {
        // Not the tests' own shaders, nor a build tree inside the checkout (its shaders/ holds SPIR-V).
        if (!folder.is_directory() || folder.path().filename() == "tests" ||
            fs::exists(folder.path() / "CMakeCache.txt"))
            continue;
        add(folder.path(), true);
        add(folder.path() / "vulkan", true);
        add(folder.path() / "shaders", false);
    }
    return files;
}

std::string readFile(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

TEST(EmbeddedShaders, AreTheRepositoryFilesByteForByte) {
    const std::map<std::string, fs::path> expected = repositoryShaderSet();
    ASSERT_GE(expected.size(), 20u);
    std::vector<std::string> names;
    for (const ShaderFile& file : embeddedShaders()) {
        names.emplace_back(file.name);
        const auto it = expected.find(std::string(file.name));
        if (it == expected.end()) {
            ADD_FAILURE() << "embedded " << file.name << " is no file of the repository's shader set";
            continue;
        }
        EXPECT_EQ(std::string(file.text), readFile(it->second)) << file.name;
    }
    EXPECT_EQ(names.size(), expected.size());
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end())) << "the set is looked up by binary search";
}

TEST(EmbeddedShaders, EveryEntryPointCompilesAtRunTime) {
    // The same sources the build-time check compiles, through the run-time include callback and
    // nothing but the embedded set.
    std::size_t count = 0;
    for (const ShaderFile& file : embeddedShaders()) {
        if (!isShaderEntryPoint(std::string(file.name))) continue;
        EXPECT_NO_THROW(sharedCompiler().compileFile(std::string(file.name))) << file.name;
        ++count;
    }
    EXPECT_GE(count, 15u);
}

TEST(EmbeddedShaders, CompileAsTheCheckoutFolderDoes) {
    // STSV_SHADER_DIR pointed at the checkout gives the same SPIR-V as the embedded set.
    const ShaderCompiler folder{fs::path(STSV_SOURCE_DIR)};
    const std::vector<ShaderDefine> defines = {{"SAMPLE_COUNT", "64"}, {"FIXED_LIGHT_TYPE", "1u"}};
    EXPECT_EQ(folder.compileFile("volumes/shaders/stsv.frag", defines),
              sharedCompiler().compileFile("volumes/shaders/stsv.frag", defines));
    EXPECT_EQ(folder.compileFile("wedges/shaders/wedge.geom"),
              sharedCompiler().compileFile("wedges/shaders/wedge.geom"));
}

TEST(ShaderCompiler, ShaderDirectoryFromEnvironment) {
    const char* old = std::getenv("STSV_SHADER_DIR");
    const std::string saved = old != nullptr ? old : "";
    const fs::path checkout = fs::path(STSV_SOURCE_DIR);
    setenv("STSV_SHADER_DIR", checkout.c_str(), 1);
    EXPECT_EQ(shaderDirectoryFromEnvironment(), checkout);
    EXPECT_EQ(ShaderCompiler().shaderDirectory(), checkout);
    EXPECT_EQ(ShaderCompiler().describeSource(), checkout.string());
    setenv("STSV_SHADER_DIR", "/no/such/shader/folder", 1);
    try {
        ShaderCompiler compiler;
        ADD_FAILURE() << "no error for a missing STSV_SHADER_DIR folder";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/no/such/shader/folder"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("STSV_SHADER_DIR"), std::string::npos) << e.what();
    }
    setenv("STSV_SHADER_DIR", "", 1);
    EXPECT_EQ(shaderDirectoryFromEnvironment(), std::nullopt);
    unsetenv("STSV_SHADER_DIR");
    EXPECT_EQ(shaderDirectoryFromEnvironment(), std::nullopt);
    EXPECT_TRUE(ShaderCompiler().shaderDirectory().empty());
    EXPECT_EQ(ShaderCompiler().describeSource(),
              "embedded (" + std::to_string(embeddedShaders().size()) + " files)");
    if (old != nullptr) setenv("STSV_SHADER_DIR", saved.c_str(), 1);
}

} // namespace
} // namespace stsv::test
