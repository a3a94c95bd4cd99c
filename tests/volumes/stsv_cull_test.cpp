// The culling of STSV volumes before they are built (volumes/stsv_cull_dh.h), against brute force:
// a volume it culls must have no shadow segment of the box's points cross its triangle's plane
// past the segment's start (the rule of scene/occlusion_rules_dh.h every method shares).
#include "volume_test_util.h"
#include "volumes/stsv_cull_dh.h"

#include <gtest/gtest.h>

namespace stsv::test {
namespace {

TEST(StsvCull, ACulledVolumeCrossesNoSegmentFromAnyPointOfTheBox) {
    // Triangles on or just inside the box's floor, lit from above by sphere lights, with the
    // floor's offset straddling the culling threshold tMin·L; and triangles anywhere.
    Rng rng(2027);
    const vec3 lo(-2.0f, -1.0f, -3.0f), hi(2.0f, 3.0f, 1.0f);
    const double diameter = length(dvec3(hi) - dvec3(lo));
    int culled = 0, kept = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const bool floor = rng.chance(0.7);
        Light light{};
        light.type = LIGHT_SPHERE;
        light.radius = rng.logUniform(1e-3f, 0.5f);
        light.position = rng.inBox(lo + vec3(0.0f, 1.0f, 0.0f), hi + vec3(0.0f, 4.0f, 0.0f));
        const vec4 sphere(light.position, light.radius);
        vec3 v[3];
        // Floor triangles sit at most a few tMin·L above lo.y: their own plane has box corners
        // behind it by that much.
        const float lift = floor ? rng.uniformf(0.0f, 3e-4f) * (light.position.y - lo.y) : 0.0f;
        for (vec3& c : v) {
            c = rng.inBox(lo, hi);
            if (floor) c.y = lo.y + lift;
        }
        const StsvTriangle t = stsvSetupTriangle(v[0], v[1], v[2], vec2(0.0f), vec2(1.0f, 0.0f),
                                                 vec2(0.0f, 1.0f), light.position, 0u, STSV_FLAG_OPAQUE, 0u);
        if ((t.flags & STSV_FLAG_DEGENERATE) != 0u) continue;
        if (!stsvVolumeCannotShadowBox(t, sphere, light, lo, hi, 100.0f)) {
            ++kept;
            continue;
        }
        ++culled;
        // The plane in double, its normal towards the light's centre (as the triangle constants).
        dvec3 normal = normalize(cross(dvec3(v[1]) - dvec3(v[0]), dvec3(v[2]) - dvec3(v[0])));
        if (dot(normal, dvec3(light.position) - dvec3(v[0])) < 0.0) normal = -normal;
        const double w = -dot(normal, dvec3(v[0]));
        for (int i = 0; i < 208; ++i) {
            // The box's corners (the farthest behind the plane), then points inside it.
            const vec3 p = i < 8 ? stsvBoxCorner(lo, hi, uint(i)) : rng.inBox(lo, hi);
            const double dp = dot(normal, dvec3(p)) + w;
            if (dp >= 0.0) continue; // p in front: no segment towards the light crosses
            const double tMin = shadowTMin(p, light.position, float(diameter));
            for (int k = 0; k < 32; ++k) {
                const dvec3 s = dvec3(light.position) + double(light.radius) * dvec3(rng.inBall());
                const double ds = dot(normal, s) + w;
                if (ds <= 0.0) continue;
                const double crossing = dp / (dp - ds);
                ASSERT_LE(crossing, tMin)
                    << "trial " << trial << ": a culled volume's plane is crossed at t = " << crossing
                    << " by the segment from " << str(dvec3(p));
            }
        }
    }
    // Both outcomes occur, so the test exercises the bound and not a constant.
    EXPECT_GT(culled, 300);
    EXPECT_GT(kept, 300);
}

TEST(StsvCull, TheFloorUnderALightIsCulledAndATriangleAcrossTheBoxIsNot) {
    const vec3 lo(-1.0f), hi(1.0f);
    Light light{};
    light.type = LIGHT_RECTANGLE;
    light.position = vec3(0.0f, 3.0f, 0.0f);
    light.radius = 0.5f;
    const vec4 sphere(light.position, light.radius);
    auto culls = [&](vec3 a, vec3 b, vec3 c) {
        const StsvTriangle t = stsvSetupTriangle(a, b, c, vec2(0.0f), vec2(1.0f, 0.0f), vec2(0.0f, 1.0f),
                                                 light.position, 0u, STSV_FLAG_OPAQUE, 0u);
        return stsvVolumeCannotShadowBox(t, sphere, light, lo, hi, 100.0f);
    };
    // The floor of the box, facing the light: every point of the box lies in front of it.
    EXPECT_TRUE(culls(vec3(-1.0f, -1.0f, -1.0f), vec3(1.0f, -1.0f, -1.0f), vec3(0.0f, -1.0f, 1.0f)));
    // A triangle through the box's middle shadows the points below it.
    EXPECT_FALSE(culls(vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 0.0f, -1.0f), vec3(0.0f, 0.0f, 1.0f)));
    // The floor with the light below it (the light on its back side): no culling.
    light.position = vec3(0.0f, -3.0f, 0.0f);
    EXPECT_FALSE(culls(vec3(-1.0f, -1.0f, -1.0f), vec3(1.0f, -1.0f, -1.0f), vec3(0.0f, -1.0f, 1.0f)));
}

// The bound is at most shadowTMin of every point of the box (what makes the culling safe).
TEST(StsvCull, TheLowerBoundIsAtMostEveryPointsStart) {
    Rng rng(5);
    const vec3 lo(-3.0f, 0.0f, -1.0f), hi(3.0f, 2.0f, 5.0f);
    const float diameter = length(hi - lo);
    for (int trial = 0; trial < 200; ++trial) {
        Light light{};
        light.type = LIGHT_DISK;
        // Near the box and up to a hundred diameters away, where shadowTMin shrinks.
        light.position = rng.onSphere() * rng.logUniform(0.1f, 100.0f * diameter);
        const float bound = stsvShadowTMinLowerBound(light, lo, hi, 50.0f);
        for (int i = 0; i < 100; ++i) {
            const vec3 p = i < 8 ? stsvBoxCorner(lo, hi, uint(i)) : rng.inBox(lo, hi);
            ASSERT_LE(bound, shadowTMin(p, light.position, diameter)) << "trial " << trial;
        }
    }
}

} // namespace
} // namespace stsv::test
