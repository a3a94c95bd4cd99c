// `stsv bench` and `stsv compare` on tiny frames with the cpu backend.
#include "cli/subcommands.h"
#include "core/image.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <utility>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::runStsv;
using test::ScratchDir;

void expectSummary(const nlohmann::json& s, const std::string& what) {
    ASSERT_TRUE(s.is_object()) << what << ": " << s.dump();
    EXPECT_EQ(s.size(), 3u) << what << " must hold exactly median, min, max: " << s.dump();
    for (const char* key : {"median", "min", "max"})
        ASSERT_TRUE(s.contains(key) && s[key].is_number()) << what;
    EXPECT_LE(s["min"].get<double>(), s["median"].get<double>()) << what;
    EXPECT_LE(s["median"].get<double>(), s["max"].get<double>()) << what;
}

// A run stopped during its second scene variant (here by an exception from the frame hook, as
// by a time limit) leaves the JSON of the first variant, marked incomplete; a finished run is
// marked complete.
TEST(BenchCli, JsonIsWrittenAfterEachVariant) {
    ScratchDir dir;
    BenchArgs args;
    args.scene = "foliage";
    args.vary = "count=2,3";
    args.methods = "stsv,reference";
    args.backends = "cpu";
    args.samples = "16";
    args.size = "16x12";
    args.repeat = 1;
    args.warmup = 0;
    args.quiet = true;
    args.json = dir.file("bench.json");
    struct Stop {};
    int frames = 0;
    args.onFrame = [&](const std::string&, bool) {
        if (++frames == 3) throw Stop{};
    };
    testing::internal::CaptureStdout();
    EXPECT_THROW(runBench(args), Stop);
    testing::internal::GetCapturedStdout();
    const nlohmann::json partial = readJson(args.json);
    EXPECT_FALSE(partial["complete"].get<bool>());
    ASSERT_EQ(partial["configurations"].size(), 2u);
    for (const nlohmann::json& c : partial["configurations"]) EXPECT_EQ(c["set"]["count"], "2");

    args.onFrame = nullptr;
    testing::internal::CaptureStdout();
    EXPECT_EQ(runBench(args), 0);
    testing::internal::GetCapturedStdout();
    const nlohmann::json done = readJson(args.json);
    EXPECT_TRUE(done["complete"].get<bool>());
    EXPECT_EQ(done["configurations"].size(), 4u);
}

TEST(BenchCli, JsonHasSummariesPerConfigurationAndCountsTimedFrames) {
    ScratchDir dir;
    BenchArgs args;
    args.scene = "fence";
    args.methods = "stsv,reference";
    args.backends = "cpu";
    args.samples = "16,32";
    args.size = "24x16";
    args.repeat = 3;
    args.warmup = 2;
    args.check = true;
    args.quiet = true;
    args.json = dir.file("bench.json");
    std::map<std::string, std::pair<int, int>> frames; // configuration → (warm-up, timed)
    args.onFrame = [&](const std::string& configuration, bool timed) {
        (timed ? frames[configuration].second : frames[configuration].first) += 1;
    };
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int code = runBench(args);
    const std::string out = testing::internal::GetCapturedStdout();
    const std::string err = testing::internal::GetCapturedStderr();
    ASSERT_EQ(code, 0) << out << err;

    // stsv/cpu and reference/cpu at two sample counts.
    ASSERT_EQ(frames.size(), 4u) << out;
    for (const auto& [name, counts] : frames) {
        EXPECT_EQ(counts.first, 2) << name << " warm-up frames";
        EXPECT_EQ(counts.second, 3) << name << " timed frames";
    }

    const nlohmann::json j = readJson(args.json);
    EXPECT_EQ(j["scene"], "fence");
    EXPECT_TRUE(j["machine"]["cpu_threads"].is_number());
    EXPECT_TRUE(j["machine"].contains("device"));
    ASSERT_EQ(j["configurations"].size(), 4u);
    for (const nlohmann::json& c : j["configurations"]) {
        const std::string name = c["method"].get<std::string>() + "/" + c["backend"].get<std::string>() +
                                 " " + std::to_string(c["samples"].get<int>());
        EXPECT_EQ(c["size"], "24x16") << name;
        EXPECT_TRUE(c["startup_ms"].is_number()) << name;
        expectSummary(c["frame_ms"], name + " frame_ms");
        EXPECT_EQ(c["repeat"], 3) << name;
        EXPECT_EQ(c["frame_ms_samples"].size(), 3u) << name;
        ASSERT_TRUE(c["passes"].is_object() && !c["passes"].empty()) << name;
        for (const auto& [pass, s] : c["passes"].items()) expectSummary(s, name + " pass " + pass);
        EXPECT_TRUE(c["speedup_vs_reference"].is_number()) << name;
        if (c["method"] == "reference") {
            EXPECT_EQ(c["backend"], "cpu");
            EXPECT_EQ(c["speedup_vs_reference"], 1.0);
            EXPECT_EQ(c["identical_bits_percent"], 100.0);
        }
        // The mirror agrees with Embree bit for bit on this frame, as the README says.
        EXPECT_EQ(c["identical_bits_percent"].get<double>(), 100.0) << name;
        EXPECT_EQ(c["differing_samples"], 0) << name;
    }
    EXPECT_TRUE(j["skipped"].empty());
}

TEST(BenchCli, ReferenceOnVulkanIsSkippedWithANoteAndRunsOnTheCpu) {
    ScratchDir dir;
    const std::vector<std::string> args = {
        "bench",     "fence", "--methods", "reference", "--backends", "vulkan", "--size", "8x8",
        "--samples", "16",    "--repeat",  "1",         "--warmup",   "0",      "--json", dir.file("b.json")};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    EXPECT_NE(r.out.find("skipped reference/vulkan"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("note:"), std::string::npos) << r.err;
    const nlohmann::json j = readJson(dir.file("b.json"));
    ASSERT_EQ(j["configurations"].size(), 1u);
    EXPECT_EQ(j["configurations"][0]["backend"], "cpu");
    ASSERT_EQ(j["skipped"].size(), 1u);
    EXPECT_EQ(j["skipped"][0]["backend"], "vulkan");
}

TEST(BenchCli, VaryMakesOneSceneVariantPerValue) {
    ScratchDir dir;
    const std::vector<std::string> args = {"bench",     "foliage", "--methods",        "stsv",   "--backends",
                                           "cpu",       "--vary",  "count=2,5",        "--size", "16x16",
                                           "--samples", "16",      "--repeat",         "1",      "--warmup",
                                           "0",         "--json",  dir.file("b.json"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json j = readJson(dir.file("b.json"));
    ASSERT_EQ(j["configurations"].size(), 2u);
    EXPECT_EQ(j["configurations"][0]["set"]["count"], "2");
    EXPECT_EQ(j["configurations"][0]["scene"]["perforated_triangles"], 8);
    EXPECT_EQ(j["configurations"][1]["scene"]["perforated_triangles"], 20);
    EXPECT_TRUE(j["configurations"][0]["speedup_vs_reference"].is_null());
}

TEST(BenchCli, VarySceneRunsEachSceneWithTheSameKnobs) {
    ScratchDir dir;
    const std::vector<std::string> args = {"bench",
                                           "--vary",
                                           "scene=fence,fence-mesh",
                                           "--set",
                                           "texture_size=8",
                                           "--methods",
                                           "dcs+stsv",
                                           "--backends",
                                           "cpu",
                                           "--size",
                                           "16x16",
                                           "--samples",
                                           "16",
                                           "--repeat",
                                           "1",
                                           "--warmup",
                                           "0",
                                           "--json",
                                           dir.file("b.json"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json j = readJson(dir.file("b.json"));
    ASSERT_EQ(j["configurations"].size(), 2u);
    EXPECT_EQ(j["configurations"][0]["scene_name"], "fence");
    EXPECT_EQ(j["configurations"][1]["scene_name"], "fence-mesh");
    // The quad's 2 perforated triangles, and the mesh of the same 8x8 texture: none perforated.
    EXPECT_EQ(j["configurations"][0]["scene"]["perforated_triangles"], 2);
    EXPECT_EQ(j["configurations"][1]["scene"]["perforated_triangles"], 0);
    EXPECT_GT(j["configurations"][1]["scene"]["triangles"].get<int>(),
              j["configurations"][0]["scene"]["triangles"].get<int>());
}

TEST(BenchCli, PresetWithOverridesAndErrors) {
    ScratchDir dir;
    const std::vector<std::string> args = {
        "bench",    "--preset", "smoke",  "--backends",       "cpu", "--size", "16x16",
        "--repeat", "1",        "--json", dir.file("b.json"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json j = readJson(dir.file("b.json"));
    EXPECT_EQ(j["preset"], "smoke");
    for (const nlohmann::json& c : j["configurations"]) {
        EXPECT_EQ(c["size"], "16x16");
        EXPECT_EQ(c["backend"], "cpu");
        EXPECT_EQ(c["repeat"], 1);
    }

    const CliResult list = runStsv({"bench", "--list-presets"});
    EXPECT_EQ(list.code, 0);
    EXPECT_NE(list.out.find("fence-1024"), std::string::npos) << list.out;

    for (const std::vector<std::string>& bad : {std::vector<std::string>{"bench", "--preset", "nope", "-q"},
                                                {"bench", "-q"},
                                                {"bench", "fence", "--samples", "16,x", "-q"},
                                                {"bench", "fence", "--repeat", "0", "-q"},
                                                {"bench", "fence", "--methods", "stsv", "--check", "-q"},
                                                {"bench", "fence", "--vary", "count", "-q"}}) {
        const CliResult e = runStsv(bad);
        EXPECT_NE(e.code, 0) << test::describe(bad, e);
        EXPECT_EQ(e.err.rfind("stsv: error: ", 0), 0u) << test::describe(bad, e);
    }
}

/// The row of `method` in compare's table, split into columns.
std::vector<std::string> tableRow(const std::string& out, const std::string& method) {
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind(method + " ", 0) == 0) {
            std::istringstream words(line);
            std::vector<std::string> columns;
            for (std::string w; words >> w;) columns.push_back(w);
            return columns;
        }
    return {};
}

TEST(CompareCli, ReferenceRowIsIdenticalAndImagesAreWritten) {
    ScratchDir dir;
    const std::vector<std::string> args = {
        "compare", "fence", "--methods",     "stsv/cpu", "--size",           "32x24", "--samples",
        "16",      "--out", dir.file("cmp"), "--json",   dir.file("c.json"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const std::vector<std::string> reference = tableRow(r.out, "reference/cpu");
    ASSERT_GE(reference.size(), 9u) << r.out;
    EXPECT_EQ(reference[1], "100.0000") << r.out; // identical %
    EXPECT_EQ(reference[2], "0") << r.out;        // differing bits
    const std::vector<std::string> stsv = tableRow(r.out, "stsv/cpu");
    ASSERT_GE(stsv.size(), 9u) << r.out;
    EXPECT_EQ(stsv[1], "100.0000") << r.out; // the mirror and Embree agree bit for bit here
    EXPECT_EQ(stsv[2], "0") << r.out;

    for (const char* file : {"reference_cpu_visibility.png", "reference_cpu_lit.png",
                             "stsv_cpu_visibility.png", "stsv_cpu_lit.png"}) {
        const std::string path = dir.file("cmp/" + std::string(file));
        ASSERT_TRUE(std::filesystem::exists(path)) << path;
        const Image8 image = readPngRgba(path);
        EXPECT_EQ(image.width, 32) << file;
        EXPECT_EQ(image.height, 24) << file;
    }
    // The heat maps carry their colour scale beneath the frame's 24 rows: 40 pixels high at one
    // pixel per font unit (padding 4, caption 12, bar 6, gap 2, numbers 12, padding 4), as wide as
    // its caption needs (wider than the 32-pixel frame); the bar runs from black to yellow.
    for (const char* file : {"stsv_cpu_diff.png", "stsv_cpu_bitdiff.png"}) {
        const std::string path = dir.file("cmp/" + std::string(file));
        ASSERT_TRUE(std::filesystem::exists(path)) << path;
        const Image8 image = readPngRgba(path);
        EXPECT_GT(image.width, 32) << file;
        ASSERT_EQ(image.height, 24 + 40) << file;
        const int barY = 24 + 4 + 12 + 3;
        EXPECT_EQ(image.at(4, barY, 0), 0) << file;
        EXPECT_EQ(image.at(4, barY, 1), 0) << file;
        EXPECT_EQ(image.at(image.width - 5, barY, 0), 255) << file;
        EXPECT_EQ(image.at(image.width - 5, barY, 1), 255) << file;
        EXPECT_EQ(image.at(image.width - 5, barY, 2), 0) << file;
    }
    const nlohmann::json j = readJson(dir.file("c.json"));
    ASSERT_EQ(j["rows"].size(), 2u);
    EXPECT_EQ(j["rows"][0]["differing_samples"], 0);
    EXPECT_EQ(j["rows"][0]["visibility"]["max_abs"], 0.0);
    EXPECT_EQ(j["rows"][0]["compared_samples"], 32 * 24 * 16);
}

TEST(CompareCli, TransmittanceReferenceGivesEachMethodsPerSampleTransmittanceError) {
    // Translucent particles: stsv and dcs+stsv, on the CPU and on Vulkan, write transmittance and
    // agree with the reference but for samples that graze an edge (and, on Vulkan, pixels whose
    // raster G-buffer point differs from the ray tracer's); pcss has no per-sample answer.
    ScratchDir dir;
    const std::vector<std::string> args = {"compare",   "particles",
                                           "--set",     "count=40",
                                           "--buffer",  "transmittance",
                                           "--backend", "cpu",
                                           "--methods", "stsv,dcs+stsv,pcss,stsv/vulkan,dcs+stsv/vulkan",
                                           "--size",    "48x36",
                                           "--samples", "16",
                                           "--json",    dir.file("t.json"),
                                           "--report",  dir.file("report"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    EXPECT_NE(r.out.find("per-sample transmittance RMSE against reference/cpu: reference/cpu 0.00000"),
              std::string::npos)
        << r.out;
    const nlohmann::json j = readJson(dir.file("t.json"));
    ASSERT_EQ(j["rows"].size(), 6u);
    EXPECT_EQ(j["rows"][0]["transmittance_rmse"], 0.0);
    for (int i : {1, 2, 4, 5}) {
        SCOPED_TRACE(j["rows"][i]["method"].get<std::string>());
        ASSERT_TRUE(j["rows"][i].contains("transmittance_rmse"));
        EXPECT_LT(j["rows"][i]["transmittance_rmse"].get<double>(), 0.02);
    }
    EXPECT_FALSE(j["rows"][3].contains("transmittance_rmse")); // pcss: a v_coef per pixel
    std::ifstream page(dir.file("report/index.html"));
    const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
    EXPECT_NE(html.find("transmittance RMSE"), std::string::npos);
}

TEST(CompareCli, NpyFiles) {
    ScratchDir dir;
    auto dump = [&](const std::string& file, const std::string& seed, const std::string& size) {
        const std::vector<std::string> args = {"render",    "fence",        "--backend", "cpu",    "--size",
                                               size,        "--samples",    "16",        "--seed", seed,
                                               "--dump-ls", dir.file(file), "-q"};
        const CliResult r = runStsv(args);
        ASSERT_EQ(r.code, 0) << test::describe(args, r);
    };
    dump("a.npy", "1", "24x16");
    dump("b.npy", "1", "24x16");
    dump("c.npy", "2", "24x16");
    dump("d.npy", "1", "16x16");

    const CliResult same = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy")});
    ASSERT_EQ(same.code, 0) << same.err;
    EXPECT_NE(same.out.find("differing samples: 0 of 6144"), std::string::npos) << same.out;

    // Another seed rotates the per-pixel sample sets: some bits must differ.
    const CliResult other =
        runStsv({"compare", dir.file("a.npy"), dir.file("c.npy"), "--out", dir.file("diff")});
    ASSERT_EQ(other.code, 0) << other.err;
    EXPECT_EQ(other.out.find("differing samples: 0 of"), std::string::npos) << other.out;
    const Image8 difference = readPngRgba(dir.file("diff/difference.png"));
    // The 24x16 frame, then its colour scale: 40 rows (see ReferenceRowIsIdenticalAndImagesAreWritten).
    EXPECT_GT(difference.width, 24);
    EXPECT_EQ(difference.height, 16 + 40);

    const CliResult mismatch = runStsv({"compare", dir.file("a.npy"), dir.file("d.npy")});
    EXPECT_NE(mismatch.code, 0);
    EXPECT_NE(mismatch.err.find("d.npy"), std::string::npos) << mismatch.err;
    const CliResult missing = runStsv({"compare", dir.file("a.npy"), dir.file("none.npy")});
    EXPECT_NE(missing.code, 0);
    EXPECT_NE(missing.err.find("none.npy"), std::string::npos) << missing.err;
}

// A counters file and a bitmask file are refused as a pair, whatever their shapes (each file's
// metadata says its kind); the same occlusion written as counters compares as the bits do.
TEST(CompareCli, CountersAndBitsCompareEachWithTheirOwnKind) {
    ScratchDir dir;
    auto dump = [&](const std::string& file, const std::string& method, const std::string& buffer) {
        const std::vector<std::string> args = {"render",    "fence",    "--backend", "cpu",          "--size",
                                               "24x16",     "--method", method,      "--buffer",     buffer,
                                               "--samples", "64",       "--dump-ls", dir.file(file), "-q"};
        const CliResult r = runStsv(args);
        ASSERT_EQ(r.code, 0) << test::describe(args, r);
    };
    dump("bits.npy", "stsv", "bitmask");
    dump("counts.npy", "stsv", "counters");
    for (const auto& [a, b] : {std::pair{"bits.npy", "counts.npy"}, std::pair{"counts.npy", "bits.npy"}}) {
        const CliResult r = runStsv({"compare", dir.file(a), dir.file(b)});
        EXPECT_EQ(r.code, 1) << r.out;
        EXPECT_NE(r.err.find("a bitmask of 64 samples"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("counters of 64 samples"), std::string::npos) << r.err;
    }
    // The reference's bits against STSV's bits, and the reference's counters against STSV's
    // counters: as many samples differ (compare pairs counters by occlusion, count > 0).
    dump("reference.npy", "reference", "bitmask");
    dump("reference_counts.npy", "reference", "counters");
    const CliResult bits = runStsv({"compare", dir.file("bits.npy"), dir.file("reference.npy")});
    ASSERT_EQ(bits.code, 0) << bits.err;
    const std::size_t at = bits.out.find("differing samples: ");
    ASSERT_NE(at, std::string::npos) << bits.out;
    const std::string differing = bits.out.substr(at, bits.out.find('\n', at) - at);
    EXPECT_NE(differing.find(" of 24576"), std::string::npos) << bits.out;
    const CliResult r = runStsv({"compare", dir.file("counts.npy"), dir.file("reference_counts.npy")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("24x16 pixels, 64 samples, counters"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(differing), std::string::npos) << "expected '" << differing << "' in\n" << r.out;
}

} // namespace
} // namespace stsv
