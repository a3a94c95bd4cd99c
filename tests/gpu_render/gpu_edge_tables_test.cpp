// The opaque edges as the Vulkan wedge passes read them (wedges/vulkan/gpu_wedge_passes.h): one
// table entry per welded edge, and one carrier record per carrier face listing the edges it
// carries (wedges/adjacency.h edgeCarriers, the rule both backends use).
#include "wedges/adjacency.h"
#include "wedges/vulkan/gpu_wedge_passes.h"

#include <gtest/gtest.h>

namespace stsv {
namespace {

void addTri(Scene& s, vec3 a, vec3 b, vec3 c) {
    s.addTriangle(a, b, c, vec2(0.0f), vec2(0.0f), vec2(0.0f), 0);
}

TEST(GpuEdgeTables, EveryCarriedEdgeSitsOnceInItsCarriersRecord) {
    // A unit cube, a triangle with collinear corners on one of its edges' line (no carrier for
    // its new edges) and a third face on a cube edge (non-manifold).
    Scene s;
    Material m;
    m.name = "opaque";
    s.materials.push_back(m);
    const vec3 c[8] = {{-.5f, -.5f, -.5f}, {.5f, -.5f, -.5f}, {.5f, .5f, -.5f}, {-.5f, .5f, -.5f},
                       {-.5f, -.5f, .5f},  {.5f, -.5f, .5f},  {.5f, .5f, .5f},  {-.5f, .5f, .5f}};
    const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    for (const auto& q : quads) {
        addTri(s, c[q[0]], c[q[1]], c[q[2]]);
        addTri(s, c[q[0]], c[q[2]], c[q[3]]);
    }
    addTri(s, c[0], c[1], vec3(2.0f, -0.5f, -0.5f));
    addTri(s, c[4], c[5], vec3(0.0f, -2.0f, 0.5f));
    const GpuEdgeTables tables = buildGpuEdgeTables(s);
    const EdgeAdjacency adj = buildEdgeAdjacency(s);
    const std::vector<std::uint32_t> carriers = edgeCarriers(adj, s);
    ASSERT_EQ(tables.edges.size(), adj.edges.size());
    std::vector<int> carried(tables.edges.size(), 0);
    std::vector<bool> listed(s.triangleCount(), false);
    for (const uvec4& carrier : tables.carriers) {
        EXPECT_FALSE(listed[carrier.x]) << "triangle " << carrier.x << " listed twice";
        listed[carrier.x] = true;
        EXPECT_NE(carrier.y, GPU_NO_EDGE) << "a carrier without edges";
        if (carrier.z == GPU_NO_EDGE) {
            EXPECT_EQ(carrier.w, GPU_NO_EDGE) << "slots filled in order";
        }
        for (std::uint32_t e : {carrier.y, carrier.z, carrier.w}) {
            if (e == GPU_NO_EDGE) continue;
            ASSERT_LT(e, tables.edges.size());
            carried[e] += 1;
            EXPECT_EQ(carrier.x, carriers[e]) << "edge " << e;
        }
    }
    std::size_t withCarrier = 0;
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        EXPECT_EQ(carried[e], carriers[e] != NO_CARRIER ? 1 : 0) << "edge " << e;
        withCarrier += carriers[e] != NO_CARRIER ? 1 : 0;
    }
    // The cube's 18 edges and the non-manifold face's two new ones.
    EXPECT_EQ(withCarrier, 20u);
}

} // namespace
} // namespace stsv
