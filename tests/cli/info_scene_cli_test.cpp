// `stsv info SCENE`: what a scene holds and what a frame would take, without rendering.
#include "cli_test_util.h"

#include <gtest/gtest.h>

#include <string>

namespace stsv::test {
namespace {

TEST(InfoScene, FenceCountsItsTrianglesMaterialsTextureLightAndCamera) {
    const CliResult r = runStsv({"info", "fence", "--json"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    // The fence: a 2-triangle chain-link quad on a 2-triangle ground (scene/procedural.cpp).
    EXPECT_EQ(j["triangles"], 4);
    EXPECT_EQ(j["perforated_triangles"], 2);
    EXPECT_EQ(j["opaque_triangles"], 2);
    ASSERT_EQ(j["materials"].size(), 2u);
    const nlohmann::json& chain = j["materials"][1];
    ASSERT_TRUE(chain.contains("alpha_texture")) << chain.dump();
    EXPECT_EQ(chain["alpha_texture"]["width"], 256); // the knob texture_size's default
    EXPECT_EQ(chain["alpha_texture"]["wrap"], "repeat");
    ASSERT_EQ(j["light_list"].size(), 1u);
    EXPECT_EQ(j["light_list"][0]["type"], "rectangle");
    EXPECT_NEAR(j["light_list"][0]["size"][0].get<double>(), 1.0, 1e-6); // light_size=1
    EXPECT_EQ(j["camera"]["fov_y_degrees"], 50.0);
    // A 30 m ground: bounds from −15 to 15 across.
    EXPECT_NEAR(j["bounds"]["extent"][0].get<double>(), 30.0, 1e-4);
}

TEST(InfoScene, FrameMemoryGrowsWithTheFrameAndHoldsTheLightSampleBuffer) {
    const CliResult small = runStsv({"info", "fence", "--json", "--size", "512x512", "--samples", "64"});
    const CliResult large = runStsv({"info", "fence", "--json", "--size", "1024x1024", "--samples", "64"});
    ASSERT_EQ(small.code, 0) << small.err;
    ASSERT_EQ(large.code, 0) << large.err;
    const double a = nlohmann::json::parse(small.out)["memory"]["frame_bytes"].get<double>();
    const double b = nlohmann::json::parse(large.out)["memory"]["frame_bytes"].get<double>();
    // N·W·H bits of the light-sample buffer alone (STSV paper §5.1): 2 MiB at 512², 64 samples.
    EXPECT_GE(a, 512.0 * 512.0 * 64.0 / 8.0);
    // Every part of a frame is per pixel: four times the pixels, four times the bytes.
    EXPECT_NEAR(b / a, 4.0, 0.01);
}

TEST(InfoScene, TextNamesTheFilesTexturesAndTheLimitAndRefusesABadScene) {
    const CliResult r =
        runStsv({"info", std::string(STSV_TEST_DATA) + "/scene/example.json", "--method", "pcss"});
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* text :
         {"perforated", "grate.png (64x64", "disk at", "memory:", "frame of pcss", "limit"})
        EXPECT_NE(r.out.find(text), std::string::npos) << "lacks '" << text << "':\n" << r.out;
    const CliResult bad = runStsv({"info", "nosuchscene"});
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("nosuchscene"), std::string::npos) << bad.err;
}

// A bare mesh becomes usable without a JSON file: the camera and the lights from the command
// line, in the scene format's objects, with the same validation and messages.
TEST(InfoScene, CameraAndLightsFromTheCommandLineReplaceOrJoinTheScenes) {
    const std::string crate = std::string(STSV_TEST_DATA) + "/scene/crate.obj";
    const std::string disk =
        R"({"type": "disk", "position": [0, 4, 0], "normal": [0, -1, 0], "radius": 0.5, "radiance": [40, 40, 40]})";
    const std::string sphere =
        R"({"type": "sphere", "position": [2, 3, 1], "radius": 0.25, "radiance": [9, 9, 9]})";
    const CliResult r = runStsv({"info", crate, "--json", "--camera",
                                 R"({"eye": [3, 2, 5], "target": [0, 0.5, 0], "fovY": 40})", "--light", disk,
                                 "--add-light", sphere});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["camera"]["eye"], nlohmann::json({3.0, 2.0, 5.0}));
    EXPECT_EQ(j["camera"]["fov_y_degrees"], 40.0);
    ASSERT_EQ(j["light_list"].size(), 2u);
    EXPECT_EQ(j["light_list"][0]["type"], "disk");
    EXPECT_EQ(j["light_list"][0]["radius"], 0.5);
    EXPECT_EQ(j["light_list"][1]["type"], "sphere");
    // --add-light alone keeps the scene's own light.
    const CliResult added = runStsv({"info", "fence", "--json", "--add-light", sphere});
    ASSERT_EQ(added.code, 0) << added.err;
    EXPECT_EQ(nlohmann::json::parse(added.out)["light_list"].size(), 2u);
    // Bad values are refused with the option and the key.
    const CliResult bad = runStsv({"info", "fence", "--light",
                                   R"({"type": "disk", "position": [0, 4, 0], )"
                                   R"("normal": [0, -1, 0], "radius": 0, "radiance": [1, 1, 1]})"});
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("--light: radius"), std::string::npos) << bad.err;
    const CliResult camera =
        runStsv({"info", "fence", "--camera", R"({"eye": [0, 1, 0], "target": [0, 1, 0]})"});
    EXPECT_EQ(camera.code, 1);
    EXPECT_NE(camera.err.find("--camera"), std::string::npos) << camera.err;
}

} // namespace
} // namespace stsv::test
