// STSV through the tree of its triangles' balls on Vulkan (DESIGN §4.5): the tree the CPU pass
// walks (volumes/ball_tree.h), built once when the renderer starts over the triangles the row
// sends through STSV and uploaded as texel tables; per light, stsv_hull.comp builds the volumes'
// records only (STSV_HULL_RECORDS_ONLY) and notes each side's record in the item table, and the
// cluster walk (gpu_cluster_walk.h, volumes/shaders/stsv_clusters.comp) lists the (pixel, volume)
// pairs whose point the volume holds for stsv_samples.comp — in place of the hulls and their draw.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "render/methods.h"
#include "render/options.h"
#include "render/vulkan/gpu_cluster_walk.h"
#include "scene/scene.h"

#include <cstddef>
#include <vector>

namespace stsv {

class Device;

/// Whether a frame's STSV volumes take the cluster walk: the extrusion stage left to the
/// renderer (--extrusion auto).
bool usesStsvClusters(const RenderOptions& options);

/// The tree's tables and the per-frame item table of one frame's STSV walk.
class StsvClusters {
  public:
    /// Over the triangles `which` sends through STSV (those with a volume on some light).
    StsvClusters(const Device& device, const Scene& scene, StsvTriangles which);

    /// The item table's binding in the STSV family's set (gpu_stsv_dh.h).
    static std::vector<DescriptorBinding> bindings();
    /// The tables, the item table and `lists` into a set.
    void writeDescriptors(DescriptorSet& set, const ClusterLists& lists) const;

    std::size_t depth() const { return m_tables.depth; }
    std::size_t leaves() const { return m_leaves; }

    /// Per item (a side of a triangle: every side 0, then every side 1) its record + 1, 0 without
    /// a volume; cleared before each light's records.
    Buffer itemRecords;

  private:
    ClusterTables m_tables;
    std::size_t m_leaves = 0;
};

} // namespace stsv
