#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/json_scene.h"
#include "scene/load.h"
#include "scene/procedural.h"

#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace stsv {
namespace {

using test::dataPath;
using test::expectError;
using test::TempDir;

const Mesh* meshNamed(const Scene& scene, const std::string& name) {
    for (const Mesh& m : scene.meshes)
        if (m.name == name) return &m;
    return nullptr;
}

Bounds meshBounds(const Scene& scene, const Mesh& mesh) {
    Bounds b;
    for (std::uint32_t t = mesh.firstTriangle; t < mesh.firstTriangle + mesh.triangleCount; ++t)
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[scene.triangles[t][k]]);
    return b;
}

TEST(JsonScene, ExampleLoadsWithEverything) {
    const Scene scene = loadScene(dataPath("example.json"));
    // ground quad 2 + fence quad 2 + grate quad 2 + crate.obj 6 quads = 12 + awning 1.
    EXPECT_EQ(scene.triangleCount(), 19u);
    ASSERT_EQ(scene.meshes.size(), 5u);
    const char* names[] = {"ground", "fence", "grate", "crate", "awning"};
    const std::uint32_t counts[] = {2, 2, 2, 12, 1};
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(scene.meshes[std::size_t(i)].name, names[i]);
        EXPECT_EQ(scene.meshes[std::size_t(i)].triangleCount, counts[i]) << names[i];
    }
    std::size_t perforated = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) perforated += scene.perforated(t);
    EXPECT_EQ(perforated, 4u) << "fence and grate";
    EXPECT_EQ(scene.textures.size(), 2u);

    std::map<std::string, const Material*> materials;
    for (const Material& m : scene.materials) materials[m.name] = &m;
    ASSERT_TRUE(materials.count("chainlink") && materials.count("grate") && materials.count("crate_wood"));
    EXPECT_TRUE(materials["chainlink"]->doubleSided);
    EXPECT_EQ(materials["chainlink"]->wrap, WrapMode::Repeat);
    EXPECT_EQ(materials["grate"]->albedo, vec3(0.5f));
    EXPECT_EQ(materials["crate_wood"]->albedo, vec3(0.55f, 0.38f, 0.22f)) << "from crate.mtl";
    // grate.png: 16-texel cells with 12 × 12 transparent holes → (12/16)² open.
    const Texture& grate = scene.textures[std::size_t(materials["grate"]->alphaTexture)];
    EXPECT_EQ(openFraction(grate), 0.5625);

    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.lights[0].type, LIGHT_RECTANGLE);
    EXPECT_NEAR(scene.lights[0].radius, std::sqrt(0.5f), 1e-6f) << "1 m × 1 m: half diagonal";
    // axisU is the tangent [1,0,0] made perpendicular to the normal: in the plane of the two.
    const vec3 n = scene.lights[0].normal;
    EXPECT_NEAR(dot(normalize(scene.lights[0].axisU), cross(vec3(1, 0, 0), n)), 0.0f, 1e-6f);
    EXPECT_GT(scene.lights[0].axisU.x, 0.0f);
    EXPECT_EQ(scene.lights[1].type, LIGHT_DISK);
    EXPECT_EQ(scene.lights[1].radius, 0.3f);
    EXPECT_EQ(scene.camera.eye, vec3(4.0f, 3.0f, 7.5f));
    EXPECT_EQ(scene.camera.fovY, 45.0f);

    // The crate: unit cube on y = 0, scaled 0.8, rotated about y, moved to (−2.2, 0, 1.6).
    const Mesh* crate = meshNamed(scene, "crate");
    ASSERT_NE(crate, nullptr);
    const Bounds cb = meshBounds(scene, *crate);
    EXPECT_NEAR(cb.lo.y, 0.0f, 1e-6f);
    EXPECT_NEAR(cb.hi.y, 0.8f, 1e-6f);
    EXPECT_NEAR(cb.center().x, -2.2f, 1e-5f);
    EXPECT_NEAR(cb.center().z, 1.6f, 1e-5f);
    // The ground quad was rotated from the xy plane onto y = 0.
    const Bounds gb = meshBounds(scene, *meshNamed(scene, "ground"));
    EXPECT_NEAR(gb.lo.y, 0.0f, 1e-5f);
    EXPECT_NEAR(gb.hi.y, 0.0f, 1e-5f);
    EXPECT_NEAR(gb.extent().x, 20.0f, 1e-4f);
}

TEST(JsonScene, TransformsApplyScaleThenRotateThenTranslate) {
    TempDir dir;
    const std::string path = dir.write("t.json", R"({
      "materials": [{"name": "m"}],
      "meshes": [{"vertices": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "triangles": [[0, 1, 2]], "material": "m",
                  "transform": {"scale": [2, 3, 4], "rotate": {"axis": [0, 0, 1], "degrees": 90}, "translate": [10, 0, 0]}},
                 {"vertices": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "triangles": [[0, 1, 2]], "material": "m",
                  "transform": {"euler": [90, 0, 90]}}],
      "lights": [{"type": "sphere", "position": [0, 5, 0], "radius": 0.5, "radiance": 1}]
    })");
    const Scene scene = loadJsonScene(path);
    // (1,0,0) → scale (2,0,0) → rot z 90° (0,2,0) → +10x (10,2,0); (0,1,0) → (0,3,0) → (−3,0,0) → (7,0,0).
    const vec3 expected[3] = {{10, 2, 0}, {7, 0, 0}, {10, 0, 4}};
    for (int k = 0; k < 3; ++k) {
        const vec3 p = scene.positions[scene.triangles[0][k]];
        EXPECT_LT(length(p - expected[k]), 1e-5f)
            << "k=" << k << " p=" << p.x << "," << p.y << "," << p.z << " (tolerance: float sin/cos of 90°)";
    }
    // Euler x then z: (1,0,0) → x: (1,0,0) → z: (0,1,0); (0,1,0) → x: (0,0,1) → z: (0,0,1).
    const vec3 p0 = scene.positions[scene.triangles[1][0]], p1 = scene.positions[scene.triangles[1][1]];
    EXPECT_LT(length(p0 - vec3(0, 1, 0)), 1e-5f);
    EXPECT_LT(length(p1 - vec3(0, 0, 1)), 1e-5f);
    EXPECT_EQ(scene.lights[0].type, LIGHT_SPHERE);
    // No camera given: one is framed around the scene.
    EXPECT_GT(length(scene.camera.eye - scene.camera.target), 0.0f);
}

TEST(JsonScene, DirectionalLightAngleIsInDegrees) {
    TempDir dir;
    const std::string path = dir.write("d.json", R"({
      "materials": [{"name": "m"}],
      "meshes": [{"quad": {"size": [1, 1]}, "material": "m"}],
      "lights": [{"type": "directional", "direction": [0, 2, 0], "angularRadius": 0.5, "radiance": [1, 2, 3]},
                 {"type": "rectangle", "position": [0, 3, 0], "axisU": [0.5, 0, 0], "axisV": [0, 0, 0.25], "radiance": 5}]
    })");
    const Scene scene = loadJsonScene(path);
    EXPECT_NEAR(scene.lights[0].angularRadius, 0.5f * 3.14159265f / 180.0f, 1e-7f);
    EXPECT_EQ(scene.lights[0].normal, vec3(0, 1, 0));
    EXPECT_EQ(scene.lights[0].radius, 0.0f);
    EXPECT_EQ(scene.lights[0].radiance, vec3(1, 2, 3));
    // Explicit half-extent axes: normal = axisU × axisV = −y (downwards), radius = half diagonal.
    EXPECT_LT(length(scene.lights[1].normal - vec3(0, -1, 0)), 1e-6f);
    EXPECT_LT(length(scene.lights[1].axisU - vec3(0.5f, 0, 0)), 1e-6f);
    EXPECT_LT(length(scene.lights[1].axisV - vec3(0, 0, 0.25f)), 1e-6f);
    EXPECT_NEAR(scene.lights[1].radius, std::sqrt(0.25f + 0.0625f), 1e-6f);
}

TEST(JsonScene, RotationListsApplyInOrderAndCommentsAreAllowed) {
    TempDir dir;
    const std::string path = dir.write("r.json", R"({
      // rotations: first about z, then about x
      "materials": [{"name": "m", "albedo": 0.5}],
      "meshes": [{"vertices": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "triangles": [[0, 1, 2]], "material": "m",
                  "transform": {"rotate": [{"axis": [0, 0, 1], "degrees": 90}, {"axis": [1, 0, 0], "degrees": 90}]}}],
      /* one light */
      "lights": [{"type": "sphere", "position": [0, 5, 0], "radius": 0.5, "radiance": 1}]
    })");
    const Scene scene = loadJsonScene(path);
    // (1,0,0) → z 90° → (0,1,0) → x 90° → (0,0,1).
    const vec3 p = scene.positions[scene.triangles[0][0]];
    EXPECT_LT(length(p - vec3(0, 0, 1)), 1e-5f)
        << p.x << "," << p.y << "," << p.z << " (float sin/cos of 90°)";
}

struct BadJson {
    const char* name;
    const char* text;
    const char* says1;
    const char* says2;
};

class BadJsonTest : public ::testing::TestWithParam<BadJson> {};

TEST_P(BadJsonTest, NamesFileAndProblem) {
    const BadJson& c = GetParam();
    TempDir dir;
    dir.write("ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string path = dir.write("bad.json", c.text);
    expectError<InputError>([&] { loadScene(path); }, {path + ":", c.says1, c.says2});
}

#define MAT R"("materials": [{"name": "m"}])"
#define TRI R"("meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "triangles": [[0,1,2]], "material": "m"}])"
#define LIGHT R"("lights": [{"type": "sphere", "position": [0,5,0], "radius": 1, "radiance": 1}])"

INSTANTIATE_TEST_SUITE_P(
    Json, BadJsonTest,
    ::testing::Values(
        BadJson{"SyntaxErrorHasLine", "{\n  \"meshes\": [\n    1 2\n  ]\n}\n", ":3:", "invalid JSON"},
        BadJson{"Truncated", "{\n  \"materials\": [{\"name\": \"m\"}],\n  \"meshes\": [\n", "invalid JSON",
                "unexpected end"},
        BadJson{"NotAnObject", "[1, 2]", "expected an object", "array"},
        BadJson{"UnknownAlphaMode",
                "{\"materials\": [{\"name\": \"m\", \"alphaMode\": \"glass\"}], " TRI ", " LIGHT "}",
                "materials[0].alphaMode", "expected \"opaque\", \"mask\" or \"blend\""},
        BadJson{"AlphaFactorAboveOne",
                "{\"materials\": [{\"name\": \"m\", \"alphaMode\": \"blend\", \"alphaFactor\": 1.5}], " TRI
                ", " LIGHT "}",
                "materials[0].alphaFactor", "must be in [0, 1]"},
        BadJson{"NegativeCutoff",
                "{\"materials\": [{\"name\": \"m\", \"alphaCutoff\": -0.1}], " TRI ", " LIGHT "}",
                "materials[0].alphaCutoff", "must be in [0, 1]"},
        BadJson{"MissingMeshes", "{" MAT ", " LIGHT "}", "missing required field 'meshes'", ""},
        BadJson{"EmptyScene", "{" MAT ", \"meshes\": [], " LIGHT "}", "meshes", "non-empty"},
        BadJson{"NoLights", "{" MAT ", " TRI ", \"lights\": []}", "lights", "non-empty"},
        BadJson{"UnknownKey", "{" MAT ", " TRI ", " LIGHT ", \"camra\": {}}", "camra", "unknown key"},
        BadJson{
            "WrongType",
            "{" MAT ", " TRI
            ", \"lights\": [{\"type\": \"sphere\", \"position\": \"up\", \"radius\": 1, \"radiance\": 1}]}",
            "lights[0].position", "expected an array of 3 numbers"},
        BadJson{"Overflow",
                "{" MAT ", " TRI ", \"lights\": [{\"type\": \"sphere\", \"position\": [0, 1e999, 0], "
                "\"radius\": 1, \"radiance\": 1}]}",
                "invalid JSON", "1e999"},
        BadJson{"NegativeSize",
                "{" MAT ", \"meshes\": [{\"quad\": {\"size\": [1, -2]}, \"material\": \"m\"}], " LIGHT "}",
                "meshes[0].quad.size", "> 0"},
        BadJson{"NegativeRadius",
                "{" MAT ", " TRI ", \"lights\": [{\"type\": \"disk\", \"position\": [0,5,0], \"normal\": "
                "[0,-1,0], \"radius\": -1, \"radiance\": 1}]}",
                "lights[0].radius", "-1 is outside the accepted light size [1e-09, 1e+09]"},
        BadJson{"ZeroNormal",
                "{" MAT ", " TRI ", \"lights\": [{\"type\": \"rectangle\", \"position\": [0,5,0], "
                "\"normal\": [0,0,0], \"size\": 1, \"radiance\": 1}]}",
                "lights[0].normal", "zero vector"},
        BadJson{"UnknownLightType", "{" MAT ", " TRI ", \"lights\": [{\"type\": \"spot\"}]}",
                "lights[0].type", "spot"},
        BadJson{"UnknownMaterial",
                "{" MAT ", \"meshes\": [{\"quad\": {\"size\": [1, 1]}, \"material\": \"steel\"}], " LIGHT "}",
                "meshes[0].material", "unknown material 'steel'"},
        BadJson{"IndexOutOfRange",
                "{" MAT ", \"meshes\": [{\"vertices\": [[0,0,0],[1,0,0],[0,1,0]], \"triangles\": [[0,1,3]], "
                "\"material\": \"m\"}], " LIGHT "}",
                "meshes[0].triangles[0][2]", "out of range"},
        BadJson{"MissingTexture",
                "{\"materials\": [{\"name\": \"m\", \"alphaTexture\": \"holes.png\"}], " TRI ", " LIGHT "}",
                "materials[0].alphaTexture", "holes.png' does not exist"},
        BadJson{"BadWrap", "{\"materials\": [{\"name\": \"m\", \"wrap\": \"mirror\"}], " TRI ", " LIGHT "}",
                "materials[0].wrap", "mirror"},
        BadJson{"MissingMeshFile", "{" MAT ", \"meshes\": [{\"file\": \"gone.obj\"}], " LIGHT "}",
                "meshes[0].file", "gone.obj' does not exist"},
        BadJson{"BadMeshExtension", "{" MAT ", \"meshes\": [{\"file\": \"bad.json\"}], " LIGHT "}",
                "meshes[0].file", "unsupported mesh format"},
        BadJson{"ZeroScale",
                "{" MAT ", \"meshes\": [{\"file\": \"ok.obj\", \"transform\": {\"scale\": 0}}], " LIGHT "}",
                "meshes[0].transform.scale", "> 0"},
        BadJson{"TwoGeometrySources",
                "{" MAT ", \"meshes\": [{\"file\": \"ok.obj\", \"quad\": {\"size\": [1, 1]}}], " LIGHT "}",
                "meshes[0]", "exactly one of"},
        BadJson{"CameraEyeIsTarget",
                "{" MAT ", " TRI ", " LIGHT ", \"camera\": {\"eye\": [1,1,1], \"target\": [1,1,1]}}",
                "camera", "coincide"}),
    [](const ::testing::TestParamInfo<BadJson>& p) { return std::string(p.param.name); });

TEST(JsonScene, BadMeshFileInsideJsonNamesTheMeshFileAndLine) {
    TempDir dir;
    const std::string obj = dir.write("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
    const std::string path =
        dir.write("s.json", "{" MAT ", \"meshes\": [{\"file\": \"broken.obj\"}], " LIGHT "}");
    expectError<InputError>([&] { loadScene(path); }, {obj + ":3:", "non-finite"});
}

TEST(JsonScene, DuplicateKeysAreRefusedWithTheirLine) {
    TempDir dir;
    // nlohmann::json keeps the last of two equal keys: the first "meshes" or "lights" was lost.
    const std::string meshes =
        dir.write("meshes.json", "{\n" MAT ",\n\"meshes\": [],\n" TRI ",\n" LIGHT "\n}\n");
    expectError<InputError>([&] { loadScene(meshes); },
                            {meshes + ":4:", "duplicate key \"meshes\" (first at line 3)"});
    const std::string lights =
        dir.write("lights.json", "{\n" MAT ",\n" TRI ",\n" LIGHT ",\n\"lights\": []\n}\n");
    expectError<InputError>([&] { loadScene(lights); },
                            {lights + ":5:", "duplicate key \"lights\" (first at line 4)"});
    // Inside a nested object, on one line; the same key in two objects is no duplicate.
    const std::string nested = dir.write(
        "nested.json", "{" MAT ", " TRI ", \"lights\": [{\"type\": \"sphere\", \"position\": [0,5,0], "
                       "\"radius\": 1, \"radius\": 2, \"radiance\": 1}]}");
    expectError<InputError>([&] { loadScene(nested); }, {nested + ":1:", "duplicate key \"radius\""});
    EXPECT_NO_THROW(
        loadScene(dir.write("apart.json", "{" MAT ", " TRI ", \"lights\": [{\"type\": \"sphere\", "
                                          "\"position\": [0,5,0], \"radius\": 1, \"radiance\": 1}, "
                                          "{\"type\": \"sphere\", \"position\": [0,6,0], "
                                          "\"radius\": 1, \"radiance\": 1}]}")));
    // The command line's JSON goes through the same reader.
    expectError<InputError>(
        [] {
            parseLightJson("--light",
                           R"({"type": "sphere", "position": [0, 5, 0], "radius": 1, "radius": 3})");
        },
        {"--light:1:", "duplicate key \"radius\""});
    expectError<InputError>(
        [] {
            parseCameraJson("--camera", "{\"eye\": [0, 1, 5],\n \"eye\": [0, 2, 5], \"target\": [0, 0, 0]}");
        },
        {"--camera:2:", "duplicate key \"eye\" (first at line 1)"});
}

TEST(JsonScene, TexcoordsOfTexturedMeshesMustNameTexels) {
    TempDir dir;
    const char* chain =
        R"("materials": [{"name": "m"}, {"name": "chain", "alphaTexture": {"generator": "chainlink", "size": 64}}])";
    // uvRepeat 1e38 of a 64-texel texture: 6.4e39 texels, far past the 2^24 a float names exactly.
    const std::string repeat = dir.write(
        "repeat.json",
        std::string("{") + chain +
            R"(, "meshes": [{"quad": {"size": [1, 1], "uvRepeat": [1e38, 1e38]}, "material": "chain"}], )" LIGHT
            "}");
    expectError<InputError>([&] { loadScene(repeat); },
                            {repeat + ": meshes[0].quad.uvRepeat: u = 1e+38 is 6.4e+39 texels", "2^24"});
    // 2^24 / 64 = 262144 repeats reach 2^24 exactly: refused; one texel less is not.
    const std::string edge = dir.write(
        "edge.json",
        std::string("{") + chain +
            R"(, "meshes": [{"quad": {"size": [1, 1], "uvRepeat": [1, 262144]}, "material": "chain"}], )" LIGHT
            "}");
    expectError<InputError>([&] { loadScene(edge); }, {"meshes[0].quad.uvRepeat: v = 262144", "2^24"});
    EXPECT_NO_THROW(loadScene(dir.write(
        "below.json",
        std::string("{") + chain +
            R"(, "meshes": [{"quad": {"size": [1, 1], "uvRepeat": [1, 262143.984375]}, "material": "chain"}], )" LIGHT
            "}")));
    // Inline texcoords: the vertex's own place.
    const std::string inlineCoordinates = dir.write(
        "inline.json",
        std::string("{") + chain +
            R"(, "meshes": [{"vertices": [[0,0,0],[1,0,0],[0,1,0]], "texcoords": [[0,0],[0,-3e20],[1,1]],)"
            R"( "triangles": [[0,1,2]], "material": "chain"}], )" LIGHT "}");
    expectError<InputError>([&] { loadScene(inlineCoordinates); },
                            {"meshes[0].texcoords[1]: v = -3e+20", "2^24"});
    // An untextured mesh's texture coordinates are never read.
    EXPECT_NO_THROW(loadScene(dir.write(
        "plain.json",
        std::string("{") + chain +
            R"(, "meshes": [{"quad": {"size": [1, 1], "uvRepeat": [1e38, 1e38]}, "material": "m"}], )" LIGHT
            "}")));
}

TEST(JsonScene, LightSizesOutsideTheirRangeAreNamed) {
    TempDir dir;
    const auto withLight = [&](const std::string& name, const std::string& light) {
        return dir.write(name, "{" MAT ", " TRI ", \"lights\": [" + light + "]}");
    };
    // A 1e20 edge: its square, the area, overflows a float (it said "non-finite parameter").
    const std::string big = withLight(
        "big.json",
        R"({"type": "rectangle", "position": [0,5,0], "normal": [0,-1,0], "size": 1e20, "radiance": 1})");
    expectError<InputError>(
        [&] { loadScene(big); },
        {big + ": lights[0].size: 1e+20 is outside the accepted light size [1e-09, 1e+09]"});
    const std::string thin = withLight(
        "thin.json",
        R"({"type": "rectangle", "position": [0,5,0], "normal": [0,-1,0], "size": [1, 1e-12], "radiance": 1})");
    expectError<InputError>([&] { loadScene(thin); },
                            {"lights[0].size[1]: 1e-12 is outside", "[1e-09, 1e+09]"});
    const std::string axis = withLight(
        "axis.json",
        R"({"type": "rectangle", "position": [0,5,0], "axisU": [1e10,0,0], "axisV": [0,0,1], "radiance": 1})");
    expectError<InputError>([&] { loadScene(axis); },
                            {"lights[0].axisU: gives an edge of 2e+10", "[1e-09, 1e+09]"});
    const std::string sphere =
        withLight("sphere.json", R"({"type": "sphere", "position": [0,5,0], "radius": 2e9, "radiance": 1})");
    expectError<InputError>([&] { loadScene(sphere); }, {"lights[0].radius: 2e+09 is outside"});
    // The ends themselves are accepted.
    EXPECT_NO_THROW(loadScene(withLight(
        "ends.json",
        R"({"type": "rectangle", "position": [0,5,0], "normal": [0,-1,0], "size": [1e-9, 1e9], "radiance": 1})")));
}

/// Sets the memory limit for one test and restores the default after it.
struct MemoryLimitForTest {
    explicit MemoryLimitForTest(std::uint64_t bytes) { setMemoryLimit(bytes); }
    ~MemoryLimitForTest() { setMemoryLimit(0); }
    MemoryLimitForTest(const MemoryLimitForTest&) = delete;
    MemoryLimitForTest& operator=(const MemoryLimitForTest&) = delete;
};

TEST(JsonScene, GeneratedTexturesCountAgainstTheMemoryLimit) {
    TempDir dir;
    const auto scene = [&](const std::string& name, int size) {
        return dir.write(name,
                         R"({"materials": [{"name": "m", "alphaTexture": {"generator": "leaf", "size": )" +
                             std::to_string(size) + "}}], " TRI ", " LIGHT "}");
    };
    const MemoryLimitForTest limit(std::uint64_t(10) << 20);
    // 2048² RGBA texels are 16 MiB, above 10 MiB; 1024² (4 MiB) fit.
    const std::string big = scene("big.json", 2048);
    expectError<UsageError>(
        [&] { loadScene(big); },
        {big + ": materials[0].alphaTexture: leaf texture of 2048x2048 texels", "16.0 MiB", "memory limit"});
    EXPECT_NO_THROW(loadScene(scene("fits.json", 1024)));
}

TEST(JsonScene, MissingFileIsAnInputError) {
    expectError<InputError>([] { loadScene("/nonexistent/scene.json"); },
                            {"/nonexistent/scene.json", "does not exist"});
}

} // namespace
} // namespace stsv
