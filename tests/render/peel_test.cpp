// Depth-peeling soft shadows (`peel`, shadowmaps/depth_grid_dh.h) on the CPU: the paper's Table 1
// case by case and on hand-built grids, then the light-sample bits against Embree on closed meshes
// (a sphere, the torus knot, the crate of tests/data): agreement grows with the march steps and
// with the subintervals. On the open fence, whose quads face away from the light, the lone back
// faces let the light through: too bright, as the paper's closed-object assumption predicts.
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

struct Agreement {
    double identical = 0.0; ///< fraction of (pixel, sample) bits equal to the reference's
    double visibilityBias = 0.0;
};

Agreement againstReference(const Scene& scene, const Frame& reference, const MethodParams& params) {
    const Frame f =
        renderCpu(scene, Method::Peel, reference.gbuffer.width, reference.gbuffer.height, params, 32);
    const LightSampleBuffer& a = f.lightSamples.at(0);
    const LightSampleBuffer& b = reference.lightSamples.at(0);
    std::size_t total = 0, same = 0;
    for (int y = 0; y < reference.gbuffer.height; ++y)
        for (int x = 0; x < reference.gbuffer.width; ++x) {
            if (!reference.gbuffer.covered(reference.gbuffer.index(x, y))) continue;
            for (int k = 0; k < 32; ++k) {
                ++total;
                same += a.occluded(x, y, k) == b.occluded(x, y, k) ? 1 : 0;
            }
        }
    Agreement result;
    result.identical = double(same) / double(total);
    result.visibilityBias =
        compareVisibility(f.visibility, reference.visibility, [](int, int) { return true; }).meanSigned;
    return result;
}

TEST(Peel, AgreesWithEmbreeOnClosedMeshesMoreWithMoreStepsAndSubintervals) {
    struct Case {
        const char* name;
        Scene scene;
    };
    const Case cases[] = {{"sphere", makeMeshScene(makeSphereMesh(48, 24), "sphere")},
                          {"knot", loadScene("knot")},
                          {"crate.obj", loadScene(std::string(STSV_TEST_DATA) + "/scene/crate.obj")}};
    for (const Case& c : cases) {
        const Frame reference = renderCpu(c.scene, Method::Reference, 128, 96, {}, 32);
        auto identical = [&](double steps, double bins) {
            return againstReference(c.scene, reference, {{"peel_steps", steps}, {"peel_bins", bins}})
                .identical;
        };
        const double steps10 = identical(10, 16), steps40 = identical(40, 16), steps160 = identical(160, 16);
        const double bins1 = identical(40, 1);
        std::printf("%s: identical bits with 16 subintervals: 10 steps %.3f %%, 40 steps %.3f %%, 160 steps "
                    "%.3f %%; 40 steps with 1 subinterval %.3f %%\n",
                    c.name, 100.0 * steps10, 100.0 * steps40, 100.0 * steps160, 100.0 * bins1);
        EXPECT_GT(steps40, steps10) << c.name;
        EXPECT_GT(steps160, steps40) << c.name;
        // One subinterval keeps only each texel's farthest surface (the ground under the mesh): the
        // mesh casts no shadow on it.
        EXPECT_GT(steps40, bins1 + 0.01) << c.name;
        // What is left at 160 steps (under 0.6 % here) is the grid's resolution: a march point off
        // its texel's centre ray is judged by the surfaces that ray meets, so a band about a texel
        // wide along the mesh's silhouettes seen from the light centre (its edges, and the
        // receivers right behind them) comes out inside or outside wrongly.
        EXPECT_GT(steps160, 0.99) << c.name;
    }
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
