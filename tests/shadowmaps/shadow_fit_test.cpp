// Fitting a map to the frame (shadowmaps/shadow_fit.h) against geometry worked out here: the
// receivers of a ground plane are the quad the image's corner rays cut from it, a caster set is
// sound (every triangle a receiver-to-light segment crosses is inside it, checked by brute force),
// a plane with the light on one side casts nothing onto itself, the view fit covers every caster
// and gives the fence more texels than the scene fit.
#include "scene/camera.h"
#include "scene/geometry.h"
#include "scene/procedural.h"
#include "shadowmaps/shadow_fit.h"

#include <gtest/gtest.h>

#include <random>

namespace stsv {
namespace {

Scene groundScene(float half) {
    Scene scene;
    addMaterial(scene, Material{});
    const vec2 t(0.0f);
    scene.addTriangle(vec3(-half, 0, -half), vec3(half, 0, half), vec3(half, 0, -half), t, t, t, 0);
    scene.addTriangle(vec3(-half, 0, -half), vec3(-half, 0, half), vec3(half, 0, half), t, t, t, 0);
    scene.camera.eye = vec3(0.0f, 2.0f, 3.0f);
    scene.camera.target = vec3(0.0f, 0.0f, 0.0f);
    scene.camera.fovY = 40.0f;
    return scene;
}

void addQuad(Scene& scene, vec3 a, vec3 b, vec3 c, vec3 d) {
    const vec2 t(0.0f);
    scene.addTriangle(a, b, c, t, t, t, 0);
    scene.addTriangle(a, c, d, t, t, t, 0);
}

/// Where the ray from the eye through image corner (ndc.x, ndc.y) ∈ {−1, 1}² meets y = 0.
vec3 cornerOnGround(const Camera& camera, float aspect, vec2 ndc) {
    const float tanHalf = std::tan(glm::radians(camera.fovY) * 0.5f);
    const mat3 worldFromView = glm::inverse(mat3(viewFromWorld(camera)));
    const vec3 d = worldFromView * vec3(ndc.x * tanHalf * aspect, ndc.y * tanHalf, -1.0f);
    return camera.eye + d * (-camera.eye.y / d.y);
}

TEST(ShadowFit, ReceiversAreTheGroundTheCameraSees) {
    // The camera looks down at a 40 m ground: the frustum cuts a trapezoid whose corners are
    // the image's corner rays on the plane.
    const Scene scene = groundScene(20.0f);
    const float aspect = 4.0f / 3.0f;
    const Bounds r = shadowReceiverBounds(scene, aspect);
    ASSERT_FALSE(r.empty());
    Bounds expected;
    for (const vec2 ndc : {vec2(-1, -1), vec2(1, -1), vec2(-1, 1), vec2(1, 1)})
        expected.extend(cornerOnGround(scene.camera, aspect, ndc));
    // Float clipping of a 40 m triangle: a few ulps of 20 m.
    const float tol = 1e-4f;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(r.lo[k], expected.lo[k], tol) << "axis " << k;
        EXPECT_NEAR(r.hi[k], expected.hi[k], tol) << "axis " << k;
    }
    EXPECT_LT(r.hi.x - r.lo.x, 10.0f); // far less than the 40 m ground
}

TEST(ShadowFit, NoReceiversWhenTheCameraLooksAway) {
    Scene scene = groundScene(1.0f);
    scene.camera.target = vec3(0.0f, 5.0f, 10.0f); // up and away from the ground
    EXPECT_TRUE(shadowReceiverBounds(scene, 1.0f).empty());
}

TEST(ShadowFit, GroundCastsNothingOntoItselfAndFarObjectsAreLeftOut) {
    Scene scene = groundScene(20.0f);
    // An occluder between the ground and the light, one beside the light's reach, one above it.
    addQuad(scene, vec3(-0.3f, 1.0f, -0.2f), vec3(0.3f, 1.0f, -0.2f), vec3(0.3f, 1.2f, 0.2f),
            vec3(-0.3f, 1.2f, 0.2f));
    addQuad(scene, vec3(15.0f, 1.0f, 15.0f), vec3(16.0f, 1.0f, 15.0f), vec3(16.0f, 1.5f, 16.0f),
            vec3(15.0f, 1.5f, 16.0f));
    addQuad(scene, vec3(-1.0f, 6.0f, -1.0f), vec3(1.0f, 6.0f, -1.0f), vec3(1.0f, 6.0f, 1.0f),
            vec3(-1.0f, 6.0f, 1.0f));
    const Light light = makeRectangleLight(vec3(0.0f, 4.0f, 0.0f), vec3(0, -1, 0), vec2(0.5f), vec3(1.0f));
    const Bounds receivers = shadowReceiverBounds(scene, 1.0f);
    const Bounds c = shadowCasterBounds(scene, light, receivers);
    ASSERT_FALSE(c.empty());
    // Exactly the first occluder's box.
    EXPECT_FLOAT_EQ(c.lo.x, -0.3f);
    EXPECT_FLOAT_EQ(c.hi.x, 0.3f);
    EXPECT_FLOAT_EQ(c.lo.y, 1.0f);
    EXPECT_FLOAT_EQ(c.hi.y, 1.2f);
    EXPECT_FLOAT_EQ(c.lo.z, -0.2f);
    EXPECT_FLOAT_EQ(c.hi.z, 0.2f);
    // Without occluders nothing can shadow the ground.
    EXPECT_TRUE(shadowCasterBounds(groundScene(20.0f), light, receivers).empty());
}

TEST(ShadowFit, DirectionalCastersReachFarTowardsTheLight) {
    Scene scene = groundScene(20.0f);
    // High above the visible ground, tilted towards the light: casts onto it from afar.
    const vec3 toward = normalize(vec3(0.3f, 1.0f, 0.2f));
    const vec3 centre = 30.0f * toward;
    addQuad(scene, centre + vec3(-0.5f, 0, -0.5f), centre + vec3(0.5f, 0, -0.5f),
            centre + vec3(0.5f, 0, 0.5f), centre + vec3(-0.5f, 0, 0.5f));
    const Light light = makeDirectionalLight(toward, 0.01f, vec3(1.0f));
    const Bounds c = shadowCasterBounds(scene, light, shadowReceiverBounds(scene, 1.0f));
    ASSERT_FALSE(c.empty());
    EXPECT_NEAR(c.lo.y, centre.y, 1e-4f);
    EXPECT_NEAR(c.hi.x, centre.x + 0.5f, 1e-4f);
}

/// Möller–Trumbore: the segment parameter in (0, 1) where a → b crosses the triangle, or −1.
float segmentHit(vec3 a, vec3 b, vec3 v0, vec3 v1, vec3 v2) {
    const vec3 d = b - a, e1 = v1 - v0, e2 = v2 - v0, p = cross(d, e2);
    const float det = dot(e1, p);
    if (std::abs(det) < 1e-12f) return -1.0f;
    const vec3 s = a - v0;
    const float u = dot(s, p) / det;
    const vec3 q = cross(s, e1);
    const float v = dot(d, q) / det;
    const float t = dot(e2, q) / det;
    return u >= 0.0f && v >= 0.0f && u + v <= 1.0f && t > 1e-4f && t < 1.0f - 1e-4f ? t : -1.0f;
}

TEST(ShadowFit, CasterBoundsHoldEveryBlockingPointFoundByBruteForce) {
    // Random triangles around the view; random segments from the receivers' box to the light:
    // wherever one crosses a triangle, the crossing lies in the caster bounds.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (const Light& light : {makeRectangleLight(vec3(0.5f, 3.0f, 0.2f), normalize(vec3(0.1f, -1.0f, 0.0f)),
                                                  vec2(1.0f, 0.6f), vec3(1.0f)),
                               makeDiskLight(vec3(-0.5f, 2.5f, 0.5f), vec3(0, -1, 0), 0.4f, vec3(1.0f)),
                               makeSphereLight(vec3(0.0f, 2.0f, -0.5f), 0.3f, vec3(1.0f))}) {
        Scene scene = groundScene(4.0f);
        for (int i = 0; i < 300; ++i) {
            const vec3 c(2.5f * u(rng), 1.0f + 1.2f * u(rng), 2.5f * u(rng));
            scene.addTriangle(c, c + 0.4f * vec3(u(rng), u(rng), u(rng)),
                              c + 0.4f * vec3(u(rng), u(rng), u(rng)), vec2(0), vec2(0), vec2(0), 0);
        }
        const Bounds receivers = shadowReceiverBounds(scene, 1.0f);
        const Bounds casters = shadowCasterBounds(scene, light, receivers);
        int crossings = 0;
        for (int s = 0; s < 4000; ++s) {
            const vec3 f(0.5f * (u(rng) + 1.0f), 0.5f * (u(rng) + 1.0f), 0.5f * (u(rng) + 1.0f));
            const vec3 p = receivers.lo + f * (receivers.hi - receivers.lo);
            const vec3 q = light.type == LIGHT_SPHERE
                               ? light.position + light.radius * vec3(u(rng), u(rng), u(rng)) * 0.57f
                           : light.type == LIGHT_RECTANGLE
                               ? light.position + u(rng) * light.axisU + u(rng) * light.axisV
                               : light.position + vec3(0.28f * u(rng), 0.0f, 0.28f * u(rng));
            for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
                const uvec3 tri = scene.triangles[t];
                const float h =
                    segmentHit(p, q, scene.positions[tri.x], scene.positions[tri.y], scene.positions[tri.z]);
                if (h < 0.0f) continue;
                ++crossings;
                const vec3 x = p + h * (q - p);
                const vec3 slack(1e-4f);
                ASSERT_TRUE(all(greaterThanEqual(x, casters.lo - slack)) &&
                            all(lessThanEqual(x, casters.hi + slack)))
                    << "triangle " << t << " blocks a segment outside the caster bounds";
            }
        }
        EXPECT_GT(crossings, 100); // the check saw blockers
    }
}

TEST(ShadowFit, ViewFitHoldsTheFenceWithFinerTexels) {
    const Scene scene = makeFenceScene();
    const Light& light = scene.lights.at(0);
    ShadowMapSettings settings;
    const Bounds receivers = shadowReceiverBounds(scene, 4.0f / 3.0f);
    settings.fit = 0;
    const ShadowMapView whole = fitFrameShadowMap(scene, light, receivers, settings);
    settings.fit = 1;
    const ShadowMapView view = fitFrameShadowMap(scene, light, receivers, settings);
    EXPECT_EQ(view.projection, SHADOW_MAP_PERSPECTIVE);
    // Every vertex of a triangle that is not in the ground plane projects inside the window.
    Bounds fence;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const uvec3 tri = scene.triangles[t];
        for (const unsigned i : {tri.x, tri.y, tri.z}) {
            const vec3 p = scene.positions[i];
            if (p.y <= scene.bounds().lo.y + 1e-4f) continue;
            fence.extend(p);
            const ShadowMapCoord c = shadowMapProject(view, p);
            ASSERT_EQ(c.valid, 1.0f);
            EXPECT_TRUE(c.uv.x >= 0.0f && c.uv.x <= 1.0f && c.uv.y >= 0.0f && c.uv.y <= 1.0f)
                << "vertex " << i << " at uv " << c.uv.x << ", " << c.uv.y;
            EXPECT_GE(c.depth, view.near);
            EXPECT_LE(c.depth, view.far);
        }
    }
    // A texel at the fence's centre is at least twice as fine as the scene fit's.
    const vec3 centre = fence.center();
    const ShadowMapCoord a = shadowMapProject(whole, centre), b = shadowMapProject(view, centre);
    const float coarse = shadowMapTexelWorld(whole, a.axial) *
                         (whole.projection == SHADOW_MAP_CUBE ? a.depth / a.axial : 1.0f);
    EXPECT_LT(2.0f * shadowMapTexelWorld(view, b.axial), coarse);
}

} // namespace
} // namespace stsv
