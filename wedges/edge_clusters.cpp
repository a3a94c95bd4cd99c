#include "wedges/edge_clusters.h"

#include "wedges/dcs_dh.h"
#include "wedges/edge_cluster_dh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace stsv {

namespace {

/// What the split sees of one edge: its midpoint and the mean of its deciding normals, and
/// whether those normals make a cone (a two-face edge with both faces non-degenerate).
struct EdgePoint {
    vec3 position;
    vec3 direction;
    bool coned;
};

struct Builder {
    const EdgeAdjacency& adj;
    std::span<const std::uint32_t> edges;
    std::span<const vec3> turn;
    std::vector<EdgePoint> points;
    EdgeClusterTree tree;
    float positionWeight;

    /// The unit deciding normals of item i (n_0/|n_0| and −n_1/|n_1|, turned), or none (false),
    /// and the largest conditioning of its faces (dcs_dh.h dcsSideRounding; infinite for a
    /// degenerate face).
    bool normals(std::uint32_t i, std::array<vec3, 2>& out, float& conditioning) const {
        const MeshEdge& edge = adj.edges[edges[i]];
        const vec3 q0 = adj.positions[edge.v0], q1 = adj.positions[edge.v1];
        conditioning = 0.f;
        bool ok = edge.faceCount == 2;
        for (std::uint32_t f = 0; f < edge.faceCount; ++f) {
            const vec3 o = adj.positions[adj.faces[edge.firstFace + f].opposite];
            const vec3 n = dcsFaceNormal(q0, q1, o);
            const float length = stsv::length(n);
            const float spans = stsv::length(q1 - q0) * stsv::length(o - q0);
            conditioning = std::max(conditioning,
                                    length > 0.f ? spans / length : std::numeric_limits<float>::infinity());
            if (!(length > 0.f)) ok = false;
            if (f < 2 && length > 0.f) out[f] = (f == 0 ? 1.f : -1.f) * n / length;
        }
        if (!ok) return false;
        if (dot(out[0], turn[i]) < 0.f) out = {-out[0], -out[1]};
        return true;
    }

    /// Nodes of the subtree over `count` items.
    static std::uint32_t subtreeNodes(std::uint32_t count) {
        return count <= EDGE_CLUSTER_LEAF ? 1u
                                          : 1u + subtreeNodes(count / 2) + subtreeNodes(count - count / 2);
    }

    /// Fills node `index` from items [first, first + count) and splits it while it holds more
    /// than a leaf: at the median of the widest of the six coordinates (position weighed by
    /// positionWeight, direction). Its two children go to `free` and free + 1, their descendants
    /// after them, the first child's before the second's: every subtree owns a fixed range, so
    /// the halves build in parallel into the same layout.
    void build(std::uint32_t index, std::uint32_t first, std::uint32_t count, std::uint32_t free) {
        if (count <= EDGE_CLUSTER_LEAF) {
            makeLeaf(index, first, count);
            return;
        }
        std::array<float, 6> lo, hi;
        lo.fill(std::numeric_limits<float>::max());
        hi.fill(-std::numeric_limits<float>::max());
        for (std::uint32_t k = first; k < first + count; ++k) {
            const EdgePoint& p = points[tree.items[k]];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p.position[a] * positionWeight);
                hi[a] = std::max(hi[a], p.position[a] * positionWeight);
                lo[3 + a] = std::min(lo[3 + a], p.direction[a]);
                hi[3 + a] = std::max(hi[3 + a], p.direction[a]);
            }
        }
        int axis = 0;
        for (int a = 1; a < 6; ++a)
            if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
        const auto key = [&](std::uint32_t item) {
            const EdgePoint& p = points[item];
            return axis < 3 ? p.position[axis] : p.direction[axis - 3];
        };
        const std::uint32_t half = count / 2;
        auto begin = tree.items.begin() + first;
        std::nth_element(begin, begin + half, begin + count, [&](std::uint32_t a, std::uint32_t b) {
            const float ka = key(a), kb = key(b);
            return ka < kb || (ka == kb && a < b);
        });
        tree.nodes[index].first = free;
        tree.nodes[index].count = 0;
        const std::uint32_t secondFree = free + 2 + subtreeNodes(half) - 1;
        const auto left = [&] { build(free, first, half, free + 2); };
        const auto right = [&] { build(free + 1, first + half, count - half, secondFree); };
        if (count > 8192) {
            tbb::parallel_invoke(left, right);
        } else {
            left();
            right();
        }
        merge(index, free, free + 1);
    }

    void makeLeaf(std::uint32_t index, std::uint32_t first, std::uint32_t count) {
        tree.nodes[index] = leaf(tree.items, first, count);
    }

    /// The leaf over items[first … first + count − 1] (count ≤ EDGE_CLUSTER_LEAF).
    EdgeClusterNode leaf(std::span<const std::uint32_t> items, std::uint32_t first,
                         std::uint32_t count) const {
        EdgeClusterNode node;
        node.first = first;
        node.count = count;
        vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        vec3 sum(0.f);
        bool coned = true;
        float conditioning = 0.f;
        std::array<vec3, 2 * EDGE_CLUSTER_LEAF> normalList;
        std::size_t normalCount = 0;
        for (std::uint32_t k = first; k < first + count; ++k) {
            const std::uint32_t item = items[k];
            const MeshEdge& edge = adj.edges[edges[item]];
            lo = min(lo, min(adj.positions[edge.v0], adj.positions[edge.v1]));
            hi = max(hi, max(adj.positions[edge.v0], adj.positions[edge.v1]));
            std::array<vec3, 2> n{vec3(0.f), vec3(0.f)};
            float own = 0.f;
            if (normals(item, n, own)) {
                normalList[normalCount++] = n[0];
                normalList[normalCount++] = n[1];
                sum += n[0] + n[1];
            } else {
                coned = false;
            }
            conditioning = std::max(conditioning, own);
        }
        // The ball holds every edge's own ball (edgeBall), which the per-point test uses.
        const vec3 centre = 0.5f * (lo + hi);
        float radius = 0.f;
        for (std::uint32_t k = first; k < first + count; ++k) {
            const MeshEdge& edge = adj.edges[edges[items[k]]];
            const vec4 ball = edgeBall(adj.positions[edge.v0], adj.positions[edge.v1]);
            radius = std::max(radius, stsv::length(vec3(ball) - centre) + ball.w);
        }
        node.ball = vec4(centre, radius * (1.f + 1e-5f));
        // Rounded up: the allowance only widens.
        node.conditioning = conditioning * (1.f + 1e-5f);
        node.cone = vec4(0.f, 0.f, 1.f, -1.f);
        const float sumLength = stsv::length(sum);
        if (coned && sumLength > 0.f && std::isfinite(node.conditioning)) {
            const vec3 axis = sum / sumLength;
            float cosHalf = 1.f;
            for (std::size_t i = 0; i < normalCount; ++i)
                cosHalf = std::min(cosHalf, dot(normalList[i], axis));
            setCone(node, axis, std::acos(std::clamp(cosHalf, -1.f, 1.f)));
        }
        return node;
    }

    /// The cone (axis, half-angle + a rounding allowance), unless it is near a half-space, where it
    /// rejects nothing. The allowance, 1e-3 rad, covers the angles' float acos, which returns 0
    /// for unit vectors up to 3.5e-4 rad apart, and keeps cos θ below 1 in float (a cone stored as
    /// cos θ = 1 would be tested as a single direction).
    static void setCone(EdgeClusterNode& node, vec3 axis, float halfAngle) {
        if (!(halfAngle + 1e-3f < 1.52f)) return;
        node.halfAngle = halfAngle + 1e-3f;
        node.cone = vec4(axis, std::cos(node.halfAngle));
    }

    void merge(std::uint32_t index, std::uint32_t a, std::uint32_t b) {
        EdgeClusterNode& node = tree.nodes[index];
        const EdgeClusterNode &na = tree.nodes[a], &nb = tree.nodes[b];
        node.ball = ballAround(na.ball, nb.ball);
        const vec3 centre(node.ball);
        node.conditioning = std::max(na.conditioning, nb.conditioning);
        node.cone = vec4(0.f, 0.f, 1.f, -1.f);
        node.halfAngle = -1.f;
        if (na.cone.w < 0.f || nb.cone.w < 0.f) return;
        const vec3 sum = vec3(na.cone) + vec3(nb.cone);
        const float sumLength = stsv::length(sum);
        if (!(sumLength > 0.f)) return;
        const vec3 axis = sum / sumLength;
        const auto spread = [&](const EdgeClusterNode& child) {
            return std::acos(std::clamp(dot(axis, vec3(child.cone)), -1.f, 1.f)) + child.halfAngle;
        };
        setCone(node, axis, std::max(spread(na), spread(nb)));
    }
};

} // namespace

EdgeClusterNode edgeCluster(const EdgeAdjacency& adj, std::uint32_t edge, vec3 turn) {
    const std::uint32_t item = 0;
    const Builder b{adj, std::span(&edge, 1), std::span(&turn, 1), {}, {}, 1.f};
    return b.leaf(std::span(&item, 1), 0, 1);
}

EdgeClusterTree buildEdgeClusters(const EdgeAdjacency& adj, const std::vector<std::uint32_t>& edges,
                                  const std::vector<vec3>& turn, float scale) {
    Builder b{adj, edges, turn, {}, {}, scale > 0.f ? 64.f / scale : 1.f};
    b.points.resize(edges.size());
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, std::uint32_t(edges.size()), 4096),
                      [&](const tbb::blocked_range<std::uint32_t>& range) {
                          for (std::uint32_t i = range.begin(); i < range.end(); ++i) {
                              const MeshEdge& edge = adj.edges[edges[i]];
                              std::array<vec3, 2> n{vec3(0.f), vec3(0.f)};
                              float conditioning = 0.f;
                              const bool coned = b.normals(i, n, conditioning);
                              const vec3 mean = n[0] + n[1];
                              const float length = stsv::length(mean);
                              b.points[i] = {0.5f * (adj.positions[edge.v0] + adj.positions[edge.v1]),
                                             coned && length > 0.f ? mean / length : vec3(0.f), coned};
                          }
                      });
    if (edges.empty()) return std::move(b.tree);
    // Edges without a cone apart from the rest, so that they widen no cone: the root's first
    // child holds the coned edges, its second the others (when both kinds exist).
    b.tree.items.resize(edges.size());
    for (std::uint32_t i = 0; i < edges.size(); ++i) b.tree.items[i] = i;
    const auto split =
        static_cast<std::uint32_t>(std::stable_partition(b.tree.items.begin(), b.tree.items.end(),
                                                         [&](std::uint32_t i) { return b.points[i].coned; }) -
                                   b.tree.items.begin());
    const auto total = static_cast<std::uint32_t>(edges.size());
    if (split == 0 || split == total) {
        b.tree.nodes.resize(Builder::subtreeNodes(total));
        b.build(0, 0, total, 1);
    } else {
        b.tree.nodes.resize(3 + Builder::subtreeNodes(split) - 1 + Builder::subtreeNodes(total - split) - 1);
        b.tree.nodes[0].first = 1;
        b.build(1, 0, split, 3);
        b.build(2, split, total - split, 3 + Builder::subtreeNodes(split) - 1);
        b.merge(0, 1, 2);
    }
    for (const EdgeClusterNode& node : b.tree.nodes) b.tree.leaves += node.count > 0 ? 1u : 0u;
    return std::move(b.tree);
}

} // namespace stsv
