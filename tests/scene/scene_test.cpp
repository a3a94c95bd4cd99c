#include "core/error.h"
#include "scene/geometry.h"
#include "scene/json_scene.h"
#include "scene/procedural.h"
#include "scene/scene.h"

#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace stsv {
namespace {

using test::expectError;

Scene validScene() {
    Scene scene = makeFenceScene();
    scene.source = "unit.json";
    return scene;
}

TEST(Validate, AcceptsTheBuiltins) {
    EXPECT_NO_THROW(makeFenceScene().validate());
    EXPECT_NO_THROW(makeFoliageScene().validate());
}

TEST(Validate, RejectsEachBrokenPart) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    struct Case {
        const char* says;
        std::function<void(Scene&)> breakIt;
    };
    const Case cases[] = {
        {"no triangles", [](Scene& s) { s.triangles.clear(), s.triangleMaterial.clear(); }},
        {"non-finite coordinate", [&](Scene& s) { s.positions[1].y = nan; }},
        {"non-finite texture coordinate", [&](Scene& s) { s.texcoords[2].x = nan; }},
        {"out-of-range vertex index", [](Scene& s) { s.triangles[0].z = 99; }},
        {"unknown material", [](Scene& s) { s.triangleMaterial[0] = 42; }},
        {"missing texture", [](Scene& s) { s.materials.back().alphaTexture = 5; }},
        {"wrong byte count", [](Scene& s) { s.textures[0].rgba.pop_back(); }},
        {"no lights", [](Scene& s) { s.lights.clear(); }},
        {"non-finite parameter", [&](Scene& s) { s.lights[0].radiance.x = nan; }},
        {"non-unit normal", [](Scene& s) { s.lights[0].normal = vec3(0, -2, 0); }},
        {"no extent", [](Scene& s) { s.lights[0].radius = 0.0f; }},
        {"camera is degenerate", [](Scene& s) { s.camera.target = s.camera.eye; }},
        {"camera is degenerate", [](Scene& s) { s.camera.fovY = 180.0f; }},
    };
    for (const Case& c : cases) {
        Scene scene = validScene();
        c.breakIt(scene);
        expectError<InputError>([&] { scene.validate(); }, {"unit.json", c.says});
    }
}

TEST(Validate, TexturedTrianglesTexcoordsMustNameTexels) {
    // The fence's triangles 2 and 3 carry the 256-texel chain-link texture; 0 and 1 are the
    // untextured ground.
    Scene fence = validScene();
    const Texture& chain = fence.textures[std::size_t(fence.materialOf(2).alphaTexture)];
    ASSERT_EQ(chain.width, 256);
    const std::uint32_t v = fence.triangles[2].y;
    // 2^24 texels is 65536 repeats of 256 texels: one texel less is accepted, 2^24 is not.
    fence.texcoords[v] = vec2((16777216.0f - 1.0f) / 256.0f, 0.5f);
    EXPECT_NO_THROW(fence.validate());
    fence.texcoords[v] = vec2(0.5f, -65536.0f);
    expectError<InputError>([&] { fence.validate(); },
                            {"unit.json", "triangle 2 vertex " + std::to_string(v), "v = -65536",
                             "1.68e+07 texels of texture 'chainlink(256)' (256 high)", "2^24"});
    fence.texcoords[v] = vec2(1e38f, 0.0f);
    expectError<InputError>([&] { fence.validate(); }, {"u = 1e+38", "2.56e+40 texels", "2^24"});

    // An untextured triangle's texture coordinates are never read: finite is enough.
    Scene ground = validScene();
    for (int k = 0; k < 3; ++k) ground.texcoords[ground.triangles[0][k]] = vec2(1e38f, -3e38f);
    EXPECT_NO_THROW(ground.validate());
}

TEST(Validate, LightSizesOutsideTheirRangeAreNamed) {
    Scene huge = validScene();
    huge.lights[0].axisU = vec3(5e19f, 0.0f, 0.0f); // a 1e20 edge: its area overflows a float
    expectError<InputError>([&] { huge.validate(); }, {"light 0 has an edge of 1e+20 world units",
                                                       "outside the accepted [1e-09, 1e+09]"});
    Scene tiny = validScene();
    tiny.lights[0].axisV = normalize(tiny.lights[0].axisV) * 1e-12f; // an area below float's normals
    expectError<InputError>([&] { tiny.validate(); }, {"light 0 has an edge of 2e-12", "[1e-09, 1e+09]"});
}

/// A fence-like scene (an 8 m ground, a 4 m x 2 m perforated quad standing on it, a light; an
/// 11.5 m bounding-box diagonal) as JSON, translated
/// by `offset` along x, camera included.
std::string quadSceneJson(double offset) {
    const std::string x = std::to_string(offset);
    return R"({
      "camera": {"eye": [)" +
           std::to_string(offset + 2.0) + R"(, 3, 8], "target": [)" + x + R"(, 0.5, 0]},
      "materials": [{"name": "ground"},
                    {"name": "grate", "alphaTexture": {"generator": "chainlink", "size": 64}}],
      "meshes": [
        {"quad": {"size": [8, 8]}, "material": "ground",
         "transform": {"translate": [)" +
           x + R"(, 0, 0], "euler": [-90, 0, 0]}},
        {"quad": {"size": [4, 2], "uvRepeat": [4, 2]}, "material": "grate",
         "transform": {"translate": [)" +
           x + R"(, 1, 0]}}],
      "lights": [{"type": "rectangle", "position": [)" +
           x + R"(, 5, -3], "normal": [0, -0.8, 0.6], "size": 1, "radiance": 100}]
    })";
}

TEST(Validate, SceneFarFromTheOriginWarnsThenRefuses) {
    test::TempDir dir;
    // At the origin floats (4.8e-7 apart at 4 m) resolve 4e-8 of the diagonal: nothing to say.
    EXPECT_TRUE(loadJsonScene(dir.write("origin.json", quadSceneJson(0.0))).warnings.empty());

    // At 1e6 floats are 2^-4 = 0.0625 apart, 0.0054 of the diagonal: a warning with the fix.
    Scene far = loadJsonScene(dir.write("far.json", quadSceneJson(1e6)));
    ASSERT_EQ(far.warnings.size(), 1u);
    for (const char* part : {"far from the origin", "coordinates up to 1e+06", "floats are 0.0625 apart",
                             "0.00544 of its 11.5-unit diagonal", "recentre the scene near the origin",
                             "translate it by [-1e+06, "})
        EXPECT_NE(far.warnings[0].find(part), std::string::npos) << far.warnings[0] << "\nmissing: " << part;
    far.validate(); // once, however often validate runs
    EXPECT_EQ(far.warnings.size(), 1u);

    // At 1e8 floats are 2^3 = 8 apart, and 1e8 ± 4 rounds to 1e8 (its even neighbour): every
    // corner at x ± 2 or x ± 4 falls on x, every triangle is flat.
    const std::string collapsed = dir.write("collapsed.json", quadSceneJson(1e8));
    expectError<InputError>(
        [&] { loadJsonScene(collapsed); },
        {collapsed, "far from the origin", "floats are 8 apart, 0.97 of its 8.25-unit diagonal",
         "4 of its 4 triangles have collapsed to lines or points", "recentre the scene near the origin"});
}

// A scene whose only triangles had collinear corners loaded, rendered background and said
// "faces skipped as degenerate: 0". validate counts the triangles of zero area and refuses a
// scene of nothing else, naming its file.
TEST(Validate, ZeroAreaTrianglesAreCountedAndAllOfThemRefused) {
    test::TempDir dir;
    const std::string mesh = R"({"name": "d", "material": "floor",
        "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 1, 0], [3, 1, 0]], "triangles": [[0, 1, 2], [2, 3, 4]]})";
    const std::string scene = R"({"materials": [{"name": "floor"}],
        "lights": [{"type": "sphere", "position": [0, 4, 0], "radius": 0.5, "radiance": 40}], "meshes": [)";
    const std::string flat = dir.write("flat.json", scene + mesh + "]}");
    expectError<InputError>([&] { loadJsonScene(flat); },
                            {flat, "every triangle is degenerate", "2 triangle(s) have zero area"});

    // Beside a triangle with area they are kept and counted, once however often validate runs.
    Scene mixed = validScene();
    const std::size_t triangles = mixed.triangleCount();
    EXPECT_EQ(mixed.zeroAreaTriangles, 0u);
    mixed.addTriangle(vec3(0, 0, 0), vec3(1, 1, 1), vec3(2, 2, 2), vec2(0), vec2(0), vec2(0), 0);
    mixed.addTriangle(vec3(5, 0, 5), vec3(5, 0, 5), vec3(5, 0, 5), vec2(0), vec2(0), vec2(0), 0);
    mixed.validate();
    mixed.validate();
    EXPECT_EQ(mixed.zeroAreaTriangles, 2u);
    EXPECT_EQ(mixed.triangleCount(), triangles + 2);
}

} // namespace
} // namespace stsv
