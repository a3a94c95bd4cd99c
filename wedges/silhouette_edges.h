// The potential silhouette edges of one light, as both backends' DCS and PW passes read them
// (DESIGN §4.5): the edges with a carrier face, in (carrier, edge) order, the tree of clusters
// over them (wedges/edge_clusters.h), each edge packed with its faces, and per carrier face the
// bound of its edges' wedges. The CPU mirror (render/cpu/cpu_wedges.cpp) walks them per screen
// tile; the Vulkan renderer uploads them for its cluster pass (shaders/wedges/dcs_clusters.comp).
#pragma once

#include "scene/scene.h"
#include "volumes/light_planes_dh.h"
#include "volumes/volume_dh.h"
#include "wedges/adjacency.h"
#include "wedges/dcs_dh.h"
#include "wedges/edge_clusters.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
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
    std::unique_ptr<FaceBound[]> m_bounds;
    std::unique_ptr<std::atomic<std::uint8_t>[]> m_state;
    mutable std::atomic<std::size_t> m_volumes{0};
};

} // namespace stsv
