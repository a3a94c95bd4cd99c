// Depth-peeling soft shadows (Liu et al. 2009, the `peel` row of the shadow-map family): a coarse
// depth grid from the light centre, marched per light sample. Compiles as C++ and GLSL
// (core/dh.h); shaders/shadowmaps/depth_grid.frag writes the grid, peel_march.comp and the CPU
// backend (render/cpu/cpu_shadowmaps.cpp) march it with the functions below.
//
// The grid has the texels of the light's fitted map (shadow_map_dh.h: one face, or six for a cube
// map). Each texel's depth range [near_p, far_p] — the nearest and the farthest surface its
// centre ray meets — is cut into B equal subintervals (`peel_bins`), and each subinterval keeps
// the farthest front-face depth and the farthest back-face depth that fall in it (front: the
// triangle faces the light, dot(n, ray) < 0). The paper keeps the same content in 8 two-channel
// render targets with MAX blending, back faces negated; here it is a storage buffer of 32-bit
// words written with atomicMax, so the grid does not depend on render-target formats and the CPU
// and GPU grids compare word for word. Per texel, peelTexelWords(B) words:
//   [0]        ~bits(near_p)   (the complement, so atomicMax keeps the nearest; 0: no surface)
//   [1]        bits(far_p)     (0: no surface)
//   [2 + 2b]   bits of the farthest front-face depth in subinterval b (0: none)
//   [3 + 2b]   bits of the farthest back-face depth in subinterval b (0: none)
// where bits() is the IEEE pattern of a positive float, which orders as the float does. A zeroed
// buffer is an empty grid.
//
// Subinterval b's value is z_b = +depth of its farthest fragment if that is a front face,
// −depth if a back face, 0 if it holds none (the paper's restored channel pair). Occlusion of a
// point at depth z in subinterval i of texel p, with j the first non-empty subinterval in front of
// i (towards the light), is the paper's Table 1:
//   z_i = 0:  occluded iff z_j > 0 (behind a front face with no back face since: inside)
//   z_i > 0:  z > z_i occluded; otherwise as z_i = 0 with z_j
//   z_i < 0:  z < |z_i| occluded (before the back face that leaves the object); otherwise not.
// A point in front of near_p, outside the map or on no surface's texel is not occluded; one
// behind far_p has z_i = 0 and j the last non-empty subinterval. The paper assumes closed,
// non-intersecting objects, so that a ray meets surfaces in pairs: behind a lone front face (an
// open quad facing the light) everything counts as inside, behind a lone back face nothing.
//
// A light sample's ray from the visible point p to the sample s is occluded when any of
// `peel_steps` points on it is: the midpoints of S equal steps, p + (k + ½)/S·(s − p).
//
// The includer defines, before including this header,
//   struct PeelGridSource                                   what the grid is read from
//   uint peelGridWord(PeelGridSource s, uint index)         word `index` of the light's grid
// and the macro PEEL_GRID_SOURCE; without it only the layout and the table are declared.
#ifndef STSV_SHADOWMAPS_DEPTH_GRID_DH_H
#define STSV_SHADOWMAPS_DEPTH_GRID_DH_H

#include "core/dh.h"
#include "shadowmaps/shadow_map_dh.h"

DH_BEGIN

DH_CONST uint PEEL_MAX_BINS = 32u;

/// 32-bit words per texel for B subintervals.
DH_FUNC uint peelTexelWords(uint bins) {
    return 2u + 2u * bins;
}
/// The first word of texel `texel` of face `face`.
DH_FUNC uint peelTexelBase(ShadowMapView v, uint face, ivec2 texel, uint bins) {
    return ((face * v.size + uint(texel.y)) * v.size + uint(texel.x)) * peelTexelWords(bins);
}

/// The word of a depth (> 0) in a subinterval or far_p slot, and back.
DH_FUNC uint peelDepthWord(float depth) {
    return floatBitsToUint(depth);
}
DH_FUNC float peelWordDepth(uint word) {
    return uintBitsToFloat(word);
}
/// The near_p slot's word: the complement, so that atomicMax keeps the nearest depth.
DH_FUNC uint peelNearWord(float depth) {
    return ~floatBitsToUint(depth);
}

/// Subinterval of depth z in a texel whose surfaces span [lo, hi]: −1 in front of lo, `bins`
/// behind hi, else floor((z − lo)/(hi − lo)·B) clamped to B − 1 (hi falls in the last one). A
/// texel with one depth (lo = hi) puts it in subinterval 0.
DH_FUNC int peelBin(float z, float lo, float hi, uint bins) {
    if (z < lo) return -1;
    if (z > hi) return int(bins);
    if (!(hi > lo)) return 0;
    float f = (z - lo) / (hi - lo) * float(bins);
    return min(int(f), int(bins) - 1);
}

/// Subinterval value from its two words: +depth of a farthest front face, −depth of a farthest
/// back face (the farther one when both are set; a tie counts as the back face), 0 empty.
DH_FUNC float peelBinValue(uint frontWord, uint backWord) {
    if (frontWord == 0u && backWord == 0u) return 0.0f;
    float front = peelWordDepth(frontWord);
    float back = peelWordDepth(backWord);
    return frontWord > backWord ? front : -back;
}

/// Table 1 of the paper: is a point at depth z occluded, given the value z_i of its own
/// subinterval and z_j of the first non-empty one in front of it (0: none)?
DH_FUNC bool peelTableOccluded(float z, float zi, float zj) {
    if (zi > 0.0f && z > zi) return true; // behind the subinterval's front face: inside
    if (zi < 0.0f) return z < -zi;        // before its back face: inside; after: outside
    return zj > 0.0f;                     // empty, or before the front face: the last surface decides
}

DH_END

#endif // STSV_SHADOWMAPS_DEPTH_GRID_DH_H

// The march, for includers that define the grid's data access (its own guard: the layout above
// may have been included before without it).
#if defined(PEEL_GRID_SOURCE) && !defined(STSV_SHADOWMAPS_DEPTH_GRID_MARCH)
#define STSV_SHADOWMAPS_DEPTH_GRID_MARCH

DH_BEGIN

/// Whether the point x lies inside an object according to the grid (Table 1 at its texel).
DH_FUNC bool peelPointOccluded(PeelGridSource src, ShadowMapView v, uint bins, vec3 x) {
    ShadowMapCoord c = shadowMapProject(v, x);
    // Nearer the light than every caster the map holds, or behind the light: nothing in front.
    if (c.valid == 0.0f || c.depth < v.near) return false;
    uint face;
    ivec2 texel;
    if (!shadowMapTexelOf(v, c.face, c.uv, face, texel)) return false;
    uint base = peelTexelBase(v, face, texel, bins);
    uint nearWord = peelGridWord(src, base);
    if (nearWord == 0u) return false; // no surface on this texel
    float lo = peelWordDepth(~nearWord);
    if (c.depth < lo) return false; // in front of the texel's nearest surface
    float hi = peelWordDepth(peelGridWord(src, base + 1u));
    int i = peelBin(c.depth, lo, hi, bins);
    float zi = 0.0f;
    if (i < int(bins))
        zi = peelBinValue(peelGridWord(src, base + 2u + 2u * uint(i)),
                          peelGridWord(src, base + 3u + 2u * uint(i)));
    float zj = 0.0f;
    for (int j = i - 1; j >= 0 && zj == 0.0f; --j)
        zj = peelBinValue(peelGridWord(src, base + 2u + 2u * uint(j)),
                          peelGridWord(src, base + 3u + 2u * uint(j)));
    return peelTableOccluded(c.depth, zi, zj);
}

/// Whether the ray from the visible point p to the light sample s is occluded: any of the
/// midpoints of `steps` equal steps inside an object.
DH_FUNC bool peelRayOccluded(PeelGridSource src, ShadowMapView v, uint bins, uint steps, vec3 p, vec3 s) {
    vec3 d = s - p;
    float inv = 1.0f / float(steps);
    for (uint k = 0u; k < steps; ++k)
        if (peelPointOccluded(src, v, bins, p + ((float(k) + 0.5f) * inv) * d)) return true;
    return false;
}

DH_END

#endif // PEEL_GRID_SOURCE
