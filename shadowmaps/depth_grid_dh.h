// Depth-peeling soft shadows (Liu et al. 2009, the `peel` row of the shadow-map family): a coarse
// depth grid from the light centre, marched per light sample. Compiles as C++ and GLSL
// (core/dh.h); shadowmaps/shaders/depth_grid.frag writes the grid, peel_march.comp and the CPU
// backend (shadowmaps/cpu/cpu_shadowmaps.cpp) march it with the functions below.
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
// A light sample's ray from the visible point p to the sample s is marched a grid texel at a time
// across the map (peelRayMarch), each step's whole depth span run through the table in the texel
// of its midpoint (peelTexelSpan): occluded when some depth is inside. The paper marches points
// at a fixed step; with 20 of them a ray on the knot (0.22 m apart against a 0.24 m tube) stepped
// over the tube and whole blobs of its shadow vanished. `peel_max_steps` caps the steps.
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

#include "shadowmaps/shadow_receiver_dh.h"

DH_BEGIN

/// Table 1 over the depths [z0, z1] (z0 ≤ z1) of one texel, nearest first: whether the nearest
/// and the farthest are inside an object, how often inside and outside change between them, and
/// whether any is inside. Along a texel's centre ray the table is a step function of the depth:
/// outside in front of near_p; in subinterval i, with z_j the first non-empty one in front, one
/// state before the depth |z_i| it keeps and one after; behind far_p the last surface's.
struct PeelSpan {
    uint first;   ///< 1: z0 is inside
    uint last;    ///< 1: z1 is inside
    uint changes; ///< inside/outside changes between z0 and z1
    uint any;     ///< 1: some depth of [z0, z1] is inside
};

DH_FUNC PeelSpan peelEmptySpan() {
    PeelSpan span;
    span.first = 0u;
    span.last = 0u;
    span.changes = 0u;
    span.any = 0u;
    return span;
}

/// The next piece of a span, nearest first.
DH_FUNC void peelSpanPush(DH_INOUT(PeelSpan) span, DH_INOUT(bool) started, bool inside) {
    uint state = inside ? 1u : 0u;
    if (!started) {
        span.first = state;
        started = true;
    } else if (span.last != state) {
        span.changes += 1u;
    }
    span.last = state;
    if (inside) span.any = 1u;
}

/// The span [z0, z1] of the texel whose words start at `base`: at most `bins` loop iterations
/// (back from the span's first subinterval to the first non-empty one in front, then forward
/// through the span's).
DH_FUNC PeelSpan peelTexelSpan(PeelGridSource src, uint base, uint bins, float z0, float z1) {
    PeelSpan span = peelEmptySpan();
    uint nearWord = peelGridWord(src, base);
    if (nearWord == 0u) return span; // no surface on this texel
    float lo = peelWordDepth(~nearWord);
    if (z1 < lo) return span; // in front of the texel's nearest surface
    float hi = peelWordDepth(peelGridWord(src, base + 1u));
    int i0 = peelBin(z0, lo, hi, bins);
    int i1 = peelBin(z1, lo, hi, bins);
    bool started = false;
    if (i0 < 0) peelSpanPush(span, started, false); // the part in front of near_p
    float zj = 0.0f;
    for (int j = min(i0, int(bins)) - 1; j >= 0 && zj == 0.0f; --j)
        zj = peelBinValue(peelGridWord(src, base + 2u + 2u * uint(j)),
                          peelGridWord(src, base + 3u + 2u * uint(j)));
    int last = min(i1, int(bins) - 1);
    for (int b = max(i0, 0); b <= last; ++b) {
        float zi = peelBinValue(peelGridWord(src, base + 2u + 2u * uint(b)),
                                peelGridWord(src, base + 3u + 2u * uint(b)));
        if (zi == 0.0f) {
            peelSpanPush(span, started, zj > 0.0f);
        } else {
            // Before the face (z ≤ z_i for a front face, z < |z_i| for a back face) and after it.
            // A back face at near_p has no depth before it in the texel: nothing is inside there.
            float edge = abs(zi);
            bool front = zi > 0.0f;
            if ((b > i0 || (front ? z0 <= edge : z0 < edge)) && (front || edge > lo))
                peelSpanPush(span, started, front ? zj > 0.0f : true);
            if (b < i1 || (front ? z1 > edge : z1 >= edge)) peelSpanPush(span, started, front);
            zj = zi;
        }
    }
    if (i1 >= int(bins)) peelSpanPush(span, started, zj > 0.0f); // behind far_p: the last surface decides
    return span;
}

/// Whether the point x lies inside an object according to the grid (Table 1 at its texel).
DH_FUNC bool peelPointOccluded(PeelGridSource src, ShadowMapView v, uint bins, vec3 x) {
    ShadowMapCoord c = shadowMapProject(v, x);
    // Nearer the light than every caster the map holds, or behind the light: nothing in front.
    if (c.valid == 0.0f || c.depth < v.near) return false;
    uint face;
    ivec2 texel;
    if (!shadowMapTexelOf(v, c.face, c.uv, face, texel)) return false;
    return peelTexelSpan(src, peelTexelBase(v, face, texel, bins), bins, c.depth, c.depth).any != 0u;
}

/// A cube map's texel seen from the centre spans at least 0.94/size radians (0.471 of its 2/size
/// tangent units, at a face's corner): the march's angular step on cube maps.
DH_CONST float PEEL_CUBE_TEXEL_ANGLE = 0.94f;

/// The outcome of one light-sample ray's march.
struct PeelMarch {
    uint occluded;  ///< 1: some step found a depth inside an object
    uint crossings; ///< inside/outside changes along the ray (counted only when asked for)
    uint steps;     ///< steps the ray's projection took (at most the cap)
    uint capped;    ///< 1: the ray needed more steps than the cap, which lengthened them
};

/// Clips t ∈ [t0, t1] to h0 + t·h1 ≥ 0 (one plane of Liang–Barsky's clip).
DH_FUNC void peelClip(float h0, float h1, DH_INOUT(float) t0, DH_INOUT(float) t1) {
    if (h1 == 0.0f) {
        if (h0 < 0.0f) t1 = -1.0f;
        return;
    }
    float t = -h0 / h1;
    if (h1 > 0.0f)
        t0 = max(t0, t);
    else
        t1 = min(t1, t);
}

/// The point of the march at fraction f of its projection, relative to the map's origin: the
/// projective interpolation between qa and qb with depths za and zb along the dividing axis
/// (perspective-correct: equal steps of f are equal steps across the map; za = zb = 1: linear).
DH_FUNC vec3 peelMarchPoint(vec3 qa, vec3 qb, float za, float zb, float f) {
    float wa = (1.0f - f) / za;
    float wb = f / zb;
    return (wa * qa + wb * qb) / (wa + wb);
}

/// The map's depth of a point relative to its origin (axial along Z, or radial on cube maps).
DH_FUNC float peelMarchDepth(ShadowMapView v, vec3 q) {
    return v.projection == SHADOW_MAP_CUBE ? length(q) : dot(q, v.axisZ);
}

/// The march of the ray from the receiver r (its point, plane and bias as the map filters take
/// them, shadow_receiver_dh.h) to the light sample s through the grid.
///  * The ray is clipped to where the grid can hold a blocker: depth at least `near`, inside the
///    window of a single-face map.
///  * Its projection on the map is cut into steps of at most one texel (max-norm across the face;
///    on cube maps PEEL_CUBE_TEXEL_ANGLE/size radians), equal across the map (perspective-correct),
///    at most `maxSteps`; a ray that needs more takes `maxSteps` longer ones and is `capped`.
///  * Each step is judged whole, not at a point: the depths it spans, in the texel of its
///    midpoint, run through Table 1 (peelTexelSpan), so an object thinner than a step along the
///    depth is not stepped over. Depths behind the receiver's plane along that texel's centre ray,
///    less the receiver's bias, are left out: the receiver's own surface does not shadow it.
/// `countAll` 0 stops at the first step inside an object; 1 marches the whole ray and counts the
/// inside/outside changes (a closed object crossed counts two: its front and its back face).
DH_FUNC PeelMarch peelRayMarch(PeelGridSource src, ShadowMapView v, uint bins, uint maxSteps,
                               ShadowReceiver r, vec3 s, uint countAll) {
    PeelMarch m;
    m.occluded = 0u;
    m.crossings = 0u;
    m.steps = 0u;
    m.capped = 0u;
    vec3 a = r.p - v.origin;
    vec3 d = s - r.p;
    float t0 = 0.0f;
    float t1 = 1.0f;
    vec3 X = v.axisX;
    vec3 Y = v.axisY;
    vec3 Z = v.axisZ;
    float width = v.window.z - v.window.x;
    if (v.projection == SHADOW_MAP_CUBE) {
        // Outside the ball of radius near: up to where the ray enters it.
        float dd = dot(d, d), ad = dot(a, d), excess = dot(a, a) - v.near * v.near;
        if (excess <= 0.0f) return m;
        float disc = ad * ad - dd * excess;
        if (disc > 0.0f && ad < 0.0f) t1 = min(t1, (-ad - sqrt(disc)) / dd);
    } else {
        float az = dot(a, Z), dz = dot(d, Z);
        float ax = dot(a, X), dx = dot(d, X), ay = dot(a, Y), dy = dot(d, Y);
        peelClip(az - v.near, dz, t0, t1);
        // The window: u0 ≤ x/z ≤ u1 (perspective, z > 0) or u0 ≤ x ≤ u1 (orthographic).
        float pz = v.projection == SHADOW_MAP_PERSPECTIVE ? az : 1.0f;
        float pdz = v.projection == SHADOW_MAP_PERSPECTIVE ? dz : 0.0f;
        peelClip(ax - v.window.x * pz, dx - v.window.x * pdz, t0, t1);
        peelClip(v.window.z * pz - ax, v.window.z * pdz - dx, t0, t1);
        peelClip(ay - v.window.y * pz, dy - v.window.y * pdz, t0, t1);
        peelClip(v.window.w * pz - ay, v.window.w * pdz - dy, t0, t1);
    }
    if (!(t1 > t0)) return m;
    vec3 qa = a + t0 * d;
    vec3 qb = a + t1 * d;
    // The dividing axis and the texels the projection crosses.
    float za = 1.0f, zb = 1.0f, texels = 0.0f;
    if (v.projection == SHADOW_MAP_ORTHOGRAPHIC) {
        vec3 e = qb - qa;
        texels = max(abs(dot(e, X)), abs(dot(e, Y))) * float(v.size) / width;
    } else {
        vec3 axis = Z;
        if (v.projection == SHADOW_MAP_CUBE) {
            // The bisector of the ray's ends seen from the centre: both lie in front of it.
            vec3 h = normalize(qa) + normalize(qb);
            axis = dot(h, h) > 1e-6f ? normalize(h) : normalize(qa);
        }
        za = dot(qa, axis);
        zb = dot(qb, axis);
        if (!(za > 0.0f) || !(zb > 0.0f)) {
            // Ends almost opposite seen from the centre: linear steps, as many as allowed.
            za = 1.0f;
            zb = 1.0f;
            texels = 3.0e38f;
        } else {
            vec3 e = qb / zb - qa / za; // across the plane at unit depth along the axis
            texels = v.projection == SHADOW_MAP_CUBE
                         ? length(e) * float(v.size) / PEEL_CUBE_TEXEL_ANGLE
                         : max(abs(dot(e, X)), abs(dot(e, Y))) * float(v.size) / width;
        }
    }
    uint n = 1u;
    if (texels > float(maxSteps)) {
        n = maxSteps;
        m.capped = 1u;
    } else if (texels > 1.0f) {
        n = uint(ceil(texels));
    }
    m.steps = n;
    float inv = 1.0f / float(n);
    float zPrev = peelMarchDepth(v, qa);
    // Whether the last depth looked at is inside; 2: none yet. As the reference leaves out the
    // receiver's own triangle, the count starts at the first depth the march looks at (a receiver
    // on an object's side away from the sample counts the face it leaves by, not the one it is on).
    uint state = 2u;
    for (uint k = 0u; k < n; ++k) {
        vec3 mid = peelMarchPoint(qa, qb, za, zb, (float(k) + 0.5f) * inv);
        float zNext = peelMarchDepth(v, peelMarchPoint(qa, qb, za, zb, float(k + 1u) * inv));
        bool nearer = zNext < zPrev; // the step runs towards the light: its start is its far end
        float lo = min(zPrev, zNext);
        float hi = max(zPrev, zNext);
        zPrev = zNext;
        PeelSpan span = peelEmptySpan();
        bool behind = false; // the whole step lies behind the receiver's plane: not looked at
        ShadowMapCoord c = shadowMapProject(v, v.origin + mid);
        uint face;
        ivec2 texel;
        if (c.valid != 0.0f && shadowMapTexelOf(v, c.face, c.uv, face, texel)) {
            uint base = peelTexelBase(v, face, texel, bins);
            uint nearWord = peelGridWord(src, base);
            // Most steps lie in front of their texel's nearest surface (or on an empty texel).
            if (nearWord != 0u && hi >= peelWordDepth(~nearWord)) {
                float limit = shadowMapPlaneDepth(v, face, texel, r.p, r.n, r.depth) - r.bias;
                if (min(hi, limit) >= lo)
                    span = peelTexelSpan(src, base, bins, lo, min(hi, limit));
                else
                    behind = true;
            }
        }
        if (span.any != 0u) {
            m.occluded = 1u;
            if (countAll == 0u) return m;
        }
        if (behind) continue;
        uint start = nearer ? span.last : span.first;
        if (state != 2u && start != state) m.crossings += 1u;
        m.crossings += span.changes;
        state = nearer ? span.first : span.last;
    }
    // The march ends outside every object: nearer than `near`, or beyond the map's window.
    if (state == 1u) m.crossings += 1u;
    return m;
}

DH_END

#endif // PEEL_GRID_SOURCE
