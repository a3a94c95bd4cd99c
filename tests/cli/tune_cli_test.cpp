// `stsv tune` and `compare --knobs`, on tiny frames with the cpu backend: a scene whose right
// knob value follows from its geometry, the defaults kept when nothing beats them, the budget,
// the --json file read back by compare, and the errors for bad input.
#include "shadowmaps/shadow_map.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::runStsv;
using test::ScratchDir;

CliResult runOk(const std::vector<std::string>& args) {
    CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 0) << test::describe(args, r);
    return r;
}

/// A scene where PCF's kernel half-width R (pcf_world_radius, metres at the receiver) has one
/// right value, `radius`:
///  * a square light of edge L at height H = 4 facing down, its edges along x and z; an opaque
///    occluder covering x ≤ xe = 0.3 at height h = 1; the ground at y = 0, 4 × 4 around the origin.
///  * Across the occluder's edge the ground's visibility is the fraction of the light beyond the
///    line through the edge: by similar triangles it rises linearly from 0 to 1 over a width
///    w = L·h/(H − h), centred where the edge projects from the light's centre (x = xe·H/(H − h)).
///  * PCF averages the shadow test over a square of half-width R at the receiver, centred on it:
///    across a straight edge that is a linear ramp of width 2R centred on the same projection.
/// The ramps coincide when 2R = w, i.e. L = 2R·(H − h)/h; a radius off by a factor f widens or
/// narrows PCF's ramp by the same factor. The camera looks obliquely at the penumbra from the
/// lit side, so the occluder hides none of it. (The map's texels, 256 over the scene box seen
/// from the light with sm_fit=0, are 2.1 cm on the ground.)
std::string writeRampScene(const ScratchDir& dir, const std::string& name, double radius) {
    const double H = 4.0, h = 1.0;
    const double edge = 2.0 * radius * (H - h) / h;
    const nlohmann::json scene = {
        {"camera", {{"eye", {1.5, 2.5, 0.0}}, {"target", {0.4, 0.0, 0.0}}, {"fovY", 12}}},
        {"materials", {{{"name", "grey"}, {"albedo", 0.7}, {"doubleSided", true}}}},
        {"meshes",
         {{{"name", "ground"},
           {"quad", {{"size", {4, 4}}}},
           {"material", "grey"},
           {"transform", {{"rotate", {{"axis", {1, 0, 0}}, {"degrees", -90}}}}}},
          {{"name", "occluder"},
           {"material", "grey"},
           {"vertices", {{-2, h, -2}, {0.3, h, -2}, {0.3, h, 2}, {-2, h, 2}}},
           {"triangles", {{0, 2, 1}, {0, 3, 2}}}}}},
        {"lights",
         {{{"type", "rectangle"},
           {"position", {0, H, 0}},
           {"normal", {0, -1, 0}},
           {"size", {edge, edge}},
           {"tangent", {1, 0, 0}},
           {"radiance", 300}}}}};
    std::string path = dir.file(name);
    test::writeText(path, scene.dump(1));
    return path;
}

/// tune's arguments for the ramp scene: PCF's radius searched (over `range`, or its own), the map
/// fixed as the scene assumes.
std::vector<std::string> rampTune(const std::string& scene, const std::string& json,
                                  const std::string& range = "") {
    return {"tune",      "pcf",         "--scenes",    scene,      "--knob", "pcf_world_radius" + range,
            "--param",   "sm_size=256", "--param",     "sm_fit=0", "--size", "48x48",
            "--samples", "64",          "--converged", "8",        "--json", json,
            "-q"};
}

std::string formatG(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

/// Every run: the reported knobs never do worse than the defaults on the training scenes.
void expectNoWorseThanDefaults(const nlohmann::json& method) {
    EXPECT_LE(method["objective"]["best"].get<double>(), method["objective"]["defaults"].get<double>());
    EXPECT_EQ(method["objective"]["defaults"].get<double>(), 1.0) << "the defaults are the objective's unit";
    if (method["training"].size() == 1) { // one scene: the objective is that scene's ratio
        EXPECT_LE(method["training"][0]["best"].get<double>(),
                  method["training"][0]["default"].get<double>());
    }
    EXPECT_LE(method["renders"].get<int>(), method["budget"].get<int>());
}

TEST(TuneCli, RecoversThePcfRadiusThatMatchesAnAnalyticPenumbra) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::string scene = writeRampScene(dir, "ramp15.json", 0.15);
    runOk(rampTune(scene, dir.file("t.json")));
    const nlohmann::json j = readJson(dir.file("t.json"));
    ASSERT_EQ(j["methods"].size(), 1u);
    const nlohmann::json& m = j["methods"][0];
    // Within 12 %: the refinement's last step is 1/64 of the log range, a factor of 1.08, and the
    // occluder's edge lands on the map's texel grid, which shifts the best radius by up to half a
    // texel (1 cm) over the ramp's 30 cm.
    EXPECT_NEAR(m["knobs"]["pcf_world_radius"].get<double>(), 0.15, 0.12 * 0.15) << m.dump(1);
    // The default as written (the float 0.06f as its shortest decimal).
    EXPECT_EQ(m["defaults"]["pcf_world_radius"].get<double>(), 0.06);
    EXPECT_TRUE(m["improved"].get<bool>());
    // The fixed knobs are part of what compare --knobs must set.
    EXPECT_EQ(m["knobs"]["sm_size"], 256);
    EXPECT_EQ(m["knobs"]["sm_fit"], 0);
    expectNoWorseThanDefaults(m);
}

TEST(TuneCli, ReportsTheDefaultsWhenNothingBeatsThem) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    // The scene built for the default radius, 6 cm, and a search over radii of 18 to 54 cm only:
    // every one of them makes a ramp three times too wide or more.
    const std::string scene = writeRampScene(dir, "ramp6.json", 0.06);
    const CliResult r = runOk(rampTune(scene, dir.file("t.json"), "=0.18:0.54"));
    const nlohmann::json m = readJson(dir.file("t.json"))["methods"][0];
    EXPECT_EQ(m["knobs"]["pcf_world_radius"].get<double>(), 0.06) << m.dump(1);
    EXPECT_FALSE(m["improved"].get<bool>());
    EXPECT_GT(m["evaluations"].get<int>(), 5) << "the search tried other radii";
    // The defaults' own error, not a later render's: the same number.
    EXPECT_EQ(m["training"][0]["best"].get<double>(), m["training"][0]["default"].get<double>());
    EXPECT_EQ(m["objective"]["best"].get<double>(), 1.0);
    EXPECT_NE(r.out.find("no point beat the defaults"), std::string::npos) << r.out;
    expectNoWorseThanDefaults(m);
}

TEST(TuneCli, TheDefaultKnobsOverTwoScenesWithHeldOutErrorsAndTheBudget) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::vector<std::string> args = {"tune",       "pcf",       "--scenes", "fence",           "knot",
                                           "--validate", "foliage",   "--param",  "sm_size=256",     "--size",
                                           "24x24",      "--samples", "16",       "--converged",     "2",
                                           "--budget",   "13",        "--json",   dir.file("t.json")};
    const CliResult r = runOk(args);
    const nlohmann::json m = readJson(dir.file("t.json"))["methods"][0];
    // pcf's tunable knobs, in the order of the knob list.
    std::vector<std::string> searched;
    for (const nlohmann::json& k : m["searched"]) searched.push_back(k["name"]);
    EXPECT_EQ(searched, (std::vector<std::string>{"sm_bias", "sm_normal_offset", "pcf_world_radius"}));
    // Two renders a point: 13 allow 6 points (12 renders), the 7th would pass it.
    EXPECT_EQ(m["renders"], 12);
    EXPECT_EQ(m["evaluations"], 6);
    EXPECT_TRUE(m["budget_spent"].get<bool>());
    ASSERT_EQ(m["training"].size(), 2u);
    EXPECT_EQ(m["training"][0]["scene"], "fence");
    ASSERT_EQ(m["validation"].size(), 1u);
    EXPECT_EQ(m["validation"][0]["scene"], "foliage");
    EXPECT_GT(m["validation"][0]["default"].get<double>(), 0.0);
    // Progress: one line per point on stderr, with the render count.
    EXPECT_NE(r.err.find("render 12 of at most 13"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("foliage"), std::string::npos) << r.out;
    expectNoWorseThanDefaults(m);
}

TEST(TuneCli, TheWorstObjectiveFindsTheKnobsNearestEverySceneBestAtOnce) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    // Two ramps that want radii a factor 9 apart: no radius is right for both.
    const std::string narrow = writeRampScene(dir, "ramp2.json", 0.02);
    const std::string wide = writeRampScene(dir, "ramp18.json", 0.18);
    auto both = [&](const std::string& objective, const std::string& json) {
        std::vector<std::string> args = rampTune(narrow, json);
        args.insert(args.begin() + 4, wide);
        args.insert(args.end(), {"--objective", objective});
        return args;
    };
    runOk(both("worst", dir.file("worst.json")));
    runOk(both("mean", dir.file("mean.json")));
    runOk(rampTune(narrow, dir.file("narrow.json")));
    runOk(rampTune(wide, dir.file("wide.json")));
    const nlohmann::json w = readJson(dir.file("worst.json"))["methods"][0];
    const nlohmann::json mean = readJson(dir.file("mean.json"))["methods"][0];
    ASSERT_EQ(w["training"].size(), 2u);
    // Each scene's own best is what tune finds on that scene alone (the same search, deterministic).
    const double own[2] = {w["training"][0]["own_best"].get<double>(),
                           w["training"][1]["own_best"].get<double>()};
    EXPECT_EQ(own[0], readJson(dir.file("narrow.json"))["methods"][0]["training"][0]["best"].get<double>());
    EXPECT_EQ(own[1], readJson(dir.file("wide.json"))["methods"][0]["training"][0]["best"].get<double>());
    // The objective is the worse of the two scenes' error over their own best (1e-6 floor, far
    // below these errors), for the defaults and for the knobs reported.
    auto worstRatio = [&](const nlohmann::json& m, const char* point) {
        double r = 0.0;
        for (int i = 0; i < 2; ++i)
            r = std::max(r, (m["training"][i][point].get<double>() + 1e-6) / (own[i] + 1e-6));
        return r;
    };
    EXPECT_DOUBLE_EQ(w["objective"]["best"].get<double>(), worstRatio(w, "best"));
    EXPECT_DOUBLE_EQ(w["objective"]["defaults"].get<double>(), worstRatio(w, "default"));
    EXPECT_LE(w["objective"]["best"].get<double>(), w["objective"]["defaults"].get<double>());
    // Each scene at the default radius, 6 cm, is a factor 3 from its own; the compromise lies
    // strictly between the two scenes' radii (each recovered within 12 %), and it is no worse on
    // the worse scene than what the mean objective picks: minimising the mean trades one scene
    // against the other, the worst objective bounds both.
    EXPECT_GT(w["objective"]["defaults"].get<double>(), 1.5);
    const double radius = w["knobs"]["pcf_world_radius"].get<double>();
    EXPECT_GT(radius, 1.12 * 0.02) << w.dump(1);
    EXPECT_LT(radius, 0.18 / 1.12) << w.dump(1);
    EXPECT_LE(w["objective"]["best"].get<double>(), worstRatio(mean, "best")) << mean.dump(1);
    EXPECT_EQ(w["own_renders"].get<int>(),
              readJson(dir.file("narrow.json"))["methods"][0]["renders"].get<int>() +
                  readJson(dir.file("wide.json"))["methods"][0]["renders"].get<int>());
    EXPECT_LE(w["renders"].get<int>(), w["budget"].get<int>());
    EXPECT_EQ(readJson(dir.file("worst.json"))["objective"].get<std::string>().rfind("worst over", 0), 0u);
}

TEST(TuneCli, TheJsonFileSetsCompareKnobs) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::string scene = writeRampScene(dir, "ramp15.json", 0.15);
    runOk(rampTune(scene, dir.file("t.json")));
    const nlohmann::json tuned = readJson(dir.file("t.json"))["methods"][0];
    const double radius = tuned["knobs"]["pcf_world_radius"].get<double>();
    ASSERT_NE(radius, 0.06) << "the file must hold a radius other than the default";

    const std::vector<std::string> compare = {
        "compare",          scene,    "--methods", "pcf/cpu,pcss/cpu", "--knobs",
        dir.file("t.json"), "--size", "48x48",     "--samples",        "64",
        "--converged",      "8",      "--json",    dir.file("c.json")};
    const CliResult r = runOk(compare);
    const nlohmann::json c = readJson(dir.file("c.json"));
    EXPECT_EQ(c["converged_reference"]["cache"], "hit") << "tune's converged reference is compare's";
    ASSERT_EQ(c["rows"].size(), 3u);
    const nlohmann::json& pcf = c["rows"][1];
    ASSERT_EQ(pcf["method"], "pcf");
    for (const auto& [name, value] : tuned["knobs"].items())
        EXPECT_EQ(pcf["knobs"][name].get<double>(), value.get<double>()) << name;
    EXPECT_EQ(pcf["knobs_file"], dir.file("t.json"));
    // The same frame against the same converged images: the error tune reported, to the last bit
    // (both are compareImages of the same two images; JSON keeps a double's every digit).
    EXPECT_EQ(pcf["converged"]["visibility_facing"]["rmse"].get<double>(),
              tuned["training"][0]["best"].get<double>());
    EXPECT_EQ(pcf["converged"]["visibility_facing"]["pixels"].get<std::size_t>(),
              tuned["training"][0]["facing_pixels"].get<std::size_t>());
    EXPECT_GT(tuned["training"][0]["facing_pixels"].get<std::size_t>(), 0u);
    // pcss is not in the file: its defaults, and no file named.
    EXPECT_EQ(c["rows"][2]["knobs"]["sm_size"].get<double>(), 2048.0);
    EXPECT_FALSE(c["rows"][2].contains("knobs_file"));
    EXPECT_NE(r.out.find("knobs of pcf/cpu from"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("knobs of pcss/cpu"), std::string::npos) << r.out;

    // An explicit --param wins over the file, and the row says so.
    std::vector<std::string> overridden = compare;
    overridden.insert(overridden.end(), {"--param", "pcf_world_radius=0.01"});
    const CliResult o = runOk(overridden);
    const nlohmann::json co = readJson(dir.file("c.json"));
    EXPECT_EQ(co["rows"][1]["knobs"]["pcf_world_radius"].get<double>(), 0.01);
    EXPECT_EQ(co["rows"][1]["knobs"]["sm_size"].get<double>(), 256.0);
    EXPECT_NE(o.out.find("pcf_world_radius=0.01 (--param; the file has " + formatG(radius) + ")"),
              std::string::npos)
        << o.out;
}

TEST(TuneCli, AFileOfSeveralMethods) {
    ScratchDir dir;
    test::writeText(dir.file("k.json"),
                    R"({"methods": [{"method": "pcf", "knobs": {"pcf_world_radius": 0.05, "sm_size": 256}},
                                    {"method": "vsm", "knobs": {"vsm_bleed": 0.3, "sm_size": 256}}]})");
    const std::vector<std::string> args = {"compare",   "fence",
                                           "--methods", "pcf/cpu,vsm/cpu",
                                           "--knobs",   dir.file("k.json"),
                                           "--size",    "16x16",
                                           "--samples", "16",
                                           "--json",    dir.file("c.json"),
                                           "-q"};
    runOk(args);
    const nlohmann::json c = readJson(dir.file("c.json"));
    EXPECT_EQ(c["rows"][1]["knobs"]["pcf_world_radius"].get<double>(), 0.05);
    EXPECT_EQ(c["rows"][2]["knobs"]["vsm_bleed"].get<double>(), 0.3);
    EXPECT_EQ(c["rows"][2]["knobs"]["sm_size"].get<double>(), 256.0);
    // One method's object alone is a file too.
    test::writeText(dir.file("one.json"), R"({"method": "pcf", "knobs": {"pcf_world_radius": 0.07}})");
    runOk({"compare", "fence", "--methods", "pcf/cpu", "--knobs", dir.file("one.json"), "--size", "16x16",
           "--samples", "16", "--param", "sm_size=256", "--json", dir.file("c.json"), "-q"});
    EXPECT_EQ(readJson(dir.file("c.json"))["rows"][1]["knobs"]["pcf_world_radius"].get<double>(), 0.07);
}

TEST(TuneCli, TheUserGuideListsTheTunableKnobsAsTheKnobListHasThem) {
    // The table of the tune section: "| `name` | lo … hi | scale | methods |".
    std::ifstream in(std::string(STSV_SOURCE_DIR) + "/docs/user-guide.md");
    ASSERT_TRUE(in.good());
    static const std::regex row(R"(^\| `(\w+)` \| (\S+) … (\S+) \| (\w+) \|.*)");
    std::map<std::string, std::string> documented;
    bool inSection = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("### ", 0) == 0) inSection = line == "### `stsv tune`";
        std::smatch m;
        if (inSection && std::regex_match(line, m, row))
            documented[m[1].str()] = m[2].str() + " … " + m[3].str() + " " + m[4].str();
    }
    std::map<std::string, std::string> listed;
    for (const ShadowMapKnob& k : shadowMapKnobs()) {
        if (!k.search.tunable) continue;
        EXPECT_GE(k.search.lo, k.min) << k.name;
        EXPECT_LE(k.search.hi, k.max) << k.name;
        listed[k.name] = formatG(k.search.lo) + " … " + formatG(k.search.hi) + " " +
                         (k.search.scale == KnobScale::Log ? "log" : "linear");
    }
    EXPECT_EQ(documented, listed);
    // The knobs that buy quality with time or memory are not searched unless named.
    for (const ShadowMapKnob& k : shadowMapKnobs())
        for (const char* cost :
             {"sm_size", "sm_fit", "peel_size", "avsm_size", "pcss_blocker_taps", "pcss_filter_taps",
              "csm_terms", "peel_bins", "peel_max_steps", "avsm_nodes", "vpcss_taps"})
            if (std::string(k.name) == cost) {
                EXPECT_FALSE(k.search.tunable) << cost;
            }
}

/// The command fails with exit 1 and a message holding `expected`.
void expectRefused(const std::vector<std::string>& args, const std::string& expected) {
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 1) << test::describe(args, r);
    EXPECT_NE(r.err.find(expected), std::string::npos) << test::describe(args, r);
}

TEST(TuneCli, BadInputIsRefusedWithAClearError) {
    ScratchDir dir;
    // The converged references go to the scratch folder's cache, not the user's.
    test::ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::vector<std::string> tiny = {"--size", "8x8", "--samples", "16", "--converged", "1", "-q"};
    auto tune = [&](std::vector<std::string> args) {
        args.insert(args.begin(), "tune");
        args.insert(args.end(), tiny.begin(), tiny.end());
        return args;
    };
    expectRefused(tune({"nosuch", "--scenes", "fence"}), "unknown method 'nosuch'");
    expectRefused(tune({"stsv", "--scenes", "fence"}), "method stsv has no knobs to tune");
    expectRefused(tune({"pcf", "--scenes", "fence", "--knob", "nosuch"}), "--knob 'nosuch' names no knob");
    expectRefused(tune({"pcf", "--scenes", "fence", "--knob", "vsm_bleed"}),
                  "--knob 'vsm_bleed' names no knob");
    expectRefused(
        tune({"pcf", "--scenes", "fence", "--knob", "pcf_world_radius", "--param", "pcf_world_radius=0.2"}),
        "either searched (--knob) or fixed (--param)");
    expectRefused(tune({"pcf", "--scenes", "fence", "--knob", "pcf_world_radius=4:99"}),
                  "the range must be LO < HI");
    expectRefused(tune({"pcf", "--scenes", "fence", "--knob", "sm_bias=x:2"}), "'x' is not a number");
    expectRefused(tune({"pcf", "--scenes", "fence", "knot", "--budget", "1"}),
                  "less than one render per training scene");
    expectRefused(tune({"pcf", "--scenes", "fence", "--validate", "fence"}), "is a training scene too");
    expectRefused(tune({"pcf", "--scenes", "fence", "--objective", "worst"}),
                  "give two or more training scenes");
    expectRefused(tune({"pcf", "--scenes", "fence", "knot", "--objective", "best"}), "--objective");
    expectRefused(tune({"pcf", "--scenes", "fence", "--json", dir.file("t.txt")}), "--json");
    expectRefused(tune({"pcf", "--scenes", "nosuchscene"}), "nosuchscene");

    // compare --knobs: the file and the entry named.
    auto compare = [&](const std::string& file) {
        return std::vector<std::string>{"compare", "fence", "--methods", "pcf/cpu", "--knobs", file,
                                        "--size",  "8x8",   "--samples", "16",      "-q"};
    };
    expectRefused(compare(dir.file("missing.json")), "missing.json");
    expectRefused({"compare", dir.file("a.npy"), dir.file("b.npy"), "--knobs", dir.file("k.json")},
                  "--knobs compares renders of a SCENE, not two files");
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"{not json", "not valid JSON"},
        {"[1, 2]", "a knobs file is an object"},
        {R"({"methods": []})", "non-empty array"},
        {R"({"methods": [{"method": "pcf"}]})", "methods[0] must be an object with \"method\""},
        {R"({"methods": [{"method": "nosuch", "knobs": {}}]})", "methods[0]: unknown method 'nosuch'"},
        {R"({"methods": [{"method": "pcf", "knobs": {}}, {"method": "pcf", "knobs": {}}]})",
         "methods[1]: method pcf is listed twice"},
        {R"({"method": "pcf", "knobs": {"nosuch": 1}})", "pcf has no knob 'nosuch'"},
        {R"({"method": "stsv", "knobs": {"pcf_world_radius": 1}})",
         "stsv has no knob 'pcf_world_radius' (its knobs: none)"},
        {R"({"method": "pcf", "knobs": {"pcf_world_radius": "3"}})",
         "knob pcf_world_radius must be a number"},
        {R"({"method": "pcf", "knobs": {"pcf_world_radius": 99}})",
         "pcf_world_radius=99 is outside pcf's range [0, 10]"},
        {R"({"method": "pcf", "knobs": {"pcf_max_radius": 2.5}})", "of whole numbers"},
        {R"({"method": "pcf", "knobs": {"pcf_radius": 3}})",
         "pcf_radius (a kernel radius in texels) was replaced"},
    };
    for (std::size_t i = 0; i < bad.size(); ++i) {
        const std::string file = dir.file("bad" + std::to_string(i) + ".json");
        test::writeText(file, bad[i].first);
        expectRefused(compare(file), bad[i].second);
        expectRefused(compare(file), file);
    }
}

} // namespace
} // namespace stsv
