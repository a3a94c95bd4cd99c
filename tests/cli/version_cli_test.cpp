// Which code produced a result: `stsv --version`, and the version in stats, bench and info JSON,
// checked against git run here on the checkout the tests were built from.
#include "cli_test_util.h"

#include "core/version.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <regex>
#include <string>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::runStsv;
using test::ScratchDir;

/// stdout of a shell command (stderr dropped), trailing newline removed; nullopt when it fails.
std::optional<std::string> commandOutput(const std::string& command) {
    test::ShellResult r = test::runShell("(" + command + " 2>/dev/null)");
    if (r.code != 0) return std::nullopt;
    while (!r.out.empty() && r.out.back() == '\n') r.out.pop_back();
    return r.out;
}

TEST(Version, IsTheGitDescribeOfTheCheckout) {
    const std::string v = version();
    EXPECT_TRUE(std::regex_match(v, std::regex(R"(\d+\.\d+\.\d+([-+][0-9A-Za-z.+-]+)?)"))) << v;
    const std::string git = "git -c safe.directory='*' -C '" + std::string(STSV_SOURCE_DIR) + "' ";
    const std::optional<std::string> head = commandOutput(git + "rev-parse --short=8 HEAD");
    if (!head) {
        // A source tarball: the release version alone.
        EXPECT_EQ(v.find('+'), std::string::npos) << v;
        return;
    }
    if (const std::optional<std::string> tag =
            commandOutput(git + "describe --tags --exact-match --match 'v[0-9]*'")) {
        EXPECT_EQ(v.rfind(tag->substr(1), 0), 0u) << v << " on tag " << *tag;
        return;
    }
    EXPECT_NE(v.find("g" + *head), std::string::npos) << v << " does not name commit " << *head;
}

TEST(Version, FlagPrintsIt) {
    const CliResult r = runStsv({"--version"});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out, "stsv " + std::string(version()) + "\n");
}

TEST(Version, StatsAndBenchJsonCarryIt) {
    ScratchDir dir;
    const std::vector<std::string> render = {
        "render", "fence",   "--backend",        "cpu", "--size", "8x8", "--samples",
        "16",     "--stats", dir.file("s.json"), "-q"};
    const CliResult r = runStsv(render);
    ASSERT_EQ(r.code, 0) << test::describe(render, r);
    EXPECT_EQ(readJson(dir.file("s.json"))["version"], version());

    const std::vector<std::string> bench = {
        "bench",     "fence", "--methods", "stsv", "--backends", "cpu", "--size", "8x8",
        "--samples", "16",    "--repeat",  "1",    "--warmup",   "0",   "--json", dir.file("b.json"),
        "-q"};
    const CliResult b = runStsv(bench);
    ASSERT_EQ(b.code, 0) << test::describe(bench, b);
    EXPECT_EQ(readJson(dir.file("b.json"))["version"], version());
}

TEST(Info, NamesTheShaderSource) {
    const CliResult json = runStsv({"info", "--json"});
    ASSERT_EQ(json.code, 0) << json.err;
    const nlohmann::json j = nlohmann::json::parse(json.out);
    EXPECT_EQ(j["version"], version());
    EXPECT_EQ(j["shaders"]["embedded"], true);
    EXPECT_EQ(j["shaders"]["source"].get<std::string>().rfind("embedded (", 0), 0u) << j["shaders"];
    const CliResult text = runStsv({"info"});
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("shaders: embedded ("), std::string::npos) << text.out;
}

} // namespace
} // namespace stsv
