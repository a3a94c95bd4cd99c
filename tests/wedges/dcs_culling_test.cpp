// The CPU DCS pass's per-sample culling (wedges/cpu/cpu_wedges.cpp): dcsSampleRegion, which
// bounds the samples an edge's crossing can count, must keep every sample the per-sample test
// would accept, at the rounding limit too: samples on the region's boundary found by bisection.
// (Its culling of edges and clusters is tested in edge_clusters_test.cpp.)
#include "wedge_test_util.h"
#include "wedges/dcs_dh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

namespace stsv {
namespace {

using test::Rng;

/// Random projected edges in a pixel's frame: h0, h1 homogeneous with w in (0, 1.5), clipped as
/// wedgeEdgeTerm clips them.
TEST(DcsCulling, SampleRegionHoldsEverySampleThatCrosses) {
    Rng rng(5);
    std::size_t crossing = 0, boundary = 0, cases = 0;
    double area = 0.0;
    for (int c = 0; c < 50000; ++c) {
        vec3 h0 = rng.inBox(vec3(-2.0f, -2.0f, 0.01f), vec3(2.0f, 2.0f, 1.5f));
        vec3 h1 = c % 5 == 0 ? h0 + rng.inBox(vec3(-0.05f), vec3(0.05f))
                             : rng.inBox(vec3(-2.0f, -2.0f, 0.01f), vec3(2.0f, 2.0f, 1.5f));
        const vec3 l = cross(h0, h1);
        if (!dcsClipEdge(1e-4f, h0, h1)) continue;
        vec2 lo, hi;
        const bool any = dcsSampleRegion(l, h0, h1, vec2(-1.0f), vec2(1.0f), lo, hi);
        ++cases;
        area += any ? double(hi.x - lo.x) * double(hi.y - lo.y) / 4.0 : 0.0;
        auto inside = [&](vec2 x) { return any && x.x >= lo.x && x.x <= hi.x && x.y >= lo.y && x.y <= hi.y; };
        for (int k = 0; k < 64; ++k) {
            const vec2 x = vec2(rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f));
            if (dcsSampleCrossing(l, h0, h1, x) == 0) continue;
            ++crossing;
            ASSERT_TRUE(inside(x)) << "case " << c << " x " << test::str(x) << " l " << test::str(l) << " a "
                                   << test::str(h0) << " b " << test::str(h1) << " box " << test::str(lo)
                                   << " " << test::str(hi);
            // The boundary towards a random point outside the crossing set.
            vec2 y = vec2(rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f));
            if (dcsSampleCrossing(l, h0, h1, y) != 0) continue;
            vec2 in = x, out = y;
            for (int step = 0; step < 40; ++step) {
                const vec2 mid = 0.5f * (in + out);
                (dcsSampleCrossing(l, h0, h1, mid) != 0 ? in : out) = mid;
            }
            ++boundary;
            ASSERT_TRUE(inside(in)) << "boundary point of case " << c;
        }
    }
    std::cout << cases << " edges, " << crossing << " crossing samples, " << boundary
              << " boundary points, mean region " << area / double(cases) << " of the square\n";
    EXPECT_GT(crossing, 100000u);
    EXPECT_LT(area / double(cases), 0.6);
}

} // namespace
} // namespace stsv
