#include "wedges/silhouette_edges.h"

#include "core/gbuffer.h"
#include "core/parallel.h"
#include "sampling/light_bounds.h"

#include <algorithm>
#include <thread>
#include <utility>

namespace stsv {

SilhouetteEdges::SilhouetteEdges(const Scene& scene, const EdgeAdjacency& adj,
                                 const std::vector<std::uint32_t>& carriers, const Light& light,
                                 float farDistance)
    : m_scene(scene), m_lightSource(light), m_farDistance(farDistance) {
    m_sceneBounds = m_scene.bounds();
    m_light = lightBoundingSphere(light, m_sceneBounds, farDistance);
    const std::vector<std::uint32_t> candidates = potentialSilhouetteEdges(adj, m_light);
    m_edgeCount = adj.edges.size();
    m_potential = candidates.size();
    // Grouped by carrier face; an edge without a carrier has k_e = 0 for every p and is dropped.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> byFace; // (triangle, edge)
    byFace.reserve(candidates.size());
    for (std::uint32_t e : candidates)
        if (carriers[e] != NO_CARRIER) byFace.emplace_back(carriers[e], e);
    std::sort(byFace.begin(), byFace.end());
    std::vector<vec3> turn; // the carriers' own normals, which orient the clusters' cones
    turn.reserve(byFace.size());
    m_edges.reserve(byFace.size());
    m_carrier.reserve(byFace.size());
    for (std::size_t i = 0; i < byFace.size(); ++i) {
        if (i == 0 || byFace[i].first != byFace[i - 1].first) m_carrierTriangle.push_back(byFace[i].first);
        m_edges.push_back(byFace[i].second);
        m_carrier.push_back(std::uint32_t(m_carrierTriangle.size() - 1));
        turn.push_back(carrierNormal(std::uint32_t(i)));
    }
    m_bounds = std::make_unique_for_overwrite<FaceBound[]>(m_carrierTriangle.size());
    m_state = std::make_unique<std::atomic<std::uint8_t>[]>(m_carrierTriangle.size());
    m_tree = buildEdgeClusters(adj, m_edges, turn, m_sceneBounds.diameter());

    // What a pixel reads of each edge, leaf after leaf.
    m_packed.resize(m_tree.items.size());
    parallelForChunks(m_packed.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const MeshEdge& edge = adj.edges[m_edges[m_tree.items[k]]];
            PackedEdge& e = m_packed[k];
            e.v0 = adj.positions[edge.v0];
            e.v1 = adj.positions[edge.v1];
            e.item = m_tree.items[k];
            e.faceCount = edge.faceCount;
            e.firstFace = edge.firstFace;
            for (uint f = 0; f < 2; ++f) {
                const bool has = f < edge.faceCount;
                const EdgeFace& face = adj.faces[edge.firstFace + (has ? f : 0)];
                const vec3 opposite = has ? adj.positions[face.opposite] : vec3(0.f);
                e.faces[f] = {opposite, has ? face.triangle : NO_TRIANGLE,
                              has ? dcsFaceNormal(e.v0, e.v1, opposite) : vec3(0.f)};
            }
        }
    });
    EdgeSideLanes& lanes = m_sideLanes;
    const std::size_t padded = m_packed.size() + EdgeSideLanes::LANES - 1;
    for (int c = 0; c < 3; ++c) {
        lanes.v0[c].assign(padded, 0.f);
        lanes.n0[c].assign(padded, 0.f);
        lanes.n1[c].assign(padded, 0.f);
    }
    lanes.t0.assign(padded, NO_TRIANGLE);
    lanes.t1.assign(padded, NO_TRIANGLE);
    lanes.many.assign(padded, 0u);
    for (std::size_t k = 0; k < m_packed.size(); ++k) {
        const PackedEdge& e = m_packed[k];
        for (int c = 0; c < 3; ++c) {
            lanes.v0[c][k] = e.v0[c];
            lanes.n0[c][k] = e.faces[0].normal[c];
            lanes.n1[c][k] = e.faces[1].normal[c];
        }
        lanes.t0[k] = e.faces[0].triangle;
        lanes.t1[k] = e.faces[1].triangle;
        lanes.many[k] = e.faceCount > 2 ? ~0u : 0u;
    }
}

vec3 SilhouetteEdges::carrierNormal(std::uint32_t item) const {
    const uvec3 t = m_scene.triangles[m_carrierTriangle[m_carrier[item]]];
    const vec3 c0 = m_scene.positions[t.x];
    return cross(m_scene.positions[t.y] - c0, m_scene.positions[t.z] - c0);
}

const FaceBound& SilhouetteEdges::carrierBound(std::uint32_t c) const {
    std::atomic<std::uint8_t>& state = m_state[c];
    if (state.load(std::memory_order_acquire) == READY) return m_bounds[c];
    std::uint8_t expected = UNBUILT;
    if (state.compare_exchange_strong(expected, BUILDING, std::memory_order_acq_rel)) {
        build(c);
        state.store(READY, std::memory_order_release);
    } else {
        while (state.load(std::memory_order_acquire) != READY) std::this_thread::yield();
    }
    return m_bounds[c];
}

bool SilhouetteEdges::isFor(const Light& light, float farDistance) const {
    const Light& l = m_lightSource;
    return l.type == light.type && l.position == light.position && l.normal == light.normal &&
           l.radius == light.radius && l.axisU == light.axisU && l.axisV == light.axisV &&
           l.angularRadius == light.angularRadius && m_farDistance == farDistance;
}

void SilhouetteEdges::build(std::uint32_t c) const {
    const uvec3 i = m_scene.triangles[m_carrierTriangle[c]];
    const vec3 c0 = m_scene.positions[i.x], c1 = m_scene.positions[i.y], c2 = m_scene.positions[i.z];
    FaceBound& b = m_bounds[c];
    b.volumeCount = 0;
    b.lightPlanes = stsvNoLightPlanes();
    // Both sides share the face's light planes.
    for (uint side = 0; side < 2; ++side)
        if (wedgeSideBound(c0, c1, c2, m_lightSource, m_light, m_farDistance, m_sceneBounds.lo,
                           m_sceneBounds.hi, side, false, b.volumes[b.volumeCount], b.lightPlanes))
            ++b.volumeCount;
    m_volumes += b.volumeCount;
}

} // namespace stsv
