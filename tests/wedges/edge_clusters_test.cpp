// The cluster tree over potential silhouette edges (wedges/edge_clusters.h) and its two tests
// (wedges/edge_cluster_dh.h): the tree's bounds hold what they claim, the light-hull test never
// rejects a ball that a segment from the region to the light meets, it is monotone (a point of a
// region, a ball inside a ball), and a node the silhouette test rejects for a region holds no edge
// that is a silhouette from any point of it — checked against brute force on real meshes.
#include "sampling/light_bounds.h"
#include "scene/geometry.h"
#include "wedge_test_util.h"
#include "wedges/adjacency.h"
#include "wedges/cpu/cpu_wedges.h"
#include "wedges/dcs_dh.h"
#include "wedges/edge_cluster_dh.h"
#include "wedges/edge_clusters.h"
#include "wedges/silhouette_edges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace stsv {
namespace {

struct Built {
    Scene scene;
    EdgeAdjacency adj;
    std::vector<std::uint32_t> edges;
    EdgeClusterTree tree;
};

/// Every edge of the mesh, each cone turned to its first face's normal.
Built buildAll(const MeshData& mesh) {
    Built b;
    b.scene = test::sceneOf(mesh);
    b.adj = buildEdgeAdjacency(b.scene, [](std::size_t) { return true; });
    std::vector<vec3> turn;
    for (std::uint32_t e = 0; e < b.adj.edges.size(); ++e) {
        b.edges.push_back(e);
        const uvec3 t = b.scene.triangles[b.adj.faces[b.adj.edges[e].firstFace].triangle];
        const vec3 c0 = b.scene.positions[t.x];
        turn.push_back(cross(b.scene.positions[t.y] - c0, b.scene.positions[t.z] - c0));
    }
    b.tree = buildEdgeClusters(b.adj, b.edges, turn, b.scene.bounds().diameter());
    return b;
}

MeshData knot() {
    return makeTorusKnotMesh(1024, 16, 0.12f);
}

/// The items below node `index`.
void collect(const EdgeClusterTree& tree, std::uint32_t index, std::vector<std::uint32_t>& out) {
    const EdgeClusterNode& node = tree.nodes[index];
    if (node.count > 0) {
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) out.push_back(tree.items[k]);
        return;
    }
    collect(tree, node.first, out);
    collect(tree, node.first + 1, out);
}

bool ballHolds(vec4 outer, vec4 inner) {
    // 1e-5 of the radius: the balls are grown by that much for rounding.
    return length(vec3(inner) - vec3(outer)) + inner.w <= outer.w * (1.0f + 1e-5f) + 1e-6f;
}

TEST(EdgeClusters, EveryEdgeOnceInLeavesOfAtMostALeafAndBoundsHoldTheirContents) {
    const Built b = buildAll(knot());
    ASSERT_FALSE(b.tree.nodes.empty());
    std::vector<std::uint32_t> items;
    collect(b.tree, 0, items);
    EXPECT_EQ(items.size(), b.edges.size());
    EXPECT_EQ(std::set<std::uint32_t>(items.begin(), items.end()).size(), b.edges.size());
    std::size_t leaves = 0;
    for (std::uint32_t n = 0; n < b.tree.nodes.size(); ++n) {
        const EdgeClusterNode& node = b.tree.nodes[n];
        if (node.count == 0) {
            for (std::uint32_t c : {node.first, node.first + 1}) {
                const EdgeClusterNode& child = b.tree.nodes[c];
                EXPECT_TRUE(ballHolds(node.ball, child.ball)) << "node " << n << " child " << c;
                // A node's cone holds its children's (or there is none).
                if (node.cone.w >= 0.0f) {
                    ASSERT_GE(child.cone.w, 0.0f);
                    const float angle =
                        std::acos(std::clamp(dot(vec3(node.cone), vec3(child.cone)), -1.0f, 1.0f));
                    EXPECT_LE(angle + child.halfAngle, node.halfAngle + 1e-5f) << "node " << n;
                }
            }
            continue;
        }
        ++leaves;
        EXPECT_LE(node.count, EDGE_CLUSTER_LEAF);
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            const MeshEdge& edge = b.adj.edges[b.edges[b.tree.items[k]]];
            const vec3 v0 = b.adj.positions[edge.v0], v1 = b.adj.positions[edge.v1];
            EXPECT_TRUE(ballHolds(node.ball, edgeBall(v0, v1))) << "leaf " << n;
            if (node.cone.w < 0.0f) continue;
            // Both deciding normals n_0 and −n_1 (or both negated) lie in the cone.
            const vec3 n0 =
                normalize(cross(v1 - v0, b.adj.positions[b.adj.faces[edge.firstFace].opposite] - v0));
            const vec3 n1 =
                -normalize(cross(v1 - v0, b.adj.positions[b.adj.faces[edge.firstFace + 1].opposite] - v0));
            const float c0 = dot(n0, vec3(node.cone)), c1 = dot(n1, vec3(node.cone));
            const bool straight = c0 >= node.cone.w - 1e-5f && c1 >= node.cone.w - 1e-5f;
            const bool turned = -c0 >= node.cone.w - 1e-5f && -c1 >= node.cone.w - 1e-5f;
            EXPECT_TRUE(straight || turned) << "leaf " << n << " edge " << b.tree.items[k];
        }
    }
    EXPECT_EQ(leaves, b.tree.leaves);
    // A smooth mesh clusters into narrow cones (its leaves are small patches, not rings around the
    // tube): nearly every leaf has one, most within 30 degrees.
    std::size_t coned = 0, narrow = 0;
    for (const EdgeClusterNode& node : b.tree.nodes) {
        coned += node.count > 0 && node.cone.w >= 0.0f ? 1u : 0u;
        narrow += node.count > 0 && node.cone.w > 0.866f ? 1u : 0u;
    }
    EXPECT_GT(coned, leaves * 9 / 10);
    EXPECT_GT(narrow, leaves / 2) << coned << " coned leaves of " << leaves;
}

TEST(EdgeClusters, OpenAndNonManifoldEdgesHaveNoConeAndAreKept) {
    // A quad (four open edges) and a fin of three triangles on one edge.
    Scene scene;
    Material m;
    scene.materials.push_back(m);
    const auto tri = [&](vec3 a, vec3 c, vec3 d) {
        scene.addTriangle(a, c, d, vec2(0.f), vec2(0.f), vec2(0.f), 0);
    };
    tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    tri({0, 0, 0}, {1, 0, 0}, {0, -1, 0});
    tri({0, 0, 0}, {1, 0, 0}, {0, 0, 1});
    const EdgeAdjacency adj = buildEdgeAdjacency(scene, [](std::size_t) { return true; });
    std::vector<std::uint32_t> edges;
    for (std::uint32_t e = 0; e < adj.edges.size(); ++e) edges.push_back(e);
    const EdgeClusterTree tree =
        buildEdgeClusters(adj, edges, std::vector<vec3>(edges.size(), vec3(0, 0, 1)), 2.0f);
    ASSERT_EQ(tree.leaves, 1u);
    EXPECT_LT(tree.nodes[0].cone.w, 0.0f);
    // Without a cone no region is rejected for silhouettes, however far.
    EXPECT_TRUE(
        clusterMayHaveSilhouette(tree.nodes[0].ball, tree.nodes[0].cone, vec4(100, 0, 0, 0.1f), 0.0f));
}

/// The smallest distance, over t ∈ [0, 1] sampled finely, from c to the ball (1 − t)·region + t·light
/// minus that ball's radius, in double precision: ≤ r exactly when the ball (c, r) meets the hull.
double hullGap(vec4 cluster, vec4 region, vec4 light) {
    double best = 1e30;
    for (int i = 0; i <= 20000; ++i) {
        const double t = i / 20000.0;
        const dvec3 centre = dvec3(vec3(region)) * (1.0 - t) + dvec3(vec3(light)) * t;
        const double radius = double(region.w) * (1.0 - t) + double(light.w) * t;
        best = std::min(best, length(dvec3(vec3(cluster)) - centre) - radius);
    }
    return best - double(cluster.w);
}

TEST(EdgeClusterTests, LightHullKeepsEveryBallASegmentMeetsAndRejectsTheFarOnes) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f), r(0.0f, 1.0f), s(-1.0f, 1.0f);
    int kept = 0, rejected = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const vec4 region(u(rng), u(rng), u(rng), trial % 3 == 0 ? 0.0f : 0.5f * r(rng));
        const vec4 light(u(rng), 4.0f + u(rng), u(rng), r(rng));
        // Half the balls about a point of the hull's axis, where the answer is less one-sided.
        const float t = r(rng);
        const vec3 near = vec3(region) * (1.0f - t) + vec3(light) * t + vec3(s(rng), s(rng), s(rng));
        const vec4 cluster(trial % 2 ? near : vec3(u(rng), u(rng), u(rng)), 0.3f * r(rng));
        const bool meets = ballMeetsLightHull(cluster, lightHull(region, light));
        const double gap = hullGap(cluster, region, light);
        // Sampling t finely overestimates the gap by at most the step times the axis length.
        if (gap < 0.0) {
            EXPECT_TRUE(meets) << "trial " << trial << ": the ball meets the hull (gap " << gap << ")";
        }
        if (gap > 1e-2) {
            EXPECT_FALSE(meets) << "trial " << trial << ": gap " << gap;
        }
        (meets ? kept : rejected) += 1;
    }
    EXPECT_GT(kept, 100);
    EXPECT_GT(rejected, 100);
}

TEST(EdgeClusterTests, LightHullIsMonotoneInTheRegionAndTheBall) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f), r(0.0f, 1.0f), s(-1.0f, 1.0f);
    int checked = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        const vec4 region(u(rng), u(rng), u(rng), 0.6f * r(rng));
        const vec4 light(u(rng), 4.0f + u(rng), u(rng), r(rng));
        const float t = r(rng);
        const vec3 near = vec3(region) * (1.0f - t) + vec3(light) * t + vec3(s(rng), s(rng), s(rng));
        const vec4 cluster(near, 0.5f * r(rng));
        // A point of the region and a ball inside the cluster's.
        vec3 offset(s(rng), s(rng), s(rng));
        if (length(offset) > 1.0f) offset /= length(offset);
        const vec4 point(vec3(region) + offset * region.w, 0.0f);
        const float innerRadius = cluster.w * r(rng);
        vec3 shift(s(rng), s(rng), s(rng));
        if (length(shift) > 1.0f) shift /= length(shift);
        const vec4 inner(vec3(cluster) + shift * (cluster.w - innerRadius), innerRadius);
        const LightHull pointHull = lightHull(point, light);
        if (ballMeetsLightHull(inner, pointHull)) {
            ++checked;
            EXPECT_TRUE(ballMeetsLightHull(cluster, pointHull)) << "trial " << trial << ": ball";
            EXPECT_TRUE(ballMeetsLightHull(inner, lightHull(region, light)))
                << "trial " << trial << ": region";
        }
    }
    EXPECT_GT(checked, 200);
}

/// The distance from c to the cone with apex p around the axis p → light centre, tangent to the
/// light's ball, in double precision (0 inside it).
double coneGap(vec3 c, vec3 p, vec4 light) {
    const dvec3 d = dvec3(c) - dvec3(p), axis = normalize(dvec3(vec3(light)) - dvec3(p));
    const double sine = double(light.w) / length(dvec3(vec3(light)) - dvec3(p));
    const double cosine = std::sqrt(1.0 - sine * sine);
    const double a = dot(d, axis), lateral = length(d - axis * a);
    if (a * cosine + lateral * sine < 0.0) return length(d);
    return std::max(0.0, lateral * cosine - a * sine);
}

TEST(EdgeClusterTests, LightConeKeepsEveryBallThePointsHullKeepsAndRejectsTheFarOnes) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f), r(0.0f, 1.0f), s(-1.0f, 1.0f);
    int kept = 0, rejected = 0, looser = 0;
    std::bernoulli_distribution often(0.5), sometimes(0.2);
    for (int trial = 0; trial < 40000; ++trial) {
        const vec3 p(u(rng), u(rng), u(rng));
        // Lights from large to tiny (a near point light makes the cone a thin needle), and
        // some with p inside them (the whole space).
        const float lightRadius = sometimes(rng) ? 1e-5f * r(rng) : (sometimes(rng) ? 8.0f : r(rng));
        const vec4 light(u(rng), 4.0f + u(rng), u(rng), lightRadius);
        // Half the balls about a point of the axis (some on it, some behind p or past the light),
        // small ones among them.
        const float t = often(rng) ? 2.0f * s(rng) : r(rng);
        const float spread = sometimes(rng) ? 0.0f : (often(rng) ? 1e-3f : 1.0f);
        const vec3 near = p * (1.0f - t) + vec3(light) * t + spread * vec3(s(rng), s(rng), s(rng));
        const vec4 ball(often(rng) ? near : vec3(u(rng), u(rng), u(rng)),
                        (sometimes(rng) ? 1e-6f : 0.3f) * r(rng));
        const bool cone = ballMeetsLightCone(ball, lightCone(p, light));
        const bool hull = ballMeetsLightHull(ball, lightHull(vec4(p, 0.0f), light));
        // Never tighter than the hull's test: the same margin about a larger set.
        if (hull) {
            EXPECT_TRUE(cone) << "trial " << trial << ": the hull keeps the ball, the cone rejects it";
        }
        if (hull != cone) ++looser;
        if (length(p - vec3(light)) <= light.w) {
            EXPECT_TRUE(cone) << "trial " << trial << ": p lies in the light";
        } else {
            const double gap = coneGap(vec3(ball), p, light) - double(ball.w);
            if (gap < 0.0) {
                EXPECT_TRUE(cone) << "trial " << trial << ": the ball meets the cone (gap " << gap << ")";
            }
            // Beyond the margin, rejected: 1e-4 of the magnitudes it sums, here below 80 (the
            // distance to the light, its radius and |p|₁ below 20, |d|₁ below 50), and rounding.
            if (gap > 1e-2) {
                EXPECT_FALSE(cone) << "trial " << trial << ": gap " << gap;
            }
        }
        // Monotone in the ball: a ball inside one the cone rejects is rejected too.
        const float innerRadius = ball.w * r(rng);
        vec3 shift(s(rng), s(rng), s(rng));
        if (length(shift) > 1.0f) shift /= length(shift);
        const vec4 inner(vec3(ball) + shift * (ball.w - innerRadius), innerRadius);
        if (ballMeetsLightCone(inner, lightCone(p, light))) {
            EXPECT_TRUE(cone) << "trial " << trial << ": a ball inside it meets the cone";
        }
        (cone ? kept : rejected) += 1;
    }
    EXPECT_GT(kept, 1000);
    EXPECT_GT(rejected, 1000);
    EXPECT_GT(looser, 0) << "the cone holds the hull's far side beyond the light";
}

TEST(EdgeClusterTests, SideLanesKeepExactlyTheEdgesWhoseWeightIsNotZero) {
    // The knot, and the knot with a fin on some of its edges (edges of three faces: `many`).
    Scene finned = makeMeshScene(knot(), "knot");
    const std::size_t knotTriangles = finned.triangleCount();
    for (std::size_t t = 0; t < knotTriangles; t += 97) {
        const uvec3 i = finned.triangles[t];
        const vec3 a = finned.positions[i.x], b = finned.positions[i.y];
        test::addTri(finned, b, a, 0.5f * (a + b) + vec3(0.0f, 0.05f, 0.0f));
    }
    for (const bool fins : {false, true}) {
        const Scene plain = makeMeshScene(knot(), "knot");
        const Scene& scene = fins ? finned : plain;
        const WedgeOccluders occ(scene);
        ASSERT_FALSE(scene.lights.empty());
        const SilhouetteEdges& sil = occ.silhouettes(scene.lights[0], farDistanceFor(scene.bounds()));
        const EdgeSideLanes& lanes = sil.sideLanes();
        const std::uint32_t n = std::uint32_t(sil.tree().items.size());
        ASSERT_GT(n, 1000u);
        std::mt19937 rng(17);
        std::uniform_real_distribution<float> u(-2.5f, 2.5f);
        std::size_t candidates = 0, excluded = 0, many = 0, tested = 0;
        for (int trial = 0; trial < 40; ++trial) {
            // Points in space, and on an edge's first vertex (every plane through it: side 0).
            const std::uint32_t at = std::uint32_t(rng() % n);
            const vec3 p = trial % 4 == 3 ? sil.packed(at).v0 : vec3(u(rng), u(rng), u(rng));
            // No receiver, or the first face of an edge (left out of its weight).
            const uint receiver =
                trial % 2 ? sil.packed(std::uint32_t(rng() % n)).faces[0].triangle : NO_TRIANGLE;
            for (std::uint32_t first = std::uint32_t(trial % 4); first < n; first += EdgeSideLanes::LANES) {
                const std::uint32_t bits = silhouetteCandidates(lanes, first, p, receiver);
                for (std::uint32_t i = 0; i < EdgeSideLanes::LANES && first + i < n; ++i) {
                    const PackedEdge& e = sil.packed(first + i);
                    const bool expected =
                        e.faceCount > 2 ||
                        dcsTwoFaceWeight(p, e.v0, e.faces[0].normal, e.faces[0].triangle, e.faces[1].normal,
                                         e.faces[1].triangle, receiver) != 0;
                    ASSERT_EQ(((bits >> i) & 1u) != 0u, expected)
                        << (fins ? "finned " : "") << "trial " << trial << " edge " << first + i;
                    candidates += expected;
                    excluded += receiver != NO_TRIANGLE &&
                                (e.faces[0].triangle == receiver || e.faces[1].triangle == receiver);
                    many += e.faceCount > 2;
                    ++tested;
                }
            }
        }
        EXPECT_GT(candidates, tested / 20);
        EXPECT_LT(candidates, tested);
        EXPECT_GT(excluded, 0u);
        if (fins) {
            EXPECT_GT(many, 0u) << "no edge of three faces among the potential silhouettes";
        }
    }
}

/// The DCS weight of an edge seen from p in float, as wedgeWorldWeight computes it (dcsWorldSide).
int floatWeight(const EdgeAdjacency& adj, const MeshEdge& edge, vec3 p) {
    int k = 0;
    for (std::uint32_t f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f)
        k += dcsWorldSide(p, adj.positions[edge.v0], adj.positions[edge.v1],
                          adj.positions[adj.faces[f].opposite]);
    return k;
}

TEST(EdgeClusterTests, ALeafTheSilhouetteTestRejectsHoldsNoSilhouetteFromAnyPointOfTheRegion) {
    const Built b = buildAll(knot());
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-2.5f, 2.5f), r(0.0f, 1.0f), s(-1.0f, 1.0f);
    std::size_t rejections = 0, pointsChecked = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const vec4 region(u(rng), u(rng), u(rng), 0.3f * r(rng));
        for (const EdgeClusterNode& node : b.tree.nodes) {
            if (node.count == 0) continue;
            // The rounding allowance the mirror passes (wedges/cpu/cpu_wedges.cpp nodeMayAdd).
            const float reach = length(vec3(region) - vec3(node.ball)) + region.w + node.ball.w;
            if (clusterMayHaveSilhouette(node.ball, node.cone, region,
                                         dcsSideRounding(reach, node.conditioning)))
                continue;
            ++rejections;
            for (int i = 0; i < 8; ++i) {
                vec3 offset(s(rng), s(rng), s(rng));
                if (length(offset) > 1.0f) offset /= length(offset);
                const vec3 p = vec3(region) + offset * region.w;
                for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                    ++pointsChecked;
                    ASSERT_EQ(floatWeight(b.adj, b.adj.edges[b.edges[b.tree.items[k]]], p), 0)
                        << "trial " << trial << ": a rejected leaf holds a silhouette from the region";
                }
            }
        }
    }
    // Many leaves face a random region, or turn away from it, as a whole.
    EXPECT_GT(rejections, 60u * b.tree.leaves / 8);
    EXPECT_GT(pointsChecked, 10000u);
}

} // namespace
} // namespace stsv
