// The GPU interface the volume families share (DESIGN §4.2, §5): the hull buffers and the list of
// deferred fragments and the cluster walk's lists, which the STSV technique (gpu_stsv_dh.h) and the wedge
// technique (gpu_wedges_dh.h) both bind in their set GPU_SET_FAMILY (render/vulkan/gpu_hulls.h,
// gpu_deferred.h), one pass after the other; the counts every volume family keeps first in its
// stats.
#ifndef STSV_RENDER_GPU_VOLUMES_DH_H
#define STSV_RENDER_GPU_VOLUMES_DH_H

#include "core/dh.h"
#include "render/vulkan/gpu_frame_dh.h"

DH_BEGIN

// Set GPU_SET_FAMILY of a volume family, after GPU_BINDING_FAMILY_STATS.
DH_CONST uint GPU_BINDING_HULL_DRAW = 1u;          ///< GpuHullDraw: draw arguments and counts (SSBO)
DH_CONST uint GPU_BINDING_HULL_RECORDS = 2u;       ///< the hulls' records, 18 uvec4 each (SSBO)
DH_CONST uint GPU_BINDING_HULL_VERTICES = 3u;      ///< uvec4 per hull vertex: xyz bits, record (SSBO)
DH_CONST uint GPU_BINDING_HULL_RECORD_TEXELS = 4u; ///< the records as rgba32ui texels
DH_CONST uint GPU_BINDING_HULL_VERTEX_TEXELS = 5u; ///< the hull vertices as rgba32ui texels
DH_CONST uint GPU_BINDING_DEFERRED_COUNT = 6u;     ///< uvec4, x: fragments deferred (SSBO)
DH_CONST uint GPU_BINDING_DEFERRED = 7u;           ///< uvec2 per deferred fragment: pixel, item (SSBO)
/// The cluster walk (render/vulkan/gpu_cluster_walk.h, render/shaders/cluster_walk.glsl): a tree
/// over a family's occluders — its nodes, GPU_CLUSTER_TEXELS rgba32ui each (ball, normal cone
/// (w < 0: none), (first, count, and two family words)), and its items, GPU_CLUSTER_TEXELS each
/// too — walked per 16 × 16 tile of pixels to the leaves, then per 4 × 4 block, level by level,
/// over lists of pairs: the pairs (tile or block, node) of each level, in two lists that
/// alternate; the (block, item) pairs it keeps; a family's candidates for its remaining tests —
/// GPU_CLUSTER_LISTS lists of the same capacity one after the other in one buffer; their counts
/// (per level, then the kept pairs', the candidates'); each block's and each tile's box of
/// visible points (lo, hi); the indirect dispatch of the next pass.
DH_CONST uint GPU_BINDING_CLUSTER_COUNTS = 8u;
DH_CONST uint GPU_BINDING_CLUSTER_PAIRS = 9u;
DH_CONST uint GPU_BINDING_CLUSTER_BLOCKS = 10u;
DH_CONST uint GPU_BINDING_CLUSTER_DISPATCH = 11u;
DH_CONST uint GPU_BINDING_CLUSTER_NODES = 12u;
DH_CONST uint GPU_BINDING_CLUSTER_ITEMS = 13u;
/// GPU_DEFERRED_TERM_TEXELS uvec4 per deferred fragment, where the pass that lists a fragment also
/// computes what its sample loop needs (DCS's walk: the edge term, wedges/shaders/wedge_term.glsl
/// wedgeTermStore); else a stand-in (SSBO).
DH_CONST uint GPU_BINDING_DEFERRED_TERMS = 14u;
DH_CONST uint GPU_DEFERRED_TERM_TEXELS = 2u;
/// The first binding a volume family declares for itself.
DH_CONST uint GPU_BINDING_VOLUME_FAMILY_FIRST = 15u;

DH_CONST uint GPU_CLUSTER_TEXELS = 3u;
DH_CONST uint GPU_CLUSTER_LISTS = 4u;
/// Levels of a tree the walk takes at most (the counts' slots before the kept pairs').
DH_CONST uint GPU_CLUSTER_MAX_DEPTH = 64u;
DH_CONST uint GPU_CLUSTER_KEPT = GPU_CLUSTER_MAX_DEPTH;            ///< the counts' slot of the kept pairs
DH_CONST uint GPU_CLUSTER_CANDIDATES = GPU_CLUSTER_MAX_DEPTH + 1u; ///< and of the candidates
DH_CONST uint GPU_CLUSTER_COUNT_SLOTS = GPU_CLUSTER_MAX_DEPTH + 2u;
/// Entries an invocation of a cluster pass takes (its workgroups are sized so, up to 65 535 of
/// them; past 2^27 entries in a list, more): lavapipe ends a shader's loops after 65 535
/// iterations in all, so no invocation may loop without bound. The args pass sizes the walk of
/// a level (GpuPush::step < GPU_CLUSTER_KEPT: its list), the pass over the kept pairs (step =
/// GPU_CLUSTER_KEPT) or the one over the candidates (step = GPU_CLUSTER_CANDIDATES).
DH_CONST uint GPU_CLUSTER_ENTRIES_PER_INVOCATION = 64u;
/// Entries a workgroup of a cluster pass gathers in shared memory before it writes them to their
/// lists (render/shaders/cluster_walk.glsl groupAppend): its invocations × the most one appends for an
/// entry it reads (a tile's 16 blocks, a leaf's items, a block's 16 pixels).
DH_CONST uint GPU_CLUSTER_GROUP_ENTRIES = 1024u;
/// Invocations of a workgroup of the STSV walk (leaves of BallTree::LEAF = 16 triangles, kept
/// one pair each) and of the DCS walk (a leaf kept as one pair; 32 measured no slower than 64).
DH_CONST uint GPU_STSV_CLUSTER_GROUP = 64u;
DH_CONST uint GPU_DCS_CLUSTER_GROUP = 32u;

/// What a hull pass counts per light: the first member of its family's stats (GpuStsvStats,
/// GpuWedgeStats), where render/vulkan/gpu_hulls.cpp reads it to size the hull buffers.
struct GpuHullCounts {
    uint volumes;   ///< volumes the hull pass (stsv_hull.comp, wedge_hull.comp) or mesh shader built
    uint triangles; ///< triangles of their hulls drawn (those facing away from the eye)
    uint overflow;  ///< mesh shader: volumes whose hull outgrew a mesh workgroup's outputs (none drawn)
    uint pad;
};

/// What a cluster walk counts per light: the second member of its family's stats.
struct GpuClusterCounts {
    uint tests;       ///< (tile or block, node) and (block, item) tests of the walk (DCS tests a
                      ///< leaf's items only for a block with a pixel whose rays meet its ball)
    uint rejected;    ///< of those, the clusters no point of the block can be shadowed by
    uint pairsNeeded; ///< the most pairs a cluster list needed, when more than it held (else 0)
    uint pad;
};

/// A hull pass's record of one volume: GPU_HULL_RECORD_TEXELS 16-byte texels (GpuStsvRecord,
/// GpuWedgeRecord), read by the fragments of hull.vert through their flat record index.
DH_CONST uint GPU_HULL_RECORD_TEXELS = 18u;

/// Items (sides of a triangle or a carrier face) per thread of a hull pass, at most: a workgroup
/// first finds which of its threads × HULL_ITEMS_PER_THREAD items have a volume (a cheap test),
/// then its threads build and clip those, so that a SIMD batch clips as many volumes as it has
/// lanes (render/vulkan/gpu_hulls.cpp chooses HULL_ITEMS_PER_THREAD per device).
DH_CONST uint GPU_HULL_MAX_ITEMS_PER_THREAD = 16u;

/// A hull pass's counts and the arguments of the indirect draw of its triangles (the first
/// four words are a VkDrawIndirectCommand). Zeroed before each hull pass.
struct GpuHullDraw {
    uint vertexCount;   ///< 3 × the triangles appended
    uint instanceCount; ///< 1, written by the hull pass
    uint firstVertex;
    uint firstInstance;
    uint records; ///< records appended
    uint pad0;
    uint pad1;
    uint pad2;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuHullCounts) == 16);
DH_STATIC_ASSERT(sizeof(GpuClusterCounts) == 16);
DH_STATIC_ASSERT(sizeof(GpuHullDraw) == 32);
#endif

DH_END

#endif // STSV_RENDER_GPU_VOLUMES_DH_H
