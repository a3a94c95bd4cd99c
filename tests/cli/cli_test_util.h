// Running the `stsv` command line in-process: argv from strings, captured stdout/stderr, and a
// scratch directory per test.
#pragma once

#include "cli/commands.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace stsv::test {

struct CliResult {
    int code = 0;
    std::string out;
    std::string err;
};

inline CliResult runStsv(std::vector<std::string> args) {
    args.insert(args.begin(), "stsv");
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    CliResult r;
    r.code = runCli(int(args.size()), argv.data());
    r.out = testing::internal::GetCapturedStdout();
    r.err = testing::internal::GetCapturedStderr();
    return r;
}

/// A shell command's exit status and its stdout and stderr together (another program the tests
/// check stsv's files with: python3, exrheader, git).
struct ShellResult {
    int code = -1; ///< -1 when it could not run or was killed
    std::string out;
};
inline ShellResult runShell(const std::string& command) {
    ShellResult r;
    std::FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.out.append(buffer, n);
    const int status = ::pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/// A JSON file the command wrote (--json, --stats).
inline nlohmann::json readJson(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

inline std::string describe(const std::vector<std::string>& args, const CliResult& r) {
    std::string text = "stsv";
    for (const std::string& a : args) text += " " + a;
    return text + "\n  exit " + std::to_string(r.code) + "\n  stdout: " + r.out + "\n  stderr: " + r.err;
}

/// A fresh directory under the system temp dir, removed at the end of the test.
class ScratchDir {
  public:
    ScratchDir() {
        const auto* info = testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() / ("stsv_cli_" + std::to_string(::getpid()) + "_" +
                                                           info->test_suite_name() + "_" + info->name());
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::string file(const std::string& name) const { return (m_path / name).string(); }
    const std::filesystem::path& path() const { return m_path; }

  private:
    std::filesystem::path m_path;
};

} // namespace stsv::test
