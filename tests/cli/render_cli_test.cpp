// `stsv render` driven in-process on tiny frames with the cpu backend: images, the --dump-ls
// layout of --dump-ls, --stats keys, and one-line errors.
#include "core/image.h"
#include "render/renderer.h"
#include "scene/load.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::runStsv;
using test::ScratchDir;

std::size_t lineCount(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

TEST(RenderCli, WritesImagesOfTheRequestedSize) {
    ScratchDir dir;
    const std::vector<std::string> args = {"render",
                                           "fence",
                                           "--backend",
                                           "cpu",
                                           "--size",
                                           "40x24",
                                           "--samples",
                                           "16",
                                           "-o",
                                           dir.file("lit.png"),
                                           "--visibility",
                                           dir.file("vis.png"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const Image8 lit = readPngRgba(dir.file("lit.png"));
    EXPECT_EQ(lit.width, 40);
    EXPECT_EQ(lit.height, 24);
    const Image8 vis = readPngRgba(dir.file("vis.png"));
    EXPECT_EQ(vis.width, 40);
    EXPECT_EQ(vis.height, 24);
    EXPECT_TRUE(r.err.empty()) << "quiet render printed: " << r.err;
}

TEST(RenderCli, ReferenceDefaultsToTheCpuBackend) {
    ScratchDir dir;
    const std::vector<std::string> args = {"render", "fence",     "--method", "reference", "--size",
                                           "16x16",  "--samples", "16",       "--stats",   dir.file("s.json"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    EXPECT_EQ(readJson(dir.file("s.json"))["options"]["backend"], "cpu");
}

/// The bits of pixel (x, y), sample k of a [H, W, N/8] uint8 array (the --dump-ls layout: bit k%8 of byte
/// k/8).
bool npyBit(const NpyArray& a, int x, int y, int k) {
    const std::size_t bytesPerPixel = a.shape[2];
    const std::size_t pixel = std::size_t(y) * a.shape[1] + std::size_t(x);
    return (a.bytes[pixel * bytesPerPixel + std::size_t(k / 8)] >> (k % 8)) & 1u;
}

TEST(RenderCli, DumpLsBitmaskLayoutMatchesTheRendererAndIsDeterministic) {
    ScratchDir dir;
    const int w = 48, h = 32, n = 32;
    auto render = [&](const std::string& file) {
        const std::vector<std::string> args = {
            "render", "fence",     "--method", "stsv",      "--backend",    "cpu", "--size",
            "48x32",  "--samples", "32",       "--dump-ls", dir.file(file), "-q"};
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 0) << test::describe(args, r);
        return readNpy(dir.file(file));
    };
    const NpyArray a = render("a.npy");
    ASSERT_EQ(a.dtype, "|u1");
    ASSERT_EQ(a.shape, (std::vector<std::size_t>{std::size_t(h), std::size_t(w), std::size_t(n / 8)}));
    ASSERT_EQ(a.bytes.size(), std::size_t(w * h * n / 8));

    // The same frame rendered through the library: every (pixel, sample) bit, with row 0 on top.
    RenderOptions o;
    o.backend = Backend::Cpu;
    o.width = w;
    o.height = h;
    o.samples = n;
    const Scene scene = loadScene("fence");
    const Frame frame = renderFrame(scene, o);
    ASSERT_EQ(frame.lightSamples.size(), 1u);
    std::size_t occluded = 0, mismatches = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < n; ++k) {
                const bool bit = npyBit(a, x, y, k);
                occluded += bit ? 1 : 0;
                if (bit != frame.lightSamples[0].occluded(x, y, k) && ++mismatches < 5)
                    ADD_FAILURE() << "x=" << x << " y=" << y << " k=" << k << " npy=" << bit;
            }
    EXPECT_EQ(mismatches, 0u);
    // A meaningful check needs both states: the fence shadows part of the ground.
    EXPECT_GT(occluded, 0u);
    EXPECT_LT(occluded, std::size_t(w * h * n));

    const NpyArray b = render("b.npy");
    EXPECT_EQ(b.shape, a.shape);
    EXPECT_TRUE(a.bytes == b.bytes) << "two renders with the same options differ";
}

TEST(RenderCli, DumpLsCountersShape) {
    ScratchDir dir;
    const std::vector<std::string> args = {
        "render", "fence",    "--backend", "cpu",       "--size",          "20x12", "--samples",
        "16",     "--buffer", "counters",  "--dump-ls", dir.file("c.npy"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const NpyArray c = readNpy(dir.file("c.npy"));
    EXPECT_TRUE(c.dtype == "|u1" || c.dtype == "<u2") << c.dtype;
    EXPECT_EQ(c.shape, (std::vector<std::size_t>{12, 20, 16}));
}

TEST(RenderCli, DumpLsWritesOneFilePerLight) {
    ScratchDir dir;
    const std::vector<std::string> args = {"render",    std::string(STSV_TEST_DATA) + "/scene/example.json",
                                           "--method",  "stsv",
                                           "--backend", "cpu",
                                           "--size",    "16x12",
                                           "--samples", "16",
                                           "--dump-ls", dir.file("ls.npy"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    for (const char* file : {"ls.npy", "ls_light1.npy"}) {
        const NpyArray a = readNpy(dir.file(file));
        EXPECT_EQ(a.shape, (std::vector<std::size_t>{12, 16, 2})) << file;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.file("ls_light2.npy")));
}

TEST(RenderCli, StatsHaveEveryOptionTimingsCountsAndMemory) {
    ScratchDir dir;
    const std::vector<std::string> args = {
        "render", "foliage",   "--method", "stsv",   "--set", "count=3", "--backend",        "cpu", "--size",
        "32x16",  "--samples", "64",       "--seed", "7",     "--stats", dir.file("s.json"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json s = readJson(dir.file("s.json"));
    ASSERT_TRUE(s.contains("frame_ms")) << s.dump(1);
    EXPECT_TRUE(s["frame_ms"].is_number());
    EXPECT_GE(s["frame_ms"].get<double>(), 0.0);
    EXPECT_TRUE(s["startup_ms"].is_number());
    ASSERT_TRUE(s["passes"].is_object());
    EXPECT_FALSE(s["passes"].empty());
    for (const auto& [name, ms] : s["passes"].items()) EXPECT_TRUE(ms.is_number()) << name;
    // Every field of RenderOptions.
    for (const char* key :
         {"method", "backend", "width", "height", "samples", "pattern", "seed", "interleave", "decorrelate",
          "buffer", "ambient", "device", "validation", "extrusion"})
        EXPECT_TRUE(s["options"].contains(key)) << "options lacks " << key << ": " << s["options"].dump();
    EXPECT_EQ(s["options"]["width"], 32);
    EXPECT_EQ(s["options"]["height"], 16);
    EXPECT_EQ(s["options"]["samples"], 64);
    EXPECT_EQ(s["options"]["seed"], 7);
    // Scene counts: 3 plants × 4 S-triangles (+ the ground).
    EXPECT_EQ(s["scene"]["perforated_triangles"], 12);
    EXPECT_GT(s["scene"]["triangles"].get<int>(), 12);
    EXPECT_EQ(s["scene"]["set"]["count"], "3");
    EXPECT_TRUE(s["scene"].contains("skipped_faces"));
    // Light-sample buffer memory is N·W·H bits (STSV paper §5.1).
    EXPECT_EQ(s["light_sample_buffer_bytes"], 32 * 16 * 64 / 8);
}

struct BadInput {
    std::vector<std::string> args;
    std::string expected; ///< text the one-line message must contain
};

TEST(RenderCli, BadInputGivesOneLineAndNonZeroExit) {
    ScratchDir dir;
    const std::vector<BadInput> cases = {
        {{"render", "nosuchscene"}, "nosuchscene"},
        {{"render", "fence", "--size", "12x"}, "12x"},
        {{"render", "fence", "--size", "0x0"}, "0x0"},
        {{"render", "fence", "--size", "100000x100000"}, "100000x100000"},
        {{"render", "fence", "--method", "pcss9"}, "pcss9"},
        {{"render", "fence", "--backend", "metal"}, "metal"},
        {{"render", "fence", "--samples", "17"}, "17"},
        {{"render", "fence", "--set", "count"}, "count"},
        {{"render", "fence", "--set", "nope=1"}, "nope"},
        {{"render", "foliage", "--set", "count=-5"}, "count"},
        {{"render", dir.file("missing.json")}, "missing.json"},
        {{"render", "fence", "-o", dir.file("no/such/dir/x.png")}, "does not exist"},
        {{"render", "fence", "--stats", dir.path().string()}, "directory"},
        {{"render", "fence", "--method", "reference", "--backend", "vulkan"}, "CPU only"},
        {{"render", "fence", "--method", "wedges"}, "wedges"},
        {{"render", "fence", "--extrusion", "compute"}, "compute"},
        {{"render", "fence", "--size", "16384x16384", "--samples", "256", "--buffer", "counters"}, "GiB"},
        {{"render"}, "scene"},
        {{"frobnicate"}, "frobnicate"},
    };
    for (const BadInput& c : cases) {
        std::vector<std::string> args = c.args;
        args.push_back("-q");
        if (c.args.size() == 1 && c.args[0] == "frobnicate") args.pop_back();
        const CliResult r = runStsv(args);
        EXPECT_NE(r.code, 0) << test::describe(args, r);
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << "message should name '" << c.expected << "'\n"
                                                             << test::describe(args, r);
        EXPECT_EQ(lineCount(r.err), 1u) << test::describe(args, r);
        EXPECT_EQ(r.err.rfind("stsv: error: ", 0), 0u) << test::describe(args, r);
    }
}

/// A scene of one ground quad under a light, whose material is `material` (JSON), and, with
/// `occluder`, a quad of material "occluder" above it.
std::string autoScene(const std::string& groundMaterial, const std::string& occluderMaterial) {
    return R"({"camera": {"eye": [0, 3, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fovY": 50},
  "materials": [)" +
           groundMaterial + ", " + occluderMaterial + R"(],
  "meshes": [
    {"name": "ground", "quad": {"size": [4, 4]}, "material": "ground",
     "transform": {"rotate": {"axis": [1, 0, 0], "degrees": -90}}},
    {"name": "occluder", "quad": {"size": [1, 1]}, "material": "occluder",
     "transform": {"translate": [0, 1, 0], "rotate": {"axis": [1, 0, 0], "degrees": -90}}}],
  "lights": [{"type": "sphere", "position": [0, 3, 0], "radius": 0.3, "radiance": [10, 10, 10]}]})";
}

TEST(RenderCli, AutoIsTheDefaultAndPicksTheMethodTheSceneCallsFor) {
    ScratchDir dir;
    const std::string opaque = R"({"name": "ground", "albedo": 0.7})";
    const std::string opaqueOccluder = R"({"name": "occluder", "albedo": 0.5})";
    const std::string perforatedGround =
        R"({"name": "ground", "albedo": 0.7, "alphaTexture": {"generator": "chainlink", "size": 64}})";
    const std::string perforatedOccluder =
        R"({"name": "occluder", "albedo": 0.5, "alphaTexture": {"generator": "chainlink", "size": 64}})";
    const std::string translucentGround =
        R"({"name": "ground", "albedo": 0.7, "alphaMode": "blend", "alphaFactor": 0.5})";
    const std::string translucentOccluder =
        R"({"name": "occluder", "albedo": 0.5, "alphaMode": "blend", "alphaFactor": 0.5})";
    struct Case {
        std::string name, ground, occluder, expected;
    };
    // dcs+stsv wherever a triangle is opaque; stsv where every one is perforated or translucent.
    const std::vector<Case> cases = {
        {"opaque-only", opaque, opaqueOccluder, "dcs+stsv"},
        {"mixed", opaque, perforatedOccluder, "dcs+stsv"},
        {"perforated-only", perforatedGround, perforatedOccluder, "stsv"},
        {"translucent-only", translucentGround, translucentOccluder, "stsv"},
        {"perforated-and-translucent", perforatedGround, translucentOccluder, "stsv"}};
    for (const Case& c : cases) {
        const std::string scene = dir.file(c.name + ".json");
        test::writeText(scene, autoScene(c.ground, c.occluder));
        for (const std::string backend : {"cpu", "vulkan"}) {
            const std::string stats = dir.file(c.name + "-" + backend + ".json");
            const std::vector<std::string> args = {
                "render",    scene, "--backend", backend, "--size", "24x16",
                "--samples", "16",  "--stats",   stats,   "-o",     dir.file(c.name + ".png")};
            const CliResult r = runStsv(args);
            ASSERT_EQ(r.code, 0) << test::describe(args, r);
            const nlohmann::json s = readJson(stats);
            EXPECT_EQ(s["options"]["method"], c.expected) << c.name << " on " << backend;
            EXPECT_EQ(s["method_requested"], "auto") << c.name;
            // The summary line names the method that ran.
            EXPECT_NE(r.err.find(": " + c.expected + " (auto) on " + backend), std::string::npos)
                << c.name << ": " << r.err;
        }
    }
    // The built-in scenes: the fence's ground is opaque; a method named is the one that runs.
    const std::vector<std::string> args = {
        "render", "fence",     "--backend", "cpu",     "--size",
        "16x16",  "--samples", "16",        "--stats", dir.file("fence.json"),
        "-q"};
    ASSERT_EQ(runStsv(args).code, 0);
    EXPECT_EQ(readJson(dir.file("fence.json"))["options"]["method"], "dcs+stsv");
    const std::vector<std::string> named = {"render",    "fence", "--method", "stsv",
                                            "--backend", "cpu",   "--size",   "16x16",
                                            "--samples", "16",    "--stats",  dir.file("named.json"),
                                            "-q"};
    ASSERT_EQ(runStsv(named).code, 0);
    EXPECT_EQ(readJson(dir.file("named.json"))["options"]["method"], "stsv");
    EXPECT_EQ(readJson(dir.file("named.json"))["method_requested"], "stsv");
}

TEST(RenderCli, AutoInBenchAndCompareListsIsTheSceneMethod) {
    ScratchDir dir;
    const std::vector<std::string> bench = {"bench",      "fence", "--methods", "auto,reference",
                                            "--backends", "cpu",   "--size",    "16x16",
                                            "--samples",  "16",    "--repeat",  "1",
                                            "--warmup",   "0",     "--json",    dir.file("bench.json"),
                                            "-q"};
    const CliResult b = runStsv(bench);
    ASSERT_EQ(b.code, 0) << test::describe(bench, b);
    std::vector<std::string> methods;
    const nlohmann::json benchJson = readJson(dir.file("bench.json"));
    for (const auto& c : benchJson["configurations"]) methods.push_back(c["method"]);
    EXPECT_EQ(methods, (std::vector<std::string>{"reference", "dcs+stsv"}));
    // A method the list names already is not run twice; a backend after auto is kept.
    const std::vector<std::string> compare = {
        "compare",   "fence", "--methods", "auto/cpu,dcs+stsv/cpu,stsv/cpu", "--size", "16x16",
        "--samples", "16",    "--json",    dir.file("compare.json"),         "-q"};
    const CliResult c = runStsv(compare);
    ASSERT_EQ(c.code, 0) << test::describe(compare, c);
    std::vector<std::string> rows;
    const nlohmann::json compareJson = readJson(dir.file("compare.json"));
    for (const auto& row : compareJson["rows"]) rows.push_back(row["method"]);
    EXPECT_EQ(rows, (std::vector<std::string>{"reference", "dcs+stsv", "stsv"}));
    // Where no scene is known, auto is refused with the reason.
    const std::vector<std::string> tune = {"tune", "auto", "--scenes", "fence", "-q"};
    const CliResult t = runStsv(tune);
    EXPECT_NE(t.code, 0);
    EXPECT_NE(t.err.find("chosen per scene"), std::string::npos) << t.err;
}

TEST(InfoCli, ListsScenesKnobsAndBackends) {
    const CliResult r = runStsv({"info"});
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* text :
         {"fence", "foliage", "count=64", "reference", "stsv", "vulkan", "cpu threads", "embree"})
        EXPECT_NE(r.out.find(text), std::string::npos) << "info lacks '" << text << "':\n" << r.out;
    // Either devices with the mesh-shader line or one line saying Vulkan is unavailable.
    EXPECT_TRUE(r.out.find("VK_EXT_mesh_shader") != std::string::npos ||
                r.out.find("vulkan: unavailable") != std::string::npos)
        << r.out;
}

} // namespace
} // namespace stsv
