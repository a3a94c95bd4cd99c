#include "gpu/shader_compiler.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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

TEST(ShaderCompiler, ResolvesIncludesRelativeToFileAndRepositoryRoot) {
    const ScratchDirectory scratch("includes");
    const fs::path& dir = scratch.path;
    // main.comp → "sub/a.glsl" (relative to main), which → "b.glsl" (relative to sub/) and
    // "volumes/stsv_dh.h" (repository root), which → "core/dh.h".
    writeFile(dir / "sub" / "a.glsl", "#include \"b.glsl\"\n#include \"volumes/stsv_dh.h\"\n"
                                      "uint fromA() { return fromB() + WRAP_CLAMP; }\n");
    writeFile(dir / "sub" / "b.glsl", "uint fromB() { return 40u; }\n");
    writeFile(dir / "main.comp", "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                                 "#include \"sub/a.glsl\"\nlayout(local_size_x = 1) in;\n"
                                 "layout(std430, binding = 0) buffer Out { uint value; };\n"
                                 "void main() { value = fromA() + VALUE_FROM_DEFINE; }\n");
    ShaderCompiler compiler(dir);
    EXPECT_FALSE(compiler.compileFile("main.comp", {{"VALUE_FROM_DEFINE", "1u"}}).empty());
    // Without the define the shader does not compile: defines really reach the preprocessor.
    EXPECT_THROW(compiler.compileFile("main.comp"), ShaderError);
}

TEST(ShaderCompiler, MissingIncludeIsAnError) {
    try {
        sharedCompiler().compileSource("#version 450\n#extension GL_GOOGLE_include_directive : require\n"
                                       "#include \"no/such_header_dh.h\"\nvoid main() {}\n",
                                       VK_SHADER_STAGE_COMPUTE_BIT, "missing_include.comp");
        FAIL() << "no ShaderError";
    } catch (const ShaderError& e) {
        EXPECT_NE(std::string(e.what()).find("no/such_header_dh.h"), std::string::npos) << e.what();
    }
}

TEST(ShaderCompiler, MissingFileIsAnInputError) {
    EXPECT_THROW(sharedCompiler().compileFile("does_not_exist.comp"), InputError);
}

TEST(ShaderCompiler, EveryShaderOfTheRepositoryCompilesAtRunTime) {
    // The same sources the build-time check compiles, through the run-time include callback.
    std::size_t count = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(sharedCompiler().shaderDirectory())) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".vert" && ext != ".geom" && ext != ".frag" && ext != ".comp" && ext != ".mesh" &&
            ext != ".task")
            continue;
        EXPECT_NO_THROW(sharedCompiler().compileFile(entry.path().filename())) << entry.path();
        ++count;
    }
    EXPECT_GE(count, 1u);
}

TEST(ShaderCompiler, ShaderDirectoryFromEnvironment) {
    const char* old = std::getenv("STSV_SHADER_DIR");
    const std::string saved = old != nullptr ? old : "";
    setenv("STSV_SHADER_DIR", "/tmp/somewhere/shaders", 1);
    EXPECT_EQ(defaultShaderDirectory(), fs::path("/tmp/somewhere/shaders"));
    unsetenv("STSV_SHADER_DIR");
    EXPECT_EQ(defaultShaderDirectory(), fs::path(STSV_SOURCE_DIR) / "shaders");
    if (old != nullptr) setenv("STSV_SHADER_DIR", saved.c_str(), 1);
}

} // namespace
} // namespace stsv::test
