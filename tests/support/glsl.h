// Test support: compile GLSL that includes the project's device/host headers with
// glslangValidator (installed by `make` with glslang-tools), so every *_dh.h is checked as GLSL.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace stsv::test {

/// Compiles `source` as `name` (the extension picks the stage) with the repository root on the
/// include path; returns "" on success, else the command and the compiler's log. A missing
/// glslangValidator is an error, not a skip: the build's set-up installs it.
inline std::string glslCompileErrors(const std::string& name, const std::string& source) {
    const auto dir = std::filesystem::temp_directory_path() / ("stsv_glsl_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto file = dir / name;
    std::ofstream(file) << source;
    const auto log = dir / (name + ".log");
    const std::string cmd = "glslangValidator -V -I" + std::string(STSV_SOURCE_DIR) + " " + file.string() +
                            " -o " + (dir / (name + ".spv")).string() + " > " + log.string() + " 2>&1";
    if (std::system(cmd.c_str()) == 0) return "";
    std::ifstream logFile(log);
    return cmd + "\n" +
           std::string(std::istreambuf_iterator<char>(logFile), std::istreambuf_iterator<char>());
}

} // namespace stsv::test
