// DCS through the cluster tree on Vulkan (DESIGN §4.5): each light's potential silhouettes,
// their tree and their carriers' bounds, built on the CPU when the renderer starts
// (wedges/silhouette_edges.h, the tables the CPU mirror walks) and uploaded as texel buffers,
// which the cluster walk (gpu_cluster_walk.h, wedges/shaders/dcs_clusters.comp) reads to list
// the (pixel, edge) pairs that add to the light's counters for wedge_samples.comp. They take the
// place of the wedge hulls and their draw.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "render/options.h"
#include "render/vulkan/gpu_cluster_walk.h"
#include "scene/scene.h"
#include "wedges/adjacency.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

class Device;

/// Whether a frame's opaque occluders take the cluster walk: DCS with the extrusion stage left to
/// the renderer (--extrusion auto). PW sums float coverage and keeps its wedge draw.
bool usesWedgeClusters(const RenderOptions& options);

/// Per light, the tables of dcs_clusters.comp (GPU_BINDING_CLUSTER_NODES, _ITEMS, and
/// gpu_wedges_dh.h GPU_BINDING_CLUSTER_BOUNDS); the stand-ins for a light without potential
/// silhouettes, or for everything when not `build`.
class WedgeClusters {
  public:
    WedgeClusters(const Device& device, const Scene& scene, const EdgeAdjacency& adjacency,
                  const std::vector<std::uint32_t>& carriers, bool build);

    static std::vector<DescriptorBinding> bindings();
    /// Light `light`'s tables and `lists` into its set (a set past the lights gets the stand-in
    /// tables).
    void writeDescriptors(DescriptorSet& set, std::size_t light, const ClusterLists& lists) const;

    /// What one light's tables hold.
    struct Counts {
        std::size_t potentialSilhouettes = 0; ///< potential silhouette edges of the light
        std::size_t leaves = 0;
        std::size_t carriers = 0; ///< bounds
        std::size_t depth = 0;    ///< levels of the tree (a lone root: 1; none: 0)
    };
    /// Per light; empty when not built.
    const std::vector<Counts>& counts() const { return m_counts; }
    /// Kept (block, leaf) pairs an invocation of dcs_clusters.comp's pixel stage takes
    /// (CLUSTER_KEPT_ENTRIES_PER_INVOCATION): dcsKeptPairsPerInvocation of the scene's edges.
    std::uint32_t keptPairsPerInvocation() const { return m_keptPairsPerInvocation; }

  private:
    struct Tables {
        ClusterTables tree;
        Buffer bounds;
        BufferView boundTexels;
    };
    Tables m_empty; ///< the stand-ins' bounds
    std::vector<Tables> m_lights;
    std::vector<Counts> m_counts;
    std::uint32_t m_keptPairsPerInvocation = 1;
};

/// Kept pairs an invocation of DCS's pixel stage may take when no edge has more than `mostFaces`
/// faces: a pair loops up to 1105 + 512·max(F, 1) times (a leaf's 32 edges and the block's 16
/// pixels, then for each edge its pixels, each with wedgeWorldWeight's loop over the faces, and
/// its appends; lavapipe runs a loop once even where every lane skips it), and an invocation
/// stays within half of lavapipe's limit of 65 535 iterations: 15 for a closed mesh, 1 from 63
/// faces. An Error (naming `source`) past 125 faces an edge, where one pair alone could exceed it.
std::uint32_t dcsKeptPairsPerInvocation(std::uint32_t mostFaces, const std::string& source);

} // namespace stsv
