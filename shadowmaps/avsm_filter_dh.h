// Lookups of adaptive volumetric shadow maps (avsm_dh.h) and volumetric PCSS (Klein et al.), as
// the CPU backend (shadowmaps/cpu/cpu_shadowmaps.cpp) runs them per pixel. Compiles as C++ and GLSL
// (core/dh.h). The map is read through a source the includer defines, as shadow_filter_dh.h's:
//   struct AvsmSource                                           what the map is read from
//   uint avsmSourceCount(AvsmSource s, uint face, ivec2 texel)  nodes of the texel
//   float avsmSourceDepth(AvsmSource s, uint face, ivec2 texel, uint j)   depth of node j
//   uint avsmSourceUnits(AvsmSource s, uint face, ivec2 texel, uint j)    its cumulative units
//   vec2 avsmSourceTap(AvsmSource s, uint i)                    Poisson-disk tap i (unit disk)
// and the macro AVSM_SOURCE.
//
// Each tap compares the nodes of its texel with the receiver's plane there less the bias
// (shadowTapTexel), as the depth-map filters compare a depth, so that with opaque blockers only
// `avsm` is a hard shadow test and `vpcss` computes what `pcss` does with the same taps.
#ifndef STSV_SHADOWMAPS_AVSM_FILTER_DH_H
#define STSV_SHADOWMAPS_AVSM_FILTER_DH_H

#ifndef AVSM_SOURCE
#error                                                                                                       \
    "define AvsmSource, avsmSourceCount, avsmSourceDepth, avsmSourceUnits and avsmSourceTap, then AVSM_SOURCE"
#endif

#include "core/dh.h"
#include "shadowmaps/avsm_dh.h"
#include "shadowmaps/shadow_receiver_dh.h"

DH_BEGIN

/// The cumulative units of texel (face, texel) in front of depth `limit`: T(limit) of the texel.
DH_FUNC uint avsmUnitsBefore(AvsmSource src, uint face, ivec2 texel, float limit) {
    uint units = 0u;
    uint count = avsmSourceCount(src, face, texel);
    for (uint j = 0u; j < count; ++j) {
        if (!(avsmSourceDepth(src, face, texel, j) < limit)) break;
        units = avsmSourceUnits(src, face, texel, j);
    }
    return units;
}

/// The transmittance the texel under uv + offset lets through to the receiver's plane there (1
/// outside the map).
DH_FUNC float avsmTapTransmittance(ShadowMapView v, AvsmSource src, ShadowReceiver r, vec2 offset) {
    uint face;
    ivec2 texel;
    float limit;
    if (!shadowTapTexel(v, r, offset, face, texel, limit)) return 1.0f;
    return avsmTransmittance(avsmUnitsBefore(src, face, texel, limit));
}

/// `avsm`: the hard translucent shadow, T of the receiver's own texel at its depth.
DH_FUNC float avsmVisibility(ShadowMapView v, AvsmSource src, ShadowReceiver r) {
    if (r.valid == 0.0f) return 1.0f;
    return avsmTapTransmittance(v, src, r, vec2(0.0f));
}

/// One tap of the blocker search (Klein et al. Eq. 6–8): every node in front of the receiver's
/// plane is a thin blocker (z_E = z_0 in Eq. 6, so its replacement blocker is its own depth),
/// weighted by the light it takes, Δ_i = T_{i−1} − T_i (Eq. 8). Adds Σ Δ_i to `weight` and
/// Σ Δ_i·z_i (axial depths) to `weighted`: Eq. 7's z_TF is their quotient, and summing them over
/// the taps gives Eq. 13's Δ-weighted average of the z_TF.
DH_FUNC void vpcssTapBlockers(ShadowMapView v, AvsmSource src, ShadowReceiver r, vec2 offset,
                              DH_INOUT(float) weight, DH_INOUT(float) weighted) {
    uint face;
    ivec2 texel;
    float limit;
    if (!shadowTapTexel(v, r, offset, face, texel, limit)) return;
    float before = 1.0f;
    uint count = avsmSourceCount(src, face, texel);
    for (uint j = 0u; j < count; ++j) {
        float depth = avsmSourceDepth(src, face, texel, j);
        if (!(depth < limit)) break;
        float after = avsmTransmittance(avsmSourceUnits(src, face, texel, j));
        float delta = before - after;
        weight += delta;
        weighted += delta * shadowTapAxial(v, r, face, texel, depth);
        before = after;
    }
}

/// Klein et al. Eq. 13: the Δ-weighted average blocker depth (axial) over the first `taps`
/// Poisson taps of PCSS's search region (pcssSearchRadius); −1 when no tap loses any light (the
/// receiver is lit). With opaque blockers only, every blocking tap weighs 1 at its nearest
/// surface: PCSS's average blocker (pcssAverageBlocker).
DH_FUNC float vpcssAverageBlocker(ShadowMapView v, AvsmSource src, ShadowReceiver r, uint taps,
                                  float maxTexels) {
    if (r.valid == 0.0f) return -1.0f;
    float radius = pcssSearchRadius(v, r, maxTexels);
    float weight = 0.0f;
    float weighted = 0.0f;
    for (uint i = 0u; i < taps; ++i)
        vpcssTapBlockers(v, src, r, radius * shadowRotate(avsmSourceTap(src, i), r.rotation), weight,
                         weighted);
    return weight > 0.0f ? weighted / weight : -1.0f;
}

/// The filter (Klein et al. Eq. 12 with the penumbra of Eq. 14, pcssFilterRadius): the mean
/// transmittance the functions of `taps` Poisson taps (from `firstTap`) of radius `radius` (uv)
/// let through to the receiver's plane. With opaque blockers only: PCSS's lit fraction.
DH_FUNC float vpcssFilter(ShadowMapView v, AvsmSource src, ShadowReceiver r, float radius, uint firstTap,
                          uint taps) {
    float sum = 0.0f;
    for (uint i = 0u; i < taps; ++i)
        sum += avsmTapTransmittance(v, src, r,
                                    radius * shadowRotate(avsmSourceTap(src, firstTap + i), r.rotation));
    return sum / float(taps);
}

DH_END

#endif // STSV_SHADOWMAPS_AVSM_FILTER_DH_H
