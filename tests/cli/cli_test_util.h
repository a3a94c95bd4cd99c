// Running the `stsv` command line in-process: argv from strings, captured stdout/stderr, and a
// scratch directory per test.
#pragma once

#include "cli/commands.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace stsv::test {

/// Sets an environment variable for the scope of a test and restores the previous value.
class ScopedEnv {
  public:
    ScopedEnv(const char* name, const std::string& value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        ::setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (m_old)
            ::setenv(m_name.c_str(), m_old->c_str(), 1);
        else
            ::unsetenv(m_name.c_str());
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

  private:
    std::string m_name;
    std::optional<std::string> m_old;
};

/// Writes `text` to `path` (binary), failing the test when the write does not complete.
inline void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

/// The bytes of the file at `path` ("" when it cannot be read).
inline std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

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

/// runStsv in a child process that may take at most `seconds`: a command that blocks (on a FIFO
/// without a reader) is killed and reported as code -1 instead of hanging the tests, as is one a
/// signal ends (its number in `err`). `prepare` runs in the child just before the command (a
/// limit, a signal's disposition, an environment variable), so that the tests' own process keeps
/// its own. The
/// child's stdout and stderr are pipes (no file size limit applies to them), drained as it runs.
inline CliResult runStsvWithin(int seconds, const std::vector<std::string>& args,
                               const std::function<void()>& prepare = {}) {
    int outPipe[2], errPipe[2];
    if (::pipe(outPipe) != 0 || ::pipe(errPipe) != 0) return {-2, "", "pipe failed"};
    std::fflush(stdout);
    std::fflush(stderr);
    const pid_t child = ::fork();
    if (child == 0) {
        ::dup2(outPipe[1], 1);
        ::dup2(errPipe[1], 2);
        ::close(outPipe[0]);
        ::close(errPipe[0]);
        std::vector<std::string> all = args;
        all.insert(all.begin(), "stsv");
        std::vector<char*> argv;
        for (std::string& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);
        if (prepare) prepare();
        const int code = runCli(int(all.size()), argv.data());
        std::fflush(stdout);
        std::fflush(stderr);
        ::_exit(code);
    }
    ::close(outPipe[1]);
    ::close(errPipe[1]);
    CliResult r;
    auto drain = [](int fd, std::string& text) {
        char buffer[4096];
        for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
    };
    ::fcntl(outPipe[0], F_SETFL, O_NONBLOCK);
    ::fcntl(errPipe[0], F_SETFL, O_NONBLOCK);
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (::waitpid(child, &status, WNOHANG) == 0) {
        drain(outPipe[0], r.out);
        drain(errPipe[0], r.err);
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(child, SIGKILL);
            ::waitpid(child, &status, 0);
            ::close(outPipe[0]);
            ::close(errPipe[0]);
            return {-1, r.out,
                    r.err + "(killed after " + std::to_string(seconds) + " s: the command blocked)"};
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    drain(outPipe[0], r.out);
    drain(errPipe[0], r.err);
    ::close(outPipe[0]);
    ::close(errPipe[0]);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (WIFSIGNALED(status)) r.err += "(killed by signal " + std::to_string(WTERMSIG(status)) + ")";
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
