// Argument helpers of the CLI: sizes, per-light paths, lists, knobs, statistics, images.
#include "cli/cli_util.h"
#include "cli/commands.h"
#include "cli/subcommands.h"
#include "core/error.h"
#include "render/frame.h"
#include "scene/load.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>

#include <array>
#include <fstream>

namespace stsv {
namespace {

TEST(ParseSize, AcceptsWidthByHeight) {
    int w = 0, h = 0;
    parseSize("512x256", w, h);
    EXPECT_EQ(w, 512);
    EXPECT_EQ(h, 256);
    parseSize("1X16384", w, h);
    EXPECT_EQ(w, 1);
    EXPECT_EQ(h, 16384);
}

TEST(ParseSize, RejectsMalformedAndOutOfRange) {
    for (const char* text : {"", "12x", "x12", "12", "12x12x12", " 12x12", "12x12 ", "-1x5", "1.5x2", "axb",
                             "0x0", "0x10", "10x0", "16385x1", "100000x100000", "9999999x1"}) {
        int w = -7, h = -7;
        try {
            parseSize(text, w, h);
            ADD_FAILURE() << "accepted '" << text << "' as " << w << "x" << h;
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find("--size"), std::string::npos)
                << "text=" << text << " " << e.what();
        }
    }
}

TEST(PerLightPath, FirstLightKeepsThePath) {
    EXPECT_EQ(perLightPath("out/ls.npy", 0), "out/ls.npy");
    EXPECT_EQ(perLightPath("ls", 0), "ls");
}

TEST(PerLightPath, OtherLightsGetASuffixBeforeTheExtension) {
    EXPECT_EQ(perLightPath("out/ls.npy", 1), "out/ls_light1.npy");
    EXPECT_EQ(perLightPath("ls.npy", 12), "ls_light12.npy");
    EXPECT_EQ(perLightPath("ls", 2), "ls_light2");                   // no extension
    EXPECT_EQ(perLightPath("a.b/c.d.npy", 3), "a.b/c.d_light3.npy"); // dots in folders and stems
    EXPECT_EQ(perLightPath("/abs/x.npy", 1), "/abs/x_light1.npy");
}

// "stsv,", "16,,32" and "repeat=1,,2" were read as "stsv", "16,32" and "1,2": an empty item is
// refused, naming the option, the list and the item's place; spaces around items are dropped.
TEST(SplitList, RefusesEmptyItemsAndDropsSpaces) {
    EXPECT_EQ(splitList("a,b", "--x"), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(splitList(" a , b", "--x"), (std::vector<std::string>{"a", "b"}));
    EXPECT_TRUE(splitList("", "--x").empty());
    EXPECT_TRUE(splitList("  ", "--x").empty());
    for (const auto& [text, place] : std::vector<std::pair<std::string, std::string>>{
             {"a,", "item 2"}, {",a", "item 1"}, {"a,,b", "item 2"}, {"a, ,b", "item 2"}, {",,", "item 1"}})
        try {
            splitList(text, "--methods");
            ADD_FAILURE() << "accepted '" << text << "'";
        } catch (const UsageError& e) {
            const std::string expected = "--methods '" + text + "': " + place + " is empty";
            EXPECT_NE(e.message().find(expected), std::string::npos) << e.message() << "\nlacks " << expected;
        }
}

TEST(ParseIntList, PositiveIntegersOnly) {
    EXPECT_EQ(parseIntList("16,64,256", "--samples"), (std::vector<int>{16, 64, 256}));
    for (const char* bad : {"", "0", "16,x", "-16", "1.5", "99999999999"})
        EXPECT_THROW(parseIntList(bad, "--samples"), UsageError) << "text=" << bad;
}

TEST(ParseSets, KeyValuePairs) {
    const SceneOptions o = parseSets({"count=4", "seed=", "a=b=c"});
    EXPECT_EQ(o.set.at("count"), "4");
    EXPECT_EQ(o.set.at("seed"), "");
    EXPECT_EQ(o.set.at("a"), "b=c");
    EXPECT_THROW(parseSets({"count"}), UsageError);
    EXPECT_THROW(parseSets({"=4"}), UsageError);
}

TEST(MethodBackend, ReferenceIsCpuOnly) {
    const MethodBackend stsv = parseMethodBackend("stsv", Backend::Vulkan);
    EXPECT_EQ(stsv.method, Method::Stsv);
    EXPECT_EQ(stsv.backend, Backend::Vulkan);
    const MethodBackend cpu = parseMethodBackend("stsv/cpu", Backend::Vulkan);
    EXPECT_EQ(cpu.backend, Backend::Cpu);
    const MethodBackend reference = parseMethodBackend("reference", Backend::Vulkan);
    EXPECT_EQ(reference.method, Method::Reference);
    EXPECT_EQ(reference.backend, Backend::Cpu);
    EXPECT_THROW(parseMethodBackend("reference/vulkan", Backend::Cpu), UsageError);
    // The wedge methods run on both backends.
    EXPECT_EQ(parseMethodBackend("dcs+stsv", Backend::Vulkan).backend, Backend::Vulkan);
    EXPECT_EQ(parseMethodBackend("dcs+stsv", Backend::Vulkan).method, Method::DcsStsv);
    EXPECT_EQ(parseMethodBackend("pw/vulkan", Backend::Cpu).backend, Backend::Vulkan);
    EXPECT_EQ(parseMethodBackend("pw/cpu", Backend::Vulkan).backend, Backend::Cpu);
    EXPECT_THROW(parseMethodBackend("no-such-method", Backend::Cpu), UsageError);
    EXPECT_THROW(parseMethodBackend("stsv/metal", Backend::Cpu), UsageError);
}

TEST(Summary, MedianMinMax) {
    const Summary odd = summarize({5.0, 1.0, 3.0});
    EXPECT_EQ(odd.median, 3.0);
    EXPECT_EQ(odd.min, 1.0);
    EXPECT_EQ(odd.max, 5.0);
    const Summary even = summarize({4.0, 1.0, 2.0, 10.0});
    EXPECT_EQ(even.median, 3.0); // mean of the two middle values, exact in binary
    EXPECT_EQ(even.min, 1.0);
    EXPECT_EQ(even.max, 10.0);
    const nlohmann::json j = toJson(summarize({2.0}));
    EXPECT_EQ(j.size(), 3u);
    EXPECT_EQ(j.at("median"), 2.0);
}

TEST(CompareImages, RmseMaxAndFractionAbove) {
    ImageF a(2, 2, 1), b(2, 2, 1);
    b.at(1, 0, 0) = 0.5f;   // one pixel off by 0.5
    b.at(0, 1, 0) = 0.003f; // one pixel off by less than 1/255
    const ImageError e = compareImages(a, b);
    // sqrt((0.25 + 0.003²) / 4); float inputs, so a float-sized tolerance
    EXPECT_NEAR(e.rmse, std::sqrt((0.25 + 0.003 * 0.003) / 4.0), 1e-6);
    EXPECT_FLOAT_EQ(float(e.maxAbs), 0.5f);
    EXPECT_DOUBLE_EQ(e.fractionAbove, 0.25);
    EXPECT_FLOAT_EQ(e.absDifference.at(1, 0, 0), 0.5f);
    EXPECT_EQ(e.absDifference.at(0, 0, 0), 0.0f);
    EXPECT_THROW(compareImages(ImageF(2, 2, 1), ImageF(2, 3, 1)), UsageError);
}

TEST(CompareImages, AnImageAgainstItselfHasNoErrorAndNoBias) {
    ImageF a(3, 2, 3);
    for (std::size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] = float(i % 7) / 7.0f;
    const ImageError e = compareImages(a, a, 0.1f);
    EXPECT_EQ(e.rmse, 0.0);
    EXPECT_EQ(e.bias, 0.0);
    EXPECT_EQ(e.maxAbs, 0.0);
    EXPECT_EQ(e.fractionAbove, 0.0);
}

TEST(CompareImages, BiasIsTheSignedMeanOfImageMinusReference) {
    // A method 0.125 darker than the reference on a quarter of its pixels, 0.25 brighter on
    // another quarter (0.125 and 0.25 are exact in float, so the sums are exact).
    ImageF reference(4, 2, 1), method(4, 2, 1);
    for (float& v : reference.pixels) v = 0.5f;
    method = reference;
    method.at(0, 0, 0) -= 0.125f;
    method.at(1, 0, 0) -= 0.125f;
    method.at(2, 1, 0) += 0.25f;
    method.at(3, 1, 0) += 0.25f;
    const ImageError e = compareImages(method, reference, 0.1f);
    EXPECT_DOUBLE_EQ(e.bias, (-2 * 0.125 + 2 * 0.25) / 8.0) << "brighter on balance: positive";
    EXPECT_DOUBLE_EQ(e.rmse, std::sqrt((2 * 0.125 * 0.125 + 2 * 0.25 * 0.25) / 8.0));
    EXPECT_DOUBLE_EQ(e.maxAbs, 0.25);
    EXPECT_DOUBLE_EQ(e.fractionAbove, 4.0 / 8.0) << "four pixels off by more than 0.1";
    // Swapping the roles flips the sign of the bias only.
    const ImageError swapped = compareImages(reference, method, 0.1f);
    EXPECT_DOUBLE_EQ(swapped.bias, -e.bias);
    EXPECT_DOUBLE_EQ(swapped.rmse, e.rmse);
    // A uniform offset is all bias: RMSE = |bias|. Channels count separately.
    ImageF rgb(2, 2, 3), darker(2, 2, 3);
    for (float& v : rgb.pixels) v = 0.75f;
    for (float& v : darker.pixels) v = 0.5f;
    const ImageError offset = compareImages(darker, rgb, 0.1f);
    EXPECT_DOUBLE_EQ(offset.bias, -0.25);
    EXPECT_DOUBLE_EQ(offset.rmse, 0.25);
    EXPECT_DOUBLE_EQ(offset.fractionAbove, 1.0);
}

TEST(HeatMap, BlackRedYellow) {
    ImageF v(4, 1, 1);
    v.at(1, 0, 0) = 0.5f;
    v.at(2, 0, 0) = 1.0f;
    v.at(3, 0, 0) = 7.0f; // clamped
    const Image8 h = heatMap(v, 1.0f);
    ASSERT_EQ(h.channels, 3);
    auto rgb = [&](int x) { return std::array<int, 3>{h.at(x, 0, 0), h.at(x, 0, 1), h.at(x, 0, 2)}; };
    EXPECT_EQ(rgb(0), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(rgb(1), (std::array<int, 3>{255, 0, 0}));
    EXPECT_EQ(rgb(2), (std::array<int, 3>{255, 255, 0}));
    EXPECT_EQ(rgb(3), (std::array<int, 3>{255, 255, 0}));
}

TEST(HeatMap, LegendShowsTheScaleAndItsNumbers) {
    const int s = 2, pad = 4 * s, line = 12 * s;
    const Image8 legend = heatLegend(0.2f, 300, "caption", s);
    ASSERT_EQ(legend.width, 300);
    ASSERT_EQ(legend.height, pad + line + 6 * s + 2 * s + line + pad);
    // The bar spans [pad, width - pad): black at its left end, red at its middle, yellow at its
    // right end, as the heat maps colour 0, scale/2 and scale.
    const int barY = pad + line + 3 * s;
    auto rgb = [&](int x, int y) {
        return std::array<int, 3>{legend.at(x, y, 0), legend.at(x, y, 1), legend.at(x, y, 2)};
    };
    EXPECT_EQ(rgb(pad, barY), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(rgb(legend.width - pad - 1, barY), (std::array<int, 3>{255, 255, 0}));
    const std::array<int, 3> middle = rgb(legend.width / 2, barY);
    EXPECT_EQ(middle[0], 255);
    EXPECT_LE(middle[1], 2); // within a column of the bar's middle
    // The numbers under the bar: "0" at its left end, "0.1" centred, "0.2+" ending at its right
    // end, each exactly as the font draws that text.
    const int labelY = pad + line + 6 * s + 2 * s;
    auto matches = [&](const std::string& text, int x) {
        Image8 expected;
        expected.width = legend.width;
        expected.height = legend.height;
        expected.channels = 3;
        expected.pixels.assign(std::size_t(expected.width) * expected.height * 3, 0);
        fillRect(expected, 0, 0, expected.width, expected.height, SHEET_BACKGROUND);
        drawText(expected, x, labelY, text, s, SHEET_TEXT);
        int lit = 0, differing = 0;
        for (int y = labelY; y < labelY + line; ++y)
            for (int u = x; u < x + textWidth(text, s); ++u) {
                const bool want = expected.at(u, y, 0) == 255, have = legend.at(u, y, 0) == 255;
                lit += want ? 1 : 0;
                differing += want != have ? 1 : 0;
            }
        return lit > 0 && differing == 0;
    };
    EXPECT_TRUE(matches("0", pad));
    EXPECT_TRUE(matches("0.1", (pad + legend.width - pad) / 2 - textWidth("0.1", s) / 2));
    EXPECT_TRUE(matches("0.2+", legend.width - pad - textWidth("0.2+", s)));
    EXPECT_FALSE(matches("0.3+", legend.width - pad - textWidth("0.3+", s))); // the check can fail
    // A long caption widens the strip rather than being cut.
    EXPECT_EQ(heatLegend(0.2f, 10, std::string(80, 'x'), 1).width, textWidth(std::string(80, 'x'), 1) + 8);
}

TEST(SampleDisagreement, FractionOfDifferingSamplesPerPixel) {
    LightSampleBuffer a(2, 1, 16, BufferKind::Bitmask);
    LightSampleBuffer b(2, 1, 16, BufferKind::Bitmask);
    a.setOccluded(0, 0, 3);
    a.setOccluded(1, 0, 15);
    b.setOccluded(1, 0, 15);
    b.setOccluded(1, 0, 0);
    b.setOccluded(1, 0, 1);
    const ImageF d = sampleDisagreement(a, b);
    EXPECT_EQ(d.at(0, 0, 0), 1.0f / 16.0f);
    EXPECT_EQ(d.at(1, 0, 0), 2.0f / 16.0f);
    EXPECT_THROW(sampleDisagreement(a, LightSampleBuffer(2, 1, 32, BufferKind::Bitmask)), UsageError);
}

TEST(CheckWritableFile, NamesTheProblem) {
    test::ScratchDir dir;
    EXPECT_NO_THROW(checkWritableFile(dir.file("x.png"), "-o"));
    try {
        checkWritableFile(dir.file("missing/x.png"), "-o");
        ADD_FAILURE() << "accepted a file in a missing directory";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
    }
    EXPECT_THROW(checkWritableFile(dir.path().string(), "-o"), UsageError); // a directory
    { std::ofstream(dir.file("plain")) << "x"; }
    EXPECT_THROW(checkWritableFile(dir.file("plain/x.png"), "-o"), UsageError); // parent is a file
    EXPECT_THROW(prepareOutputDirectory(dir.file("plain"), "--out"), UsageError);
    EXPECT_NO_THROW(prepareOutputDirectory(dir.file("a/b"), "--out"));
    EXPECT_TRUE(std::filesystem::is_directory(dir.file("a/b")));
}

TEST(FrameMemory, AbsurdFramesAreRefusedBeforeAllocation) {
    RenderOptions o;
    o.width = o.height = 16384;
    o.samples = 256;
    Scene lights64, oneLight, twoLights;
    lights64.lights.resize(64);
    oneLight.lights.resize(1);
    twoLights.lights.resize(2);
    // 16384² × 32 bytes = 8 GiB of bitmask per light: 64 lights exceed any machine this runs on.
    EXPECT_THROW(checkFrameMemory(o, lights64), UsageError);
    o.width = o.height = 16;
    EXPECT_NO_THROW(checkFrameMemory(o, oneLight));
    // A bitmask stores 32-bit words: 16² pixels × (28 + 16 + 4·8) bytes for 256 samples; Vulkan
    // STSV adds the list of fragments for its sample pass (two a pixel, 8 bytes each) and their
    // words (another 32 bytes a pixel), once for all lights.
    EXPECT_EQ(estimateFrameBytes(o, oneLight), 256.0 * (28.0 + 16.0 + 32.0) + 256.0 * (16.0 + 32.0));
    EXPECT_EQ(estimateFrameBytes(o, twoLights), 256.0 * (28.0 + 16.0 + 2.0 * 32.0) + 256.0 * (16.0 + 32.0));
    o.backend = Backend::Cpu;
    EXPECT_EQ(estimateFrameBytes(o, oneLight), 256.0 * (28.0 + 16.0 + 32.0));
}

// The scale presets measure what their descriptions say: these occluder counts, with the
// reference in the same run and the bit check.
TEST(BenchPresets, ScalePresetsSpanTheirOccluderCountsWithTheReferenceAndCheck) {
    const nlohmann::json presets = loadBenchPresets();
    const struct {
        const char* preset;
        const char* countKey; ///< of the scene stats
        std::vector<std::size_t> counts;
    } cases[] = {{"foliage-scale", "perforated_triangles", {1000, 4000, 16000, 26000, 64000}},
                 {"knot-scale", "triangles", {11520 + 2, 46080 + 2, 184320 + 2}}};
    for (const auto& c : cases) {
        BenchArgs args;
        applyBenchPreset(args, presets, c.preset);
        EXPECT_TRUE(args.check) << c.preset;
        const std::vector<std::string> methods = splitList(args.methods, "--methods");
        EXPECT_NE(std::find(methods.begin(), methods.end(), "reference"), methods.end()) << c.preset;
        const std::size_t eq = args.vary.find('=');
        ASSERT_NE(eq, std::string::npos) << c.preset;
        const std::vector<std::string> values = splitList(args.vary.substr(eq + 1), "--vary");
        ASSERT_EQ(values.size(), c.counts.size()) << c.preset;
        for (std::size_t i = 0; i < values.size(); ++i) {
            SceneOptions options;
            options.set[args.vary.substr(0, eq)] = values[i];
            const Scene scene = loadScene(args.scene, options);
            EXPECT_EQ(sceneStats(scene)[c.countKey].get<std::size_t>(), c.counts[i])
                << c.preset << " " << values[i];
        }
    }
}

TEST(BenchPresets, EveryPresetAppliesAndNamesValidOptions) {
    const nlohmann::json presets = loadBenchPresets();
    ASSERT_FALSE(presets.empty());
    for (const std::string name : {"fence-1024", "fence-samples", "foliage-scale", "knot-scale", "smoke"})
        EXPECT_TRUE(presets.contains(name)) << "missing preset " << name;
    for (const auto& [name, preset] : presets.items()) {
        BenchArgs args;
        applyBenchPreset(args, presets, name);
        EXPECT_TRUE(!args.scene.empty() || args.vary.rfind("scene=", 0) == 0) << name << " names no scene";
        EXPECT_FALSE(preset.value("description", "").empty()) << name << " has no description";
        int w = 0, h = 0;
        EXPECT_NO_THROW(parseSize(args.size, w, h)) << name;
        for (const std::string& m : splitList(args.methods, "--methods"))
            EXPECT_NO_THROW(parseMethod(m)) << name;
        for (const std::string& b : splitList(args.backends, "--backends"))
            EXPECT_NO_THROW(parseBackend(b)) << name;
        for (int n : parseIntList(args.samples, "--samples")) {
            RenderOptions o;
            o.samples = n;
            EXPECT_NO_THROW(validate(o)) << name;
        }
    }
}

TEST(BenchPresets, CommandLineOverridesThePreset) {
    const nlohmann::json presets = loadBenchPresets();
    BenchArgs args;
    args.size = "32x32";
    args.given = {"--size"};
    applyBenchPreset(args, presets, "fence-1024");
    EXPECT_EQ(args.size, "32x32");
    EXPECT_EQ(args.scene, "fence");
    EXPECT_EQ(args.samples, "64");
    try {
        applyBenchPreset(args, presets, "nope");
        ADD_FAILURE() << "accepted an unknown preset";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("fence-1024"), std::string::npos)
            << "should list presets: " << e.what();
    }
}

TEST(BenchPresets, UnknownKeyAndBadFileAreErrors) {
    test::ScratchDir dir;
    { std::ofstream(dir.file("p.json")) << R"({"x": {"scene": "fence", "sizes": "1x1"}})"; }
    const nlohmann::json presets = loadBenchPresets(dir.file("p.json"));
    BenchArgs args;
    EXPECT_THROW(applyBenchPreset(args, presets, "x"), UsageError);
    { std::ofstream(dir.file("bad.json")) << "{"; }
    EXPECT_THROW(loadBenchPresets(dir.file("bad.json")), InputError);
    EXPECT_THROW(loadBenchPresets(dir.file("none.json")), InputError);
}

// A presets file holding an empty object said "unknown preset 'tiny' (presets: )", a "samples"
// array printed nlohmann's "[json.exception.type_error.302] ...", and "repeat": 1e30 became
// --repeat -2147483648 (a double converted to int out of range). Each names the file, the preset,
// the key and what it takes; every number is checked before it is converted.
TEST(BenchPresets, AFileWithoutPresetsOrAValueOfTheWrongTypeOrRangeIsNamed) {
    test::ScratchDir dir;
    auto refusal = [&](const std::string& json) -> std::string {
        { std::ofstream(dir.file("p.json"), std::ios::trunc) << json; }
        BenchArgs args;
        args.presetsFile = dir.file("p.json");
        try {
            applyBenchPreset(args, loadBenchPresets(args.presetsFile), "tiny");
        } catch (const Error& e) {
            return e.message();
        }
        return "accepted: repeat " + std::to_string(args.repeat) + ", warmup " + std::to_string(args.warmup) +
               ", seed " + std::to_string(args.options.seed);
    };
    const std::string file = dir.file("p.json");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"{}", "unknown preset 'tiny': " + file + " holds no presets"},
        {R"({"tiny": {"samples": [16]}})",
         "preset 'tiny' of " + file + ": \"samples\" must be a string, as --samples takes it, not an array"},
        {R"({"tiny": {"scene": 3}})", "preset 'tiny' of " + file + ": \"scene\" must be a string"},
        {R"({"tiny": {"repeat": 1e30}})",
         "preset 'tiny' of " + file + ": \"repeat\" 1e+30 is out of range (1 to 10000)"},
        {R"({"tiny": {"repeat": -1e30}})", "\"repeat\" -1e+30 is out of range (1 to 10000)"},
        {R"({"tiny": {"repeat": 2.5}})", "\"repeat\" 2.5 is not a whole number (1 to 10000)"},
        {R"({"tiny": {"repeat": "3"}})", "\"repeat\" must be a whole number (1 to 10000), not a string"},
        {R"({"tiny": {"warmup": 18446744073709551615}})",
         "\"warmup\" 18446744073709551615 is out of range (0 to 1000)"},
        {R"({"tiny": {"warmup": -1}})", "\"warmup\" -1 is out of range (0 to 1000)"},
        {R"({"tiny": {"seed": 4294967296}})", "\"seed\" 4294967296 is out of range (0 to 4294967295)"},
        {R"({"tiny": {"seed": NaN}})", "not valid JSON"},
        {R"({"tiny": {"check": 1}})", "\"check\" must be true or false, not a number"},
        {R"({"tiny": {"set": "count=3"}})", "\"set\" must be an array of strings"},
        {R"({"tiny": {"param": [1]}})", "\"param\" must be an array of strings"},
        {R"({"tiny": [1]})", "preset 'tiny' must be an object of option → value, not an array"},
        {R"({"tiny": {"description": 1}})", "preset 'tiny': \"description\" must be a string, not a number"},
    };
    for (const auto& [json, expected] : cases) {
        const std::string message = refusal(json);
        EXPECT_NE(message.find(expected), std::string::npos)
            << json << "\n  said: " << message << "\n  lacks: " << expected;
        EXPECT_EQ(message.find("json.exception"), std::string::npos) << json << ": " << message;
    }
    // In range, whole numbers written as floats are whole numbers.
    EXPECT_EQ(refusal(R"({"tiny": {"repeat": 2.0, "warmup": 0, "seed": 4294967295}})"),
              "accepted: repeat 2, warmup 0, seed 4294967295");
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

// SSIM (Wang et al. 2004, Eq. 13): 1 for equal images; for two flat images only the luminance
// term is left, (2·μx·μy + C1) / (μx² + μy² + C1), the same at every pixel; a pattern against
// its inverse has contrast and structure terms of −1.
TEST(StructuralSimilarity, EqualFlatAndInvertedImagesGiveTheClosedForms) {
    ImageF a(24, 20, 3), b(24, 20, 3);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 24; ++x)
            for (int c = 0; c < 3; ++c) a.at(x, y, c) = float((x * 7 + y * 3 + c) % 11) / 10.0f;
    EXPECT_DOUBLE_EQ(structuralSimilarity(a, a), 1.0);

    ImageF flat3(16, 16, 1), flat5(16, 16, 1);
    std::fill(flat3.pixels.begin(), flat3.pixels.end(), 0.3f);
    std::fill(flat5.pixels.begin(), flat5.pixels.end(), 0.5f);
    const double c1 = 1e-4, mx = double(0.3f), my = double(0.5f);
    // Floats of 0.3 and 0.5 through a weighted mean: agreement to 1e-6 of the closed form.
    EXPECT_NEAR(structuralSimilarity(flat3, flat5), (2 * mx * my + c1) / (mx * mx + my * my + c1), 1e-6);

    ImageF checker(16, 16, 1), inverse(16, 16, 1);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            checker.at(x, y, 0) = (x + y) % 2 ? 0.9f : 0.1f;
            inverse.at(x, y, 0) = 1.0f - checker.at(x, y, 0);
        }
    // Means are ≈ 0.5 in both, so luminance ≈ 1 and the rest ≈ −1 (C2 = 9e-4 against σ² = 0.16).
    EXPECT_LT(structuralSimilarity(checker, inverse), -0.95);
    // compareImages reports it.
    EXPECT_DOUBLE_EQ(compareImages(a, a).ssim, 1.0);
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

// What the loaders noted about a scene reaches the user once it is loaded, with the scene it is
// about, escaped like every message; -q keeps it back.
TEST(SceneWarnings, PrintedWithTheSceneUnlessQuiet) {
    Scene scene;
    scene.source = "models/tree.gltf";
    scene.warnings = {"2 primitives of mode LINES skipped", std::string("name \0 with a NUL", 17)};
    testing::internal::CaptureStderr();
    printSceneWarnings(scene, false);
    const std::string printed = testing::internal::GetCapturedStderr();
    EXPECT_EQ(printed, "stsv: warning: models/tree.gltf: 2 primitives of mode LINES skipped\n"
                       "stsv: warning: models/tree.gltf: name \\x00 with a NUL\n");
    testing::internal::CaptureStderr();
    printSceneWarnings(scene, true);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

} // namespace
} // namespace stsv
