// The wedge technique's GPU interface (DESIGN §4.5, §5): its bindings in set GPU_SET_FAMILY after
// the volume families' shared ones (gpu_volumes_dh.h), its stats, the welded-edge tables and the
// record a fragment reads about its carrier's bound.
#ifndef STSV_RENDER_GPU_WEDGES_DH_H
#define STSV_RENDER_GPU_WEDGES_DH_H

#include "core/dh.h"
#include "render/vulkan/gpu_volumes_dh.h"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"

DH_BEGIN

DH_CONST uint GPU_BINDING_EDGES =
    GPU_BINDING_VOLUME_FAMILY_FIRST; ///< GpuEdge[]: welded edges of the opaque triangles (SSBO)
DH_CONST uint GPU_BINDING_EDGE_FACES = GPU_BINDING_EDGES + 1u; ///< GpuEdgeFace[], grouped per edge (SSBO)
DH_CONST uint GPU_BINDING_CARRIER_TEXELS =
    GPU_BINDING_EDGES + 2u; ///< rgba32ui per carrier face: triangle, its carried edges
DH_CONST uint GPU_BINDING_EDGE_TEXELS =
    GPU_BINDING_EDGES + 3u; ///< GpuEdge[] as rgba32ui texels, GPU_EDGE_TEXELS each
DH_CONST uint GPU_BINDING_EDGE_FACE_TEXELS = GPU_BINDING_EDGES + 4u; ///< GpuEdgeFace[] as rgba32ui texels
DH_CONST uint GPU_BINDING_CENTER =
    GPU_BINDING_EDGES + 5u; ///< r32i storage image: the layer count D(r) at the light centre

/// A light's potential silhouettes for the cluster walk (dcs_clusters.comp; render/vulkan/
/// gpu_wedge_clusters.cpp uploads them per light, wedges/silhouette_edges.h): the tree's nodes
/// (data: first, count, conditioning, 0) and its items, each edge as a cluster of its
/// own (edge_clusters.h edgeCluster; data: adjacency edge, carrier, conditioning, 0),
/// bound at the shared GPU_BINDING_CLUSTER_NODES and _ITEMS (gpu_volumes_dh.h); the carriers'
/// bounds, GPU_CLUSTER_BOUND_TEXELS each ((volumes, planes of volume 0, of volume 1, light
/// planes), the two volumes' planes, the light planes).
DH_CONST uint GPU_BINDING_CLUSTER_BOUNDS = GPU_BINDING_EDGES + 6u;
/// rgba32ui texels: the nodes and the triangles of the tree D(r) is counted through
/// (wedges/layer_bvh_dh.h; dcs_center.comp).
DH_CONST uint GPU_BINDING_LAYER_NODES = GPU_BINDING_EDGES + 7u;
DH_CONST uint GPU_BINDING_LAYER_TRIANGLES = GPU_BINDING_EDGES + 8u;
DH_CONST uint GPU_CLUSTER_BOUND_TEXELS = 1u + 2u * STSV_VOLUME_MAX_PLANES + STSV_LIGHT_PLANES_MAX;
/// uint[] (SSBO), DCS's choice between crossings and rays (dcsBlockCastsRays, layerCountGaps;
/// dcs_center.comp, dcs_clusters.comp, dcs_rays.comp): the indirect dispatch of the rays
/// (GPU_DCS_RAY_DISPATCH), the count of the blocks listed for rays (GPU_DCS_RAY_BLOCK_COUNT), then
/// per block of the frame the edges the walk kept for it (GPU_DCS_BLOCK_EDGES + block; 0 without
/// the walk) with GPU_DCS_BLOCK_GAP, then the list of the blocks with rays to cast, then a bit a
/// pixel (dcsPixelGapWord): its segments' gaps meet a triangle.
DH_CONST uint GPU_BINDING_DCS_BLOCKS = GPU_BINDING_EDGES + 9u;
DH_CONST uint GPU_DCS_RAY_DISPATCH = 0u; ///< x, y, z of vkCmdDispatchIndirect
DH_CONST uint GPU_DCS_RAY_BLOCK_COUNT = 3u;
DH_CONST uint GPU_DCS_BLOCK_EDGES = 4u;
/// The top bit of a block's word: a pixel of the block has segment gaps that meet a triangle
/// (set by dcs_center.comp), so the block is listed for rays whatever its edges. The walk's sum of
/// edges stays below it (a block keeps fewer than 2^31 edges).
DH_CONST uint GPU_DCS_BLOCK_GAP = 0x80000000u;

/// Whether all the pixels of the block whose word is `word` count their samples through the layer
/// tree: its kept edges exceed `edgesPerSample` per sample (dcsBlockCastsRays).
DH_FUNC bool dcsBlockWordCastsRays(uint word, uint samples, float edgesPerSample) {
    return dcsBlockCastsRays(word & ~GPU_DCS_BLOCK_GAP, samples, edgesPerSample);
}

/// The word of the buffer that holds pixel `pixelIndex`'s gap bit (1u << pixelIndex % 32), for a
/// frame of `blocks` blocks.
DH_FUNC uint dcsPixelGapWord(uint blocks, uint pixelIndex) {
    return GPU_DCS_BLOCK_EDGES + 2u * blocks + pixelIndex / 32u;
}

/// A workgroup of dcs_rays.comp's rays: each of a block's 16 pixels with 4 of its samples.
DH_CONST uint GPU_DCS_RAY_SAMPLES_PER_GROUP = 4u;
/// The most workgroups along x of the rays' dispatch (the least maxComputeWorkGroupCount[0] a device has).
DH_CONST uint GPU_DCS_RAY_GROUPS_MAX = 65535u;

DH_CONST uint GPU_NO_EDGE = 0xffffffffu; ///< an empty slot of a carrier's edges

/// What the wedge passes count per light (atomic counters in the shaders).
struct GpuWedgeStats {
    GpuHullCounts hull;    ///< wedge_hull.comp or wedge.mesh
    GpuClusterCounts walk; ///< dcs_clusters.comp
    uint fragments;        ///< wedge-pass fragments that passed the depth test
    uint inside;           ///< of those, p inside the bound with the edge a silhouette seen from p
    uint listed; ///< DCS fragments listed for wedge_samples.comp, past the end too (the walk: all parts')
    uint centerVisits;   ///< tree nodes the segments p → r visited (dcs_center.comp)
    uint centerTests;    ///< triangles they were tested with
    uint listedPart;     ///< the most one list held (past the end too): the walk's worst part's
    uint centerCutShort; ///< segments whose count stopped at LAYER_BVH_MAX_VISITS
    uint rayPixels;      ///< covered pixels whose block cast rays (dcs_rays.comp)
};

/// What a wedge fragment needs about its carrier's bound (wedge.geom's flat varyings, or a
/// record of the wedge hull pass): ids = (carrier, side | light planes' count << 8 | the
/// carried edges that are potential silhouettes << 16 (bit k: slot k), planeCount,
/// WEDGE_SIDE0_PRESENT | side 0's planeCount), the volume's planes, side 0's planes (side 1
/// leaves their points to side 0), the carrier's light planes. std430: 18 × 16 bytes.
struct GpuWedgeRecord {
    uvec4 ids;
    vec4 planes[STSV_VOLUME_MAX_PLANES];
    vec4 planesSide0[STSV_VOLUME_MAX_PLANES];
    vec4 lightPlanes[STSV_LIGHT_PLANES_MAX];
};

/// GpuWedgeRecord as 16-byte texels.
DH_CONST uint GPU_WEDGE_RECORD_PLANES = 1u;
DH_CONST uint GPU_WEDGE_RECORD_PLANES_SIDE0 = 6u;
DH_CONST uint GPU_WEDGE_RECORD_LIGHT_PLANES = 11u;

/// One welded edge of the opaque triangles (wedges/adjacency.h). std430: 2 × 16 bytes.
struct GpuEdge {
    vec3 v0;        ///< world units
    uint firstFace; ///< into GpuEdgeFace[]
    vec3 v1;        ///< world units
    uint faceCount; ///< 1 open, 2 manifold, > 2 non-manifold
};

/// GpuEdge as 16-byte texels: (v0, firstFace), (v1, faceCount).
DH_CONST uint GPU_EDGE_TEXELS = 2u;

/// One triangle incident to an edge. std430: 16 bytes.
struct GpuEdgeFace {
    vec3 opposite; ///< world units; the triangle's third vertex
    uint triangle; ///< scene triangle index
};

/// GpuEdgeFace as 16-byte texels: (opposite, triangle).
DH_CONST uint GPU_EDGE_FACE_TEXELS = 1u;

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuWedgeStats) == 64);
DH_STATIC_ASSERT(offsetof(GpuWedgeStats, hull) == 0);
DH_STATIC_ASSERT(offsetof(GpuWedgeStats, walk) == 16);
DH_STATIC_ASSERT(sizeof(GpuWedgeRecord) == 16 * GPU_HULL_RECORD_TEXELS);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, planes) == 16 * GPU_WEDGE_RECORD_PLANES);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, planesSide0) == 16 * GPU_WEDGE_RECORD_PLANES_SIDE0);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, lightPlanes) == 16 * GPU_WEDGE_RECORD_LIGHT_PLANES);
DH_STATIC_ASSERT(sizeof(GpuEdge) == 32);
DH_STATIC_ASSERT(sizeof(GpuEdgeFace) == 16);
#endif

DH_END

#endif // STSV_RENDER_GPU_WEDGES_DH_H
