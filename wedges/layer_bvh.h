// The hierarchy over the opaque triangles that D(r), the layer count at the light centre, is
// counted through (wedges/layer_bvh_dh.h): one tree per scene, for every light and pixel. The
// Vulkan renderer uploads its tables (wedges/shaders/dcs_center.comp); the CPU mirror runs the
// same traversal (layerCount, wedges/cpu/cpu_wedges.cpp).
#pragma once

#include "core/dh.h"
#include "scene/scene.h"
#include "wedges/layer_bvh_dh.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// The tables of layer_bvh_dh.h.
struct LayerBvhTables {
    std::vector<uvec4> nodes;     ///< LAYER_BVH_NODE_TEXELS a node, node 0 the root
    std::vector<uvec4> triangles; ///< LAYER_BVH_TRIANGLE_TEXELS a triangle, leaf after leaf
    std::uint32_t depth = 0;      ///< levels of nodes (0: no triangle)

    std::uint32_t nodeCount() const {
        return static_cast<std::uint32_t>(nodes.size() / LAYER_BVH_NODE_TEXELS);
    }
};

/// The tree over the scene's opaque occluders (Scene::opaqueOccluder), split at the median of
/// the longest axis of the triangles' centres down to leaves of LAYER_BVH_LEAF_MAX, each box
/// grown by more than the crossing test's rounding for points of the scene's bounds.
/// Deterministic.
LayerBvhTables buildLayerBvh(const Scene& scene);

/// layer_bvh_dh.h layerCount on the CPU: the opaque triangles the segment p → r crosses at t in
/// [tMin, 1] of r − p, scene triangle `ignore` left out, stopping after `maxVisits` node visits
/// as the GPU does (work.cutShort).
std::uint32_t layerCount(const LayerBvhTables& tables, vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                         LayerCountWork& work, std::uint32_t maxVisits = LAYER_BVH_MAX_VISITS);

/// layer_bvh_dh.h layerCountGaps on the CPU: layerCount, and whether an opaque triangle other
/// than `ignore` meets a gap of `gaps` (gapMet).
std::uint32_t layerCountGaps(const LayerBvhTables& tables, vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                             const LayerGaps& gaps, LayerCountWork& work, bool& gapMet,
                             std::uint32_t maxVisits = LAYER_BVH_MAX_VISITS);

} // namespace stsv
