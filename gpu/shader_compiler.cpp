#include "gpu/shader_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;

namespace stsv {
namespace {

std::optional<std::string> readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

const ShaderFile* findEmbedded(const fs::path& name) {
    const std::string key = name.lexically_normal().generic_string();
    const std::span<const ShaderFile> files = embeddedShaders();
    const auto it = std::lower_bound(files.begin(), files.end(), key,
                                     [](const ShaderFile& f, const std::string& k) { return f.name < k; });
    return it != files.end() && it->name == key ? &*it : nullptr;
}

/// A file found by name: the name glslang reports it by, and its text.
struct FoundFile {
    std::string name;
    std::string text;
};

/// `candidate` read from disk, or from the embedded set when `onDisk` is false.
std::optional<FoundFile> findFile(const fs::path& candidate, bool onDisk) {
    if (!onDisk) {
        const ShaderFile* file = findEmbedded(candidate);
        if (file == nullptr) return std::nullopt;
        return FoundFile{std::string(file->name), std::string(file->text)};
    }
    std::error_code error;
    if (!fs::is_regular_file(candidate, error)) return std::nullopt;
    std::optional<std::string> text = readText(candidate);
    if (!text) return std::nullopt;
    return FoundFile{candidate.lexically_normal().string(), std::move(*text)};
}

void initializeGlslang() {
    // glslang keeps process-wide tables; initialised once and never finalised (finalising
    // while another compiler object lives would break it).
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}

EShLanguage toLanguage(VkShaderStageFlagBits stage) {
    switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
        return EShLangVertex;
    case VK_SHADER_STAGE_GEOMETRY_BIT:
        return EShLangGeometry;
    case VK_SHADER_STAGE_FRAGMENT_BIT:
        return EShLangFragment;
    case VK_SHADER_STAGE_COMPUTE_BIT:
        return EShLangCompute;
    case VK_SHADER_STAGE_MESH_BIT_EXT:
        return EShLangMesh;
    case VK_SHADER_STAGE_TASK_BIT_EXT:
        return EShLangTask;
    default:
        throw UsageError("unsupported shader stage " + std::to_string(int(stage)));
    }
}

/// Resolves #include "x" against the including file's folder, then the tops of the set;
/// #include <x> against the tops only.
class Includer : public glslang::TShader::Includer {
  public:
    Includer(std::vector<fs::path> tops, bool onDisk) : m_tops(std::move(tops)), m_onDisk(onDisk) {}

    IncludeResult* includeLocal(const char* header, const char* includer, size_t /*depth*/) override {
        std::vector<fs::path> candidates;
        if (includer != nullptr && *includer != '\0')
            candidates.push_back(fs::path(includer).parent_path() / header);
        for (const fs::path& top : m_tops) candidates.push_back(top / header);
        return resolve(header, candidates);
    }

    IncludeResult* includeSystem(const char* header, const char* /*includer*/, size_t /*depth*/) override {
        std::vector<fs::path> candidates;
        for (const fs::path& top : m_tops) candidates.push_back(top / header);
        return resolve(header, candidates);
    }

    void releaseInclude(IncludeResult* result) override {
        if (result == nullptr) return;
        delete static_cast<std::string*>(result->userData);
        delete result;
    }

  private:
    std::vector<fs::path> m_tops;
    bool m_onDisk;

    IncludeResult* resolve(const char* header, const std::vector<fs::path>& candidates) {
        for (const fs::path& candidate : candidates) {
            std::optional<FoundFile> found = findFile(candidate, m_onDisk);
            if (!found) continue;
            auto* data = new std::string(std::move(found->text));
            return new IncludeResult(found->name, data->data(), data->size(), data);
        }
        // An empty header name tells glslang the include failed; the data is its message.
        std::string message = std::string("cannot find '") + header + "' (searched";
        for (const fs::path& candidate : candidates)
            message.append(" ").append(candidate.lexically_normal().string());
        message += m_onDisk ? ")" : " in the embedded shader set)";
        auto* data = new std::string(std::move(message));
        return new IncludeResult("", data->data(), data->size(), data);
    }
};

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\0')) s.pop_back();
    return s;
}

} // namespace

ShaderError::ShaderError(const std::string& file, const std::string& log)
    : Error("GLSL compile error in " + file + ":\n" + trimmed(log)), m_file(file), m_log(log) {}

VkShaderStageFlagBits shaderStageFromPath(const fs::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".vert") return VK_SHADER_STAGE_VERTEX_BIT;
    if (ext == ".geom") return VK_SHADER_STAGE_GEOMETRY_BIT;
    if (ext == ".frag") return VK_SHADER_STAGE_FRAGMENT_BIT;
    if (ext == ".comp") return VK_SHADER_STAGE_COMPUTE_BIT;
    if (ext == ".mesh") return VK_SHADER_STAGE_MESH_BIT_EXT;
    if (ext == ".task") return VK_SHADER_STAGE_TASK_BIT_EXT;
    throw UsageError("cannot tell the shader stage of '" + path.string() +
                     "' (expected .vert, .geom, .frag, .comp, .mesh or .task)");
}

bool isShaderEntryPoint(const fs::path& path) {
    const std::string ext = path.extension().string();
    return ext == ".vert" || ext == ".geom" || ext == ".frag" || ext == ".comp" || ext == ".mesh" ||
           ext == ".task";
}

std::optional<fs::path> shaderDirectoryFromEnvironment() {
    const char* dir = std::getenv("STSV_SHADER_DIR");
    if (dir == nullptr || *dir == '\0') return std::nullopt;
    return fs::path(dir);
}

ShaderCompiler::ShaderCompiler() : m_directory(shaderDirectoryFromEnvironment().value_or(fs::path())) {
    std::error_code error;
    if (!m_directory.empty() && !fs::is_directory(m_directory, error))
        throw InputError(m_directory.string(), "STSV_SHADER_DIR names no folder");
    initializeGlslang();
}

ShaderCompiler::ShaderCompiler(fs::path directory) : m_directory(std::move(directory)) {
    if (m_directory.empty()) throw UsageError("the shader folder is an empty path");
    initializeGlslang();
}

std::string ShaderCompiler::describeSource() const {
    if (m_directory.empty()) return "embedded (" + std::to_string(embeddedShaders().size()) + " files)";
    return m_directory.string();
}

std::vector<uint32_t> ShaderCompiler::compileFile(const fs::path& name,
                                                  const std::vector<ShaderDefine>& defines) const {
    const VkShaderStageFlagBits stage = shaderStageFromPath(name);
    const bool onDisk = !m_directory.empty();
    std::optional<FoundFile> file = findFile(onDisk ? m_directory / name : name, onDisk);
    if (!file) {
        if (onDisk) throw InputError((m_directory / name).string(), "cannot read shader file");
        throw InputError(name.string(), "no such shader in the embedded set of " +
                                            std::to_string(embeddedShaders().size()) + " files");
    }
    return compileSource(file->text, stage, file->name, defines);
}

std::vector<uint32_t> ShaderCompiler::compileSource(const std::string& source, VkShaderStageFlagBits stage,
                                                    const std::string& virtualPath,
                                                    const std::vector<ShaderDefine>& defines) const {
    const EShLanguage language = toLanguage(stage);
    std::string preamble;
    for (const ShaderDefine& define : defines)
        preamble += "#define " + define.name + " " + define.value + "\n";

    glslang::TShader shader(language);
    const char* strings[] = {source.c_str()};
    const int lengths[] = {int(source.size())};
    const char* names[] = {virtualPath.c_str()};
    shader.setStringsWithLengthsAndNames(strings, lengths, names, 1);
    shader.setPreamble(preamble.c_str());
    shader.setEnvInput(glslang::EShSourceGlsl, language, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_3);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_6);
    const auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);

    std::vector<fs::path> tops = {fs::path()};
    if (!m_directory.empty()) tops = {m_directory.lexically_normal()};
    Includer includer(std::move(tops), !m_directory.empty());
    if (!shader.parse(GetDefaultResources(), 450, false, messages, includer))
        throw ShaderError(virtualPath, shader.getInfoLog());

    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) throw ShaderError(virtualPath, program.getInfoLog());

    std::vector<uint32_t> spirv;
    spv::SpvBuildLogger logger;
    glslang::SpvOptions options;
    options.disableOptimizer = true; // the driver optimises; keeps compile time low
    glslang::GlslangToSpv(*program.getIntermediate(language), spirv, &logger, &options);
    if (spirv.empty()) throw ShaderError(virtualPath, "SPIR-V generation failed: " + logger.getAllMessages());
    return spirv;
}

} // namespace stsv
