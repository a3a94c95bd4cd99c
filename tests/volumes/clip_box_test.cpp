// A box clipped by half-spaces (volumes/clip_box_dh.h): the polyhedron is the intersection, closed
// without cracks and wound outwards; and the STSV volume's hull (volumeHull) encloses every
// point the fragment's plane tests accept.
#include "tests/support/extrusion.h"
#include "volume_test_util.h"
#include "volumes/clip_box_dh.h"
#include "volumes/extrusion_dh.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <tuple>
#include <vector>

namespace stsv {
namespace {

using test::Rng;
using test::str;

/// The planes of the polyhedron's faces (outward unit normal n, offset: n·x + d ≤ 0 inside), in
/// double, from each face's first three non-collinear corners; faces too thin for a plane skipped.
std::vector<dvec4> facePlanes(const ClippedBox& b) {
    std::vector<dvec4> planes;
    for (uint f = 0; f < b.faceCount; ++f) {
        const uint o = f * CLIP_MAX_FACE_VERTICES;
        dvec3 n(0.0);
        const dvec3 a(b.corner[o]);
        for (uint i = 1; i + 1 < b.count[f]; ++i)
            n += cross(dvec3(b.corner[o + i]) - a, dvec3(b.corner[o + i + 1]) - a);
        if (length(n) < 1e-12) continue;
        n = normalize(n);
        planes.push_back(dvec4(n, -dot(n, a)));
    }
    return planes;
}

bool insideFaces(const std::vector<dvec4>& planes, vec3 p, double tol) {
    for (const dvec4& f : planes)
        if (dot(dvec3(f), dvec3(p)) + f.w > tol) return false;
    return true;
}

/// Every directed edge between distinct corners has its reverse in another face: the surface is
/// closed, and shared edges have bitwise equal ends (rasterised without cracks).
void expectClosed(const ClippedBox& b, const std::string& what) {
    using Key = std::tuple<float, float, float, float, float, float>;
    std::map<Key, int> edges;
    for (uint f = 0; f < b.faceCount; ++f) {
        const uint o = f * CLIP_MAX_FACE_VERTICES;
        for (uint i = 0; i < b.count[f]; ++i) {
            const vec3 a = b.corner[o + i], c = b.corner[o + (i + 1) % b.count[f]];
            if (a == c) continue;
            ++edges[{a.x, a.y, a.z, c.x, c.y, c.z}];
        }
    }
    for (const auto& [e, count] : edges) {
        const auto [ax, ay, az, cx, cy, cz] = e;
        EXPECT_EQ(count, 1) << what;
        const auto reverse = edges.find({cx, cy, cz, ax, ay, az});
        EXPECT_TRUE(reverse != edges.end() && reverse->second == 1)
            << "edge " << str(vec3(ax, ay, az)) << " → " << str(vec3(cx, cy, cz)) << " has no twin; " << what;
    }
}

TEST(ClipBox, RandomHalfSpacesGiveTheirIntersectionClosedAndOutward) {
    Rng rng(2024);
    long pointsChecked = 0, inside = 0, polyhedra = 0, empty = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const vec3 lo = rng.inCube(2.0f), hi = lo + vec3(rng.uniformf(0.1f, 3.0f), rng.uniformf(0.1f, 3.0f),
                                                         rng.uniformf(0.1f, 3.0f));
        const uint count = uint(rng.index(int(CLIP_MAX_PLANES)) + 1);
        vec4 planes[CLIP_MAX_PLANES];
        for (uint j = 0; j < CLIP_MAX_PLANES; ++j) {
            const vec3 n = rng.onSphere();
            // Through a point of the box or near it, so most planes cut.
            const vec3 through = rng.inBox(lo - 0.2f * (hi - lo), hi + 0.2f * (hi - lo));
            planes[j] = vec4(n, -dot(n, through));
        }
        const ClippedBox b = clipBox(lo, hi, planes, count, 0.0f);
        const auto inPlanes = [&](vec3 p) {
            if (any(lessThan(p, lo)) || any(greaterThan(p, hi))) return false;
            for (uint j = 0; j < count; ++j)
                if (dot(vec3(planes[j]), p) + planes[j].w < 0.0f) return false;
            return true;
        };
        const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " planes";
        ASSERT_LE(b.faceCount, CLIP_MAX_FACES);
        if (b.faceCount == 0) {
            ++empty;
            for (int i = 0; i < 200; ++i) EXPECT_FALSE(inPlanes(rng.inBox(lo, hi))) << what;
            continue;
        }
        ++polyhedra;
        ASSERT_GE(b.faceCount, 4u) << what;
        for (uint f = 0; f < b.faceCount; ++f) ASSERT_LE(b.count[f], CLIP_MAX_FACE_VERTICES);
        expectClosed(b, what);
        EXPECT_LE(clipBoxTriangleCount(b), CLIP_MAX_TRIANGLES) << what;
        // Outward: every corner on the inner side of every face's plane.
        const std::vector<dvec4> faces = facePlanes(b);
        const double size = length(hi - lo);
        for (uint f = 0; f < b.faceCount; ++f)
            for (uint i = 0; i < b.count[f]; ++i)
                EXPECT_TRUE(insideFaces(faces, b.corner[f * CLIP_MAX_FACE_VERTICES + i], 1e-5 * size))
                    << what;
        // The intersection: points of the box in the planes are inside the faces, and points
        // clearly outside the planes (1e-4 box diagonals) are outside them.
        for (int i = 0; i < 300; ++i) {
            const vec3 p = rng.inBox(lo, hi);
            ++pointsChecked;
            if (inPlanes(p)) {
                ++inside;
                EXPECT_TRUE(insideFaces(faces, p, 1e-5 * size)) << "p=" << str(p) << " " << what;
                continue;
            }
            bool clearlyOut = false;
            for (uint j = 0; j < count; ++j)
                clearlyOut = clearlyOut || dot(vec3(planes[j]), p) + planes[j].w < -1e-4f * size;
            if (clearlyOut) {
                EXPECT_FALSE(insideFaces(faces, p, -1e-5 * size)) << "p=" << str(p) << " " << what;
            }
        }
    }
    std::printf("[clip box] %ld polyhedra, %ld empty, %ld points (%ld inside)\n", polyhedra, empty,
                pointsChecked, inside);
    EXPECT_GT(polyhedra, 1000);
    EXPECT_GT(empty, 50);
    EXPECT_GT(inside, 50'000);
}

TEST(ClipBox, ShallowCutsAreLeftOutAndOnlyThey) {
    // Planes that shave at most minCut off the box are skipped: the polyhedron holds the
    // intersection, is no more than minCut outside any plane, and has no face of a skipped plane.
    Rng rng(77);
    long skipped = 0, applied = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const vec3 lo(0.0f), hi(1.0f);
        const float minCut = 0.01f;
        vec4 planes[CLIP_MAX_PLANES];
        const uint count = uint(rng.index(int(CLIP_MAX_PLANES)) + 1);
        for (uint j = 0; j < count; ++j) {
            const vec3 n = rng.onSphere();
            // The box's farthest corner outside this plane lies 0 … 3·minCut beyond it.
            float reach = -1e30f;
            for (uint k = 0; k < 8; ++k) reach = std::max(reach, -dot(n, clipBoxCorner(lo, hi, k)));
            planes[j] = vec4(n, reach - rng.uniformf(0.0f, 3.0f) * minCut);
        }
        const ClippedBox b = clipBox(lo, hi, planes, count, minCut);
        ASSERT_GE(b.faceCount, 4u);
        expectClosed(b, "trial " + std::to_string(trial));
        const std::vector<dvec4> faces = facePlanes(b);
        for (uint j = 0; j < count; ++j) {
            float deepest = 0.0f;
            for (uint k = 0; k < 8; ++k)
                deepest = std::max(deepest, -(dot(vec3(planes[j]), clipBoxCorner(lo, hi, k)) + planes[j].w));
            (deepest > minCut ? applied : skipped) += 1;
        }
        for (int i = 0; i < 200; ++i) {
            const vec3 p = rng.inBox(lo, hi);
            bool in = true, farOut = false;
            for (uint j = 0; j < count; ++j) {
                const float v = dot(vec3(planes[j]), p) + planes[j].w;
                in = in && v >= 0.0f;
                farOut = farOut || v < -1.0001f * minCut;
            }
            if (in) {
                EXPECT_TRUE(insideFaces(faces, p, 1e-5)) << "p=" << str(p);
            }
            // Outside a plane by more than minCut: that plane cut deeper, so it was applied.
            if (farOut) {
                EXPECT_FALSE(insideFaces(faces, p, -1e-5)) << "p=" << str(p);
            }
        }
    }
    EXPECT_GT(skipped, 1000);
    EXPECT_GT(applied, 1000);
}

TEST(ClipBox, PlanesThroughCornersAndEdgesStayClosed) {
    // Ties: planes through box corners, along box edges and through each other's lines.
    const vec3 lo(0.0f), hi(1.0f);
    vec4 planes[CLIP_MAX_PLANES];
    planes[0] = vec4(normalize(vec3(1.0f, 1.0f, 1.0f)),
                     -dot(normalize(vec3(1.0f, 1.0f, 1.0f)), vec3(1.0f, 0.0f, 0.0f)));
    planes[1] = vec4(normalize(vec3(-1.0f, 1.0f, 0.0f)), 0.0f); // through the edge x = y, z
    planes[2] = vec4(0.0f, 0.0f, 1.0f, 0.0f);                   // the face z = 0 itself
    planes[3] = vec4(normalize(vec3(1.0f, -1.0f, 1.0f)), 0.0f); // through the corner 0
    const ClippedBox b = clipBox(lo, hi, planes, 4u, 0.0f);
    ASSERT_GE(b.faceCount, 4u);
    expectClosed(b, "tied planes");
}

// ---------------------------------------------------------------------------------------------
// The STSV volume's hull.

TEST(VolumeHull, EnclosesWhatTheFragmentAcceptsAndLittleMore) {
    // Triangles under square lights of every size and distance, boxes around them: every point of
    // the box that passes the volume's planes and the light planes (what stsv.frag accepts) lies
    // inside the hull; and the hull covers less of the box than the strip of the volume.
    Rng rng(91);
    long accepted = 0, hullHits = 0, stripHits = 0, samples = 0, volumes = 0, triangles = 0;
    for (int config = 0; config < 1500; ++config) {
        const vec3 v0 = rng.inCube(1.0f), v1 = rng.inCube(1.0f), v2 = rng.inCube(1.0f);
        Bounds bounds;
        bounds.extend(vec3(-4.0f));
        bounds.extend(vec3(4.0f));
        const vec3 centre = (v0 + v1 + v2) / 3.0f + rng.onSphere() * rng.uniformf(1.5f, 8.0f);
        vec3 t, b;
        const vec3 axis = rng.onSphere();
        t = normalize(cross(axis, vec3(0.3f, 1.0f, 0.2f)));
        b = cross(axis, t);
        const float size = rng.logUniform(0.01f, 2.0f);
        t *= size;
        b *= size * rng.uniformf(0.2f, 1.0f);
        const vec4 sphere(centre, length(t + b));
        const StsvLightPlanes lp = stsvLightPlanes(v0, v1, v2, centre, t, b, bounds.lo, bounds.hi);
        for (const StsvVolume& v : buildTriangleVolumes(v0, v1, v2, sphere, bounds)) {
            if (v.flags & STSV_VOLUME_EMPTY) continue;
            const ClippedBox hull = volumeHull(v, lp, v0, v1, v2, bounds);
            ++volumes;
            triangles += hull.faceCount ? clipBoxTriangleCount(hull) : 0;
            expectClosed(hull, "config " + std::to_string(config));
            const std::vector<dvec4> faces = facePlanes(hull);
            // The strip as the rasteriser sees it: its eight triangles' planes.
            std::vector<dvec4> strip;
            dvec3 centroid(0.0);
            for (int i = 0; i < 10; ++i) centroid += dvec3(vec3(v.vertices[i])) / 10.0;
            for (int i = 0; i < 8; ++i) {
                const dvec3 a(vec3(v.vertices[i])), c(vec3(v.vertices[i + 1])), d(vec3(v.vertices[i + 2]));
                dvec3 n = cross(c - a, d - a);
                if (length(n) < 1e-12) continue;
                n = normalize(n);
                if (dot(n, centroid - a) > 0.0) n = -n;
                strip.push_back(dvec4(n, -dot(n, a)));
            }
            for (int i = 0; i < 400; ++i) {
                const vec3 p = rng.inBox(bounds.lo, bounds.hi);
                ++samples;
                const bool inHull = faces.empty() ? false : insideFaces(faces, p, 1e-6);
                hullHits += inHull;
                stripHits += insideFaces(strip, p, 1e-6);
                if (!stsvPointInVolume(v, p) || !stsvPointInLightPlanes(lp, p)) continue;
                ++accepted;
                EXPECT_TRUE(inHull) << "p=" << str(p) << " accepted but outside the hull; v0=" << str(v0)
                                    << " v1=" << str(v1) << " v2=" << str(v2) << " light c=" << str(centre)
                                    << " T=" << str(t) << " B=" << str(b);
            }
        }
    }
    std::printf("[volume hull] %ld volumes, %.1f triangles each; of %ld points in the box: accepted %ld, in "
                "the hull %ld, in the strip %ld\n",
                volumes, double(triangles) / double(volumes), samples, accepted, hullHits, stripHits);
    EXPECT_GT(accepted, 10'000);
    EXPECT_LT(hullHits, stripHits / 2);
}

} // namespace
} // namespace stsv
