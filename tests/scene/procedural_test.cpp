#include "scene/camera.h"
#include "scene/geometry.h"
#include "scene/load.h"
#include "scene/procedural.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace stsv {
namespace {

bool insideFrustum(const Camera& camera, vec3 p, float aspect) {
    const vec4 clip = clipFromView(camera, aspect, 0.01f, 1000.0f) * viewFromWorld(camera) * vec4(p, 1.0f);
    if (clip.w <= 0.0f) return false;
    const vec3 ndc = vec3(clip) / clip.w;
    return std::abs(ndc.x) <= 1.0f && std::abs(ndc.y) <= 1.0f && ndc.z >= 0.0f && ndc.z <= 1.0f;
}

/// Where the ray from the light centre through p meets the ground y = 0.
vec3 shadowOnGround(const Light& light, vec3 p) {
    const float t = light.position.y / (light.position.y - p.y);
    return light.position + t * (p - light.position);
}

std::size_t perforatedCount(const Scene& scene) {
    std::size_t n = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) n += scene.perforated(t) ? 1 : 0;
    return n;
}

TEST(ChainLink, OpenFractionIsBetween60And80Percent) {
    for (int size : {32, 64, 256, 512}) {
        const double open = openFraction(makeChainLinkTexture(size));
        EXPECT_GE(open, 0.6) << "size=" << size;
        EXPECT_LE(open, 0.8) << "size=" << size;
    }
}

TEST(ChainLink, IsBinary) {
    const Texture t = makeChainLinkTexture(128);
    for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x)
            ASSERT_TRUE(t.alpha(x, y) == 0 || t.alpha(x, y) == 255) << x << "," << y;
}

TEST(ChainLink, WrapContinuesThePattern) {
    // The header promises 4 × 4 whole diamonds per tile, so the pattern has period size/4 in x
    // and in y; comparing every texel with the one a period further *with wrap-around* checks
    // that the tile's last columns/rows continue into its first ones exactly.
    const int n = 256, period = n / 4;
    const Texture t = makeChainLinkTexture(n);
    int mismatches = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            mismatches += t.alpha(x, y) != t.alpha((x + period) % n, y) ? 1 : 0;
            mismatches += t.alpha(x, y) != t.alpha(x, (y + period) % n) ? 1 : 0;
        }
    EXPECT_EQ(mismatches, 0);
}

TEST(ChainLink, SeamIsNoMoreDiscontinuousThanTheInterior) {
    // Implementation-independent seamlessness: the number of alpha changes across the wrap seam
    // (column n−1 → 0, row n−1 → 0) lies within the range seen across interior column/row pairs.
    for (int n : {64, 100, 256}) {
        const Texture t = makeChainLinkTexture(n);
        auto columnChanges = [&](int x0, int x1) {
            int c = 0;
            for (int y = 0; y < n; ++y) c += t.alpha(x0, y) != t.alpha(x1, y) ? 1 : 0;
            return c;
        };
        auto rowChanges = [&](int y0, int y1) {
            int c = 0;
            for (int x = 0; x < n; ++x) c += t.alpha(x, y0) != t.alpha(x, y1) ? 1 : 0;
            return c;
        };
        int colMin = n, colMax = 0, rowMin = n, rowMax = 0;
        for (int i = 0; i + 1 < n; ++i) {
            colMin = std::min(colMin, columnChanges(i, i + 1));
            colMax = std::max(colMax, columnChanges(i, i + 1));
            rowMin = std::min(rowMin, rowChanges(i, i + 1));
            rowMax = std::max(rowMax, rowChanges(i, i + 1));
        }
        EXPECT_GE(columnChanges(n - 1, 0), colMin) << "n=" << n;
        EXPECT_LE(columnChanges(n - 1, 0), colMax) << "n=" << n;
        EXPECT_GE(rowChanges(n - 1, 0), rowMin) << "n=" << n;
        EXPECT_LE(rowChanges(n - 1, 0), rowMax) << "n=" << n;
    }
}

TEST(Leaf, HasLeavesAndTransparentBorderAndStemFoot) {
    const int n = 128;
    const Texture t = makeLeafTexture(n);
    const double open = openFraction(t);
    EXPECT_GT(open, 0.3) << "a sprite, not a solid card";
    EXPECT_LT(open, 0.85) << "enough leaf to cast a shadow";
    for (int i = 0; i < n; ++i) {
        EXPECT_EQ(t.alpha(i, 0), 0) << "top row, x=" << i;
        EXPECT_EQ(t.alpha(0, i), 0) << "left column, y=" << i;
        EXPECT_EQ(t.alpha(n - 1, i), 0) << "right column, y=" << i;
    }
    EXPECT_EQ(t.alpha(n / 2, n - 1), 255) << "the stem reaches the bottom edge (the ground)";
}

TEST(Fence, HasExactlyTwoPerforatedTrianglesOnAGround) {
    const Scene scene = makeFenceScene();
    EXPECT_EQ(scene.triangleCount(), 4u);
    EXPECT_EQ(perforatedCount(scene), 2u);
    const Bounds b = scene.bounds();
    EXPECT_EQ(b.lo.y, 0.0f);
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.perforated(t)) continue;
        const Material& m = scene.materialOf(t);
        EXPECT_EQ(m.wrap, WrapMode::Repeat);
        EXPECT_TRUE(m.doubleSided);
        const double open = openFraction(scene.textures[std::size_t(m.alphaTexture)]);
        EXPECT_GE(open, 0.6);
        EXPECT_LE(open, 0.8);
    }
}

TEST(Fence, TextureRepeatsAcrossTheFence) {
    const Scene scene = makeFenceScene();
    float uMin = 1e9f, uMax = -1e9f, vMin = 1e9f, vMax = -1e9f, yMin = 1e9f, yMax = -1e9f, xMin = 1e9f,
          xMax = -1e9f;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.perforated(t)) continue;
        for (int k = 0; k < 3; ++k) {
            const vec2 uv = scene.texcoords[scene.triangles[t][k]];
            const vec3 p = scene.positions[scene.triangles[t][k]];
            uMin = std::min(uMin, uv.x), uMax = std::max(uMax, uv.x), vMin = std::min(vMin, uv.y),
            vMax = std::max(vMax, uv.y);
            xMin = std::min(xMin, p.x), xMax = std::max(xMax, p.x), yMin = std::min(yMin, p.y),
            yMax = std::max(yMax, p.y);
        }
    }
    EXPECT_EQ(uMax - uMin, 16.0f);
    EXPECT_EQ(vMax - vMin, 8.0f);
    EXPECT_EQ(xMax - xMin, 4.0f) << "4 m wide";
    EXPECT_EQ(yMax - yMin, 2.0f) << "2 m high";
    EXPECT_EQ(yMin, 0.0f) << "stands on the ground";
}

TEST(Fence, ShadowFallsOnTheGroundInView) {
    const Scene scene = makeFenceScene();
    ASSERT_EQ(scene.lights.size(), 1u);
    const Light& light = scene.lights[0];
    EXPECT_EQ(light.type, LIGHT_RECTANGLE);
    EXPECT_GT(light.position.y, 2.0f) << "above the fence top";
    // The shadow of the fence's top edge (seen from the light centre) is on the ground in front
    // of the fence (camera side, +z), inside the view, and lit by the light's front side.
    for (float x : {-2.0f, 0.0f, 2.0f}) {
        const vec3 s = shadowOnGround(light, vec3(x, 2.0f, 0.0f));
        EXPECT_GT(s.z, 0.5f) << "x=" << x;
        EXPECT_TRUE(insideFrustum(scene.camera, s, 1.0f)) << "shadow point " << s.x << "," << s.z;
        EXPECT_GT(dot(light.normal, s - light.position), 0.0f);
    }
    for (vec3 corner : {vec3(-2, 0, 0), vec3(2, 0, 0), vec3(-2, 2, 0), vec3(2, 2, 0)})
        for (float aspect : {1.0f, 16.0f / 9.0f})
            EXPECT_TRUE(insideFrustum(scene.camera, corner, aspect))
                << corner.x << "," << corner.y << " aspect " << aspect;
}

TEST(Fence, LightSizeKnobSetsTheRectangle) {
    SceneOptions options;
    options.set["light_size"] = "2.5";
    const Scene scene = loadScene("fence", options);
    const Light& light = scene.lights[0];
    EXPECT_NEAR(length(light.axisU), 1.25f, 1e-5f) << "half extent; float rounding of normalize";
    EXPECT_NEAR(length(light.axisV), 1.25f, 1e-5f);
    EXPECT_NEAR(light.radius, 1.25f * std::sqrt(2.0f), 1e-5f) << "bounding sphere = half diagonal";
    EXPECT_NEAR(dot(light.axisU, light.normal), 0.0f, 1e-5f);
    EXPECT_NEAR(dot(light.axisV, light.normal), 0.0f, 1e-5f);
}

TEST(Foliage, CountKnobScalesSTrianglesExactly) {
    for (int count : {1, 7, 64, 4000}) {
        SceneOptions options;
        options.set["count"] = std::to_string(count);
        const Scene scene = loadScene("foliage", options);
        EXPECT_EQ(perforatedCount(scene), 4u * std::size_t(count)) << "count=" << count;
        EXPECT_EQ(scene.triangleCount() - perforatedCount(scene), 2u) << "opaque ground";
    }
}

TEST(Foliage, DefaultHasAFewHundredSTrianglesInView) {
    const Scene scene = loadScene("foliage");
    EXPECT_EQ(perforatedCount(scene), 256u);
    std::size_t inView = 0, corners = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.perforated(t)) continue;
        for (int k = 0; k < 3; ++k, ++corners)
            inView += insideFrustum(scene.camera, scene.positions[scene.triangles[t][k]], 1.0f);
    }
    EXPECT_EQ(inView, corners) << "every plant vertex is in the (square) view";
    // The plants' shadows (projected from the light centre) land on the ground in front of the light.
    const Light& light = scene.lights[0];
    EXPECT_GT(light.position.y, 3.0f);
    const vec3 s = shadowOnGround(light, vec3(0.0f, 0.8f, 0.0f));
    EXPECT_TRUE(insideFrustum(scene.camera, s, 1.0f)) << s.x << "," << s.z;
}

TEST(Foliage, LargePatchStaysInView) {
    SceneOptions options;
    options.set["count"] = "4000";
    const Scene scene = loadScene("foliage", options);
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.perforated(t)) continue;
        for (int k = 0; k < 3; ++k)
            ASSERT_TRUE(insideFrustum(scene.camera, scene.positions[scene.triangles[t][k]], 1.0f))
                << "t=" << t;
    }
}

TEST(Foliage, SeedIsDeterministic) {
    SceneOptions a, b;
    a.set["seed"] = "7";
    b.set["seed"] = "8";
    const Scene s1 = loadScene("foliage", a), s2 = loadScene("foliage", a), s3 = loadScene("foliage", b);
    EXPECT_EQ(s1.positions, s2.positions);
    EXPECT_NE(s1.positions, s3.positions);
}

TEST(Foliage, PlantsStandOnTheGroundAndAreDoubleSided) {
    const Scene scene = loadScene("foliage");
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.perforated(t)) continue;
        EXPECT_TRUE(scene.materialOf(t).doubleSided);
        EXPECT_EQ(scene.materialOf(t).wrap, WrapMode::Clamp);
        float yMin = 1e9f;
        for (int k = 0; k < 3; ++k) yMin = std::min(yMin, scene.positions[scene.triangles[t][k]].y);
        EXPECT_EQ(yMin, 0.0f) << "t=" << t;
    }
}

TEST(Lights, RadiusIsTheBoundingSphereOfEveryType) {
    const Light rect = makeRectangleLight(vec3(0), vec3(0, -1, 0), vec2(2.0f, 1.0f), vec3(1));
    EXPECT_NEAR(rect.radius, std::sqrt(1.0f + 0.25f), 1e-6f) << "half diagonal";
    EXPECT_NEAR(rect.radius, length(rect.axisU + rect.axisV), 1e-6f);
    EXPECT_EQ(makeDiskLight(vec3(0), vec3(0, 1, 0), 0.3f, vec3(1)).radius, 0.3f);
    EXPECT_EQ(makeSphereLight(vec3(0), 0.4f, vec3(1)).radius, 0.4f);
    const Light sun = makeDirectionalLight(vec3(0, 2, 0), 0.01f, vec3(1));
    EXPECT_EQ(sun.radius, 0.0f);
    EXPECT_EQ(sun.normal, vec3(0, 1, 0));
    EXPECT_EQ(sun.angularRadius, 0.01f);
}

TEST(Lights, RectangleTangentIsHonoured) {
    const Light rect = makeRectangleLight(vec3(0), vec3(0, -1, 0), vec2(2.0f, 1.0f), vec3(1), vec3(0, 0, 3));
    EXPECT_EQ(normalize(rect.axisU), vec3(0, 0, 1));
    EXPECT_NEAR(length(rect.axisU), 1.0f, 1e-6f);
    EXPECT_NEAR(length(rect.axisV), 0.5f, 1e-6f);
}

TEST(Tube, IsWoundOutwards) {
    // Counter-clockwise seen from outside: the signed volume Σ v0·(v1 × v2)/6 of the closed tube is
    // positive, the area of its 12-sided cross-section, (12/2)·sin(2π/12)·r², times the length of
    // the polyline through the rings' centres (within 3 %: the rings tilt along the curve).
    const int segments = 480, sides = 12;
    const float r = 0.12f;
    const MeshData knot = makeTorusKnotMesh(segments, sides, r);
    double volume = 0.0;
    for (const uvec3& t : knot.triangles)
        volume += double(dot(knot.positions[t.x], cross(knot.positions[t.y], knot.positions[t.z]))) / 6.0;
    auto centre = [&](int i) {
        dvec3 c(0.0);
        for (int j = 0; j < sides; ++j) c += dvec3(knot.positions[std::size_t((i % segments) * sides + j)]);
        return c / double(sides);
    };
    double length = 0.0;
    for (int i = 0; i < segments; ++i) length += glm::distance(centre(i), centre(i + 1));
    const double expected =
        0.5 * sides * std::sin(6.283185307179586 / sides) * double(r) * double(r) * length;
    EXPECT_GT(volume, 0.97 * expected);
    EXPECT_LT(volume, 1.03 * expected);
}

} // namespace
} // namespace stsv
