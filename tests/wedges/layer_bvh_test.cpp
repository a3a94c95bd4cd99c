// The tree D(r) is counted through (wedges/layer_bvh.h): its tables hold every opaque triangle
// once inside its boxes, and its count along a segment (D(r) on both backends) is Embree's and
// the double-precision count of the crossings.
#include "reference/embree_scene.h"
#include "scene/occlusion_rules_dh.h"
#include "wedge_test_util.h"
#include "wedges/layer_bvh.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace stsv {
namespace {

vec3 corner(const LayerBvhTables& t, std::uint32_t i, int k) {
    return uintBitsToFloat(uvec3(t.triangles[LAYER_BVH_TRIANGLE_TEXELS * i + std::uint32_t(k)]));
}

/// Walks the tables from the root: each leaf's triangles inside the box its parent gives it,
/// each node's boxes inside its own; returns the scene triangles of the leaves, in order.
void collect(const LayerBvhTables& t, std::uint32_t child, vec3 lo, vec3 hi,
             std::vector<std::uint32_t>& out) {
    if (child == LAYER_BVH_EMPTY) return;
    if ((child & LAYER_BVH_LEAF) != 0) {
        const std::uint32_t first = (child & ~LAYER_BVH_LEAF) >> 3, count = (child & 7u) + 1;
        ASSERT_LE(count, LAYER_BVH_LEAF_MAX);
        for (std::uint32_t i = first; i < first + count; ++i) {
            for (int k = 0; k < 3; ++k) {
                const vec3 v = corner(t, i, k);
                ASSERT_TRUE(all(greaterThanEqual(v, lo)) && all(lessThanEqual(v, hi)))
                    << "leaf triangle " << i << " outside its box";
            }
            out.push_back(t.triangles[LAYER_BVH_TRIANGLE_TEXELS * i].w);
        }
        return;
    }
    ASSERT_LT(child, t.nodeCount());
    const uvec4* n = &t.nodes[LAYER_BVH_NODE_TEXELS * child];
    const vec4 a = uintBitsToFloat(n[0]), b = uintBitsToFloat(n[1]), c = uintBitsToFloat(n[2]);
    const vec3 lo0(a), hi0(a.w, b.x, b.y), lo1(b.z, b.w, c.x), hi1(c.y, c.z, c.w);
    // An empty child (beside a root's only leaf) has an empty box: lo > hi.
    for (int k = 0; k < 2; ++k) {
        const vec3 l = k == 0 ? lo0 : lo1, h = k == 0 ? hi0 : hi1;
        if (n[3][k] == LAYER_BVH_EMPTY) {
            EXPECT_GT(l.x, h.x) << "node " << child;
            continue;
        }
        for (const vec3& v : {l, h})
            ASSERT_TRUE(all(greaterThanEqual(v, lo)) && all(lessThanEqual(v, hi))) << "node " << child;
    }
    collect(t, n[3].x, lo0, hi0, out);
    collect(t, n[3].y, lo1, hi1, out);
}

std::vector<std::uint32_t> leafTriangles(const LayerBvhTables& t) {
    std::vector<std::uint32_t> out;
    if (t.nodeCount() > 0) collect(t, 0, vec3(-3e38f), vec3(3e38f), out);
    return out;
}

TEST(LayerBvh, HoldsEveryOpaqueTriangleOnceInsideItsBoxes) {
    // Soups of 1 to 1000 triangles (one leaf under the root, one level, many) and a knot.
    for (int n : {1, 4, 5, 17, 1000, 0}) {
        Scene scene = n > 0 ? Scene{} : test::sceneOf(test::makeTorusKnotMesh(300, 8, 0.15f));
        if (n > 0) scene.materials.push_back(Material{});
        test::Rng rng(std::uint64_t(n) + 1);
        for (int i = 0; i < n; ++i) {
            const vec3 a = rng.inBox(vec3(-5), vec3(5));
            test::addTri(scene, a, a + rng.inBox(vec3(-1), vec3(1)), a + rng.inBox(vec3(-1), vec3(1)));
        }
        // A perforated triangle: not an occluder of the layer count.
        Material fence;
        fence.name = "fence";
        fence.alphaTexture = 0;
        scene.materials.push_back(fence);
        test::addTri(scene, vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0),
                     std::uint32_t(scene.materials.size() - 1));
        const LayerBvhTables t = buildLayerBvh(scene);
        std::vector<std::uint32_t> leaves = leafTriangles(t);
        std::sort(leaves.begin(), leaves.end());
        std::vector<std::uint32_t> opaque;
        for (std::uint32_t i = 0; i < scene.triangleCount(); ++i)
            if (scene.opaqueOccluder(i)) opaque.push_back(i);
        EXPECT_EQ(leaves, opaque) << n << " triangles";
        EXPECT_LE(t.depth, LAYER_BVH_STACK);
        // A median split: ⌈log2(n / leaf)⌉ + 1 levels at most.
        EXPECT_LE(double(t.depth),
                  std::ceil(std::log2(std::max(1.0, double(opaque.size()) / LAYER_BVH_LEAF_MAX))) + 1.0);
    }
    Scene empty;
    empty.materials.push_back(Material{});
    EXPECT_EQ(buildLayerBvh(empty).nodeCount(), 0u);
    LayerCountWork work{};
    EXPECT_EQ(layerCount(buildLayerBvh(empty), vec3(0), vec3(1), 1e-4f, NO_TRIANGLE, work), 0u);
}

TEST(LayerBvh, CountsAStackOfQuadsBetweenThePointAndTheLight) {
    // Ten unit quads at heights 1 … 10: a segment from height 0 to h + 0.5 crosses h of them,
    // at every spot under the quads and none outside them.
    Scene scene;
    scene.materials.push_back(Material{});
    for (int k = 1; k <= 10; ++k) {
        const float y = float(k);
        test::addTri(scene, vec3(-1, y, -1), vec3(-1, y, 1), vec3(1, y, 1));
        test::addTri(scene, vec3(-1, y, -1), vec3(1, y, 1), vec3(1, y, -1));
    }
    const LayerBvhTables t = buildLayerBvh(scene);
    test::Rng rng(3);
    for (int i = 0; i < 2000; ++i) {
        const vec3 p(rng.uniform(-0.99f, 0.99f), 0.0f, rng.uniform(-0.99f, 0.99f));
        const int h = rng.index(11);
        const vec3 r = p + vec3(rng.uniform(-0.001f, 0.001f), float(h) + 0.5f, 0.0f);
        LayerCountWork work{};
        ASSERT_EQ(layerCount(t, p, r, SHADOW_T_MIN, NO_TRIANGLE, work), std::uint32_t(h))
            << test::str(p) << " height " << h;
        EXPECT_EQ(work.cutShort, 0u);
        const vec3 outside = p + vec3(2.5f, 0.0f, 0.0f);
        ASSERT_EQ(layerCount(t, outside, outside + vec3(0, 11, 0), SHADOW_T_MIN, NO_TRIANGLE, work), 0u);
    }
}

TEST(LayerBvh, CountsASegmentThroughASharedEdgeOrVertexOnce) {
    // Three layers, each a 2 × 2 grid of quads split along alternating diagonals about a centre
    // vertex shared by six triangles: segments exactly through the shared edges and diagonals,
    // straight up and slanted, and straight up through the centre (its products exactly 0), cross
    // each layer once. (Slanted through the vertex, the products round to either side of 0 and
    // the fan may take the segment more or less than once: layer_bvh_dh.h.)
    Scene scene;
    scene.materials.push_back(Material{});
    for (int k = 1; k <= 3; ++k) {
        const float y = float(k);
        for (int qx = 0; qx < 2; ++qx)
            for (int qz = 0; qz < 2; ++qz) {
                const float x0 = float(qx) - 1.0f, z0 = float(qz) - 1.0f;
                const vec3 a(x0, y, z0), b(x0 + 1, y, z0), c(x0 + 1, y, z0 + 1), d(x0, y, z0 + 1);
                if ((qx + qz) % 2 == 0) {
                    test::addTri(scene, a, d, c);
                    test::addTri(scene, a, c, b);
                } else {
                    test::addTri(scene, a, d, b);
                    test::addTri(scene, b, d, c);
                }
            }
    }
    const LayerBvhTables t = buildLayerBvh(scene);
    // Points of the interior: the centre, the shared edges, the diagonals.
    const vec3 points[] = {vec3(0, 0, 0),         vec3(0.5f, 0, 0),     vec3(0, 0, -0.5f),
                           vec3(0.25f, 0, 0.25f), vec3(-0.5f, 0, 0.5f), vec3(0.5f, 0, 0.5f)};
    for (const vec3 p : points) {
        LayerCountWork work{};
        EXPECT_EQ(layerCount(t, p, p + vec3(0, 5, 0), SHADOW_T_MIN, NO_TRIANGLE, work), 3u)
            << test::str(p) << " up";
        if (p == vec3(0.0f)) continue;
        // Slanted, through the same point of the middle layer (and interior points of the others).
        const vec3 at = p + vec3(0, 2, 0), step(0.1f, 2.0f, 0.05f);
        EXPECT_EQ(layerCount(t, at - step, at + step, SHADOW_T_MIN, NO_TRIANGLE, work), 3u)
            << test::str(p) << " slanted";
    }
    // The outer corners: on the grid's border a segment through a corner vertex belongs to the
    // one triangle there, or (moved off it) to none, never to two.
    for (const vec3 p : {vec3(1, 0, 1), vec3(-1, 0, -1)}) {
        LayerCountWork work{};
        EXPECT_LE(layerCount(t, p, p + vec3(0, 5, 0), SHADOW_T_MIN, NO_TRIANGLE, work), 3u) << test::str(p);
    }
}

TEST(LayerBvh, ASegmentPastTheVisitLimitIsCutShortAndSaysSo) {
    // 240 000 small horizontal triangles stacked along the y axis, every box on the segment's
    // way: a count would visit every node of the tree, past LAYER_BVH_MAX_VISITS.
    Scene scene;
    scene.materials.push_back(Material{});
    const int n = 240000;
    for (int k = 0; k < n; ++k) {
        const float y = 1.0f + float(k) * 1e-5f;
        test::addTri(scene, vec3(-0.1f, y, -0.1f), vec3(0.1f, y, -0.1f), vec3(0.0f, y, 0.1f));
    }
    const LayerBvhTables t = buildLayerBvh(scene);
    ASSERT_GT(t.nodeCount(), LAYER_BVH_MAX_VISITS);
    LayerCountWork work{};
    const std::uint32_t count =
        layerCount(t, vec3(0.0f), vec3(0.0f, 5.0f, 0.0f), SHADOW_T_MIN, NO_TRIANGLE, work);
    EXPECT_EQ(work.cutShort, 1u);
    EXPECT_EQ(work.visits, LAYER_BVH_MAX_VISITS);
    EXPECT_LT(count, std::uint32_t(n));
    // Without the limit (the CPU mirror's count) it crosses every triangle.
    LayerCountWork whole{};
    EXPECT_EQ(
        layerCount(t, vec3(0.0f), vec3(0.0f, 5.0f, 0.0f), SHADOW_T_MIN, NO_TRIANGLE, whole, 0xffffffffu),
        std::uint32_t(n));
    EXPECT_EQ(whole.cutShort, 0u);
    // A segment above the stack meets one box of the root's at most: no triangle, not cut.
    LayerCountWork above{};
    EXPECT_EQ(layerCount(t, vec3(0.0f, 3.5f, 0.0f), vec3(0.0f, 5.0f, 0.0f), SHADOW_T_MIN, NO_TRIANGLE, above),
              0u);
    EXPECT_EQ(above.cutShort, 0u);
    EXPECT_LE(above.visits, 1u);
}

TEST(LayerBvh, CountsAsEmbreeAndAsDoublePrecisionOnAKnot) {
    // Segments from points on the knot (their own triangle left out, the self-shadowing rule)
    // and in the air around it to a light centre near it and to one far away (a directional
    // light's), as the centre count casts them.
    Scene scene = test::sceneOf(test::makeTorusKnotMesh(400, 12, 0.2f));
    test::addTri(scene, vec3(-4, -2, -4), vec3(-4, -2, 4), vec3(4, -2, 4));
    test::addTri(scene, vec3(-4, -2, -4), vec3(4, -2, 4), vec3(4, -2, -4));
    const LayerBvhTables t = buildLayerBvh(scene);
    const EmbreeScene embree(scene);
    const float diameter = scene.bounds().diameter();
    test::Rng rng(7);
    std::vector<std::uint32_t> scratch;
    std::size_t embreeDiffers = 0, exactDiffers = 0, occluded = 0, visits = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        vec3 p;
        std::uint32_t ignore = NO_TRIANGLE;
        if (i % 2 == 0) {
            ignore = std::uint32_t(rng.index(int(scene.triangleCount())));
            const uvec3 tri = scene.triangles[ignore];
            const float u = rng.uniform(), v = rng.uniform() * (1.0f - u);
            p = scene.positions[tri.x] * (1.0f - u - v) + scene.positions[tri.y] * u +
                scene.positions[tri.z] * v;
        } else {
            p = rng.inBox(vec3(-3, -2, -3), vec3(3, 2, 3));
        }
        const vec3 r = i % 3 == 0 ? vec3(0.3f, 60.0f, -20.0f) : rng.inBox(vec3(-1, 3, -1), vec3(1, 4, 1));
        const float tMin = shadowTMin(p, r, diameter);
        LayerCountWork work{};
        const std::uint32_t count = layerCount(t, p, r, tMin, ignore, work);
        ASSERT_EQ(work.cutShort, 0u);
        visits += work.visits;
        const std::uint32_t expected = embree.countLayers(p, r, tMin, ignore, scratch);
        occluded += expected > 0;
        if (count != expected && ++embreeDiffers <= 5)
            std::printf("differs from embree: p %s r %s: %u, embree %u\n", test::str(p).c_str(),
                        test::str(r).c_str(), count, expected);
        if (int(count) != test::countCrossings(scene, p, r, tMin, ignore)) ++exactDiffers;
    }
    std::printf(
        "%d segments, %zu occluded, %zu differ from embree, %zu from double precision; %.1f node visits "
        "a segment (%u nodes, depth %u)\n",
        n, occluded, embreeDiffers, exactDiffers, double(visits) / n, t.nodeCount(), t.depth);
    EXPECT_GT(occluded, std::size_t(n / 10));
    EXPECT_EQ(embreeDiffers, 0u);
    // Double precision decides differently only where a segment grazes an edge or ends within
    // rounding of a triangle (float positions on the surface): a handful in 20 000.
    EXPECT_LE(exactDiffers, std::size_t(n / 2000));
}

} // namespace
} // namespace stsv
