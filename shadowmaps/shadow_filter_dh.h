// Percentage-closer filters of a light-space map (DESIGN §4.6), as shaders/shadowmaps/shadow_filter.comp
// and the CPU backend (render/cpu/cpu_shadowmaps.cpp) both run them per pixel:
//  * PCF (Reeves, Salesin & Cook 1987): the fraction of map taps over a fixed (2r+1)² texel
//    kernel around the receiver's texel that do not block it.
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
#include "sampling/light_sampling_dh.h"
#include "shadowmaps/shadow_map_dh.h"

DH_BEGIN

/// A receiver as the filters see it.
struct ShadowReceiver {
    vec3 p;      ///< world units: the visible point, moved along n by the normal offset
    float bias;  ///< constant depth bias, in the map's depth units
    vec3 n;      ///< unit: the receiver's normal, turned towards the light
    float texel; ///< world size of a map texel at the receiver (shadowMapTexelWorld)
    vec2 uv;     ///< the receiver's place in its face
    uint face;
    float depth;   ///< d_r: the receiver's depth in the map (axial, or radial for cube maps)
    vec2 rotation; ///< (cos, sin) of the tap rotation of this pixel
    float valid;   ///< 0 when the receiver lies behind the map's face (no lookup: lit)
    float pad0;
};

/// Rotation of the Poisson taps at a pixel: the same per-pixel hash as the light samples'
/// decorrelation (sampling/light_sampling_dh.h), as an angle; none without decorrelation.
DH_FUNC vec2 shadowTapRotation(uvec2 pixel, uint seed, bool decorrelated) {
    if (!decorrelated) return vec2(1.0f, 0.0f);
    float angle = 6.28318530718f * float(decorrelationOffset(pixel, seed).x) * (1.0f / SAMPLING_FIXED_ONE);
    return vec2(cos(angle), sin(angle));
}

/// The receiver at visible point p with shading normal n. Biases in texels of the map at p:
/// the constant one along the depth, the normal offset along n.
DH_FUNC ShadowReceiver shadowReceiver(ShadowMapView v, vec3 p, vec3 n, float biasTexels,
                                      float normalOffsetTexels, vec2 rotation) {
    ShadowReceiver r;
    vec3 towardLight = v.projection == SHADOW_MAP_ORTHOGRAPHIC ? -v.axisZ : v.origin - p;
    r.n = dot(n, towardLight) < 0.0f ? -n : n;
    ShadowMapCoord c = shadowMapProject(v, p);
    r.texel = shadowMapTexelWorld(v, c.axial);
    r.p = p + (normalOffsetTexels * r.texel) * r.n;
    c = shadowMapProject(v, r.p);
    r.uv = c.uv;
    r.face = c.face;
    r.depth = c.depth;
    r.bias = biasTexels * r.texel;
    r.rotation = rotation;
    r.valid = c.valid;
    r.pad0 = 0.0f;
    return r;
}

/// The receiver's depth along the axis of its face (world units), the depth PCSS's similar
/// triangles take: a plane parallel to the face has one such depth, and a world length at the
/// receiver parallel to the face spans length/(axial·window width) in uv. r.depth itself but on
/// cube maps, which store distances from the centre.
DH_FUNC float shadowReceiverAxial(ShadowMapView v, ShadowReceiver r) {
    if (v.projection != SHADOW_MAP_CUBE) return r.depth;
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, r.face, X, Y, Z);
    return dot(r.p - v.origin, Z);
}

/// Whether the map's surface in the texel under uv + offset lies in front of the receiver's
/// plane there (by more than the bias); `blockerAxial` gets that surface's depth along the axis
/// of the receiver's face (the stored depth, but on cube maps: a tap may land on another face,
/// and its stored distance from the centre grows off the axis even on a plane parallel to the
/// face).
DH_FUNC bool shadowTapBlocks(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, vec2 offset,
                             DH_OUT(float) blockerAxial) {
    uint face;
    ivec2 texel;
    blockerAxial = SHADOW_MAP_EMPTY;
    if (!shadowMapTexelOf(v, r.face, r.uv + offset, face, texel)) return false;
    float stored = shadowMapSourceDepth(src, face, texel);
    if (stored >= SHADOW_MAP_EMPTY) return false;
    bool blocks = stored < shadowMapPlaneDepth(v, face, texel, r.p, r.n, r.depth) - r.bias;
    blockerAxial = stored;
    if (blocks && v.projection == SHADOW_MAP_CUBE) {
        vec3 o, d, X, Y, Z;
        shadowMapTexelRay(v, face, texel, o, d);
        shadowMapFaceBasis(v, r.face, X, Y, Z);
        blockerAxial = stored * dot(d, Z) / length(d);
    }
    return blocks;
}

/// PCF over the (2·radius + 1)² texels around the receiver: the lit fraction.
DH_FUNC float pcfVisibility(ShadowMapView v, ShadowMapSource src, ShadowReceiver r, int radius) {
    if (r.valid == 0.0f) return 1.0f;
    float step = 1.0f / float(v.size);
    uint lit = 0u;
    for (int y = -radius; y <= radius; ++y)
        for (int x = -radius; x <= radius; ++x) {
            float blockerAxial;
            if (!shadowTapBlocks(v, src, r, vec2(float(x), float(y)) * step, blockerAxial)) lit += 1u;
        }
    float side = float(2 * radius + 1);
    return float(lit) / (side * side);
}

DH_FUNC vec2 shadowRotate(vec2 t, vec2 rotation) {
    return vec2(rotation.x * t.x - rotation.y * t.y, rotation.y * t.x + rotation.x * t.y);
}

/// Radius, in uv, of PCSS's blocker search (step 1): half of w_search = w_light·(d_r − near)/d_r
/// on the near plane for perspective and cube maps (d_r the receiver's axial depth); for
/// orthographic maps (a directional light of width 2·tan θ per unit distance) half of
/// w_light·(d_r − near) on the receiver.
DH_FUNC float pcssSearchRadius(ShadowMapView v, ShadowReceiver r, float maxTexels) {
    float width = v.window.z - v.window.x;
    float d = shadowReceiverAxial(v, r);
    float radius = v.projection == SHADOW_MAP_ORTHOGRAPHIC
                       ? 0.5f * v.lightWidth * max(d - v.near, 0.0f) / width
                       : 0.5f * v.lightWidth * max(d - v.near, 0.0f) / (d * v.near * width);
    return min(radius, maxTexels / float(v.size));
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

/// Step 3's kernel radius in uv: half the penumbra w_p = (d_r − d_b)·w_light/d_b (Fernando 2005,
/// parallel planes; w_light·(d_r − d_b) for orthographic maps), as seen in the map at the
/// receiver, at most maxTexels texels. d_r and d_b (pcssAverageBlocker) are axial depths.
DH_FUNC float pcssFilterRadius(ShadowMapView v, ShadowReceiver r, float blockerDepth, float maxTexels) {
    float width = v.window.z - v.window.x;
    float d = shadowReceiverAxial(v, r);
    float db = max(blockerDepth, 1e-6f);
    float radius = v.projection == SHADOW_MAP_ORTHOGRAPHIC
                       ? 0.5f * v.lightWidth * max(d - db, 0.0f) / width
                       : 0.5f * (max(d - db, 0.0f) * v.lightWidth / db) / (d * width);
    return min(radius, maxTexels / float(v.size));
}

/// Whether pcssFilterRadius cut the penumbra's kernel to maxTexels: the picture then shows a
/// penumbra narrower than the one PCSS estimated (the stats count such pixels).
DH_FUNC bool pcssKernelClamped(ShadowMapView v, ShadowReceiver r, float blockerDepth, float maxTexels) {
    return pcssFilterRadius(v, r, blockerDepth, 3.0e38f) > maxTexels / float(v.size);
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
