// Light-space shadow maps (DESIGN §4.6): the projection of one light's map, the texel grid, the
// ray through a texel centre (the CPU traces the map along it, the rasteriser samples it at the
// same points), and the receiver-plane depth a texel is compared with. Compiles as C++ and
// GLSL (core/dh.h); shadowmaps/shaders/shadowmap.* and the CPU backend (shadowmaps/cpu/cpu_shadowmaps.cpp)
// both use it.
//
// A map holds, per texel, the linear depth of the nearest opaque surface along the texel-centre
// ray from the light centre: the distance along the map's axis (perspective and orthographic
// maps) or from the centre (cube maps), which the similar triangles of PCSS need. A texel that
// sees nothing holds SHADOW_MAP_EMPTY. Texel (i, j) of a face covers uv ∈ [i, i+1]/size ×
// [j, j+1]/size; its centre is the sample the rasteriser and the ray take; row 0 is v = 0 (the
// top row under the Vulkan viewport).
#ifndef STSV_SHADOWMAPS_SHADOW_MAP_DH_H
#define STSV_SHADOWMAPS_SHADOW_MAP_DH_H

#include "core/dh.h"

DH_BEGIN

DH_CONST uint SHADOW_MAP_PERSPECTIVE = 0u;  ///< one face looking along the light normal (rectangles, disks)
DH_CONST uint SHADOW_MAP_CUBE = 1u;         ///< six 90° faces around the light centre (spheres, wide fits)
DH_CONST uint SHADOW_MAP_ORTHOGRAPHIC = 2u; ///< one face along a directional light's direction

DH_CONST uint SHADOW_MAP_MAX_FACES = 6u;
/// Depth of a texel that sees no surface: farther than every receiver, so always lit.
DH_CONST float SHADOW_MAP_EMPTY = 3.0e38f;

/// One light's map. std430: 6 × 16 bytes.
struct ShadowMapView {
    vec3 origin;     ///< world units: the light centre; for orthographic maps a point of the plane depth 0
    uint projection; ///< SHADOW_MAP_*
    vec3 axisX;      ///< unit; the face's u direction (perspective, orthographic)
    uint size;       ///< texels per face edge
    vec3 axisY;      ///< unit; the face's v direction
    float near;      ///< world units: nearest axial depth a blocker can have (the scene box)
    vec3 axisZ;      ///< unit; the viewing direction (away from the light)
    float far;       ///< world units: farthest axial depth of the scene box
    vec4 window; ///< (u0, v0, u1, v1): the face on the plane z = 1 (perspective, cube: (−1, −1, 1, 1)),
                 ///< or in world units on the plane z = 0 (orthographic); square (u1 − u0 = v1 − v0)
    float lightWidth; ///< w_light of PCSS: world units (rectangle: larger edge; disk, sphere: diameter);
                      ///< orthographic maps: 2·tan(angular radius), the width per unit distance
    uint faces;       ///< 1, or 6 for cube maps
    /// Vulkan: the device address of what the map's row builds beside the depth map (the
    /// filtered planes, the depth grid, the transmittance functions), low and high 32 bits
    uint representationLow;
    uint representationHigh;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(ShadowMapView) == 96);
#endif

/// The image family's variants (ShadowFilterParams::method; the C++ names them ShadowMapMethod,
/// shadow_map.h, and describes each in the variant table, shadowmaps/variants.cpp). The filtered
/// representations' selectors are in filtered_shadow_dh.h, each beside its math.
DH_CONST uint SHADOW_FILTER_PCF = 1u;
DH_CONST uint SHADOW_FILTER_PCSS = 2u;
DH_CONST uint SHADOW_FILTER_PEEL = 8u;
DH_CONST uint SHADOW_FILTER_AVSM = 9u;
DH_CONST uint SHADOW_FILTER_VPCSS = 10u;

/// The knobs of a frame's filter as both backends read them, with their defaults (the knob
/// names after the colons; render/methods.cpp lists them). On the host they are the base of
/// ShadowMapSettings (shadow_map.h), which adds what only the host reads; the shaders read them
/// ahead of the views in one buffer (shadowFilterParams sets `method`, `channels` and the
/// effective `mip`). Several methods start from other values (defaultShadowMapSettings).
/// std430: 7 × 16 bytes.
struct ShadowFilterParams {
    float bias DH_DEFAULT(1.0f);         ///< sm_bias: constant depth bias, texels at the receiver
    float normalOffset DH_DEFAULT(0.0f); ///< sm_normal_offset: receiver moved along its normal, texels
    /// pcss_max_kernel: largest filter radius, texels. PCSS's cost is its taps, not its radius,
    /// so the default clips no plausible penumbra: a 1 m penumbra on a 2048² map spans about 256
    /// texels, and 1024 is half the map.
    float maxKernel DH_DEFAULT(1024.0f);
    /// pcf_world_radius: PCF's kernel half-width at the receiver, world units (metres), turned into
    /// texels per pixel through the receiver's texel size: the same penumbra at every map size and
    /// fit (it replaced pcf_radius, which counted texels). 6 cm is the fixed width nearest every
    /// tuning scene's own best at once (docs/measurements.md, "Fair defaults").
    float pcfWorldRadius DH_DEFAULT(0.06f);
    uint blockerTaps DH_DEFAULT(32u); ///< pcss_blocker_taps
    /// pcss_filter_taps: 128 against 64 cut the tap noise (RMSE on fence 0.0169 → 0.0137,
    /// particles 0.0146 → 0.0135) for a filter pass twice as long, still shorter than the search.
    uint filterTaps DH_DEFAULT(128u);
    /// pcss_max_search: largest blocker-search radius, texels: a safety bound on the region of
    /// Fernando 2005 (the light seen from the receiver through the map's near plane), whose cuts
    /// the stats count. Half the default map, as pcss_max_kernel: on the maps fitted to the view
    /// the region spans hundreds of texels (64 cut 70 % of fence's pixels and the hidden
    /// parallel planes' penumbra); 32 taps spread that wide still find the fence's wires.
    float maxSearch DH_DEFAULT(1024.0f);
    uint method DH_DEFAULT(0u); ///< SHADOW_FILTER_* (set by shadowFilterParams)
    // The filtered representations (filtered_shadow_dh.h).
    uint channels DH_DEFAULT(0u); ///< values per texel (set by shadowFilterParams)
    /// fm_mip: 0 summed-area tables, 1 mip pyramids (filteredBoxTaps); to the shaders whether
    /// mips are read (ESM and EVSM always: filteredUsesMip)
    uint mip DH_DEFAULT(0u);
    uint kernel DH_DEFAULT(1u); ///< fm_kernel: 0 `worldRadius`, 1 sized per pixel by PCSS's blocker search
    /// fm_world_radius: the fixed kernel's half-width at the receiver (fm_kernel=0), world units
    /// (metres), turned into texels per pixel (it replaced fm_radius, which counted texels)
    float worldRadius DH_DEFAULT(0.02f);
    float minVariance DH_DEFAULT(1e-5f);  ///< vsm_min_variance: of the normalised depth (VSM, EVSM)
    float bleed DH_DEFAULT(0.0f);         ///< vsm_bleed: light-bleeding reduction, 0 off (VSM, EVSM)
    float esmC DH_DEFAULT(80.0f);         ///< esm_c: the exponent
    float evsmPositive DH_DEFAULT(40.0f); ///< evsm_positive: c⁺
    float evsmNegative DH_DEFAULT(5.0f);  ///< evsm_negative: c⁻
    float msmBias DH_DEFAULT(6e-7f); ///< msm_bias: α of the moment bias (the trade-off: docs/methods.md)
    uint csmTerms DH_DEFAULT(16u);   ///< csm_terms: M
    uint csmDamp DH_DEFAULT(1u);     ///< csm_damp: Lanczos σ factors on the terms
    uint peelBins DH_DEFAULT(16u);   ///< peel_bins: subintervals of each grid texel's depth range
    /// peel_max_steps: most march steps per light-sample ray. The march steps a texel at a time
    /// across the grid (depth_grid_dh.h); this caps what a ray may cost, and the stats count the
    /// rays it cuts short.
    uint peelMaxSteps DH_DEFAULT(1024u);
    uint avsmNodes DH_DEFAULT(8u); ///< avsm_nodes: nodes of each texel's transmittance function
    uint vpcssTaps
        DH_DEFAULT(25u); ///< vpcss_taps: Poisson taps of the search and of the filter (the paper's 25)
    /// pcf_max_radius: taps either side at most ((2·r + 1)² taps a pixel), a bound on the cost; a
    /// wider kernel keeps its world width with its taps more than a texel apart (measured within
    /// 1 % of the full kernel's error at 8 on fence, foliage, knot and particles). The stats
    /// count the pixels whose taps are more than three texels apart.
    int pcfMaxRadius DH_DEFAULT(12);
    uint pad0 DH_DEFAULT(0u);
    uint pad1 DH_DEFAULT(0u);
    uint pad2 DH_DEFAULT(0u);
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(ShadowFilterParams) == 112);
#endif

/// The orthonormal frame of face `face` (X, Y across, Z along the view). A cube map's faces
/// look along +x, −x, +y, −y, +z, −z of the map's frame (axisX, axisY, axisZ).
DH_FUNC void shadowMapFaceBasis(ShadowMapView v, uint face, DH_OUT(vec3) X, DH_OUT(vec3) Y, DH_OUT(vec3) Z) {
    X = v.axisX;
    Y = v.axisY;
    Z = v.axisZ;
    if (v.projection != SHADOW_MAP_CUBE) return;
    vec3 a = v.axisX, b = v.axisY, c = v.axisZ;
    if (face == 0u) {
        Z = a;
        X = -c;
        Y = b;
    } else if (face == 1u) {
        Z = -a;
        X = c;
        Y = b;
    } else if (face == 2u) {
        Z = b;
        X = a;
        Y = -c;
    } else if (face == 3u) {
        Z = -b;
        X = a;
        Y = c;
    } else if (face == 4u) {
        Z = c;
        X = a;
        Y = b;
    } else {
        Z = -c;
        X = -a;
        Y = b;
    }
}

/// The cube face whose view contains direction d (given in world space): the major axis of d
/// in the map's frame.
DH_FUNC uint shadowMapCubeFace(ShadowMapView v, vec3 d) {
    vec3 l = vec3(dot(d, v.axisX), dot(d, v.axisY), dot(d, v.axisZ));
    vec3 m = abs(l);
    if (m.x >= m.y && m.x >= m.z) return l.x >= 0.0f ? 0u : 1u;
    if (m.y >= m.z) return l.y >= 0.0f ? 2u : 3u;
    return l.z >= 0.0f ? 4u : 5u;
}

/// Face coordinates s (on the plane z = 1, or world units for orthographic maps) → uv ∈ [0, 1]².
DH_FUNC vec2 shadowMapUvOf(ShadowMapView v, vec2 s) {
    return (s - vec2(v.window.x, v.window.y)) / (v.window.z - v.window.x);
}
DH_FUNC vec2 shadowMapFacePoint(ShadowMapView v, vec2 uv) {
    return vec2(v.window.x, v.window.y) + uv * (v.window.z - v.window.x);
}

/// Where a world point falls in the map.
struct ShadowMapCoord {
    vec2 uv;     ///< on its face
    uint face;   ///< 0 for single-face maps
    float depth; ///< the map's depth of the point (axial, or radial for cube maps)
    float axial; ///< distance along the face's axis (world units)
    float valid; ///< 1 when the point lies in front of the face (axial > 0), else 0
    float pad0;
    float pad1;
};

DH_FUNC ShadowMapCoord shadowMapProject(ShadowMapView v, vec3 p) {
    ShadowMapCoord c;
    vec3 q = p - v.origin;
    c.face = v.projection == SHADOW_MAP_CUBE ? shadowMapCubeFace(v, q) : 0u;
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, c.face, X, Y, Z);
    vec3 l = vec3(dot(q, X), dot(q, Y), dot(q, Z));
    c.axial = l.z;
    c.valid = v.projection == SHADOW_MAP_ORTHOGRAPHIC || l.z > 0.0f ? 1.0f : 0.0f;
    vec2 s = v.projection == SHADOW_MAP_ORTHOGRAPHIC ? vec2(l.x, l.y) : vec2(l.x, l.y) / max(l.z, 1e-30f);
    c.uv = shadowMapUvOf(v, s);
    c.depth = v.projection == SHADOW_MAP_CUBE ? length(q) : l.z;
    c.pad0 = 0.0f;
    c.pad1 = 0.0f;
    return c;
}

/// Vulkan clip coordinates of a world point in face `face` (shadowmaps/shaders/shadowmap.vert): x, y span
/// the window, z runs from near (0) to far (w); with perspective division the NDC point of a
/// texel centre is 2·uv − 1, so the rasteriser samples the texel-centre rays.
DH_FUNC vec4 shadowMapClip(ShadowMapView v, uint face, vec3 p) {
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, face, X, Y, Z);
    vec3 q = p - v.origin;
    vec3 l = vec3(dot(q, X), dot(q, Y), dot(q, Z));
    float width = v.window.z - v.window.x;
    float range = v.far - v.near;
    if (v.projection == SHADOW_MAP_ORTHOGRAPHIC)
        return vec4(2.0f * (l.x - v.window.x) / width - 1.0f, 2.0f * (l.y - v.window.y) / width - 1.0f,
                    (l.z - v.near) / range, 1.0f);
    return vec4(2.0f * (l.x - v.window.x * l.z) / width - l.z, 2.0f * (l.y - v.window.y * l.z) / width - l.z,
                v.far * (l.z - v.near) / range, l.z);
}

/// The ray through face point uv of face `face`: origin o and direction d with d·Z = 1, as
/// shadowMapTexelRay's through a texel centre.
DH_FUNC void shadowMapFaceRay(ShadowMapView v, uint face, vec2 uv, DH_OUT(vec3) o, DH_OUT(vec3) d) {
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, face, X, Y, Z);
    vec2 s = shadowMapFacePoint(v, uv);
    if (v.projection == SHADOW_MAP_ORTHOGRAPHIC) {
        o = v.origin + s.x * X + s.y * Y;
        d = Z;
    } else {
        o = v.origin;
        d = s.x * X + s.y * Y + Z;
    }
}

/// The ray through the centre of texel `texel` of face `face`: origin o and direction d with
/// d·Z = 1, so the ray parameter t of a point is its axial depth. The stored depth of a hit at
/// t is shadowMapDepthAlong(v, d, t).
DH_FUNC void shadowMapTexelRay(ShadowMapView v, uint face, ivec2 texel, DH_OUT(vec3) o, DH_OUT(vec3) d) {
    shadowMapFaceRay(v, face, (vec2(texel) + vec2(0.5f)) / float(v.size), o, d);
}

DH_FUNC float shadowMapDepthAlong(ShadowMapView v, vec3 d, float t) {
    return v.projection == SHADOW_MAP_CUBE ? t * length(d) : t;
}

/// The texel of face `face` that holds uv, following a cube map's taps across to the face they
/// land on; false outside a single-face map (nothing there: lit).
DH_FUNC bool shadowMapTexelOf(ShadowMapView v, uint face, vec2 uv, DH_OUT(uint) faceOut,
                              DH_OUT(ivec2) texel) {
    faceOut = face;
    if (v.projection == SHADOW_MAP_CUBE && (uv.x < 0.0f || uv.x >= 1.0f || uv.y < 0.0f || uv.y >= 1.0f)) {
        vec3 X, Y, Z;
        shadowMapFaceBasis(v, face, X, Y, Z);
        vec2 s = shadowMapFacePoint(v, uv);
        vec3 dir = s.x * X + s.y * Y + Z;
        faceOut = shadowMapCubeFace(v, dir);
        shadowMapFaceBasis(v, faceOut, X, Y, Z);
        vec3 l = vec3(dot(dir, X), dot(dir, Y), dot(dir, Z));
        uv = shadowMapUvOf(v, vec2(l.x, l.y) / l.z);
    }
    float size = float(v.size);
    vec2 t = floor(uv * size);
    if (t.x < 0.0f || t.y < 0.0f || t.x >= size || t.y >= size) {
        if (v.projection != SHADOW_MAP_CUBE) return false;
        t = clamp(t, vec2(0.0f), vec2(size - 1.0f)); // round-off at a cube edge
    }
    texel = ivec2(t);
    return true;
}

/// Depth, in the map's measure, of the receiver's tangent plane (point p, normal n) along the
/// ray through face point uv (shadowMapPlaneDepthAt), or the centre ray of texel `texel`: the
/// depth a planar receiver has in that texel (receiver-plane depth bias, Isidoro 2006), so taps far from the
/// receiver's own texel compare with the receiver's surface there, not with its centre's depth. `fallback`
/// when the ray runs along the plane.
DH_FUNC float shadowMapPlaneDepthAt(ShadowMapView v, uint face, vec2 uv, vec3 p, vec3 n, float fallback) {
    vec3 o, d;
    shadowMapFaceRay(v, face, uv, o, d);
    float denom = dot(n, d);
    float t = dot(n, p - o);
    // Rays within about 0.06° of the plane: the intersection is ill-conditioned.
    if (abs(denom) <= 1e-3f * length(d) || t / denom <= 0.0f) return fallback;
    return shadowMapDepthAlong(v, d, t / denom);
}
DH_FUNC float shadowMapPlaneDepth(ShadowMapView v, uint face, ivec2 texel, vec3 p, vec3 n, float fallback) {
    return shadowMapPlaneDepthAt(v, face, (vec2(texel) + vec2(0.5f)) / float(v.size), p, n, fallback);
}

/// World size of one texel at axial depth `axial` (the unit of the bias knobs).
DH_FUNC float shadowMapTexelWorld(ShadowMapView v, float axial) {
    float width = v.window.z - v.window.x;
    float perUv = v.projection == SHADOW_MAP_ORTHOGRAPHIC ? width : axial * width;
    return perUv / float(v.size);
}

DH_END

#endif // STSV_SHADOWMAPS_SHADOW_MAP_DH_H
