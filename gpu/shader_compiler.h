// Run-time GLSL → SPIR-V with glslang (DESIGN §5). Shaders #include the same *_dh.h headers as
// the C++ mirror. The text comes from the shader set embedded in the program at build time
// (cmake/Shaders.cmake), or, for shader development, from a folder on disk (STSV_SHADER_DIR).
#pragma once

#include "core/error.h"

#include "gpu/vulkan.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
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

/// One file of the shader set: its name in the set and its text. A file's name is its path from
/// the repository's root, GLSL ("volumes/shaders/stsv.frag") and headers ("volumes/stsv_dh.h")
/// alike, which is also the layout installed to share/stsv/shaders.
struct ShaderFile {
    std::string_view name;
    std::string_view text;
};

/// The shader set built into the program, sorted by name.
std::span<const ShaderFile> embeddedShaders();

/// Stage from the file extension: .vert .geom .frag .comp .mesh .task (UsageError otherwise).
VkShaderStageFlagBits shaderStageFromPath(const std::filesystem::path& path);

/// True for the names of shader entry points (a stage extension), false for headers.
bool isShaderEntryPoint(const std::filesystem::path& path);

/// The folder the environment variable STSV_SHADER_DIR names; nullopt when it is unset or empty.
std::optional<std::filesystem::path> shaderDirectoryFromEnvironment();

/// Compiles GLSL 4.50+ for Vulkan 1.3 (SPIR-V 1.6). Stateless apart from where it reads, so one
/// instance can serve the whole program; compile calls are not thread-safe.
///
/// `#include "x/y.h"` resolves against the including file's folder, then against the top of the
/// set: on disk, the folder read (a checkout's root, or an installed share/stsv/shaders).
class ShaderCompiler {
  public:
    /// Reads the folder STSV_SHADER_DIR names when it is set (InputError when that is no
    /// folder), else the embedded set.
    ShaderCompiler();
    /// Reads the shaders from `directory` on disk.
    explicit ShaderCompiler(std::filesystem::path directory);

    /// The folder the shaders are read from; empty for the embedded set.
    const std::filesystem::path& shaderDirectory() const { return m_directory; }
    /// "embedded (N files)", or the folder.
    std::string describeSource() const;

    /// Compiles `name`, a file of the set (or relative to the folder), e.g. "volumes/shaders/stsv.geom".
    std::vector<uint32_t> compileFile(const std::filesystem::path& name,
                                      const std::vector<ShaderDefine>& defines = {}) const;
    /// Compiles in-memory source; `virtualPath` names it in error messages and is the base for
    /// relative includes.
    std::vector<uint32_t> compileSource(const std::string& source, VkShaderStageFlagBits stage,
                                        const std::string& virtualPath,
                                        const std::vector<ShaderDefine>& defines = {}) const;

  private:
    std::filesystem::path m_directory;
};

} // namespace stsv
