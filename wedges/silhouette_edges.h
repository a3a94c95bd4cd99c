// The potential silhouette edges of one light, as both backends' DCS and PW passes read them
// (DESIGN §4.5): the edges with a carrier face, in (carrier, edge) order, the tree of clusters
// over them (wedges/edge_clusters.h), each edge packed with its faces, and per carrier face the
// bound of its edges' wedges. The CPU mirror (wedges/cpu/cpu_wedges.cpp) walks them per screen
// tile; the Vulkan renderer uploads them for its cluster pass (wedges/shaders/dcs_clusters.comp).
#pragma once

#include "scene/scene.h"
#include "volumes/light_planes_dh.h"
#include "volumes/volume_dh.h"
#include "wedges/adjacency.h"
#include "wedges/dcs_dh.h"
#include "wedges/edge_clusters.h"
#include "wedges/wedge_bound_dh.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace stsv {

/// A face of an edge, copied next to it (PackedEdge).
struct PackedFace {
    vec3 opposite; ///< the face's vertex opposite the edge
    uint triangle; ///< scene triangle
    vec3 normal;   ///< dcsFaceNormal(v0, v1, opposite) (0 for an unused face): the per-point test's plane
};

/// The data access of wedges/wedge_fragment_dh.h on the CPU: the edge's faces copied next to it
/// (`local`, two at most) or, for an edge with more, in the adjacency.
struct WedgeFaces {
    const EdgeAdjacency* adjacency;
    const PackedFace* local; ///< null: the faces first … first + count − 1 of the adjacency
    uint first;
    uint count;
};

/// One non-degenerate carrier face's bound of the wedges of the potential silhouette edges it
/// carries (wedges/adjacency.h edgeCarriers), by the rule of wedge_bindings.glsl
/// wedgeSetupBound: its STSV volume of each side the light sees, and its light planes. A segment
/// that touches an edge touches the closed face, which STSV bounds conservatively. Trivial, so
/// that storage for every carrier costs no page until a pixel needs its bound.
struct FaceBound {
    StsvVolume volumes[2];
    StsvLightPlanes lightPlanes;
    std::uint32_t volumeCount;

    bool contains(vec3 p) const {
        bool inside = false;
        for (std::uint32_t v = 0; v < volumeCount && !inside; ++v) inside = stsvPointInVolume(volumes[v], p);
        return inside && stsvPointInLightPlanes(lightPlanes, p);
    }
};

/// One potential silhouette edge as a pixel reads it: its vertices and, for two faces at most,
/// the faces themselves.
struct PackedEdge {
    vec3 v0, v1;
    std::uint32_t item; ///< the edge's index in (carrier, edge) order
    std::uint32_t faceCount;
    std::uint32_t firstFace; ///< into the adjacency's faces
    PackedFace faces[2];     ///< the first two (unused ones: NO_TRIANGLE)

    WedgeFaces wedgeFaces(const EdgeAdjacency& adj) const {
        return faceCount <= 2 ? WedgeFaces{&adj, faces, 0u, faceCount}
                              : WedgeFaces{&adj, nullptr, firstFace, faceCount};
    }
};

/// What the per-point silhouette test of an edge of one or two faces reads (dcsTwoFaceWeight), as
/// lanes: one array per component, in the tree's item order, so that a pixel tests LANES edges of
/// a leaf at once. Each array is padded by LANES − 1 entries, so that LANES consecutive positions
/// from any edge can be read. An edge of more than two faces has `many` set (its test is
/// wedgeWorldWeight's, one at a time).
struct EdgeSideLanes {
    static constexpr std::size_t LANES = 4;
    std::vector<float> v0[3];          ///< the edge's first vertex, x, y, z
    std::vector<float> n0[3];          ///< its first face's normal (PackedFace::normal)
    std::vector<float> n1[3];          ///< its second face's normal (0 when it has one face)
    std::vector<std::uint32_t> t0, t1; ///< their scene triangles (NO_TRIANGLE for none)
    std::vector<std::uint32_t> many;   ///< all bits set for an edge of more than two faces, else 0
};

namespace side_lanes {
using FloatLanes = float __attribute__((vector_size(4 * EdgeSideLanes::LANES)));
using IntLanes = std::int32_t __attribute__((vector_size(4 * EdgeSideLanes::LANES)));
static_assert(EdgeSideLanes::LANES == 4, "silhouetteCandidates gathers four lanes' bits");

template <class Lanes, class T> inline Lanes loadLanes(const std::vector<T>& array, std::uint32_t first) {
    Lanes lanes;
    std::memcpy(&lanes, array.data() + first, sizeof lanes);
    return lanes;
}

/// dcsPlaneSide of four edges at once, in the same operations and order (the same result); 0
/// where the face is the receiver's.
inline IntLanes planeSides(const std::vector<float> (&n)[3], const std::vector<float> (&v0)[3],
                           const std::vector<std::uint32_t>& triangle, std::uint32_t first, vec3 p,
                           uint receiver) {
    const FloatLanes s = loadLanes<FloatLanes>(n[0], first) * (loadLanes<FloatLanes>(v0[0], first) - p.x) +
                         loadLanes<FloatLanes>(n[1], first) * (loadLanes<FloatLanes>(v0[1], first) - p.y) +
                         loadLanes<FloatLanes>(n[2], first) * (loadLanes<FloatLanes>(v0[2], first) - p.z);
    const IntLanes side = (s < 0.0f) - (s > 0.0f); // comparisons give −1 where true
    return side & (loadLanes<IntLanes>(triangle, first) != std::int32_t(receiver));
}

} // namespace side_lanes

/// Bit i set where edge first + i of `lanes` may be a silhouette from p: dcsTwoFaceWeight ≠ 0
/// with `receiver`'s face left out, or more than two faces (then wedgeWorldWeight decides). The
/// CPU mirror's first per-pixel test of a leaf's edges, four at a time and without a branch per
/// edge; the weight of those it keeps is computed again, one at a time.
inline std::uint32_t silhouetteCandidates(const EdgeSideLanes& lanes, std::uint32_t first, vec3 p,
                                          uint receiver) {
    using namespace side_lanes;
    const IntLanes weight = planeSides(lanes.n0, lanes.v0, lanes.t0, first, p, receiver) +
                            planeSides(lanes.n1, lanes.v0, lanes.t1, first, p, receiver);
    const IntLanes keep = (weight != 0) | loadLanes<IntLanes>(lanes.many, first);
    return std::uint32_t((keep[0] & 1) | (keep[1] & 2) | (keep[2] & 4) | (keep[3] & 8));
}

/// The potential silhouettes of one light with a carrier, in (carrier, edge) order — the order
/// the CPU's pixels visit them in (PW sums in it) — the tree of clusters over them, and their
/// carriers' bounds, each built when first asked for: most carriers never hold a pixel's
/// silhouette edge that crosses its light. `scene` must outlive it.
class SilhouetteEdges {
  public:
    SilhouetteEdges(const Scene& scene, const EdgeAdjacency& adjacency,
                    const std::vector<std::uint32_t>& carriers, const Light& light, float farDistance);

    /// Edge `position` of the tree's items (EdgeClusterTree::items order).
    const PackedEdge& packed(std::uint32_t position) const { return m_packed[position]; }
    /// The silhouette tests' data of the edges, in the same order as packed().
    const EdgeSideLanes& sideLanes() const { return m_sideLanes; }
    /// The adjacency index of item `item`'s edge.
    std::uint32_t edge(std::uint32_t item) const { return m_edges[item]; }
    /// The index of item `item`'s carrier among the carriers (0 … carrierCount() − 1).
    std::uint32_t carrier(std::uint32_t item) const { return m_carrier[item]; }
    std::size_t carrierCount() const { return m_carrierTriangle.size(); }
    /// The normal of item `item`'s carrier (its winding's), which orients the clusters' cones.
    vec3 carrierNormal(std::uint32_t item) const;

    const EdgeClusterTree& tree() const { return m_tree; }
    vec4 light() const { return m_light; } ///< the light's bounding ball (sampling/light_bounds.h)

    /// The bound of item `item`'s carrier, built by the first thread that asks.
    const FaceBound& bound(std::uint32_t item) const { return carrierBound(m_carrier[item]); }
    /// The bound of carrier `c` (carrier()), built by the first thread that asks.
    const FaceBound& carrierBound(std::uint32_t c) const;

    /// Volumes of the bounds built so far.
    std::size_t volumesBuilt() const { return m_volumes.load(); }

    /// Whether these are the silhouettes of `light` at `farDistance` (its geometry; not its radiance).
    bool isFor(const Light& light, float farDistance) const;

    std::size_t edgeCount() const { return m_edgeCount; }      ///< welded edges of the opaque triangles
    std::size_t potentialCount() const { return m_potential; } ///< of those, potential silhouettes

  private:
    static constexpr std::uint8_t UNBUILT = 0, BUILDING = 1, READY = 2;

    void build(std::uint32_t c) const;

    const Scene& m_scene;
    Light m_lightSource;
    float m_farDistance;
    std::size_t m_edgeCount = 0;
    std::size_t m_potential = 0;
    Bounds m_sceneBounds;
    vec4 m_light;
    std::vector<std::uint32_t> m_edges;   ///< per item, its adjacency edge
    std::vector<std::uint32_t> m_carrier; ///< per item, its carrier's index
    std::vector<std::uint32_t> m_carrierTriangle;
    EdgeClusterTree m_tree;
    std::vector<PackedEdge> m_packed;
    EdgeSideLanes m_sideLanes;
    std::unique_ptr<FaceBound[]> m_bounds;
    std::unique_ptr<std::atomic<std::uint8_t>[]> m_state;
    mutable std::atomic<std::size_t> m_volumes{0};
};

} // namespace stsv
