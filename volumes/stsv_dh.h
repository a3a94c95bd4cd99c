// Soft Textured Shadow Volumes: projective transmittance lookup (STSV paper §2.4, Eq. 1–5).
// The texel rule and the segments' start, which every method shares, are in
// scene/occlusion_rules_dh.h. Compiles as C++ and as GLSL (see core/dh.h).
//
// Formulation (DESIGN §4.3). For an S-triangle (v0, v1, v2) with unit normal n oriented
// towards the light centre:
//   M = [v1−v0 | v2−v0 | n]⁻¹                                   (Eq. 2, with −n → n)
//   (pu, pv, pw) = M·(p − v0),  e = −pw                          (e > 0: p behind the triangle)
//   W = [[e, 0, pu], [0, e, pv], [0, 0, 1]],  J = W·M            (Eq. 3: p is the projective centre)
//   h = J·(s − p)                                                (Eq. 1 without S)
// h.xy / h.z are the barycentrics (b1, b2) of the point where the line p→s meets the plane,
// at parameter t = e / h.z along p→s. The segment crosses the plane iff t ∈ (tMin, tMax), the
// gaps at its ends (scene/occlusion_rules_dh.h: tMin = shadowTMin, tMax = shadowTMax(tMin)); the
// sample is blocked by the triangle's extent iff, with h' = h·sign(h.z),
//   h'.x ≥ 0, h'.y ≥ 0, h'.x + h'.y ≤ h'.z                       (the paper's test, §2.4)
// and the texel at uv = t0 + (t1−t0)·b1 + (t2−t0)·b2 (Eq. 4–5, the matrix S) is opaque.
// This test is two-sided: it is exact for either side of the plane, so it serves both
// volumes of the double-sided construction.
#ifndef STSV_VOLUMES_STSV_DH_H
#define STSV_VOLUMES_STSV_DH_H

#include "core/dh.h"
#include "sampling/sample_region_dh.h"
#include "scene/occlusion_rules_dh.h"

DH_BEGIN

/// StsvTriangle::flags bits.
DH_CONST uint STSV_FLAG_CLAMP = 1u;      ///< texture wrap mode is clamp (else repeat)
DH_CONST uint STSV_FLAG_OPAQUE = 2u;     ///< no texture: every covered sample is blocked
DH_CONST uint STSV_FLAG_DEGENERATE = 4u; ///< zero-area triangle: blocks nothing
/// Translucent (a Blend material, with a transmittance buffer): a crossing adds the optical depth
/// of its texel's alpha (scene/occlusion_rules_dh.h) from the material's table; with
/// STSV_FLAG_OPAQUE as well, the constant α of a material without a texture (table entry 255).
DH_CONST uint STSV_FLAG_TRANSLUCENT = 8u;

/// Per-triangle constants (computed once per triangle and light). std430: 7 × 16 bytes.
struct StsvTriangle {
    vec4 m0;       ///< row 0 of M (xyz) and −row0·v0 (w): M(p − v0).x = dot(m0.xyz, p) + m0.w
    vec4 m1;       ///< row 1 of M, same convention
    vec4 m2;       ///< row 2 of M = unit normal towards the light centre; w = −n·v0
    vec2 uv0;      ///< texture coordinates of v0 (S, Eq. 4)
    vec2 uvE1;     ///< t1 − t0
    vec2 uvE2;     ///< t2 − t0
    uint texture;  ///< texture index (meaningless with STSV_FLAG_OPAQUE)
    uint flags;    ///< STSV_FLAG_*
    uint triangle; ///< index of the triangle in the scene (self-shadowing rule)
    uint material; ///< the triangle's material (its optical-depth table, STSV_FLAG_TRANSLUCENT)
    uint pad1;
    uint pad2;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(StsvTriangle) == 96);
#endif

/// Per-pixel, per-triangle state: J applied to the light frame, so that a light sample at
/// s = c + a·T + b·B costs h = h0 + a·hT + b·hB (two FMAs per component).
struct StsvPixel {
    vec3 h0;    ///< J·(c − p)
    float e;    ///< signed distance from p to the plane, positive behind the triangle (Eq. 3's e)
    vec3 hT;    ///< J·T
    float tMin; ///< segments start at this fraction of p→s (shadowTMin)
    vec3 hB;    ///< J·B
    float pad1;
};

/// Builds the per-triangle constants. `lightCenter` orients the normal (towards the light).
DH_FUNC StsvTriangle stsvSetupTriangle(vec3 v0, vec3 v1, vec3 v2, vec2 t0, vec2 t1, vec2 t2, vec3 lightCenter,
                                       uint textureIndex, uint flags, uint triangleIndex) {
    StsvTriangle t;
    vec3 e1 = v1 - v0;
    vec3 e2 = v2 - v0;
    vec3 nRaw = cross(e1, e2);
    float area2 = length(nRaw);
    float scale = max(max(length(e1), length(e2)), 1e-30f);
    t.uv0 = t0;
    t.uvE1 = t1 - t0;
    t.uvE2 = t2 - t0;
    t.texture = textureIndex;
    t.triangle = triangleIndex;
    t.material = 0u;
    t.pad1 = 0u;
    t.pad2 = 0u;
    if (!(area2 > 1e-7f * scale * scale)) {
        // Degenerate (or non-finite): blocks nothing. Rows chosen so every test fails.
        t.m0 = vec4(0.0f);
        t.m1 = vec4(0.0f);
        t.m2 = vec4(0.0f);
        t.flags = flags | STSV_FLAG_DEGENERATE;
        return t;
    }
    vec3 n = nRaw / area2;
    if (dot(n, lightCenter - v0) < 0.0f) n = -n;
    // M = [e1 | e2 | n]⁻¹ (Eq. 2); glm and GLSL matrices are column-major, so the columns
    // are e1, e2, n, and transpose(inverse) gives the rows.
    mat3 minv = inverse(mat3(e1, e2, n));
    vec3 r0 = vec3(minv[0][0], minv[1][0], minv[2][0]);
    vec3 r1 = vec3(minv[0][1], minv[1][1], minv[2][1]);
    t.m0 = vec4(r0, -dot(r0, v0));
    t.m1 = vec4(r1, -dot(r1, v0));
    t.m2 = vec4(n, -dot(n, v0));
    t.flags = flags;
    return t;
}

/// Per-pixel setup for visible point p and the light frame (c, T, B) of this pixel
/// (s = c + a·T + b·B). Builds J = W·M (Eq. 3) and applies it to the frame. `tMin` is the
/// segments' start (shadowTMin(p, c, sceneDiameter)).
DH_FUNC StsvPixel stsvSetupPixel(StsvTriangle t, vec3 p, vec3 c, vec3 T, vec3 B, float tMin) {
    float pu = dot(vec3(t.m0), p) + t.m0.w;
    float pv = dot(vec3(t.m1), p) + t.m1.w;
    float pw = dot(vec3(t.m2), p) + t.m2.w;
    float e = -pw;
    // Rows of J = W·M: J0 = e·M0 + pu·M2, J1 = e·M1 + pv·M2, J2 = M2.
    vec3 j0 = e * vec3(t.m0) + pu * vec3(t.m2);
    vec3 j1 = e * vec3(t.m1) + pv * vec3(t.m2);
    vec3 j2 = vec3(t.m2);
    vec3 d = c - p;
    StsvPixel px;
    px.h0 = vec3(dot(j0, d), dot(j1, d), dot(j2, d));
    px.hT = vec3(dot(j0, T), dot(j1, T), dot(j2, T));
    px.hB = vec3(dot(j0, B), dot(j1, B), dot(j2, B));
    px.e = e;
    px.tMin = tMin;
    px.pad1 = 0.0f;
    return px;
}

/// Homogeneous barycentrics of light sample (a, b) of the frame: h = J·(s − p).
DH_FUNC vec3 stsvSampleH(StsvPixel px, vec2 ab) {
    return px.h0 + ab.x * px.hT + ab.y * px.hB;
}

/// True iff the segment p→s (from t = tMin to shadowTMax(tMin)) crosses the triangle's extent;
/// `bary` gets (b1, b2) of the crossing. Texture not consulted.
DH_FUNC bool stsvSegmentHitsTriangle(vec3 h, float e, float tMin, DH_OUT(vec2) bary) {
    float sgn = h.z < 0.0f ? -1.0f : 1.0f;
    vec3 hs = h * sgn;
    float es = e * sgn;
    bary = vec2(0.0f);
    // t = es / hs.z must lie in (tMin, tMax): crossing between p and s, past both gaps.
    if (!(es > tMin * hs.z && es < shadowTMax(tMin) * hs.z)) return false;
    // Inside the triangle (the paper's three comparisons).
    if (hs.x < 0.0f || hs.y < 0.0f || hs.x + hs.y > hs.z) return false;
    bary = vec2(hs) / hs.z;
    return true;
}

/// Texture coordinates of the crossing (Eq. 4–5: S applied, then the projection).
DH_FUNC vec2 stsvTexcoord(StsvTriangle t, vec2 bary) {
    return t.uv0 + bary.x * t.uvE1 + bary.y * t.uvE2;
}

/// One light sample against one S-triangle, as the fragment shader and the CPU mirror run it:
/// true iff the segment p→s crosses the triangle's extent. `texel` gets the texel to test with
/// alphaBlocks (only meaningful for textured triangles, i.e. without STSV_FLAG_OPAQUE).
DH_FUNC bool stsvSampleCrosses(StsvTriangle t, StsvPixel px, vec2 ab, ivec2 textureSize,
                               DH_OUT(ivec2) texel) {
    vec2 bary;
    texel = ivec2(0);
    if (!stsvSegmentHitsTriangle(stsvSampleH(px, ab), px.e, px.tMin, bary)) return false;
    if ((t.flags & STSV_FLAG_OPAQUE) == 0u)
        texel = texelAt(stsvTexcoord(t, bary), textureSize,
                        (t.flags & STSV_FLAG_CLAMP) != 0u ? WRAP_CLAMP : WRAP_REPEAT);
    return true;
}

/// The light-frame points (a, b) of [lo, hi] whose segment p→s can cross the triangle, bounded:
/// the rectangle clipped by the five half-planes of stsvSegmentHitsTriangle, which are linear in
/// (a, b) because h = h0 + a·hT + b·hB (Eq. 1). With σ = sign(e), a crossing needs σ·h.z > σ·e > 0,
/// so hs = σ·h and the test reads σh.x ≥ 0, σh.y ≥ 0, σ(h.z − h.x − h.y) ≥ 0 (inside the
/// triangle), σ(tMax·h.z − e) ≥ 0 and σ(e − tMin·h.z) ≥ 0 (t in (tMin, tMax)): the triangle projected from
/// p onto the light, cut to the segment. Every half-plane is widened by 1e-5 of the magnitudes
/// of its terms, and the box by 1e-5 of the rectangle, far beyond the float rounding of the
/// per-sample test and of the clipping, so a sample outside the returned box fails
/// stsvSegmentHitsTriangle (sampleRegionOfHalfPlanes): testing only the samples inside it
/// changes no result. False when no point of the rectangle can cross.
DH_FUNC bool stsvSampleRegion(StsvPixel px, vec2 lo, vec2 hi, DH_OUT(vec2) regionLo, DH_OUT(vec2) regionHi) {
    regionLo = lo;
    regionHi = hi;
    if (!(px.e != 0.0f)) return false;
    float sigma = px.e > 0.0f ? 1.0f : -1.0f;
    // Half-plane j: f(a, b) = c.x + c.y·a + c.z·b ≥ 0.
    vec3 hx = sigma * vec3(px.h0.x, px.hT.x, px.hB.x);
    vec3 hy = sigma * vec3(px.h0.y, px.hT.y, px.hB.y);
    vec3 hz = sigma * vec3(px.h0.z, px.hT.z, px.hB.z);
    vec3 es = vec3(sigma * px.e, 0.0f, 0.0f);
    vec3 planes[SAMPLE_REGION_MAX_PLANES];
    planes[0] = hx;
    planes[1] = hy;
    planes[2] = hz - hx - hy;
    float tMax = shadowTMax(px.tMin);
    planes[3] = tMax * hz - es;
    planes[4] = es - px.tMin * hz;
    // The magnitudes the per-sample test rounds against: those of the terms before they cancel.
    vec3 mags[SAMPLE_REGION_MAX_PLANES];
    mags[0] = abs(hx);
    mags[1] = abs(hy);
    mags[2] = abs(hx) + abs(hy) + abs(hz);
    mags[3] = tMax * abs(hz) + abs(es);
    mags[4] = abs(es) + px.tMin * abs(hz);
    return sampleRegionOfHalfPlanes(planes, mags, 5u, lo, hi, regionLo, regionHi);
}

DH_END

#endif // STSV_VOLUMES_STSV_DH_H
