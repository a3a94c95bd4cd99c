// The STSV technique's GPU interface (DESIGN §4.2, §5): its bindings in set GPU_SET_FAMILY after
// the volume families' shared ones (gpu_volumes_dh.h), its stats, and the record a fragment reads
// about its volume.
#ifndef STSV_RENDER_GPU_STSV_DH_H
#define STSV_RENDER_GPU_STSV_DH_H

#include "core/dh.h"
#include "render/vulkan/gpu_volumes_dh.h"
#include "volumes/extrusion_dh.h"

DH_BEGIN

/// stsv_samples.comp's mask words of the listed fragments, pixel-major (SSBO; bitmask frames).
DH_CONST uint GPU_BINDING_STSV_MASK_WORDS = GPU_BINDING_VOLUME_FAMILY_FIRST;
/// The cluster walk's volumes (stsv_hull.comp with STSV_HULL_RECORDS_ONLY): per item (a side of
/// a triangle: every side 0, then every side 1) its record + 1, 0 without a volume (SSBO).
DH_CONST uint GPU_BINDING_STSV_ITEM_RECORDS = GPU_BINDING_VOLUME_FAMILY_FIRST + 1u;

/// What the STSV passes count per light (atomic counters in the shaders).
struct GpuStsvStats {
    GpuHullCounts hull;    ///< stsv_hull.comp or stsv.mesh
    GpuClusterCounts walk; ///< stsv_clusters.comp
    uint fragments;        ///< fragments that passed the depth test (volume behind the visible point); the
                           ///< walk: (pixel, volume) plane tests
    uint inside;           ///< of those, p inside the volume and on its side: they run the sample loop
    uint listed;     ///< fragments listed for stsv_samples.comp, past the end too (the walk: all parts')
    uint deferred;   ///< listed fragments whose samples stsv_samples.comp tested
    uint listedPart; ///< the most one list held (past the end too): the walk's worst part's
    uint pad0;
    uint pad1;
    uint pad2;
};

/// What an STSV fragment needs about its volume (STSV paper §3): the triangle constants of
/// Eq. 2–5, the volume's planes and the triangle's light planes. Flat varyings of the geometry
/// and mesh shaders; a record of the hull pass, read by index. std430: 18 × 16 bytes.
struct GpuStsvRecord {
    vec4 m0;
    vec4 m1;
    vec4 m2;
    vec4 uv0E1; ///< uv0 (xy), uvE1 (zw)
    vec4 uvE2;  ///< uvE2 (xy), zw unused
    uvec4 ids;  ///< texture, flags, triangle, side | planeCount << 8 | light planes' count << 16
    vec4 planes[STSV_VOLUME_MAX_PLANES];
    vec4 lightPlanes[STSV_LIGHT_PLANES_MAX];
};

/// GpuStsvRecord as 16-byte texels: its ids, its first plane, its first light plane.
DH_CONST uint GPU_STSV_RECORD_IDS = 5u;
DH_CONST uint GPU_STSV_RECORD_PLANES = 6u;
DH_CONST uint GPU_STSV_RECORD_LIGHT_PLANES = 11u;

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuStsvStats) == 64);
DH_STATIC_ASSERT(offsetof(GpuStsvStats, hull) == 0);
DH_STATIC_ASSERT(offsetof(GpuStsvStats, walk) == 16);
DH_STATIC_ASSERT(sizeof(GpuStsvRecord) == 16 * GPU_HULL_RECORD_TEXELS);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, ids) == 16 * GPU_STSV_RECORD_IDS);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, planes) == 16 * GPU_STSV_RECORD_PLANES);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, lightPlanes) == 16 * GPU_STSV_RECORD_LIGHT_PLANES);
#endif

DH_END

#endif // STSV_RENDER_GPU_STSV_DH_H
