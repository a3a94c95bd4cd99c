#include "wedges/adjacency.h"

#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace stsv {

namespace {

/// Bit pattern of a position with −0 folded into +0, for exact-position welding.
struct PositionKey {
    std::uint32_t bits[3];
    bool operator==(const PositionKey& o) const { return std::memcmp(bits, o.bits, sizeof bits) == 0; }
};

PositionKey keyOf(vec3 p) {
    PositionKey k{};
    for (int c = 0; c < 3; ++c) {
        const float v = p[c] == 0.0f ? 0.0f : p[c];
        std::memcpy(&k.bits[c], &v, sizeof v);
    }
    return k;
}

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint32_t b : k.bits) h = (h ^ b) * 1099511628211ull;
        return std::size_t(h ^ (h >> 29));
    }
};

struct HalfEdge {
    std::uint32_t v0, v1; ///< sorted
    EdgeFace face;
};

} // namespace

EdgeAdjacency buildEdgeAdjacency(const Scene& scene, const std::function<bool(std::size_t)>& include) {
    EdgeAdjacency adj;
    constexpr std::uint32_t NONE = std::numeric_limits<std::uint32_t>::max();
    adj.weldedVertex.assign(scene.positions.size(), NONE);
    std::unordered_map<PositionKey, std::uint32_t, PositionHash> welded;
    auto weld = [&](std::uint32_t v) {
        if (adj.weldedVertex[v] != NONE) return adj.weldedVertex[v];
        const auto [it, inserted] =
            welded.try_emplace(keyOf(scene.positions[v]), std::uint32_t(adj.positions.size()));
        if (inserted) adj.positions.push_back(scene.positions[v]);
        adj.weldedVertex[v] = it->second;
        return it->second;
    };

    std::vector<HalfEdge> halfEdges;
    halfEdges.reserve(scene.triangleCount() * 3);
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (include && !include(t)) continue;
        ++adj.triangles;
        const uvec3 idx = scene.triangles[t];
        const std::uint32_t w[3] = {weld(idx.x), weld(idx.y), weld(idx.z)};
        if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
            ++adj.degenerateSkipped;
            continue;
        }
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t a = w[i], b = w[(i + 1) % 3], o = w[(i + 2) % 3];
            halfEdges.push_back({std::min(a, b), std::max(a, b), {std::uint32_t(t), o, a < b}});
        }
    }
    std::sort(halfEdges.begin(), halfEdges.end(), [](const HalfEdge& x, const HalfEdge& y) {
        if (x.v0 != y.v0) return x.v0 < y.v0;
        if (x.v1 != y.v1) return x.v1 < y.v1;
        return x.face.triangle < y.face.triangle;
    });
    adj.faces.reserve(halfEdges.size());
    for (std::size_t i = 0; i < halfEdges.size();) {
        std::size_t j = i;
        MeshEdge edge{halfEdges[i].v0, halfEdges[i].v1, std::uint32_t(adj.faces.size()), 0};
        for (; j < halfEdges.size() && halfEdges[j].v0 == edge.v0 && halfEdges[j].v1 == edge.v1; ++j)
            adj.faces.push_back(halfEdges[j].face);
        edge.faceCount = std::uint32_t(j - i);
        if (edge.faceCount == 1)
            ++adj.openEdges;
        else if (edge.faceCount == 2) {
            ++adj.manifoldEdges;
            if (adj.faces[edge.firstFace].forward == adj.faces[edge.firstFace + 1].forward)
                ++adj.inconsistentEdges;
        } else
            ++adj.nonManifoldEdges;
        adj.edges.push_back(edge);
        i = j;
    }
    return adj;
}

std::vector<std::uint32_t> potentialSilhouetteEdges(const EdgeAdjacency& adj, vec4 lightSphere) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t e = 0; e < adj.edges.size(); ++e) {
        const MeshEdge& edge = adj.edges[e];
        if (edge.faceCount != 2) {
            out.push_back(e);
            continue;
        }
        const vec3 q0 = adj.positions[edge.v0], q1 = adj.positions[edge.v1];
        if (dcsPotentialSilhouette(q0, q1, adj.positions[adj.faces[edge.firstFace].opposite],
                                   adj.positions[adj.faces[edge.firstFace + 1].opposite], lightSphere))
            out.push_back(e);
    }
    return out;
}

std::vector<std::uint32_t> edgeCarriers(const EdgeAdjacency& adj, const Scene& scene) {
    std::vector<std::uint32_t> carriers(adj.edges.size(), NO_CARRIER);
    for (std::size_t e = 0; e < adj.edges.size(); ++e) {
        const MeshEdge& edge = adj.edges[e];
        for (std::uint32_t f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f) {
            const uvec3 i = scene.triangles[adj.faces[f].triangle];
            if (stsvTriangleIsDegenerate(scene.positions[i.x], scene.positions[i.y], scene.positions[i.z]))
                continue;
            carriers[e] = adj.faces[f].triangle;
            break;
        }
    }
    return carriers;
}

} // namespace stsv
