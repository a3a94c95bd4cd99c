// The shadow-map technique's GPU interface (DESIGN §4.6, §5): its bindings in set GPU_SET_FAMILY,
// its stats, and the map texel as the rasteriser writes it. Its parameters (ShadowFilterParams)
// and the map's frame (ShadowMapView) are the family's own, in shadowmaps/shadow_map_dh.h.
#ifndef STSV_RENDER_GPU_SHADOWMAPS_DH_H
#define STSV_RENDER_GPU_SHADOWMAPS_DH_H

#include "core/dh.h"
#include "render/vulkan/gpu_frame_dh.h"
#include "shadowmaps/shadow_map_dh.h"

DH_BEGIN

DH_CONST uint GPU_BINDING_SHADOW_MAP =
    1u; ///< the light's map: gpuShadowDepthWord words, faces × size² (SSBO)
DH_CONST uint GPU_BINDING_SHADOW_VIEWS = 2u; ///< ShadowFilterParams then ShadowMapView per light (SSBO)
DH_CONST uint GPU_BINDING_SHADOW_TAPS = 3u;  ///< Poisson-disk taps: blocker set, then filter set (SSBO)

/// What the filter passes count per light.
struct GpuShadowMapStats {
    uint kernelClamped; ///< PCSS: pixels whose filter radius pcss_max_kernel clamped (shadow_filter.comp)
    uint pad0;
    uint pad1;
    uint pad2;
};

/// A map texel as the rasteriser writes it with atomicMax: the bits of the depth (a positive
/// float, whose bits order as its value) inverted, so the nearest surface wins and a cleared
/// word (0) reads as no surface.
DH_FUNC uint gpuShadowDepthWord(float depth) {
    return ~floatBitsToUint(depth);
}
DH_FUNC float gpuShadowDepthOf(uint word) {
    return word == 0u ? SHADOW_MAP_EMPTY : uintBitsToFloat(~word);
}

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuShadowMapStats) == 16);
#endif

DH_END

#endif // STSV_RENDER_GPU_SHADOWMAPS_DH_H
