#include "core/error.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "scene/procedural.h"

#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <map>

#include <sstream>

namespace stsv {
namespace {

using test::dataPath;
using test::expectError;
using test::TempDir;

TEST(Load, BuiltinNamesAndKnobs) {
    EXPECT_EQ(builtinSceneNames(),
              (std::vector<std::string>{"fence", "foliage", "fence-mesh", "particles", "knot"}));
    std::vector<std::string> foliage;
    for (const SceneKnob& k : builtinSceneKnobs("foliage")) foliage.push_back(k.name);
    EXPECT_NE(std::find(foliage.begin(), foliage.end(), "count"), foliage.end());
    EXPECT_NE(std::find(foliage.begin(), foliage.end(), "seed"), foliage.end());
    for (const std::string& name : builtinSceneNames()) {
        EXPECT_FALSE(describeBuiltinScene(name).empty());
        for (const SceneKnob& k : builtinSceneKnobs(name)) {
            // Every advertised default is accepted when given explicitly and changes nothing.
            SceneOptions options;
            options.set[k.name] = k.defaultValue;
            EXPECT_EQ(loadScene(name, options).positions, loadScene(name).positions) << name << " " << k.name;
        }
    }
    expectError<UsageError>([] { builtinSceneKnobs("forest"); }, {"forest", "fence, foliage"});
}

TEST(Load, ParticlesAreLightFacingTranslucentBillboardsBesideACube) {
    SceneOptions options;
    options.set["count"] = "50";
    options.set["opacity"] = "0.8";
    const Scene s = loadScene("particles", options);
    ASSERT_EQ(s.triangleCount(), 2u + 12u + 100u);
    const vec3 light = s.lights[0].position;
    std::size_t translucent = 0;
    for (std::size_t t = 0; t < s.triangleCount(); ++t) {
        if (!s.translucent(t)) continue;
        ++translucent;
        const Material& m = s.materialOf(t);
        EXPECT_EQ(m.alphaFactor, 0.8f);
        // The billboard's plane is normal to the direction to the light centre.
        const vec3 a = s.positions[s.triangles[t].x], b = s.positions[s.triangles[t].y],
                   c = s.positions[s.triangles[t].z];
        const vec3 n = normalize(cross(b - a, c - a));
        const vec3 centre = t % 2 == 0 ? 0.5f * (a + c) : 0.5f * (a + b);
        EXPECT_GT(std::abs(dot(n, normalize(light - centre))), 0.9999f) << "triangle " << t;
    }
    EXPECT_EQ(translucent, 100u);
    // The Gaussian sprite: peak at the centre, 0 outside the inscribed disc.
    const Texture g = makeGaussianTexture(64);
    // Texel (31, 31): r² = 2·(0.5/32)², 255·exp(−r²/0.32) = 254.6; texel (0, 31): r² = 0.9692,
    // 255·exp(−0.9692/0.32) = 12.3; texel (0, 0) lies outside the disc.
    EXPECT_EQ(g.alpha(31, 31), 255);
    EXPECT_EQ(g.alpha(0, 31), 12);
    EXPECT_EQ(g.alpha(0, 0), 0);
}

TEST(Load, FenceFabricIsOneTranslucentQuadBehindTheFence) {
    SceneOptions options;
    options.set["fabric"] = "0.4";
    const Scene s = loadScene("fence", options);
    ASSERT_EQ(s.triangleCount(), loadScene("fence").triangleCount() + 2);
    for (std::size_t t = s.triangleCount() - 2; t < s.triangleCount(); ++t) {
        EXPECT_TRUE(s.translucent(t));
        EXPECT_EQ(s.materialOf(t).alphaFactor, 0.4f);
        EXPECT_EQ(s.positions[s.triangles[t].x].z, -0.3f);
    }
    EXPECT_FALSE(loadScene("fence").hasTranslucent());
}

TEST(Load, KnotIsAClosedTubeOnTheGround) {
    SceneOptions options;
    options.set["segments"] = "40";
    options.set["sides"] = "6";
    const Scene knot = loadScene("knot", options);
    // 2 · segments · sides tube triangles, plus the 2 ground triangles of makeMeshScene.
    EXPECT_EQ(knot.triangleCount(), 2u * 40u * 6u + 2u);
    EXPECT_EQ(loadScene("knot").triangleCount(), 2u * 480u * 12u + 2u);
    // Closed: every tube edge is used exactly twice (by index; the tube shares its vertices).
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t t = 0; t + 2 < knot.triangleCount(); ++t) {
        const uvec3 i = knot.triangles[t];
        for (auto [a, b] : {std::pair{i.x, i.y}, std::pair{i.y, i.z}, std::pair{i.z, i.x}})
            ++uses[{std::min(a, b), std::max(a, b)}];
    }
    for (const auto& [edge, count] : uses) EXPECT_EQ(count, 2) << edge.first << "-" << edge.second;
    EXPECT_EQ(knot.lights.size(), 1u);
    expectError<UsageError>(
        [] {
            SceneOptions bad;
            bad.set["sides"] = "2";
            loadScene("knot", bad);
        },
        {"sides"});
}

TEST(Load, UnknownNameListsBuiltins) {
    expectError<UsageError>([] { loadScene("forest"); }, {"'forest'", "fence, foliage", ".json"});
}

TEST(Load, UnknownExtensionIsAUsageError) {
    expectError<UsageError>([] { loadScene("model.ply"); },
                            {"model.ply", "'.ply'", ".json, .obj, .off, .gltf or .glb"});
}

TEST(Load, UnknownKnobNamesKeyAndAcceptedOnes) {
    SceneOptions options;
    options.set["cuont"] = "10";
    expectError<UsageError>([&] { loadScene("foliage", options); }, {"'cuont'", "count", "seed"});
}

TEST(Load, FilesTakeNoKnobs) {
    SceneOptions options;
    options.set["count"] = "10";
    expectError<UsageError>([&] { loadScene(dataPath("example.json"), options); }, {"'count'", "none"});
}

TEST(Load, MalformedKnobValues) {
    for (const char* value : {"ten", "0", "-5", "12x", "1e3", ""}) {
        SceneOptions options;
        options.set["count"] = value;
        expectError<UsageError>([&] { loadScene("foliage", options); },
                                {"count=" + std::string(value), "integer"});
    }
    for (const char* value : {"0", "-1", "nan", "inf", "big"}) {
        SceneOptions options;
        options.set["light_size"] = value;
        expectError<UsageError>([&] { loadScene("fence", options); },
                                {"light_size=" + std::string(value), "number"});
    }
}

TEST(Load, MissingFileIsAnInputError) {
    expectError<InputError>([] { loadScene("/nonexistent/bunny.obj"); },
                            {"/nonexistent/bunny.obj", "does not exist"});
    expectError<InputError>([] { loadScene("/nonexistent/bunny.off"); },
                            {"/nonexistent/bunny.off", "does not exist"});
}

/// NDC of p through the camera at aspect `aspect` (Vulkan clip: x, y ∈ [−1, 1], z ∈ [0, 1]).
vec3 ndcOf(const Camera& camera, vec3 p, float aspect, float zNear, float zFar) {
    const vec4 clip = clipFromView(camera, aspect, zNear, zFar) * viewFromWorld(camera) * vec4(p, 1.0f);
    EXPECT_GT(clip.w, 0.0f) << "in front of the camera";
    return vec3(clip) / clip.w;
}

void expectFramed(const Scene& scene, const Bounds& meshBounds) {
    const float d = length(meshBounds.extent());
    for (float aspect : {1.0f, 16.0f / 9.0f})
        for (int corner = 0; corner < 8; ++corner) {
            const vec3 p((corner & 1) ? meshBounds.hi.x : meshBounds.lo.x,
                         (corner & 2) ? meshBounds.hi.y : meshBounds.lo.y,
                         (corner & 4) ? meshBounds.hi.z : meshBounds.lo.z);
            const vec3 ndc = ndcOf(scene.camera, p, aspect, 0.01f * d, 100.0f * d);
            EXPECT_LE(std::abs(ndc.x), 1.0f) << "corner " << corner << " aspect " << aspect;
            EXPECT_LE(std::abs(ndc.y), 1.0f) << "corner " << corner << " aspect " << aspect;
            EXPECT_GE(ndc.z, 0.0f);
            EXPECT_LE(ndc.z, 1.0f);
        }
}

TEST(Load, BareObjIsFramedAboveAGroundUnderALight) {
    TempDir dir;
    // A tall thin box away from the origin: framing must follow the mesh, not assume the origin.
    const std::string obj =
        dir.write("tower.obj", "v 10 5 -3\nv 11 5 -3\nv 11 9 -3\nv 10 9 -3\n"
                               "v 10 5 -2\nv 11 5 -2\nv 11 9 -2\nv 10 9 -2\n"
                               "f 5 6 7 8\nf 2 1 4 3\nf 1 5 8 4\nf 6 2 3 7\nf 8 7 3 4\nf 1 2 6 5\n");
    const Scene scene = loadScene(obj);
    ASSERT_EQ(scene.meshes.size(), 2u);
    EXPECT_EQ(scene.meshes[0].name, "tower");
    EXPECT_EQ(scene.meshes[0].triangleCount, 12u);
    EXPECT_EQ(scene.meshes[1].name, "ground");
    const Bounds mb{vec3(10, 5, -3), vec3(11, 9, -2)};
    // The ground is below the mesh and extends beyond it on every side.
    for (std::uint32_t t = scene.meshes[1].firstTriangle; t < scene.meshes[1].firstTriangle + 2; ++t) {
        for (int k = 0; k < 3; ++k) {
            EXPECT_LT(scene.positions[scene.triangles[t][k]].y, mb.lo.y);
            EXPECT_GT(scene.positions[scene.triangles[t][k]].y, mb.lo.y - 0.01f * length(mb.extent()));
        }
        const vec3 a = scene.positions[scene.triangles[t][0]], b = scene.positions[scene.triangles[t][1]],
                   c = scene.positions[scene.triangles[t][2]];
        EXPECT_GT(cross(b - a, c - a).y, 0.0f) << "ground faces up";
    }
    const Bounds all = scene.bounds();
    EXPECT_LT(all.lo.x, mb.lo.x - 1.0f);
    EXPECT_GT(all.hi.z, mb.hi.z + 1.0f);
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_GT(scene.lights[0].position.y, mb.hi.y);
    EXPECT_LT(scene.lights[0].normal.y, 0.0f) << "light faces down";
    expectFramed(scene, mb);
}

TEST(Load, BareOffIsFramed) {
    TempDir dir;
    const std::string off = dir.write("TRI.OFF", "OFF\n3 1 0\n-50 0 0\n50 0 0\n0 80 0\n3 0 1 2\n");
    const Scene scene = loadScene(off); // upper-case extension accepted
    expectFramed(scene, Bounds{vec3(-50, 0, 0), vec3(50, 80, 0)});
}

TEST(Load, BareObjWithExampleCrate) {
    const Scene scene = loadScene(dataPath("crate.obj"));
    EXPECT_EQ(scene.triangleCount(), 14u);
    expectFramed(scene, Bounds{vec3(-0.5f, 0, -0.5f), vec3(0.5f, 1, 0.5f)});
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

TEST(Load, KnobPrintsAsSetSyntax) {
    std::ostringstream out;
    out << SceneKnob{"count", "64", "plants"};
    EXPECT_EQ(out.str(), "count=64");
}

} // namespace
} // namespace stsv
