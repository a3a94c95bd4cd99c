// Edge adjacency with welding (seams, duplicated vertices, non-manifold and open edges) and
// silhouette sets against brute force.
#include "core/gbuffer.h"
#include "sampling/light_bounds.h"
#include "scene/geometry.h"
#include "wedge_test_util.h"
#include "wedges/adjacency.h"

#include <gtest/gtest.h>

#include <map>

namespace stsv {
namespace {

/// The DCS weight of edge `e` seen from p (wedges/dcs_dh.h dcsFaceSide), in double precision:
/// the sum over its faces (except `ignoreTriangle`) of the side of the face's third vertex
/// relative to the plane through p and the edge, ±1 (0 in the plane), with the orientation
/// m = (v0 − p) × (v1 − p). Non-zero iff the edge is a silhouette as seen from p.
int edgeWeightFrom(const EdgeAdjacency& adj, std::uint32_t e, dvec3 p, std::uint32_t ignoreTriangle) {
    const MeshEdge& edge = adj.edges[e];
    const dvec3 m = cross(dvec3(adj.positions[edge.v0]) - p, dvec3(adj.positions[edge.v1]) - p);
    int k = 0;
    for (std::uint32_t f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f) {
        if (adj.faces[f].triangle == ignoreTriangle) continue;
        const double side = dot(m, dvec3(adj.positions[adj.faces[f].opposite]) - p);
        k += side > 0.0 ? 1 : (side < 0.0 ? -1 : 0);
    }
    return k;
}

Scene emptyScene() {
    Scene scene;
    Material m;
    m.name = "opaque";
    scene.materials.push_back(m);
    return scene;
}

/// The corners of the unit cube about the origin.
const vec3 CUBE[8] = {{-.5f, -.5f, -.5f}, {.5f, -.5f, -.5f}, {.5f, .5f, -.5f}, {-.5f, .5f, -.5f},
                      {-.5f, -.5f, .5f},  {.5f, -.5f, .5f},  {.5f, .5f, .5f},  {-.5f, .5f, .5f}};

/// Every face of the cube with its own four vertices (as OBJ loaders emit at UV seams), two
/// triangles a face, outward winding.
void addCube(Scene& s) {
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    for (const auto& q : quads) {
        test::addTri(s, CUBE[q[0]], CUBE[q[1]], CUBE[q[2]]);
        test::addTri(s, CUBE[q[0]], CUBE[q[2]], CUBE[q[3]]);
    }
}

/// Face count of the edge between two positions, 0 if absent.
std::uint32_t facesOn(const EdgeAdjacency& adj, vec3 a, vec3 b) {
    for (const MeshEdge& e : adj.edges) {
        const vec3 p = adj.positions[e.v0], q = adj.positions[e.v1];
        if ((p == a && q == b) || (p == b && q == a)) return e.faceCount;
    }
    return 0;
}

TEST(Adjacency, CubeWithSeamsWeldsClosed) {
    // Every face of a unit cube with its own four vertices (as OBJ loaders emit at UV seams),
    // corners at ±0.5 but one face written with −0.0-free and one with signed-zero variants.
    Scene s = emptyScene();
    addCube(s);
    ASSERT_EQ(s.positions.size(), 36u); // unindexed: nothing shared before welding
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    EXPECT_EQ(adj.positions.size(), 8u);
    EXPECT_EQ(adj.edges.size(), 18u); // 12 cube edges + 6 diagonals
    EXPECT_EQ(adj.manifoldEdges, 18u);
    EXPECT_EQ(adj.openEdges, 0u);
    EXPECT_EQ(adj.nonManifoldEdges, 0u);
    EXPECT_EQ(adj.inconsistentEdges, 0u);
    for (const MeshEdge& e : adj.edges) {
        // The two faces run the edge in opposite directions (consistent winding survives welding).
        EXPECT_NE(adj.faces[e.firstFace].forward, adj.faces[e.firstFace + 1].forward);
        // The opposite vertex is neither end of the edge.
        for (std::uint32_t f = e.firstFace; f < e.firstFace + 2; ++f) {
            EXPECT_NE(adj.faces[f].opposite, e.v0);
            EXPECT_NE(adj.faces[f].opposite, e.v1);
        }
    }
}

TEST(Adjacency, SignedZeroWeldsAndDistinctNearbyVerticesDoNot) {
    Scene s = emptyScene();
    test::addTri(s, vec3(0.0f, 0.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f));
    test::addTri(s, vec3(-0.0f, 0.0f, -0.0f), vec3(0.0f, 1.0f, 0.0f),
                 vec3(-1.0f, 0.0f, 0.0f)); // shares (0,0,0)–(0,1,0)
    test::addTri(s, vec3(1.0f, 0.0f, 0.0f), vec3(1e-6f, 1.0f, 0.0f),
                 vec3(1.0f, 1.0f, 0.0f)); // 1e-6 away: not welded
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    EXPECT_EQ(adj.positions.size(), 6u);
    EXPECT_EQ(facesOn(adj, vec3(0.0f), vec3(0.0f, 1.0f, 0.0f)), 2u);
    EXPECT_EQ(facesOn(adj, vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f)), 1u);
    EXPECT_EQ(adj.manifoldEdges, 1u);
    EXPECT_EQ(adj.openEdges, 7u);
}

TEST(Adjacency, NonManifoldOpenAndDegenerate) {
    Scene s = emptyScene();
    const vec3 a(0.0f), b(0.0f, 1.0f, 0.0f);
    test::addTri(s, a, b, vec3(1.0f, 0.0f, 0.0f));
    test::addTri(s, b, a, vec3(-1.0f, 0.0f, 0.0f));
    test::addTri(s, a, b, vec3(0.0f, 0.0f, 1.0f)); // third face on a–b: non-manifold
    test::addTri(s, a, a, vec3(5.0f));             // repeated vertex: degenerate, skipped
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    EXPECT_EQ(adj.degenerateSkipped, 1u);
    EXPECT_EQ(facesOn(adj, a, b), 3u);
    EXPECT_EQ(adj.nonManifoldEdges, 1u);
    EXPECT_EQ(adj.openEdges, 6u);
    // Open and non-manifold edges are potential silhouettes for any light.
    const std::vector<std::uint32_t> potential = potentialSilhouetteEdges(adj, vec4(0.0f, 10.0f, 0.0f, 0.1f));
    EXPECT_EQ(potential.size(), adj.edges.size());
    // Include filter: only the first triangle.
    const EdgeAdjacency one = buildEdgeAdjacency(s, [](std::size_t t) { return t == 0; });
    EXPECT_EQ(one.edges.size(), 3u);
    EXPECT_EQ(one.openEdges, 3u);
}

TEST(EdgeCarriers, EveryEdgeWithALiveFaceIsCarriedByItsFirstLiveFace) {
    // A cube, a triangle with collinear corners on one of its edges' line (live for the adjacency,
    // degenerate for the volumes) and a third face on a cube edge (non-manifold): both backends'
    // wedge passes bound an edge's wedge by its carrier's volumes, so every edge with a
    // non-degenerate face must have one, its first such face, and the others none.
    Scene s = emptyScene();
    addCube(s);
    test::addTri(s, CUBE[0], CUBE[1], vec3(2.0f, -0.5f, -0.5f)); // collinear with the edge 0–1
    test::addTri(s, CUBE[4], CUBE[5], vec3(0.0f, -2.0f, 0.5f));  // a third face on 4–5
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    const std::vector<std::uint32_t> carriers = edgeCarriers(adj, s);
    ASSERT_EQ(carriers.size(), adj.edges.size());
    auto degenerate = [&](std::uint32_t t) {
        const uvec3 i = s.triangles[t];
        // Collinear corners: a zero cross product (the test's triangles are exact in float).
        return length(cross(s.positions[i.y] - s.positions[i.x], s.positions[i.z] - s.positions[i.x])) ==
               0.0f;
    };
    std::size_t live = 0;
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        std::uint32_t first = NO_CARRIER;
        for (std::uint32_t f = adj.edges[e].firstFace;
             f < adj.edges[e].firstFace + adj.edges[e].faceCount && first == NO_CARRIER; ++f)
            if (!degenerate(adj.faces[f].triangle)) first = adj.faces[f].triangle;
        EXPECT_EQ(carriers[e], first) << "edge " << e;
        live += first != NO_CARRIER ? 1 : 0;
    }
    // The cube's 18 edges and the non-manifold face's two new ones; the collinear triangle's two
    // new edges have no live face.
    EXPECT_EQ(live, 20u);
    EXPECT_EQ(adj.edges.size(), 22u);
}

TEST(Silhouettes, FromPointMatchesFrontBackBruteForce) {
    // Closed, consistently wound meshes: an edge is a silhouette from p iff its two faces face p
    // differently — computed from the winding normals, independently of edgeWeightFrom's
    // third-vertex rule. Also: the weight of a silhouette of a closed mesh is ±2.
    test::Rng rng(11);
    for (const MeshData& mesh :
         {test::makeTorusMesh(24, 10, 1.0f, 0.4f), test::makeTorusKnotMesh(96, 8, 0.12f)}) {
        const Scene s = test::sceneOf(mesh);
        const EdgeAdjacency adj = buildEdgeAdjacency(s);
        ASSERT_EQ(adj.openEdges + adj.nonManifoldEdges, 0u);
        std::size_t silhouettes = 0, checked = 0;
        for (int i = 0; i < 40; ++i) {
            const vec3 p = rng.inBox(vec3(-3.0f), vec3(3.0f));
            for (std::uint32_t e = 0; e < adj.edges.size(); ++e) {
                const MeshEdge& edge = adj.edges[e];
                bool front[2];
                for (int f = 0; f < 2; ++f) {
                    const uvec3 t = s.triangles[adj.faces[edge.firstFace + f].triangle];
                    const dvec3 v0(s.positions[t.x]), v1(s.positions[t.y]), v2(s.positions[t.z]);
                    front[f] = dot(cross(v1 - v0, v2 - v0), dvec3(p) - v0) > 0.0;
                }
                const int k = edgeWeightFrom(adj, e, dvec3(p), NO_TRIANGLE);
                ASSERT_EQ(k != 0, front[0] != front[1]) << "p=" << test::str(p) << " edge " << e;
                if (k != 0) {
                    ASSERT_EQ(std::abs(k), 2) << "p=" << test::str(p);
                    ++silhouettes;
                }
                ++checked;
            }
        }
        EXPECT_GT(silhouettes, checked / 50);
    }
}

TEST(Silhouettes, PotentialSetHoldsEverySilhouetteFromTheLight) {
    // Brute force: sample points of the light's bounding sphere; every edge that is a silhouette
    // from one of them must be in the potential set, and the set must be a real reduction.
    test::Rng rng(12);
    const Scene s = test::sceneOf(test::makeTorusKnotMesh(128, 8, 0.15f));
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    for (const vec4 sphere :
         {vec4(0.5f, 3.0f, -0.4f, 0.5f), vec4(0.0f, 0.0f, 2.0f, 0.2f), vec4(0.0f, 0.1f, 0.0f, 0.05f)}) {
        const std::vector<std::uint32_t> potential = potentialSilhouetteEdges(adj, sphere);
        std::vector<bool> in(adj.edges.size(), false);
        for (std::uint32_t e : potential) in[e] = true;
        for (int i = 0; i < 400; ++i) {
            vec3 d = rng.inBox(vec3(-1.0f), vec3(1.0f));
            if (length(d) > 1.0f) continue;
            const vec3 x = vec3(sphere) + sphere.w * d;
            for (std::uint32_t e = 0; e < adj.edges.size(); ++e) {
                if (edgeWeightFrom(adj, e, dvec3(x), NO_TRIANGLE) != 0) {
                    ASSERT_TRUE(in[e]) << "edge " << e << " is a silhouette from x=" << test::str(x);
                }
            }
        }
        std::printf("potential silhouettes for sphere (%.1f %.1f %.1f r %.2f): %zu of %zu edges\n", sphere.x,
                    sphere.y, sphere.z, sphere.w, potential.size(), adj.edges.size());
        if (sphere.y > 2.0f) {
            EXPECT_LT(potential.size(), adj.edges.size() / 2);
        }
    }
}

} // namespace
} // namespace stsv
