// The CPU DCS pass's conservative culling (render/cpu/cpu_wedges.cpp): dcsBoxSide, which drops an
// edge for a box of visible points when it can be a silhouette from none of them, and
// dcsSampleRegion, which bounds the samples an edge's crossing can count. Each must keep
// everything the per-point or per-sample test would accept, at the rounding limit too: points
// on a box's corners and faces, samples on the region's boundary found by bisection.
#include "wedge_test_util.h"
#include "wedges/dcs_dh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

namespace stsv {
namespace {

using test::Rng;

TEST(DcsCulling, BoxSideIsTheSideOfEveryPointOfTheBox) {
    Rng rng(3);
    std::size_t strict = 0, points = 0, touching = 0;
    for (int c = 0; c < 20000; ++c) {
        const vec3 v0 = rng.inBox(vec3(-2.0f), vec3(2.0f));
        const vec3 v1 = v0 + rng.inBox(vec3(-0.3f), vec3(0.3f));
        const vec3 o = v0 + rng.inBox(vec3(-0.3f), vec3(0.3f));
        vec3 lo = rng.inBox(vec3(-3.0f), vec3(3.0f));
        vec3 hi = lo + rng.inBox(vec3(0.0f), vec3(c % 3 == 0 ? 0.01f : 0.5f));
        if (c % 4 == 1) {
            // A box with a corner on the face's plane: the answer must not be strict.
            const vec3 n = cross(v1 - v0, o - v0);
            const vec3 corner = lo - n * (dot(n, lo - v0) / dot(n, n));
            hi = corner + (hi - lo);
            lo = corner;
            ++touching;
        }
        const int side = dcsBoxSide(v0, v1, o, lo, hi);
        if (side == 0) continue;
        ++strict;
        for (int k = 0; k < 40; ++k) {
            vec3 p = rng.inBox(lo, hi);
            if (k < 8) p = vec3((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
            ++points;
            ASSERT_EQ(dcsWorldSide(p, v0, v1, o), side)
                << "case " << c << " p " << test::str(p) << " box " << test::str(lo) << " " << test::str(hi);
        }
    }
    std::cout << strict << " strict boxes, " << points << " points checked, " << touching
              << " boxes touching the plane\n";
    EXPECT_GT(strict, 5000u);
}

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
