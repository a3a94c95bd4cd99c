// The command line on the Vulkan backend and the sampling options every backend takes: each
// option changes the light-sample buffer (so it reaches the renderer) and the Vulkan buffer equals
// the CPU mirror's bit for bit (the mirror is checked against Embree elsewhere); --device,
// --against, --heat-scale, the default output name, the --stats keys the user guide lists, and
// the exit statuses of the error paths.
#include "cli_test_util.h"

#include "cli/cli_util.h"
#include "core/error.h"
#include "core/image.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>

namespace stsv::test {
namespace {

namespace fs = std::filesystem;

/// The "differing samples: N of M" count of `stsv compare A B`.
long differingSamples(const std::string& a, const std::string& b) {
    const CliResult r = runStsv({"compare", a, b});
    EXPECT_EQ(r.code, 0) << r.err;
    const std::size_t at = r.out.find("differing samples: ");
    if (at == std::string::npos) return -1;
    return std::stol(r.out.substr(at + 19));
}

TEST(VulkanCli, SamplingOptionsReachBothBackendsAlike) {
    ScratchDir dir;
    auto dump = [&](const std::string& name, const std::string& backend, std::vector<std::string> extra) {
        std::vector<std::string> args = {"render",       "fence",   "--backend",
                                         backend,        "--size",  "24x16",
                                         "--samples",    "16",      "--dump-ls",
                                         dir.file(name), "--stats", dir.file(name + ".stats.json"),
                                         "-q",           "-o",      dir.file(name + ".png")};
        args.insert(args.end(), extra.begin(), extra.end());
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 0) << describe(args, r);
        return readJson(dir.file(name + ".stats.json"));
    };
    dump("default_cpu.npy", "cpu", {});
    const nlohmann::json base = dump("default_vulkan.npy", "vulkan", {});
    EXPECT_EQ(differingSamples(dir.file("default_vulkan.npy"), dir.file("default_cpu.npy")), 0);
    EXPECT_EQ(base["options"]["backend"], "vulkan");
    const std::vector<std::pair<std::vector<std::string>, std::pair<std::string, nlohmann::json>>> options = {
        {{"--pattern", "uniform"}, {"pattern", "uniform"}},
        {{"--pattern", "stratified"}, {"pattern", "stratified"}},
        {{"--interleave", "2"}, {"interleave", 2}},
        {{"--no-decorrelate"}, {"decorrelate", false}},
        {{"--seed", "9"}, {"seed", 9}},
    };
    for (const auto& [extra, key] : options) {
        const std::string name = extra[0].substr(2) + (extra.size() > 1 ? "_" + extra[1] : "");
        SCOPED_TRACE(name);
        dump(name + "_cpu.npy", "cpu", extra);
        const nlohmann::json stats = dump(name + "_vulkan.npy", "vulkan", extra);
        EXPECT_EQ(stats["options"][key.first], key.second);
        EXPECT_EQ(differingSamples(dir.file(name + "_vulkan.npy"), dir.file(name + "_cpu.npy")), 0)
            << "the Vulkan backend takes " << name << " as the CPU mirror does";
        EXPECT_GT(differingSamples(dir.file(name + "_cpu.npy"), dir.file("default_cpu.npy")), 20)
            << name << " changes which samples are taken";
    }
}

TEST(VulkanCli, DeviceSelection) {
    ScratchDir dir;
    const std::vector<std::string> common = {"render", "fence", "--backend",      "vulkan",
                                             "--size", "8x8",   "--samples",      "16",
                                             "-q",     "-o",    dir.file("x.png")};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = common;
        args.insert(args.end(), extra.begin(), extra.end());
        return runStsv(args);
    };
    const CliResult first = with({"--device", "0", "--stats", dir.file("s.json")});
    EXPECT_EQ(first.code, 0) << first.err;
    EXPECT_EQ(readJson(dir.file("s.json"))["options"]["device"], "0");
    const CliResult byName = with({"--device", "llvmpipe"});
    EXPECT_EQ(byName.code, 0) << byName.err;
    const CliResult missing = with({"--device", "97"});
    EXPECT_EQ(missing.code, 1);
    EXPECT_NE(missing.err.find("97"), std::string::npos) << missing.err;
    const CliResult unmatched = with({"--device", "no-such-gpu"});
    EXPECT_EQ(unmatched.code, 1);
    EXPECT_NE(unmatched.err.find("no-such-gpu"), std::string::npos) << unmatched.err;
}

TEST(VulkanCli, CompareAgainstAnotherMethodAndBackend) {
    ScratchDir dir;
    // Against the CPU mirror, the Vulkan STSV row is identical bit for bit and the mirror's own
    // row is the reference row of the table.
    const CliResult r = runStsv({"compare", "fence", "--methods", "stsv/vulkan", "--against", "stsv/cpu",
                                 "--size", "24x16", "--samples", "16", "--json", dir.file("c.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = readJson(dir.file("c.json"));
    EXPECT_EQ(j["against"], "stsv/cpu");
    ASSERT_EQ(j["rows"].size(), 2u);
    EXPECT_EQ(j["rows"][0]["method"], "stsv");
    EXPECT_EQ(j["rows"][0]["backend"], "cpu");
    EXPECT_EQ(j["rows"][1]["backend"], "vulkan");
    EXPECT_EQ(j["rows"][1]["differing_samples"], 0);
    EXPECT_EQ(j["rows"][1]["identical_percent"], 100.0);
}

TEST(VulkanCli, HeatScaleSetsTheColourOfADifference) {
    // Two visibilities 0.125 apart everywhere: yellow at --heat-scale 0.125, red (half way) at 0.25.
    ScratchDir dir;
    ImageF a(4, 3, 1), b(4, 3, 1);
    for (float& v : a.pixels) v = 0.5f;
    for (float& v : b.pixels) v = 0.625f;
    writeNpy(dir.file("a.npy"), a);
    writeNpy(dir.file("b.npy"), b);
    auto colour = [&](const std::string& scale) {
        const std::string out = dir.file("out_" + scale);
        const CliResult r =
            runStsv({"compare", dir.file("a.npy"), dir.file("b.npy"), "--out", out, "--heat-scale", scale});
        EXPECT_EQ(r.code, 0) << r.err;
        const Image8 heat = readPngRgba(out + "/difference.png");
        return std::array<int, 3>{heat.at(1, 1, 0), heat.at(1, 1, 1), heat.at(1, 1, 2)};
    };
    EXPECT_EQ(colour("0.125"), (std::array<int, 3>{255, 255, 0}));
    EXPECT_EQ(colour("0.25"), (std::array<int, 3>{255, 0, 0}));
    EXPECT_EQ(colour("1"), (std::array<int, 3>{64, 0, 0})); // 0.125: a quarter of the way to red
    const CliResult bad = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy"), "--heat-scale", "0"});
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("--heat-scale"), std::string::npos) << bad.err;
}

TEST(VulkanCli, DefaultOutputIsTheScenesNameAsPng) {
    ScratchDir dir;
    const fs::path before = fs::current_path();
    fs::current_path(dir.path());
    const CliResult r =
        runStsv({"render", "fence", "--backend", "vulkan", "--size", "12x8", "--samples", "16", "-q"});
    fs::current_path(before);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir.file("fence.png")));
    const Image8 image = readPngRgba(dir.file("fence.png"));
    EXPECT_EQ(image.width, 12);
    EXPECT_EQ(image.height, 8);
}

TEST(VulkanCli, StatsHoldTheKeysTheUserGuideLists) {
    ScratchDir dir;
    const CliResult r = runStsv({"render", "fence", "--backend", "vulkan", "--method", "pcss", "--size",
                                 "12x8", "--samples", "16", "--param", "pcss_filter_taps=24", "--stats",
                                 dir.file("s.json"), "-q", "-o", dir.file("x.png")});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = readJson(dir.file("s.json"));
    for (const char* key :
         {"method", "backend", "width", "height", "samples", "pattern", "seed", "interleave", "decorrelate",
          "buffer", "ambient", "device", "validation", "extrusion", "params"})
        EXPECT_TRUE(j["options"].contains(key)) << "options." << key;
    for (const char* key :
         {"source", "spec", "set", "triangles", "perforated_triangles", "skipped_faces", "lights"})
        EXPECT_TRUE(j["scene"].contains(key)) << "scene." << key;
    for (const char* key : {"startup_ms", "frame_ms", "command", "version", "outputs"})
        EXPECT_TRUE(j.contains(key)) << key;
    // Every parameter of the method, given or default.
    EXPECT_EQ(j["options"]["params"]["pcss_filter_taps"], 24);
    for (const char* param :
         {"sm_size", "sm_bias", "pcss_blocker_taps", "pcss_max_kernel", "pcss_max_search"})
        EXPECT_TRUE(j["options"]["params"].contains(param)) << param;
}

TEST(VulkanCli, BenchReportsAFailingConfigurationAndRunsTheOthers) {
    // No Vulkan device 97: the Vulkan configuration fails, the CPU ones run; the run exits 1, the
    // table and stderr name the failure, and the JSON holds it as "error" with no timings.
    ScratchDir dir;
    const std::vector<std::string> args = {
        "bench",    "fence",  "--methods", "stsv,reference",  "--backends", "vulkan,cpu", "--device",
        "97",       "--size", "8x8",       "--samples",       "16",         "--repeat",   "1",
        "--warmup", "0",      "--json",    dir.file("b.json")};
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 1) << describe(args, r);
    EXPECT_NE(r.err.find("stsv: error: stsv/vulkan 16: device index 97"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("failed: device index 97"), std::string::npos) << r.out;
    const nlohmann::json j = readJson(dir.file("b.json"));
    EXPECT_EQ(j["complete"], true);
    int failed = 0, ran = 0;
    for (const nlohmann::json& c : j["configurations"]) {
        if (c["backend"] == "vulkan") {
            ++failed;
            EXPECT_NE(c["error"].get<std::string>().find("device index 97"), std::string::npos) << c.dump();
            EXPECT_FALSE(c.contains("frame_ms") && c["frame_ms"].is_object()) << c.dump();
        } else {
            ++ran;
            EXPECT_FALSE(c.contains("error") && !c["error"].is_null()) << c.dump();
            EXPECT_EQ(c["frame_ms_samples"].size(), 1u) << c.dump();
        }
    }
    EXPECT_EQ(failed, 1);
    EXPECT_EQ(ran, 2);
}

TEST(ExitStatus, ErrorsOutOfMemoryAndBugsAreTold) {
    auto run = [](const std::function<int()>& body) {
        testing::internal::CaptureStderr();
        const int code = runReportingErrors(body);
        return std::make_pair(code, testing::internal::GetCapturedStderr());
    };
    const auto ok = run([] { return 0; });
    EXPECT_EQ(ok.first, 0);
    EXPECT_EQ(ok.second, "");
    const auto input = run([]() -> int { throw InputError("scene.json", "bad thing"); });
    EXPECT_EQ(input.first, 1);
    EXPECT_EQ(input.second.rfind("stsv: error: scene.json", 0), 0u) << input.second;
    const auto memory = run([]() -> int { throw std::bad_alloc(); });
    EXPECT_EQ(memory.first, 1);
    EXPECT_NE(memory.second.find("out of memory"), std::string::npos) << memory.second;
    EXPECT_NE(memory.second.find("memory limit"), std::string::npos) << memory.second;
    const auto bug = run([]() -> int { throw std::logic_error("an invariant broke"); });
    EXPECT_EQ(bug.first, 2);
    EXPECT_EQ(bug.second, "stsv: internal error: an invariant broke\n");
    const auto unknown = run([]() -> int { throw 42; });
    EXPECT_EQ(unknown.first, 2);
    EXPECT_NE(unknown.second.find("internal error"), std::string::npos) << unknown.second;
}

} // namespace
} // namespace stsv::test
