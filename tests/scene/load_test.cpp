#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/camera.h"
#include "scene/load.h"
#include "scene/procedural.h"

#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
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

/// Sets the memory limit for one test and restores the default after it.
struct MemoryLimitForTest {
    explicit MemoryLimitForTest(std::uint64_t bytes) { setMemoryLimit(bytes); }
    ~MemoryLimitForTest() { setMemoryLimit(0); }
    MemoryLimitForTest(const MemoryLimitForTest&) = delete;
    MemoryLimitForTest& operator=(const MemoryLimitForTest&) = delete;
};

/// What a width × height picture from the scene's camera shows, by triangle coverage (alpha
/// ignored): pixel centres inside some projected triangle, and inside one of a mesh other than
/// the ground.
struct Coverage {
    std::size_t any = 0;
    std::size_t object = 0;
};

Coverage coverage(const Scene& scene, int width, int height) {
    const Bounds box = scene.bounds();
    const float reach = length(box.center() - scene.camera.eye) + 0.5f * length(box.extent());
    const float zNear = 1e-6f * reach; // triangles are clipped there (w ≥ zNear)
    const mat4 clipFromWorld = clipFromView(scene.camera, float(width) / float(height), zNear, 2.0f * reach) *
                               viewFromWorld(scene.camera);
    std::vector<std::uint8_t> seen(std::size_t(width) * height, 0); // bit 0: any, bit 1: object
    std::vector<bool> ground(scene.triangleCount(), false);
    for (const Mesh& m : scene.meshes)
        if (m.name == "ground")
            for (std::uint32_t t = m.firstTriangle; t < m.firstTriangle + m.triangleCount; ++t)
                ground[t] = true;
    std::vector<vec4> polygon, clipped;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        polygon.clear();
        for (int k = 0; k < 3; ++k)
            polygon.push_back(clipFromWorld * vec4(scene.positions[scene.triangles[t][k]], 1.0f));
        // Sutherland–Hodgman against the near plane w = zNear.
        clipped.clear();
        for (std::size_t i = 0; i < polygon.size(); ++i) {
            const vec4 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
            if (a.w >= zNear) clipped.push_back(a);
            if ((a.w >= zNear) != (b.w >= zNear))
                clipped.push_back(a + (b - a) * ((zNear - a.w) / (b.w - a.w)));
        }
        if (clipped.size() < 3) continue;
        std::vector<vec2> p;
        for (const vec4& c : clipped)
            p.emplace_back((c.x / c.w * 0.5f + 0.5f) * float(width),
                           (c.y / c.w * 0.5f + 0.5f) * float(height));
        const std::uint8_t bits = ground[t] ? 1 : 3;
        for (std::size_t f = 1; f + 1 < p.size(); ++f) { // fan
            const vec2 a = p[0], b = p[f], c = p[f + 1];
            const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            if (!(std::abs(area) > 0.0f)) continue;
            const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x})))),
                      x1 = std::min(width - 1, int(std::ceil(std::max({a.x, b.x, c.x})))),
                      y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y})))),
                      y1 = std::min(height - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const vec2 q(float(x) + 0.5f, float(y) + 0.5f);
                    const auto edge = [&](vec2 u, vec2 v) {
                        return ((v.x - u.x) * (q.y - u.y) - (v.y - u.y) * (q.x - u.x)) * area;
                    };
                    if (edge(a, b) >= 0.0f && edge(b, c) >= 0.0f && edge(c, a) >= 0.0f)
                        seen[std::size_t(y) * width + x] |= bits;
                }
        }
    }
    Coverage result;
    for (const std::uint8_t s : seen) {
        result.any += s & 1;
        result.object += (s >> 1) & 1;
    }
    return result;
}

/// The four corners of a rectangle light (the centre and ± each half-extent).
std::vector<vec3> lightCorners(const Light& light) {
    return {light.position - light.axisU - light.axisV, light.position + light.axisU - light.axisV,
            light.position + light.axisU + light.axisV, light.position - light.axisU + light.axisV};
}

/// `value` as `--set` takes it: a whole number in full, others in their shortest round-trip text.
std::string knobText(double value) {
    char buffer[32];
    const char* end =
        value == std::floor(value) && std::abs(value) < 1e15
            ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<long long>(value)).ptr
            : std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general).ptr;
    return std::string(static_cast<const char*>(buffer), end);
}

// Each end of every knob's documented range, the others at their defaults, gives a picture worth
// looking at (as `stsv render SCENE --set k=v --size 160x120` does): the scene loads without a
// warning, the camera's 160 x 120 pixels see triangles in more than half of the picture and the
// scene's own object (not only the ground) in some, and the lights lie above every triangle,
// facing down. Memory is not what is tested: the limit is raised for loading.
TEST(KnobRanges, EachEndLoadsAPictureOfTheScene) {
    const MemoryLimitForTest limit(std::uint64_t(1) << 40);
    for (const std::string& name : builtinSceneNames())
        for (const SceneKnob& knob : builtinSceneKnobs(name)) {
            const std::vector<std::string> ends =
                knob.kind == SceneKnob::Kind::Seed
                    ? std::vector<std::string>{"0", "18446744073709551615"}
                    : std::vector<std::string>{knobText(knob.lo), knobText(knob.hi)};
            if (knob.kind != SceneKnob::Kind::Seed) { // the range `stsv info` shows is the one tested
                EXPECT_NE(knob.description.find("[" + ends[0] + ", " + ends[1] + "]"), std::string::npos)
                    << name << " " << knob.name << ": " << knob.description;
            }
            for (const std::string& value : ends) {
                SCOPED_TRACE(name + " --set " + knob.name + "=" + value);
                SceneOptions options;
                options.set[knob.name] = value;
                Scene scene;
                try {
                    scene = loadScene(name, options);
                } catch (const std::exception& e) {
                    ADD_FAILURE() << e.what();
                    continue;
                }
                EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
                const Coverage c = coverage(scene, 160, 120);
                EXPECT_GT(c.any, 160u * 120u / 2u) << "pixels that see a triangle";
                EXPECT_GT(c.object, 0u) << "pixels that see the scene's object";
                float top = -1e30f;
                for (const vec3& p : scene.positions) top = std::max(top, p.y);
                for (const Light& light : scene.lights) {
                    EXPECT_LT(light.normal.y, 0.0f) << "the light faces down";
                    for (const vec3& corner : lightCorners(light))
                        EXPECT_GT(corner.y, top) << "a light corner at " << corner.x << ", " << corner.y
                                                 << ", " << corner.z << " is not above the scene";
                }
            }
        }
}

TEST(KnobRanges, ValuesJustOutsideAreRefusedWithTheRange) {
    for (const std::string& name : builtinSceneNames())
        for (const SceneKnob& knob : builtinSceneKnobs(name)) {
            if (knob.kind == SceneKnob::Kind::Seed) continue;
            const bool integer = knob.kind == SceneKnob::Kind::Integer;
            const double below = integer ? knob.lo - 1.0 : std::nextafter(knob.lo, -HUGE_VAL);
            const double above = integer ? knob.hi + 1.0 : std::nextafter(knob.hi, HUGE_VAL);
            for (const double value : {below, above}) {
                SceneOptions options;
                options.set[knob.name] = knobText(value);
                expectError<UsageError>([&] { loadScene(name, options); },
                                        {knob.name + "=" + knobText(value),
                                         "[" + knobText(knob.lo) + ", " + knobText(knob.hi) + "]"});
            }
        }
}

TEST(KnobRanges, LightSizesThatBreakTheLightNameTheRange) {
    // 1e-30 was inside the documented (0, 100]: its area underflowed and the radiance was infinite.
    SceneOptions tiny;
    tiny.set["light_size"] = "1e-30";
    expectError<UsageError>([&] { loadScene("fence", tiny); }, {"light_size=1e-30", "[0.0001, 10]"});
    // The foliage light of 1000 m reached through the ground; it now moves back to clear the plants.
    SceneOptions large;
    large.set["light_size"] = "1000";
    const Scene foliage = loadScene("foliage", large);
    EXPECT_FLOAT_EQ(2.0f * length(foliage.lights[0].axisU), 1000.0f);
    EXPECT_GT(foliage.lights[0].position.y, 100.0f);
}

TEST(KnobRanges, RepeatTimesTextureSizeMustNameTexels) {
    SceneOptions options;
    options.set["repeat"] = "4096";
    options.set["texture_size"] = "8192";
    expectError<UsageError>([&] { loadScene("fence", options); },
                            {"repeat x texture_size = 4096 x 8192", "2^24"});
}

TEST(KnobRanges, GeneratedTexturesCountAgainstTheMemoryLimit) {
    const MemoryLimitForTest limit(std::uint64_t(10) << 20);
    // 2048² RGBA texels are 16 MiB, above the 10 MiB limit; the default 256² fits.
    for (const char* scene : {"fence", "foliage"}) {
        SceneOptions options;
        options.set["texture_size"] = "2048";
        expectError<UsageError>(
            [&] { loadScene(scene, options); },
            {std::string(scene) + ":", "texture of 2048x2048 texels", "16.0 MiB", "memory limit"});
    }
    EXPECT_NO_THROW(loadScene("fence"));
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

TEST(Load, ParticlesHeightLowersTheCloudOntoTheGround) {
    // Billboard centres: within the 1.2 m ball around (−0.6, height, 0), and at least a
    // half-width (0.25 m) above the ground. At the default 2 the centres stay 0.8 m above the
    // ground; at 0.9 the cloud rests on it, centres down to 0.25 m.
    for (const char* height : {"2", "0.9"}) {
        SceneOptions options;
        options.set["count"] = "400";
        options.set["height"] = height;
        const Scene s = loadScene("particles", options);
        const float h = std::stof(height);
        float lowest = 1e30f;
        for (std::size_t t = 0; t < s.triangleCount(); t += 1) {
            if (!s.translucent(t) || t % 2 != 0) continue;
            const vec3 a = s.positions[s.triangles[t].x], c = s.positions[s.triangles[t].z];
            const vec3 centre = 0.5f * (a + c);
            EXPECT_LE(length(centre - vec3(-0.6f, h, 0.0f)), 1.2f + 1e-4f) << height;
            EXPECT_GE(centre.y, 0.25f - 1e-4f) << height;
            lowest = std::min(lowest, centre.y);
        }
        if (h == 2.0f)
            EXPECT_GT(lowest, 0.8f - 1e-4f);
        else
            EXPECT_LT(lowest, 0.35f); // 400 centres in the ball's lower cap down to the ground
    }
    SceneOptions bad;
    bad.set["height"] = "0.2";
    expectError<UsageError>([&] { loadScene("particles", bad); }, {"particles", "height=0.2"});
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
