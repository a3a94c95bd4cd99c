// Depth-peeling soft shadows (`peel`, shadowmaps/depth_grid_dh.h) on the CPU: the paper's Table 1
// case by case and on hand-built grids, the march on hand-built grids (a thin object and a
// one-texel wall that fixed points step over, the surfaces a ray crosses), then the light-sample
// bits and counters against Embree on closed meshes (a sphere, the torus knot, the crate of
// tests/data), the cap's stats and warning. On the open fence, whose quads face away from the
// light, the lone back faces let the light through: too bright, as the paper's closed-object
// assumption predicts.
#include "scene/geometry.h"
#include "scene/load.h"
#include "shadowmaps/depth_grid.h"
#include "tests/render/shadow_map_test_util.h"
#include "tests/wedges/wedge_test_util.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace stsv {
namespace {

using namespace test;

TEST(DepthGrid, TableOneCaseByCase) {
    // z_i = 0: the first non-empty subinterval in front decides.
    EXPECT_TRUE(peelTableOccluded(5.0f, 0.0f, 3.0f));   // after a front face: inside
    EXPECT_FALSE(peelTableOccluded(5.0f, 0.0f, -3.0f)); // after a back face: outside
    EXPECT_FALSE(peelTableOccluded(5.0f, 0.0f, 0.0f));  // nothing in front
    // z_i > 0 (a front face at 6), z in front of it: as z_i = 0.
    EXPECT_TRUE(peelTableOccluded(5.0f, 6.0f, 3.0f));
    EXPECT_FALSE(peelTableOccluded(5.0f, 6.0f, -3.0f));
    EXPECT_FALSE(peelTableOccluded(5.0f, 6.0f, 0.0f));
    // z behind it: inside, whatever is in front.
    EXPECT_TRUE(peelTableOccluded(6.5f, 6.0f, 0.0f));
    EXPECT_TRUE(peelTableOccluded(6.5f, 6.0f, -3.0f));
    // z_i < 0 (a back face at 6): inside before it, outside after it.
    EXPECT_TRUE(peelTableOccluded(5.5f, -6.0f, 0.0f));
    EXPECT_TRUE(peelTableOccluded(5.5f, -6.0f, -3.0f));
    EXPECT_FALSE(peelTableOccluded(6.5f, -6.0f, 3.0f));
    EXPECT_FALSE(peelTableOccluded(6.5f, -6.0f, 0.0f));
}

/// A one-texel orthographic grid looking along +z from z = 0: every point with |x|, |y| < 1
/// falls on its texel, at depth z.
DepthGrid oneTexelGrid(uint bins, const std::vector<GridSurface>& surfaces) {
    ShadowMapView v{};
    v.origin = vec3(0.0f);
    v.projection = SHADOW_MAP_ORTHOGRAPHIC;
    v.axisX = vec3(1.0f, 0.0f, 0.0f);
    v.axisY = vec3(0.0f, 1.0f, 0.0f);
    v.axisZ = vec3(0.0f, 0.0f, 1.0f);
    v.size = 1;
    v.near = 0.1f;
    v.far = 100.0f;
    v.window = vec4(-1.0f, -1.0f, 1.0f, 1.0f);
    v.faces = 1;
    DepthGrid grid(v, bins);
    fillDepthGridTexel(grid.texel(0, ivec2(0)), bins, surfaces);
    return grid;
}

bool inside(const DepthGrid& grid, float z) {
    return peelPointOccluded(PeelGridSource{&grid}, grid.view, grid.bins, vec3(0.2f, -0.3f, z));
}

TEST(DepthGrid, PointsOnHandBuiltGridsFollowTheTable) {
    // Two closed objects on the ray: [2, 4] and [6, 7]; 8 subintervals of 0.625 over [2, 7] hold
    // the faces in 0 (+2), 3 (−4), 6 (+6) and 7 (−7).
    const DepthGrid two = oneTexelGrid(8, {{4.0f, false}, {2.0f, true}, {7.0f, false}, {6.0f, true}});
    const std::uint32_t* w = two.texel(0, ivec2(0));
    EXPECT_EQ(peelWordDepth(~w[0]), 2.0f);
    EXPECT_EQ(peelWordDepth(w[1]), 7.0f);
    EXPECT_EQ(peelBinValue(w[2], w[3]), 2.0f);
    EXPECT_EQ(peelBinValue(w[2 + 2 * 3], w[3 + 2 * 3]), -4.0f);
    EXPECT_EQ(peelBinValue(w[2 + 2 * 6], w[3 + 2 * 6]), 6.0f);
    EXPECT_EQ(peelBinValue(w[2 + 2 * 7], w[3 + 2 * 7]), -7.0f);
    EXPECT_EQ(peelBinValue(w[2 + 2 * 1], w[3 + 2 * 1]), 0.0f);
    EXPECT_FALSE(inside(two, 1.0f)); // in front of everything
    EXPECT_TRUE(inside(two, 3.0f));  // empty subinterval after the front face at 2
    EXPECT_TRUE(inside(two, 3.9f));  // its own subinterval holds the back face at 4, still ahead
    EXPECT_FALSE(inside(two, 4.5f)); // after the back face at 4
    EXPECT_FALSE(inside(two, 5.9f)); // before the front face at 6, in its subinterval
    EXPECT_TRUE(inside(two, 6.2f));  // after it
    EXPECT_TRUE(inside(two, 6.9f));  // before the back face at 7
    EXPECT_FALSE(inside(two, 8.0f)); // behind everything, the last surface a back face
    EXPECT_FALSE(inside(two, 50.0f));

    // Open geometry: behind a lone front face everything is inside, behind a lone back face nothing.
    const DepthGrid front = oneTexelGrid(16, {{3.0f, true}});
    EXPECT_FALSE(inside(front, 2.0f));
    EXPECT_TRUE(inside(front, 3.5f));
    EXPECT_TRUE(inside(front, 90.0f));
    const DepthGrid back = oneTexelGrid(16, {{3.0f, false}});
    EXPECT_FALSE(inside(back, 2.0f));
    EXPECT_FALSE(inside(back, 3.5f));

    // Front and back face in one subinterval: the farther one is kept (the paper's MAX).
    const DepthGrid both = oneTexelGrid(1, {{2.0f, true}, {2.5f, false}, {9.0f, true}});
    EXPECT_EQ(peelBinValue(both.texel(0, ivec2(0))[2], both.texel(0, ivec2(0))[3]), 9.0f);
    // An empty texel is lit.
    const DepthGrid empty = oneTexelGrid(16, {});
    EXPECT_FALSE(inside(empty, 5.0f));
}

/// The receiver a march starts from: the visible point p with normal n, no bias.
ShadowReceiver receiverAt(const DepthGrid& grid, vec3 p, vec3 n) {
    return shadowReceiver(grid.view, p, n, 0.0f, 0.0f, vec2(1.0f, 0.0f));
}

TEST(DepthGrid, AThinObjectAlongTheRayIsNotSteppedOver) {
    // An object 0.02 deep on the one texel's centre ray, and a ray along that ray from depth 9 to
    // depth 0.5: its projection stays in the texel, one step whose depth span [0.5, 9] runs
    // through Table 1 whole. Twenty points along it (the old fixed march, 0.425 apart) all fall
    // outside.
    const DepthGrid grid = oneTexelGrid(16, {{5.0f, true}, {5.02f, false}});
    const vec3 p(0.2f, -0.3f, 9.0f), s(0.2f, -0.3f, 0.5f);
    for (int k = 0; k < 20; ++k)
        EXPECT_FALSE(peelPointOccluded(PeelGridSource{&grid}, grid.view, grid.bins,
                                       p + ((float(k) + 0.5f) / 20.0f) * (s - p)));
    const PeelMarch m = peelRayMarch(PeelGridSource{&grid}, grid.view, grid.bins, 1024,
                                     receiverAt(grid, p, vec3(0, 0, -1)), s, 1u);
    EXPECT_EQ(m.occluded, 1u);
    EXPECT_EQ(m.crossings, 2u); // in through the front face, out through the back
    EXPECT_EQ(m.steps, 1u);
    EXPECT_EQ(m.capped, 0u);
}

TEST(DepthGrid, TheMarchStepsATexelAtATimeAcrossTheGrid) {
    // A 64² orthographic grid over [−1, 1]² (texels 1/32 wide) with a wall one texel wide (column
    // 40, every row) from depth 2 to 8, and a slanted ray from texel column 3 to column 60: 58
    // steps of at most a texel find the wall. Twenty points along it, 2.9 texels apart, land in
    // columns 39 and 41. Capped at 20 steps, the march steps the same 2.9 texels and misses it too.
    ShadowMapView v = oneTexelGrid(1, {}).view;
    v.size = 64;
    DepthGrid grid(v, 16);
    for (int y = 0; y < 64; ++y)
        fillDepthGridTexel(grid.texel(0, ivec2(40, y)), 16, {{2.0f, true}, {8.0f, false}});
    const vec3 p(-0.9f, 0.01f, 9.0f), s(0.9f, 0.01f, 1.0f);
    const PeelGridSource src{&grid};
    std::size_t inside = 0;
    for (int k = 0; k < 20; ++k)
        inside += peelPointOccluded(src, v, 16, p + ((float(k) + 0.5f) / 20.0f) * (s - p));
    EXPECT_EQ(inside, 0u);
    const ShadowReceiver r = receiverAt(grid, p, vec3(0, 0, -1));
    const PeelMarch m = peelRayMarch(src, v, 16, 1024, r, s, 1u);
    EXPECT_EQ(m.occluded, 1u);
    EXPECT_EQ(m.crossings, 2u);
    EXPECT_EQ(m.steps, 58u); // 1.8 across, 32 texels a unit: 57.6
    EXPECT_EQ(m.capped, 0u);
    const PeelMarch capped = peelRayMarch(src, v, 16, 20, r, s, 0u);
    EXPECT_EQ(capped.capped, 1u);
    EXPECT_EQ(capped.steps, 20u);
    EXPECT_EQ(capped.occluded, 0u);
}

TEST(DepthGrid, TheMarchCountsTheSurfacesItCrosses) {
    const vec3 n(0.0f, 0.0f, -1.0f);
    // Two closed objects, [2, 4] and [6, 7]: four surfaces from depth 9 to the light.
    const DepthGrid two = oneTexelGrid(8, {{4.0f, false}, {2.0f, true}, {7.0f, false}, {6.0f, true}});
    const vec3 p(0.2f, -0.3f, 9.0f), s(0.2f, -0.3f, 0.5f);
    PeelMarch m = peelRayMarch(PeelGridSource{&two}, two.view, two.bins, 1024, receiverAt(two, p, n), s, 1u);
    EXPECT_EQ(m.occluded, 1u);
    EXPECT_EQ(m.crossings, 4u);
    // From between them: the nearer one only.
    m = peelRayMarch(PeelGridSource{&two}, two.view, two.bins, 1024,
                     receiverAt(two, vec3(0.2f, -0.3f, 5.0f), n), s, 1u);
    EXPECT_EQ(m.crossings, 2u);
    // From inside the nearer one (a receiver on its far side): the way out.
    m = peelRayMarch(PeelGridSource{&two}, two.view, two.bins, 1024,
                     receiverAt(two, vec3(0.2f, -0.3f, 3.0f), n), s, 1u);
    EXPECT_EQ(m.occluded, 1u);
    EXPECT_EQ(m.crossings, 1u);
    // A lone front face (an open quad facing the light) above the receiver: one surface.
    const DepthGrid front = oneTexelGrid(16, {{3.0f, true}, {9.5f, true}});
    m = peelRayMarch(PeelGridSource{&front}, front.view, front.bins, 1024, receiverAt(front, p, n), s, 1u);
    EXPECT_EQ(m.occluded, 1u);
    EXPECT_EQ(m.crossings, 1u);
    // A lone back face lets the light through (the closed-object assumption).
    const DepthGrid back = oneTexelGrid(16, {{3.0f, false}, {9.5f, true}});
    m = peelRayMarch(PeelGridSource{&back}, back.view, back.bins, 1024, receiverAt(back, p, n), s, 1u);
    EXPECT_EQ(m.occluded, 0u);
    EXPECT_EQ(m.crossings, 0u);
    // Nearer the light than the grid's near plane (0.1), nothing is looked at.
    m = peelRayMarch(PeelGridSource{&two}, two.view, two.bins, 1024,
                     receiverAt(two, vec3(0.2f, -0.3f, 0.05f), n), vec3(0.2f, -0.3f, 0.01f), 1u);
    EXPECT_EQ(m.steps, 0u);
    EXPECT_EQ(m.occluded, 0u);
}

// NOLINTNEXTLINE(bugprone-exception-escape): json's move cannot throw (its invariant check is unmarked)
struct Agreement {
    double identical = 0.0; ///< fraction of (pixel, sample) bits equal to the reference's
    double missed = 0.0;    ///< fraction of the reference's occluded bits that peel leaves lit
    double visibilityBias = 0.0;
    nlohmann::json stats; ///< peel's frame stats
};

Agreement againstReference(const Scene& scene, const Frame& reference, const MethodParams& params) {
    const Frame f =
        renderCpu(scene, Method::Peel, reference.gbuffer.width, reference.gbuffer.height, params, 32);
    const LightSampleBuffer& a = f.lightSamples.at(0);
    const LightSampleBuffer& b = reference.lightSamples.at(0);
    std::size_t total = 0, same = 0, occluded = 0, missed = 0;
    for (int y = 0; y < reference.gbuffer.height; ++y)
        for (int x = 0; x < reference.gbuffer.width; ++x) {
            if (!reference.gbuffer.covered(reference.gbuffer.index(x, y))) continue;
            for (int k = 0; k < 32; ++k) {
                ++total;
                same += a.occluded(x, y, k) == b.occluded(x, y, k) ? 1 : 0;
                occluded += b.occluded(x, y, k) ? 1 : 0;
                missed += b.occluded(x, y, k) && !a.occluded(x, y, k) ? 1 : 0;
            }
        }
    Agreement result;
    result.identical = double(same) / double(total);
    result.missed = double(missed) / double(std::max<std::size_t>(occluded, 1));
    result.stats = f.stats;
    result.visibilityBias =
        compareVisibility(f.visibility, reference.visibility, [](int, int) { return true; }).meanSigned;
    return result;
}

TEST(Peel, AgreesWithEmbreeOnClosedMeshesAtATexelAStep) {
    // The march steps a grid texel at a time (peel_max_steps only caps it) and judges each
    // step's whole depth span, so on closed meshes what is left is the grid's resolution: a step
    // off its texel's centre ray is judged by the surfaces that ray meets, and a band about a
    // texel wide along the silhouettes seen from the light centre comes out wrong. The fixed
    // march of 20 points a ray this replaced stepped over the knot's 0.24 m tube (steps of about
    // 0.22 m): 95.7 % and 99.3 % identical bits here at 10 and 40 points, 99.7 % at 160, and at
    // 20 points 98.4 % on the knot at 320 × 240 × 64 (docs/methods.md). Capping the march at a
    // few steps (longer ones) and one subinterval (each texel keeps only its farthest surface,
    // the ground under the mesh) agree less.
    struct Case {
        const char* name;
        Scene scene;
    };
    const Case cases[] = {{"sphere", makeMeshScene(makeSphereMesh(48, 24), "sphere")},
                          {"knot", loadScene("knot")},
                          {"crate.obj", loadScene(std::string(STSV_TEST_DATA) + "/scene/crate.obj")}};
    for (const Case& c : cases) {
        const Frame reference = renderCpu(c.scene, Method::Reference, 128, 96, {}, 32);
        const Agreement defaults = againstReference(c.scene, reference, {});
        const Agreement capped = againstReference(c.scene, reference, {{"peel_max_steps", 3}});
        const Agreement bins1 = againstReference(c.scene, reference, {{"peel_bins", 1}});
        const nlohmann::json& march = defaults.stats["shadow_maps"][0]["march"];
        const nlohmann::json& cappedMarch = capped.stats["shadow_maps"][0]["march"];
        std::printf(
            "%s: identical bits at the defaults %.3f %% (missed %.3f %% of the occluded), capped at 3 "
            "steps %.3f %% (missed %.3f %%), 1 subinterval %.3f %%; march %s\n",
            c.name, 100.0 * defaults.identical, 100.0 * defaults.missed, 100.0 * capped.identical,
            100.0 * capped.missed, 100.0 * bins1.identical, march.dump().c_str());
        // Measured 99.73 %, 99.75 % and 99.90 %: above what 160 fixed points reached.
        EXPECT_GT(defaults.identical, 0.995) << c.name;
        EXPECT_LT(capped.identical, defaults.identical) << c.name;
        EXPECT_GT(capped.missed, defaults.missed) << c.name;
        EXPECT_GT(defaults.identical, bins1.identical + 0.01) << c.name;
        // The rays clipped to the grid's depths and window cross a few dozen texels at most here:
        // no ray reaches the cap; capped at 3 steps, many do, and none takes more.
        EXPECT_EQ(march["capped_rays"], 0) << c.name;
        EXPECT_GT(march["steps_mean"].get<double>(), 1.0) << c.name;
        EXPECT_LT(march["steps_max"].get<int>(), 128) << c.name;
        EXPECT_EQ(march["rays"].get<std::size_t>(), cappedMarch["rays"].get<std::size_t>()) << c.name;
        EXPECT_GT(cappedMarch["capped_rays"].get<std::size_t>(), 0u) << c.name;
        EXPECT_EQ(cappedMarch["steps_max"], 3) << c.name;
    }
    // The knot's tube: the old march at 20 points left 1.6 % of the frame's bits wrong, most of
    // them occluded bits it missed (visibility bias +0.016); now a few in a hundred of the
    // occluded bits are missed (measured 2.6 %), at its silhouettes.
    const Scene knot = loadScene("knot");
    const Agreement k = againstReference(knot, renderCpu(knot, Method::Reference, 128, 96, {}, 32), {});
    EXPECT_LT(k.missed, 0.04);
    EXPECT_LT(std::abs(k.visibilityBias), 0.005);
}

TEST(Peel, RaysPastTheCapAreCountedAndWarnedOf) {
    const Scene knot = loadScene("knot");
    const Frame f = renderCpu(knot, Method::Peel, 64, 48, {{"peel_max_steps", 2}}, 16);
    const nlohmann::json& march = f.stats["shadow_maps"][0]["march"];
    const std::size_t rays = march["rays"].get<std::size_t>(),
                      capped = march["capped_rays"].get<std::size_t>();
    EXPECT_GT(capped, 0u);
    EXPECT_LE(capped, rays);
    EXPECT_DOUBLE_EQ(march["capped_fraction"].get<double>(), double(capped) / double(rays));
    EXPECT_EQ(march["max_steps"], 2);
    bool warned = false;
    for (const std::string& w : frameWarnings(f.stats))
        warned =
            warned || (w.find("peel_max_steps=2") != std::string::npos &&
                       w.find(std::to_string(capped) + " of " + std::to_string(rays)) != std::string::npos);
    EXPECT_TRUE(warned) << f.stats["shadow_maps"].dump();
    // At the default cap nothing is said.
    const Frame d = renderCpu(knot, Method::Peel, 64, 48, {}, 16);
    for (const std::string& w : frameWarnings(d.stats))
        EXPECT_EQ(w.find("peel_max_steps"), std::string::npos) << w;
}

TEST(Peel, CountersCountTheSurfacesEachRayCrosses) {
    // The grid holds, per texel, the depths of the surfaces its centre ray meets (the nearest,
    // the farthest, and per subinterval the farthest front and back face); Table 1 makes of them
    // an inside/outside function of the depth. A ray's count is how often it changes along the
    // march: entering and leaving a closed object, two — the reference's count of the triangles
    // it crosses. From the first depth the march looks at, as the reference leaves out the
    // receiver's own triangle (a receiver on the far side of the knot's tube counts 1, its way
    // out). It is a count of the grid's surfaces, not the scene's: subintervals that merge
    // surfaces lose pairs, and a ray running along a surface across texels whose centre rays
    // meet it at different depths counts the steps between them.
    const Scene knot = loadScene("knot");
    auto frame = [&](Method m, BufferKind kind) {
        RenderOptions o;
        o.method = m;
        o.backend = Backend::Cpu;
        o.width = 128;
        o.height = 96;
        o.samples = 32;
        o.buffer = kind;
        return makeCpuRenderer(knot, o)->render();
    };
    const Frame peel = frame(Method::Peel, BufferKind::Counters);
    const Frame bits = frame(Method::Peel, BufferKind::Bitmask);
    const Frame reference = frame(Method::Reference, BufferKind::Counters);
    std::size_t samples = 0, equal = 0, sameOcclusion = 0, deep = 0, occluded = 0;
    double peelLayers = 0.0, referenceLayers = 0.0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 128; ++x) {
            if (!reference.gbuffer.covered(reference.gbuffer.index(x, y))) continue;
            for (int k = 0; k < 32; ++k) {
                const int a = peel.lightSamples[0].count(x, y, k),
                          b = reference.lightSamples[0].count(x, y, k);
                ++samples;
                equal += a == b ? 1 : 0;
                sameOcclusion += (a > 0) == bits.lightSamples[0].occluded(x, y, k) ? 1 : 0;
                deep += a >= 3 ? 1 : 0;
                if (b > 0) {
                    ++occluded;
                    peelLayers += a;
                    referenceLayers += b;
                }
            }
        }
    std::printf(
        "knot counters: %.3f %% of the samples count as the reference, %zu count 3 or more; mean over "
        "the reference's occluded samples %.3f against %.3f\n",
        100.0 * double(equal) / double(samples), deep, peelLayers / double(occluded),
        referenceLayers / double(occluded));
    // A count above 0 is an occluded bit, exactly.
    EXPECT_EQ(sameOcclusion, samples);
    // Layers, not one per occluded sample: the knot's tubes overlap seen from the light.
    EXPECT_GT(deep, samples / 1000);
    // Measured 99.2 % here, 99.4 % at 160 × 120 × 64 (the 0/1 count this replaced: 95.5 %).
    EXPECT_GT(double(equal) / double(samples), 0.985);
    // Texels whose centre rays meet a surface at different depths add a pair now and then: the
    // mean over the occluded samples lies within 15 % of the reference's.
    EXPECT_NEAR(peelLayers / double(occluded), referenceLayers / double(occluded),
                0.15 * referenceLayers / double(occluded));
}

TEST(Peel, TheOpenFenceLetsLightThroughItsLoneBackFaces) {
    // The fence is one quad whose winding faces away from the light: in the grid it is a back face
    // with no front face before it, which Table 1 reads as leaving an object: nothing behind it is
    // occluded, and the only occluded march points are the few between the quad and the end of
    // its own subinterval's back face (none: the quad is the texel's nearest depth).
    const Scene scene = loadScene("fence");
    const Frame reference = renderCpu(scene, Method::Reference, 128, 96, {}, 32);
    const Agreement peel = againstReference(scene, reference, {});
    std::printf("fence: peel identical bits %.4f %%, visibility bias against the reference %+.4f\n",
                100.0 * peel.identical, peel.visibilityBias);
    EXPECT_GT(peel.visibilityBias, 0.01);
}

} // namespace
} // namespace stsv
