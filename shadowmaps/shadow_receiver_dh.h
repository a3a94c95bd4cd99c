// The receiver of a light-space map lookup (DESIGN §4.6): the visible point with its biases as
// every filter of the shadow-map family sees it, the tap rotation, the texel a tap lands in with
// the depth the receiver's plane has there, and PCSS's search and penumbra radii (Fernando 2005),
// which the depth-map filters (shadow_filter_dh.h), the filtered representations
// (filtered_lookup_dh.h) and the transmittance functions (avsm_dh.h) share. Compiles as C++ and
// GLSL (core/dh.h); no map data is read here.
#ifndef STSV_SHADOWMAPS_SHADOW_RECEIVER_DH_H
#define STSV_SHADOWMAPS_SHADOW_RECEIVER_DH_H

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

/// Whether the receiver lies on the map: in front of its face and, for single-face maps, inside
/// its window (a receiver outside has no caster on its centre ray; the stats count clamped
/// kernels and searches only where they can change the picture).
DH_FUNC bool shadowReceiverOnMap(ShadowMapView v, ShadowReceiver r) {
    if (r.valid == 0.0f) return false;
    return v.projection == SHADOW_MAP_CUBE ||
           (r.uv.x >= 0.0f && r.uv.y >= 0.0f && r.uv.x <= 1.0f && r.uv.y <= 1.0f);
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

/// The texel of the map under uv + offset from the receiver, and `limit`: the depth of the
/// receiver's plane along that texel's centre ray less the bias (receiver-plane depth bias), so
/// that a surface stored nearer than `limit` lies in front of the receiver there. False where no
/// texel holds the tap (outside a single-face map: nothing there, lit).
DH_FUNC bool shadowTapTexel(ShadowMapView v, ShadowReceiver r, vec2 offset, DH_OUT(uint) face,
                            DH_OUT(ivec2) texel, DH_OUT(float) limit) {
    limit = 0.0f;
    if (!shadowMapTexelOf(v, r.face, r.uv + offset, face, texel)) return false;
    limit = shadowMapPlaneDepth(v, face, texel, r.p, r.n, r.depth) - r.bias;
    return true;
}

/// A depth `stored` in texel `texel` of face `face`, along the axis of the receiver's face: the
/// stored depth itself, but on cube maps (a tap may land on another face, and its stored distance
/// from the centre grows off the axis even on a plane parallel to the face).
DH_FUNC float shadowTapAxial(ShadowMapView v, ShadowReceiver r, uint face, ivec2 texel, float stored) {
    if (v.projection != SHADOW_MAP_CUBE) return stored;
    vec3 o, d, X, Y, Z;
    shadowMapTexelRay(v, face, texel, o, d);
    shadowMapFaceBasis(v, r.face, X, Y, Z);
    return stored * dot(d, Z) / length(d);
}

/// Texels of the map at the receiver that a world length `world` spans there (across the map's
/// axis): the unit change of the kernels given in world units (pcf_world_radius,
/// fm_world_radius), so one setting gives the same world kernel at every map size and fit.
DH_FUNC float shadowReceiverTexels(ShadowReceiver r, float world) {
    return world / max(r.texel, 1e-30f);
}

DH_FUNC vec2 shadowRotate(vec2 t, vec2 rotation) {
    return vec2(rotation.x * t.x - rotation.y * t.y, rotation.y * t.x + rotation.x * t.y);
}

/// Radius, in uv, of PCSS's blocker search (step 1): half of w_search = w_light·(d_r − near)/d_r
/// on the near plane for perspective and cube maps (d_r the receiver's axial depth); for
/// orthographic maps (a directional light of width 2·tan θ per unit distance) half of
/// w_light·(d_r − near) on the receiver. Fernando's near plane is where blockers begin; a map's
/// near plane can lie far closer to the light (a ceiling the light is flush with, a shelf it hangs
/// under: near ≈ 0), and the region then spans the whole hemisphere and finds those surfaces at
/// depth ≈ 0 beside the light, whose kernel w_p → ∞ darkens a lit room. So the search's near plane
/// is at least ½·w_light from the light's centre: the region's half-angle stays under 45°, and
/// blockers nearer the light than its own half-width (which shape the light more than they cast a
/// penumbra) are found only within it.
DH_FUNC float pcssSearchRadius(ShadowMapView v, ShadowReceiver r, float maxTexels) {
    float width = v.window.z - v.window.x;
    float d = shadowReceiverAxial(v, r);
    float near = max(v.near, 0.5f * v.lightWidth);
    float radius = v.projection == SHADOW_MAP_ORTHOGRAPHIC
                       ? 0.5f * v.lightWidth * max(d - v.near, 0.0f) / width
                       : 0.5f * v.lightWidth * max(d - near, 0.0f) / (d * near * width);
    return min(radius, maxTexels / float(v.size));
}

/// Whether pcssSearchRadius cut the blocker search to maxTexels: blockers beyond it are not
/// found, so a penumbra wider than the search reads lit on its outer side (the stats count such
/// receivers).
DH_FUNC bool pcssSearchClamped(ShadowMapView v, ShadowReceiver r, float maxTexels) {
    return pcssSearchRadius(v, r, 3.0e38f) > maxTexels / float(v.size);
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

/// PCSS's step after its blocker search (Fernando 2005, step 2), for any search (the depth map's
/// pcssAverageBlocker, volumetric PCSS's vpcssAverageBlocker): the filter radius in uv from the
/// average blocker depth (−1 where the search found none: lit), and whether the search's region
/// and the kernel were cut (the stats count them). Both backends run it per pixel.
struct PcssBlockerStep {
    float radius;
    uint searchClamped; ///< 1: pcssSearchClamped on a receiver the map covers
    uint kernelClamped; ///< 1: pcssKernelClamped where a blocker was found
};
DH_FUNC PcssBlockerStep pcssBlockerStep(ShadowMapView v, ShadowReceiver r, float blockerDepth,
                                        float maxSearch, float maxKernel) {
    PcssBlockerStep step;
    step.radius = blockerDepth < 0.0f ? -1.0f : pcssFilterRadius(v, r, blockerDepth, maxKernel);
    step.searchClamped = shadowReceiverOnMap(v, r) && pcssSearchClamped(v, r, maxSearch) ? 1u : 0u;
    step.kernelClamped = blockerDepth >= 0.0f && pcssKernelClamped(v, r, blockerDepth, maxKernel) ? 1u : 0u;
    return step;
}

DH_END

#endif // STSV_SHADOWMAPS_SHADOW_RECEIVER_DH_H
