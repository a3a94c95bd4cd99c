// Run-time GLSL → SPIR-V with glslang (DESIGN §5). Shaders #include the same *_dh.h headers
// as the C++ mirror: "x/y.h" resolves relative to the including file, then to the repository
// root (STSV_SOURCE_DIR), then to the shader directory.
#pragma once

#include "core/error.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace stsv {

/// GLSL that does not compile; what() holds glslang's log, whose lines name file and line.
class ShaderError : public Error {
  public:
    ShaderError(const std::string& file, const std::string& log);
    const std::string& file() const { return m_file; }
    const std::string& log() const { return m_log; }

  private:
    std::string m_file;
    std::string m_log;
};

/// `#define name value` injected before the shader's first line (e.g. {"SAMPLE_COUNT", "64"}).
struct ShaderDefine {
    std::string name;
    std::string value;
};

/// Stage from the file extension: .vert .geom .frag .comp .mesh .task (UsageError otherwise).
VkShaderStageFlagBits shaderStageFromPath(const std::filesystem::path& path);

/// STSV_SHADER_DIR from the environment if set, else STSV_SOURCE_DIR "/shaders".
std::filesystem::path defaultShaderDirectory();

/// Compiles GLSL 4.50+ for Vulkan 1.3 (SPIR-V 1.6). Stateless apart from its directories, so
/// one instance can serve the whole program; compile calls are not thread-safe.
class ShaderCompiler {
  public:
    explicit ShaderCompiler(std::filesystem::path shaderDirectory = defaultShaderDirectory(),
                            std::filesystem::path sourceRoot = STSV_SOURCE_DIR);

    const std::filesystem::path& shaderDirectory() const { return m_shaderDirectory; }

    /// Compiles `name` (relative to the shader directory, or absolute), e.g. "stsv.geom".
    std::vector<uint32_t> compileFile(const std::filesystem::path& name,
                                      const std::vector<ShaderDefine>& defines = {}) const;
    /// Compiles in-memory source; `virtualPath` names it in error messages and is the base for
    /// relative includes.
    std::vector<uint32_t> compileSource(const std::string& source, VkShaderStageFlagBits stage,
                                        const std::string& virtualPath,
                                        const std::vector<ShaderDefine>& defines = {}) const;

  private:
    std::filesystem::path m_shaderDirectory;
    std::filesystem::path m_sourceRoot;
};

} // namespace stsv
