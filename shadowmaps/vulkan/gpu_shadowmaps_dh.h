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
/// `avsm`, `vpcss`: the light's fragment lists, per texel the head (a fragment's index + 1; 0
/// ends a list) (SSBO), and where the fragments are (GpuAvsmLists, SSBO): one uvec4 each, depth
/// bits, optical-depth units, triangle, the next fragment of its texel's list (index + 1), reached
/// by device address (they outgrow a storage buffer's range: 10 000 particles at 1024² list 56 M,
/// 898 MB). The transmittance functions built from them are reached by device address too
/// (ShadowMapView::representationLow/High), words as gpuAvsmHeader and gpuAvsmNodeWord lay them out.
DH_CONST uint GPU_BINDING_AVSM_HEADS = 4u;
DH_CONST uint GPU_BINDING_AVSM_LISTS = 5u;

struct GpuAvsmLists {
    uint fragmentsLow;  ///< the fragments' device address, low
    uint fragmentsHigh; ///< and high 32 bits
    uint capacity;      ///< fragments they hold
    uint pad0;
};

/// What the shadow-map passes count per light.
struct GpuShadowMapStats {
    uint kernelClamped;  ///< PCSS, vpcss: pixels whose filter radius pcss_max_kernel clamped;
                         ///< PCF: whose taps pcf_max_radius spread more than three texels apart
                         ///< (shadow_filter.comp)
    uint avsmFragments;  ///< fragments listed (avsm_fragments.frag), past the list's end too
    uint avsmTexels;     ///< texels whose function has nodes (avsm_build.comp)
    uint avsmNodes;      ///< nodes over those texels
    uint avsmMaxNodes;   ///< the most nodes of one texel
    uint avsmOverflowed; ///< texels that had more surfaces than nodes
    /// 1 when a fragment found the lists full: with avsmFragments no larger than the lists, its
    /// count wrapped past 2^32
    uint avsmLost;
    uint searchClamped; ///< PCSS, vpcss, fm_kernel=1: pixels whose blocker search pcss_max_search cut
    uint peelCapped;    ///< `peel`: rays that needed more than peel_max_steps (peel_march.comp)
    uint peelStepsLow;  ///< `peel`: the steps of every ray, a 64-bit sum: low 32 bits
    uint peelStepsHigh; ///< and the carries into the high 32
    uint peelLongest;   ///< `peel`: the most steps of one ray
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

/// The words of a light's transmittance functions (`avsm`, `vpcss`), uints: one header per texel
/// (face-major, then row-major as the map), its node count in bits 0–7 and bit 8 set where a
/// node was dropped; then per texel `maxNodes` (depth bits, cumulative units) pairs.
DH_FUNC uint gpuAvsmHeader(uint count, uint overflowed) {
    return count | (overflowed << 8u);
}
DH_FUNC uint gpuAvsmHeaderCount(uint header) {
    return header & 255u;
}
DH_FUNC uint gpuAvsmHeaderOverflowed(uint header) {
    return (header >> 8u) & 1u;
}
/// The word of node j's depth in a map of `texels` texels (its units follow it).
DH_FUNC uint gpuAvsmNodeWord(uint texels, uint texel, uint maxNodes, uint j) {
    return texels + 2u * (texel * maxNodes + j);
}

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuShadowMapStats) == 48);
DH_STATIC_ASSERT(sizeof(GpuAvsmLists) == 16);
#endif

DH_END

#endif // STSV_RENDER_GPU_SHADOWMAPS_DH_H
