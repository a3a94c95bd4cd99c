#include "core/error.h"
#include "scene/geometry.h"
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

} // namespace
} // namespace stsv
