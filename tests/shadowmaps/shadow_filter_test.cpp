// The filters of shadowmaps/shadow_filter_dh.h on maps written out here, texel by texel, from a
// plane whose geometry is known: a blocker half-plane parallel to a map face at axial depth 2, a
// receiver plane parallel to it at axial depth 5. PCSS's steps then have closed forms: the
// average blocker depth is 2 wherever on the face the receiver lies, and the kernel radius is
// half of w_p = (5 − 2)·w/2 on the receiver.
#include "shadowmaps/shadow_filter.h"

#include <vector>

#include <gtest/gtest.h>

#include <cmath>

namespace stsv {
namespace {

constexpr float BLOCKER_DEPTH = 2.0f;  ///< world units along the face's axis
constexpr float RECEIVER_DEPTH = 5.0f; ///< world units along the face's axis
constexpr float LIGHT_WIDTH = 0.5f;    ///< w_light, world units

/// A light at the origin, the map's frame the world's, `size` texels a face.
ShadowMapView view(uint projection, uint size) {
    ShadowMapView v{};
    v.projection = projection;
    v.origin = vec3(0.0f);
    v.axisX = vec3(1, 0, 0);
    v.axisY = vec3(0, 1, 0);
    v.axisZ = vec3(0, 0, 1);
    v.size = size;
    v.faces = projection == SHADOW_MAP_CUBE ? 6u : 1u;
    v.window = vec4(-1.0f, -1.0f, 1.0f, 1.0f);
    v.near = 1.0f;
    v.far = 10.0f;
    v.lightWidth = LIGHT_WIDTH;
    return v;
}

/// Every texel's depth: the half-plane z = BLOCKER_DEPTH, x < edge (or x > edge for side > 0;
/// world coordinates, the cube's face 4 looks along +z), in the map's measure (axial on a single
/// face, distance on a cube).
std::vector<float> blockerMap(const ShadowMapView& v, float edge, float side = -1.0f) {
    std::vector<float> depth(std::size_t(v.faces) * v.size * v.size, SHADOW_MAP_EMPTY);
    for (uint f = 0; f < v.faces; ++f)
        for (uint y = 0; y < v.size; ++y)
            for (uint x = 0; x < v.size; ++x) {
                vec3 o, d;
                shadowMapTexelRay(v, f, ivec2(int(x), int(y)), o, d);
                if (d.z <= 0.0f) continue;
                const float t = BLOCKER_DEPTH / d.z; // o + t·d on the plane
                if (side * (o.x + t * d.x - edge) <= 0.0f) continue;
                depth[(std::size_t(f) * v.size + y) * v.size + x] =
                    v.projection == SHADOW_MAP_CUBE ? t * length(d) : t;
            }
    return depth;
}

struct Pcss {
    float blocker;  ///< pcssAverageBlocker
    float radiusUv; ///< pcssFilterRadius
    float v;        ///< pcssFilter
};

/// PCSS for the receiver on the plane z = RECEIVER_DEPTH at (x, y), normal towards the light.
Pcss pcssAt(const ShadowMapView& v, const std::vector<float>& depth, const std::vector<vec2>& taps, float x,
            float y) {
    const ShadowMap map{v, depth};
    const ShadowMapSource src{&map, taps.data()};
    const ShadowReceiver r =
        shadowReceiver(v, vec3(x, y, RECEIVER_DEPTH), vec3(0, 0, -1), 1.0f, 0.0f, vec2(1.0f, 0.0f));
    Pcss out{};
    out.blocker = pcssAverageBlocker(v, src, r, 32u, 1024.0f);
    out.radiusUv = out.blocker < 0.0f ? -1.0f : pcssFilterRadius(v, r, out.blocker, 1024.0f);
    out.v = out.blocker < 0.0f ? 1.0f : pcssFilter(v, src, r, out.radiusUv, 32u, 64u);
    return out;
}

std::vector<vec2> taps() {
    std::vector<vec2> t = poissonDiskTaps(32, 1u);
    const std::vector<vec2> filter = poissonDiskTaps(64, 2u);
    t.insert(t.end(), filter.begin(), filter.end());
    return t;
}

TEST(PcssSteps, BlockerDepthAndKernelOnAPerspectiveFace) {
    // The receiver under the blocker's edge: the edge (x = 0.4 at depth 2) seen from the light
    // centre falls on the receiver plane at x = 1.0.
    const ShadowMapView v = view(SHADOW_MAP_PERSPECTIVE, 512);
    const std::vector<float> depth = blockerMap(v, 0.4f);
    const std::vector<vec2> t = taps();
    const Pcss p = pcssAt(v, depth, t, 1.0f, 0.3f);
    // Every blocker lies on z = 2: the average is 2 up to the float rays (1e-6 relative).
    EXPECT_NEAR(p.blocker, BLOCKER_DEPTH, 1e-4f);
    // w_p = (5 − 2)·0.5/2 = 0.75 m on the receiver; the face spans 2·5 = 10 m there.
    EXPECT_NEAR(p.radiusUv, 0.5f * 0.75f / 10.0f, 1e-5f);
    // The hard edge through the kernel's centre: half the disk lit, to the 64 taps' balance.
    EXPECT_NEAR(p.v, 0.5f, 0.1f);
    // Far inside the shadow (every tap blocks) and far outside the search (nothing found).
    EXPECT_EQ(pcssAt(v, depth, t, -2.0f, 0.0f).v, 0.0f);
    EXPECT_LT(pcssAt(v, depth, t, 3.0f, 0.0f).blocker, 0.0f);
}

TEST(PcssSteps, TheSearchRegionsNearPlaneIsAtLeastHalfTheLightsWidthFromIt) {
    // Half of w_search = w·(d_r − near)/d_r on the near plane, in uv of a face 2 units wide at
    // depth 1: 0.25·(5 − near)/(5·near·2).
    ShadowMapView v = view(SHADOW_MAP_PERSPECTIVE, 512);
    const ShadowReceiver r =
        shadowReceiver(v, vec3(0.0f, 0.0f, RECEIVER_DEPTH), vec3(0, 0, -1), 1.0f, 0.0f, vec2(1.0f, 0.0f));
    EXPECT_NEAR(pcssSearchRadius(v, r, 3.0e38f), 0.25f * 4.0f / 10.0f, 1e-6f); // near = 1
    // A map whose near plane touches the light (a surface flush with it): the region is the one
    // at ½·w = 0.25, 0.25·4.75/2.5 = 0.475, not 0.25·4.99/0.1 = 12.5 (a half-angle of 86°).
    v.near = 0.01f;
    EXPECT_NEAR(pcssSearchRadius(v, r, 3.0e38f), 0.475f, 1e-6f);
    v.near = 0.25f;
    EXPECT_NEAR(pcssSearchRadius(v, r, 3.0e38f), 0.475f, 1e-6f);
    // Beyond ½·w, the map's own near plane, as Fernando's.
    v.near = 0.5f;
    EXPECT_NEAR(pcssSearchRadius(v, r, 3.0e38f), 0.25f * 4.5f / 5.0f, 1e-6f);
}

TEST(PcssSteps, BlockerDepthAndKernelOffTheAxisOfACubeFace) {
    // The same planes seen through a cube map, the receiver 37° off face 4's axis: the average
    // blocker depth and the kernel are taken along the face's axis, as on a perspective face
    // (distances from the centre gave 2.42 and a kernel 15 % too narrow here).
    const ShadowMapView v = view(SHADOW_MAP_CUBE, 512);
    const float x = 3.75f, edge = x * BLOCKER_DEPTH / RECEIVER_DEPTH; // the edge's hard shadow at x
    const std::vector<float> depth = blockerMap(v, edge);
    const std::vector<vec2> t = taps();
    const Pcss p = pcssAt(v, depth, t, x, 0.0f);
    EXPECT_NEAR(p.blocker, BLOCKER_DEPTH, 1e-4f);
    EXPECT_NEAR(p.radiusUv, 0.5f * 0.75f / 10.0f, 1e-5f);
    EXPECT_NEAR(p.v, 0.5f, 0.1f);
    // Near the face's edge (x/z = 0.98) with the blockers beyond it (x > the edge's shadow): the
    // taps that cross onto face 0 read distances along face 0's rays, taken back to face 4's axis.
    const float near = 4.9f;
    const std::vector<float> depth2 = blockerMap(v, near * BLOCKER_DEPTH / RECEIVER_DEPTH, 1.0f);
    const Pcss q = pcssAt(v, depth2, t, near, 0.0f);
    EXPECT_NEAR(q.blocker, BLOCKER_DEPTH, 1e-4f);
    EXPECT_NEAR(q.v, 0.5f, 0.1f);
}

TEST(PcfSteps, LitOutsideShadowedInsideAndHalfOnTheEdge) {
    const ShadowMapView v = view(SHADOW_MAP_PERSPECTIVE, 512);
    const std::vector<float> depth = blockerMap(v, 0.4f);
    const std::vector<vec2> t = taps();
    const ShadowMap map{v, depth};
    const ShadowMapSource src{&map, t.data()};
    auto pcf = [&](float x) {
        const ShadowReceiver r =
            shadowReceiver(v, vec3(x, 0.3f, RECEIVER_DEPTH), vec3(0, 0, -1), 1.0f, 0.0f, vec2(1.0f, 0.0f));
        return pcfVisibility(v, src, r, 2.5f * r.texel, 16); // the 5 × 5 texels around the receiver's
    };
    EXPECT_EQ(pcf(-2.0f), 0.0f);
    EXPECT_EQ(pcf(3.0f), 1.0f);
    // On the hard edge: 2 or 3 of the kernel's 5 columns (texel-centre sampling) are shadowed.
    // The half-width of 2.5 texels goes to world units and back: its float round-off weighs the
    // outer ring by 1 ± 10⁻⁶.
    const float edge = pcf(1.0f);
    EXPECT_TRUE(std::abs(edge - 10.0f / 25.0f) < 1e-5f || std::abs(edge - 15.0f / 25.0f) < 1e-5f) << edge;
}

} // namespace
} // namespace stsv
