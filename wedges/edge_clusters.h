// A hierarchy over the potential silhouette edges of one light (DESIGN §4.5): clusters of edges
// near each other in space and in normal direction, each with a ball around its edges and the
// cone of the normals that decide whether they are silhouettes, in a binary tree whose nodes
// bound their children. A region of receiver points rejects a whole subtree at once when no
// segment from it to the light meets the node's ball, or when no edge below can be a silhouette
// from any point of it (wedges/edge_cluster_dh.h) — the culling of Hierarchical Penumbra Casting
// (Lehtinen, Laine and Aila 2008) turned around: the receivers' regions query the occluders'
// tree.
#pragma once

#include "core/dh.h"
#include "wedges/adjacency.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// Edges per leaf at most.
inline constexpr std::uint32_t EDGE_CLUSTER_LEAF = 32;

struct EdgeClusterNode {
    vec4 ball; ///< centre, radius around the endpoints of its edges (world units)
    /// Unit axis and cosine of the half-angle of the cone of the edges' deciding normals; w < 0: no
    /// cone (an edge without two faces or with a degenerate face below, or a cone too wide).
    vec4 cone;
    float halfAngle = -1.f; ///< radians (the cone's, for merging); < 0: no cone
    /// The largest conditioning κ = |v1 − v0|·|o − v0| / |n| of the faces below, which scales
    /// the rounding allowance of the cone test (dcs_dh.h dcsSideRounding); infinite with a
    /// degenerate face (then there is no cone).
    float conditioning = 0.f;
    std::uint32_t first = 0; ///< leaf: into EdgeClusterTree::items; inner: the first child node
    std::uint32_t count = 0; ///< leaf: number of items; inner: 0 (two children, first and first + 1)
};

struct EdgeClusterTree {
    std::vector<EdgeClusterNode> nodes; ///< nodes[0] is the root (when there is any edge)
    std::vector<std::uint32_t> items;   ///< indices into the edge list given, leaf after leaf
    std::size_t leaves = 0;
};

/// The tree over `edges` (adjacency edge indices; items refer to their positions in it). `turn`
/// holds, per item, a normal whose side decides each edge's cone orientation (its carrier face's
/// own normal): the pair (n_0, −n_1) of a two-face edge is negated together where n_0 opposes it.
/// `scale` (world units, the scene's size) weighs position against normal direction when splitting.
EdgeClusterTree buildEdgeClusters(const EdgeAdjacency& adj, const std::vector<std::uint32_t>& edges,
                                  const std::vector<vec3>& turn, float scale);

/// Adjacency edge `edge` as a cluster of its own: the leaf buildEdgeClusters makes of it alone
/// (its ball, the cone of its deciding normals oriented by `turn`, its rounding allowance), for
/// the per-edge culling of a block of pixels (wedges/shaders/dcs_clusters.comp).
EdgeClusterNode edgeCluster(const EdgeAdjacency& adj, std::uint32_t edge, vec3 turn);

} // namespace stsv
