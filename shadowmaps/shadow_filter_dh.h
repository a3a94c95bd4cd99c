// Percentage-closer filters of a light-space map (DESIGN §4.6), as shadowmaps/shaders/shadow_filter.comp
// and the CPU backend (shadowmaps/cpu/cpu_shadowmaps.cpp) both run them per pixel:
//  * PCF (Reeves, Salesin & Cook 1987): the fraction of map taps over a fixed kernel around the
//    receiver's texel that do not block it; the kernel is a world half-width at the receiver,
//    converted to texels per pixel.
//  * PCSS (Fernando 2005), three steps: (1) blocker search over the region the light subtends
//    as seen from the receiver, w_search = w_light·(d_r − near)/d_r on the near plane; (2) the
//    average depth d_b of the blockers found; (3) penumbra w_p = (d_r − d_b)·w_light/d_b on the
//    receiver (parallel planes), then PCF over a kernel of that width.
// Each tap compares the stored depth of its texel with the receiver's tangent plane along that
// texel's centre ray (shadowMapPlaneDepth), less a constant bias, so a flat receiver does not
// shadow itself however wide the kernel (receiver-plane depth bias).
//
// Data access differs (a storage buffer on the GPU, a vector on the CPU), so the includer
// defines, before including this header,
//   struct ShadowMapSource                                          what the map is read from
//   float shadowMapSourceDepth(ShadowMapSource s, uint face, ivec2 texel)   the stored depth
//   vec2 shadowMapSourceTap(ShadowMapSource s, uint i)              Poisson-disk tap i (unit disk)
// and the macro SHADOW_MAP_SOURCE.
#ifndef STSV_SHADOWMAPS_SHADOW_FILTER_DH_H
#define STSV_SHADOWMAPS_SHADOW_FILTER_DH_H

#ifndef SHADOW_MAP_SOURCE
#error "define ShadowMapSource, shadowMapSourceDepth and shadowMapSourceTap, then SHADOW_MAP_SOURCE"
#endif

#include "core/dh.h"
#include "shadowmaps/shadow_receiver_dh.h"

DH_BEGIN

/// Whether the map's surface in the texel under uv + offset lies in front of the receiver's
/// plane there (by more than the bias); `blockerAxial` gets that surface's depth along the axis
/// of the receiver's face (shadowTapAxial).
DH_FUNC bool shadowTapBlocks(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, vec2 offset,
                             DH_OUT(float) blockerAxial) {
    uint face;
    ivec2 texel;
    float limit;
    blockerAxial = SHADOW_MAP_EMPTY;
    if (!shadowTapTexel(v, r, offset, face, texel, limit)) return false;
    float stored = shadowMapSourceDepth(src, face, texel);
    if (stored >= SHADOW_MAP_EMPTY) return false;
    bool blocks = stored < limit;
    blockerAxial = blocks ? shadowTapAxial(v, r, face, texel, stored) : stored;
    return blocks;
}

/// Whether pcfVisibility spreads its taps more than three texels apart at the receiver (its
/// kernel, `worldRadius` either side, wider than 3·(maxRadius + ½) texels): a blocker three texels
/// wide can then fall between them (the stats count such receivers). Up to 2.6 texels apart the
/// error against the converged reference moved by under 1 % on fence, foliage, knot, particles.
DH_FUNC bool pcfKernelStrided(ShadowReceiver r, float worldRadius, int maxRadius) {
    return shadowReceiverTexels(r, worldRadius) > 3.0f * (float(maxRadius) + 0.5f);
}

/// PCF (Reeves et al. 1987) over a square of half-width `worldRadius` (world units) at the
/// receiver, centred on the receiver's texel: the lit fraction. The half-width h in texels
/// (shadowReceiverTexels, at least the receiver's own texel, h = ½) makes the kernel:
///  * h ≤ maxRadius + ½: the (2k + 1)² texels around the receiver's texel, k = ⌈h − ½⌉, the
///    outer ring weighted by the part of it the square covers, so the width is continuous in h
///    (h = k + ½ is the plain (2k + 1)² box);
///  * beyond: (2·maxRadius + 1)² taps at the centres of as many equal cells of the square, more
///    than a texel apart: the cost stays bounded and the world width stays.
DH_FUNC float pcfVisibility(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, float worldRadius,
                            int maxRadius) {
    if (r.valid == 0.0f) return 1.0f;
    float h = max(shadowReceiverTexels(r, worldRadius), 0.5f);
    // (A thousandth of a texel over k + ½ adds no ring: round-off of a width given in texels.)
    int k = int(ceil(h - 0.501f));
    float spacing = 1.0f, edge = h - (float(k) - 0.5f); // the outer ring's coverage, in (0, 1.001)
    if (k > maxRadius) {
        k = maxRadius;
        spacing = 2.0f * h / float(2 * k + 1);
        edge = 1.0f;
    }
    float step = spacing / float(v.size);
    float lit = 0.0f, total = 0.0f;
    for (int y = -k; y <= k; ++y)
        for (int x = -k; x <= k; ++x) {
            float w = (abs(x) == k && k > 0 ? edge : 1.0f) * (abs(y) == k && k > 0 ? edge : 1.0f);
            float blockerAxial;
            if (!shadowTapBlocks(v, src, r, vec2(float(x), float(y)) * step, blockerAxial)) lit += w;
            total += w;
        }
    return lit / total;
}

/// The filters of the depth map over a kernel of fixed world width at the receiver, by their
/// selector (p.method): the variants whose row reads the depths and searches no blockers
/// (filtersFixedDepthKernel), one per-pixel step on both backends. `strided` says whether the
/// receiver, on the map, has its taps spread more than three texels apart (the stats count it).
/// pcf is the only one so far; another kernel is its selector, its row and a branch here.
DH_FUNC float depthKernelVisibility(ShadowMapView v, ShadowMapSource src, ShadowReceiver r,
                                    ShadowFilterParams p, DH_OUT(bool) strided) {
    strided = shadowReceiverOnMap(v, r) && pcfKernelStrided(r, p.pcfWorldRadius, p.pcfMaxRadius);
    return pcfVisibility(v, src, r, p.pcfWorldRadius, p.pcfMaxRadius);
}

/// Steps 1 and 2: the average depth, along the axis of the receiver's face, of the blockers the
/// first `taps` Poisson taps find within the search radius; −1 when there is none (the receiver is
/// lit).
DH_FUNC float pcssAverageBlocker(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, uint taps,
                                 float maxTexels) {
    if (r.valid == 0.0f) return -1.0f;
    float radius = pcssSearchRadius(v, r, maxTexels);
    float sum = 0.0f;
    uint count = 0u;
    for (uint i = 0u; i < taps; ++i) {
        float blockerAxial;
        if (shadowTapBlocks(v, src, r, radius * shadowRotate(shadowMapSourceTap(src, i), r.rotation),
                            blockerAxial)) {
            sum += blockerAxial;
            count += 1u;
        }
    }
    return count == 0u ? -1.0f : sum / float(count);
}

/// Step 3: PCF over `taps` Poisson taps (from tap index `firstTap`) of radius `radius` (uv).
DH_FUNC float pcssFilter(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, float radius, uint firstTap,
                         uint taps) {
    uint lit = 0u;
    for (uint i = 0u; i < taps; ++i) {
        float blockerAxial;
        vec2 offset = radius * shadowRotate(shadowMapSourceTap(src, firstTap + i), r.rotation);
        if (!shadowTapBlocks(v, src, r, offset, blockerAxial)) lit += 1u;
    }
    return float(lit) / float(taps);
}

DH_END

#endif // STSV_SHADOWMAPS_SHADOW_FILTER_DH_H
