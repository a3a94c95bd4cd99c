// One Soft Textured Shadow Volume (STSV paper §2.2–2.3, §4.2, Fig. 6; DESIGN §4.2): its planes,
// its ten-vertex strip and the point-in-volume test. Compiles as C++ and as GLSL 4.50 (see core/dh.h): the
// geometry shader calls stsvBuildVolume per S-triangle and emits `vertices` as one ten-vertex strip, the CPU
// mirror calls the same function.
//
// Construction, for an S-triangle t = (v0, v1, v2), a light bounding sphere (c, r) and one side σ
// of the triangle (σ = 0: the side of c; σ = 1: the other side, the paper's §6 double-sided fix):
//  1. n_σ: unit normal of t towards the lit side. Only light points x with n_σ·(x − v0) ≥ 0 shadow
//     through side σ; their region is bounded by the sphere (ĉ, r̂): (c, r) when c is on side σ,
//     else the disk where the sphere crosses the plane (ĉ = projection of c, r̂ = √(r² − d²)).
//  2. Front cap t' (§2.2, after [AAM03]): keep the vertex closest to ĉ, pull the others along their
//     rays from ĉ to the same distance R. t lies behind t' as seen from ĉ.
//  3. Outer plane of each edge of t' (the penumbra wedge's outer quad): through the edge, tangent
//     to the sphere, sphere on the negative side and t' on the positive side. Every segment from a
//     light point (negative side) through t (non-negative side, because t lies beyond t' on rays
//     from ĉ) ends on the positive side: the planes are conservative.
//  4. Side edges along the intersection of adjacent outer planes (cross(n_a, n_b), away from ĉ);
//     back cap parallel to the front cap, beyond the scene box; ten-vertex strip (Fig. 6). When the
//     side planes meet between the caps (their apex), the prism ends there: one cap collapses to
//     the apex and the strip is a tetrahedron (its collapsed triangles rasterise nothing).
// Conservative fallbacks, never NaN: an edge of t' whose line meets the sphere, or with the sphere
// across it on the triangle's side, has no outer plane: it is left out of `planes` and bounded in
// the strip by a plane outside the box (STSV_VOLUME_NO_TANGENT). When the sphere crosses the plane
// of t', the front cap lies in the triangle's plane instead (STSV_VOLUME_TRIANGLE_CAP). Outer
// planes nearly parallel to the caps (corners far outside the box) are replaced in the strip by
// upright planes outside the box. When the side planes lean both ways across the caps, the strip
// closes them across the whole box along their cone's axis (STSV_VOLUME_CONE_STRIP); when even
// that fails, it is a prism around the whole box behind the triangle (STSV_VOLUME_BOX). Degenerate
// triangles and unlit sides give empty volumes.
//
// `planes` always hold the triangle's plane (p behind t, side σ), then the plane of t' when it is
// the front cap, then the outer planes that exist; all shifted outwards by a small slack (rounding)
// so that the volume is conservative in float. The strip encloses {p in every plane} ∩ box, so a
// fragment of the strip's back faces behind the visible point p is produced for every p inside
// (DESIGN §4.2: one fragment per pixel and volume, as the strip is convex), and the fragment
// shader's stsvPointInVolume(p) removes the rest.
#ifndef STSV_VOLUMES_VOLUME_DH_H
#define STSV_VOLUMES_VOLUME_DH_H

#include "core/dh.h"
#include "volumes/clip_box_dh.h"

DH_BEGIN

/// StsvVolume::flags bits.
// clang-format off
DH_CONST uint STSV_VOLUME_EMPTY = 1u;          ///< contains no point (degenerate triangle, or no light on this side)
DH_CONST uint STSV_VOLUME_DEGENERATE = 2u;     ///< zero-area or non-finite input (with STSV_VOLUME_EMPTY)
DH_CONST uint STSV_VOLUME_NO_TANGENT = 4u;     ///< an edge of t' has no outer plane: that side is open in `planes`
DH_CONST uint STSV_VOLUME_TRIANGLE_CAP = 8u;   ///< sphere crosses the plane of t': front cap in the triangle's plane
DH_CONST uint STSV_VOLUME_BOX = 16u;           ///< strip is the prism around the box behind the triangle
DH_CONST uint STSV_VOLUME_CONE_STRIP = 32u;    ///< strip closes the side planes across the box, not at the front cap
// clang-format on

DH_CONST uint STSV_VOLUME_MAX_PLANES = 5u;
DH_CONST uint STSV_STRIP_VERTEX_COUNT = 10u;

/// Outward slack of the stored planes, in units of the scene box diagonal, plus 0.2 × as much per
/// unit of the box's largest coordinate magnitude: float rounding of the construction and of the
/// world-space plane test (a few 1e-7 of |p|) stays well below it.
DH_CONST float STSV_VOLUME_SLACK = 1e-5f;
/// The rasterised geometry (strip or clipped box) lies this much (box diagonals) beyond the slack
/// outside the stored planes, and STSV_STRIP_MARGIN outside the box: more than the rounding of
/// the corners it is built from, so it encloses every point the planes accept.
DH_CONST float STSV_STRIP_EXPANSION = 4e-4f;
DH_CONST float STSV_STRIP_MARGIN = 1e-3f;

/// One STSV (one side of one S-triangle). std430: 16 × 16 bytes.
struct StsvVolume {
    vec4 planes[STSV_VOLUME_MAX_PLANES]; ///< world space (n, d), unit n: p is inside iff
                                         ///< dot(n, p) + d ≥ 0 for the first planeCount
    vec4 vertices[10]; ///< world space, w = 1: triangle strip (STSV Fig. 6), front cap first, faces outward
                       ///< (CCW)
    uint planeCount;   ///< 0…STSV_VOLUME_MAX_PLANES
    uint flags;        ///< STSV_VOLUME_*
    uint pad0;
    uint pad1;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(StsvVolume) == 256);
#endif

/// Strip order: F_i is front-cap vertex i, B_i the back-cap vertex on the same side edge. With
/// F0 F1 F2 counter-clockwise seen from the light, every strip triangle (odd ones with their first
/// two vertices swapped, as Vulkan/GL rasterise strips) is counter-clockwise seen from outside:
/// F0 F1 F2 | B2 F0 B0 F1 B1 B2 B0 → front cap, the three side quads, back cap last.
DH_FUNC bool stsvFiniteVec(vec3 v) {
    return !(any(isnan(v)) || any(isinf(v)));
}

DH_FUNC vec3 stsvBoxCorner(vec3 lo, vec3 hi, uint i) {
    return vec3((i & 1u) != 0u ? hi.x : lo.x, (i & 2u) != 0u ? hi.y : lo.y, (i & 4u) != 0u ? hi.z : lo.z);
}

/// The point common to three planes (n·x + d = 0, unit normals); false if they are (nearly)
/// dependent or the point is not finite.
DH_FUNC bool stsvIntersectPlanes(vec4 a, vec4 b, vec4 c, DH_OUT(vec3) x) {
    vec3 na = vec3(a);
    vec3 nb = vec3(b);
    vec3 nc = vec3(c);
    vec3 bc = cross(nb, nc);
    float det = dot(na, bc);
    x = vec3(0.0f);
    if (!(abs(det) > 1e-7f)) return false;
    x = -(a.w * bc + b.w * cross(nc, na) + c.w * cross(na, nb)) / det;
    return stsvFiniteVec(x);
}

/// Outer plane of the penumbra wedge of edge (a, b) ([AAM03], STSV §2.2): contains the edge, is
/// tangent to the sphere (center, radius) with the sphere on its negative side, and has `inner` (the
/// third vertex) strictly on its positive side. When both tangent planes qualify (sphere beyond the
/// edge line), the one whose normal leans most towards `towardLight` bounds the shadow behind the
/// triangle more tightly. False when none exists: the edge line meets the sphere, or the sphere
/// reaches across the edge on the triangle's side.
DH_FUNC bool stsvOuterPlane(vec3 a, vec3 b, vec3 inner, vec3 center, float radius, vec3 towardLight,
                            DH_OUT(vec4) plane) {
    plane = vec4(0.0f);
    vec3 e = b - a;
    float len = length(e);
    if (!(len > 0.0f)) return false;
    vec3 dir = e / len;
    vec3 w = center - a;
    vec3 q = w - dot(w, dir) * dir; // centre relative to the edge line, perpendicular part
    float ql = length(q);
    if (!(ql > radius)) return false;
    vec3 u = q / ql;
    vec3 v = cross(dir, u);
    // Unit normals n ⊥ dir with n·q = −radius: the sphere touches the plane from the negative side.
    float alpha = -radius / ql;
    float beta = sqrt(max(1.0f - alpha * alpha, 0.0f));
    vec3 n1 = alpha * u + beta * v;
    vec3 n2 = alpha * u - beta * v;
    vec3 toInner = inner - a;
    float minSide = 1e-6f * length(toInner);
    bool ok1 = dot(n1, toInner) > minSide;
    bool ok2 = dot(n2, toInner) > minSide;
    if (!ok1 && !ok2) return false;
    vec3 n = ok1 ? n1 : n2;
    if (ok1 && ok2 && dot(n2, towardLight) > dot(n1, towardLight)) n = n2;
    plane = vec4(n, -dot(n, a));
    return true;
}

/// A volume that contains nothing (every point fails planes[0]); the strip collapses to `at`.
DH_FUNC StsvVolume stsvEmptyVolume(vec3 at, uint flags) {
    StsvVolume v;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) v.planes[i] = vec4(0.0f, 0.0f, 0.0f, -1.0f);
    for (uint i = 0u; i < 10u; ++i) v.vertices[i] = vec4(at, 1.0f);
    v.planeCount = 1u;
    v.flags = flags | STSV_VOLUME_EMPTY;
    v.pad0 = 0u;
    v.pad1 = 0u;
    return v;
}

/// Writes the strip of Fig. 6 from front cap (f0, f1, f2) and back cap (b0, b1, b2), b_i behind f_i.
/// `toLight` is the outward normal of the front cap; the order is swapped if the caps run clockwise
/// around it (judged on the larger cap: one of them may have collapsed to a point).
DH_FUNC void stsvWriteStrip(DH_INOUT(StsvVolume) v, vec3 f0, vec3 f1, vec3 f2, vec3 b0, vec3 b1, vec3 b2,
                            vec3 toLight) {
    if (dot(cross(f1 - f0, f2 - f0) + cross(b1 - b0, b2 - b0), toLight) < 0.0f) {
        vec3 t = f1;
        f1 = f2;
        f2 = t;
        t = b1;
        b1 = b2;
        b2 = t;
    }
    v.vertices[0] = vec4(f0, 1.0f);
    v.vertices[1] = vec4(f1, 1.0f);
    v.vertices[2] = vec4(f2, 1.0f);
    v.vertices[3] = vec4(b2, 1.0f);
    v.vertices[4] = vec4(f0, 1.0f);
    v.vertices[5] = vec4(b0, 1.0f);
    v.vertices[6] = vec4(f1, 1.0f);
    v.vertices[7] = vec4(b1, 1.0f);
    v.vertices[8] = vec4(b2, 1.0f);
    v.vertices[9] = vec4(b0, 1.0f);
}

/// Corners of the convex solid {s0, s1, s2 ≥ 0} ∩ {backLevel ≤ axis·x ≤ frontLevel} (unit `axis`),
/// written as a prism f_i (front cap) / b_i (back cap), corner i on s_{i−1} ∩ s_i. The side planes
/// bound a cone with apex A = s0 ∩ s1 ∩ s2 whose edges r_i run along s_{i−1} ∩ s_i. When all edges
/// lean the same way along `axis` and A lies between the caps, the solid ends at A: the cap on
/// A's side collapses to A (a tetrahedron). Without an apex the edges are parallel and every cross
/// section is the same triangle. False when the solid is not such a closed prism (edges leaning
/// both ways, caps crossing, corners outside the half-spaces beyond rounding).
DH_FUNC bool stsvClosePrism(vec4 s0, vec4 s1, vec4 s2, vec3 axis, float frontLevel, float backLevel,
                            DH_OUT(vec3) f0, DH_OUT(vec3) f1, DH_OUT(vec3) f2, DH_OUT(vec3) b0,
                            DH_OUT(vec3) b1, DH_OUT(vec3) b2) {
    vec3 apex;
    bool hasApex = stsvIntersectPlanes(s0, s1, s2, apex);
    vec3 n0 = vec3(s0);
    vec3 n1 = vec3(s1);
    vec3 n2 = vec3(s2);
    vec3 r0 = cross(n2, n0); // edge at corner 0, oriented into the cone below
    vec3 r1 = cross(n0, n1);
    vec3 r2 = cross(n1, n2);
    if (dot(r0, n1) < 0.0f) r0 = -r0;
    if (dot(r1, n2) < 0.0f) r1 = -r1;
    if (dot(r2, n0) < 0.0f) r2 = -r2;
    bool towards = dot(axis, r0) > 0.0f && dot(axis, r1) > 0.0f && dot(axis, r2) > 0.0f;
    bool away = dot(axis, r0) < 0.0f && dot(axis, r1) < 0.0f && dot(axis, r2) < 0.0f;
    float apexLevel = dot(axis, apex);
    bool between = hasApex && apexLevel < frontLevel && apexLevel > backLevel;
    bool frontAtApex = between && away;   // nothing in front of the apex
    bool backAtApex = between && towards; // nothing behind the apex
    bool ok = !(hasApex && !towards && !away);
    ok = ok && !(hasApex && towards && apexLevel >= frontLevel); // cone entirely in front of the slab
    ok = ok && !(hasApex && away && apexLevel <= backLevel);     // cone entirely behind it
    vec4 front = vec4(-axis, frontLevel);
    vec4 back = vec4(axis, -backLevel);
    f0 = apex;
    f1 = apex;
    f2 = apex;
    b0 = apex;
    b1 = apex;
    b2 = apex;
    if (!frontAtApex) {
        ok = ok && stsvIntersectPlanes(front, s2, s0, f0);
        ok = ok && stsvIntersectPlanes(front, s0, s1, f1);
        ok = ok && stsvIntersectPlanes(front, s1, s2, f2);
    }
    if (!backAtApex) {
        ok = ok && stsvIntersectPlanes(back, s2, s0, b0);
        ok = ok && stsvIntersectPlanes(back, s0, s1, b1);
        ok = ok && stsvIntersectPlanes(back, s1, s2, b2);
    }
    if (!ok) return false;
    // Every corner in every half-space, up to rounding (~1e-7·|corner|; lengths here are in box
    // diagonals), and caps turning the same way unless one collapsed.
    for (uint j = 0u; j < 5u; ++j) {
        vec4 pl = j == 0u ? front : (j == 1u ? back : (j == 2u ? s0 : (j == 3u ? s1 : s2)));
        vec3 n = vec3(pl);
        ok = ok && dot(n, f0) + pl.w >= -(1e-4f + 1e-6f * length(f0));
        ok = ok && dot(n, f1) + pl.w >= -(1e-4f + 1e-6f * length(f1));
        ok = ok && dot(n, f2) + pl.w >= -(1e-4f + 1e-6f * length(f2));
        ok = ok && dot(n, b0) + pl.w >= -(1e-4f + 1e-6f * length(b0));
        ok = ok && dot(n, b1) + pl.w >= -(1e-4f + 1e-6f * length(b1));
        ok = ok && dot(n, b2) + pl.w >= -(1e-4f + 1e-6f * length(b2));
    }
    float extent =
        max(max(max(length(f0), length(f1)), max(length(f2), length(b0))), max(length(b1), length(b2)));
    ok = ok && extent < 100.0f; // corners within 100 box diagonals: nearly parallel planes give up
    float frontTurn = dot(cross(f1 - f0, f2 - f0), axis);
    float backTurn = dot(cross(b1 - b0, b2 - b0), axis);
    if (backAtApex) return ok && abs(frontTurn) > 1e-12f;
    if (frontAtApex) return ok && abs(backTurn) > 1e-12f;
    return ok && abs(frontTurn) > 1e-12f && frontTurn * backTurn > 0.0f;
}

/// Shortens the prism whose side edges run from f_i through b_i at its b end: b_i move along
/// their edges onto the plane of the box face, moved `margin` outwards, that cuts all three edges
/// nearest to f (the least sum of the edges' parameters). The box lies inside each of its faces'
/// planes, so the shortened prism still holds prism ∩ box. A face qualifies when every f_i is
/// strictly inside its plane and every b_i on it or beyond: the plane then crosses the three side
/// edges and neither cap, and the section is the new cap. Nothing changes when no face does.
/// (A prism leaving the box through its bottom under an oblique light reaches far below it
/// behind the box's farthest corner: on screen that is a long streak of fragments behind every
/// receiver that the point-in-volume test rejects.)
DH_FUNC void stsvCutPrismAtBox(vec3 f0, vec3 f1, vec3 f2, DH_INOUT(vec3) b0, DH_INOUT(vec3) b1,
                               DH_INOUT(vec3) b2, vec3 boxLo, vec3 boxHi, float margin) {
    float best = 3.0f;
    vec3 c0 = b0;
    vec3 c1 = b1;
    vec3 c2 = b2;
    for (uint face = 0u; face < 6u; ++face) {
        uint axis = face / 2u;
        // Outward normal ±e_axis; a point x is beyond the plane where sgn·(x[axis] − level) > 0.
        float sgn = (face & 1u) != 0u ? 1.0f : -1.0f;
        float level = (face & 1u) != 0u ? boxHi[axis] + margin : boxLo[axis] - margin;
        vec3 df = sgn * (vec3(f0[axis], f1[axis], f2[axis]) - vec3(level));
        vec3 db = sgn * (vec3(b0[axis], b1[axis], b2[axis]) - vec3(level));
        if (!(all(lessThan(df, vec3(0.0f))) && all(greaterThanEqual(db, vec3(0.0f))))) continue;
        vec3 t = df / (df - db); // in (0, 1]: where each edge meets the plane
        float sum = t.x + t.y + t.z;
        if (!(sum < best)) continue;
        best = sum;
        c0 = f0 + t.x * (b0 - f0);
        c1 = f1 + t.y * (b1 - f1);
        c2 = f2 + t.z * (b2 - f2);
        // On the plane exactly: interpolation rounds the cut coordinate.
        c0[axis] = level;
        c1[axis] = level;
        c2[axis] = level;
    }
    b0 = c0;
    b1 = c1;
    b2 = c2;
}

/// Zero-area or non-finite triangle, by the criterion of stsvSetupTriangle (stsv_dh.h), so that a
/// triangle without volume is also one that blocks nothing.
DH_FUNC bool stsvTriangleIsDegenerate(vec3 v0, vec3 v1, vec3 v2) {
    vec3 e1 = v1 - v0;
    vec3 e2 = v2 - v0;
    float area2 = length(cross(e1, e2));
    float edgeScale = max(max(length(e1), length(e2)), 1e-30f);
    return !(area2 > 1e-7f * edgeScale * edgeScale) || !stsvFiniteVec(v0) || !stsvFiniteVec(v1) ||
           !stsvFiniteVec(v2);
}

/// The frame a triangle's volume is built in: relative to v0, in units of the diagonal of the
/// scene box grown to hold the triangle, so that thresholds are absolute and nothing overflows at
/// huge or tiny scene scales; x_world = origin + scale·x.
struct StsvVolumeFrame {
    vec3 origin;    ///< world units: v0
    float scale;    ///< world units per frame unit: the box diagonal
    vec3 boxLo;     ///< frame units: the box, grown to hold the triangle
    float invScale; ///< 1 / scale
    vec3 boxHi;
    float slack; ///< frame units: the outward slack of every stored plane (STSV_VOLUME_SLACK)
};

DH_FUNC StsvVolumeFrame stsvVolumeFrame(vec3 v0, vec3 v1, vec3 v2, vec3 boundsLo, vec3 boundsHi) {
    StsvVolumeFrame f;
    vec3 boxLoW = min(min(boundsLo, v0), min(v1, v2));
    vec3 boxHiW = max(max(boundsHi, v0), max(v1, v2));
    f.origin = v0;
    f.scale = max(length(boxHiW - boxLoW), 1e-30f);
    f.invScale = 1.0f / f.scale;
    vec3 farW = max(abs(boxLoW), abs(boxHiW));
    f.slack = STSV_VOLUME_SLACK * (1.0f + 0.2f * max(max(farW.x, farW.y), farW.z) * f.invScale);
    f.boxLo = (boxLoW - v0) * f.invScale;
    f.boxHi = (boxHiW - v0) * f.invScale;
    return f;
}

/// A plane (n, d) of the frame in world space: x_world = origin + scale·x.
DH_FUNC vec4 stsvPlaneToWorld(StsvVolumeFrame f, vec4 plane) {
    vec3 m = vec3(plane);
    return vec4(m, plane.w * f.scale - dot(m, f.origin));
}

/// A world-space plane in the frame.
DH_FUNC vec4 stsvPlaneToFrame(StsvVolumeFrame f, vec4 plane) {
    vec3 m = vec3(plane);
    return vec4(m, (plane.w + dot(m, f.origin)) * f.invScale);
}

/// Number of volumes the triangle needs for this light: 2 when the light's bounding sphere
/// (centre xyz, radius w) straddles the triangle's plane — both sides are lit (STSV §6) — else 1.
/// Degenerate triangles: 1 (an empty volume). A sphere touching the plane within float rounding
/// counts as straddling (conservative).
DH_FUNC uint stsvSideCount(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere) {
    if (stsvTriangleIsDegenerate(v0, v1, v2)) return 1u;
    vec3 n = normalize(cross(v1 - v0, v2 - v0));
    vec3 c = vec3(lightSphere);
    float d = abs(dot(n, c - v0));
    float slack = 1e-6f * (length(c - v0) + abs(lightSphere.w));
    return d < lightSphere.w + slack ? 2u : 1u;
}

/// The plane of t' (q0, q1, q2) as the front cap (STSV §2.2), facing away from the light's disk
/// (centre ch, radius rh, in the volume's frame) and `slack` outwards, when the whole disk lies in
/// front of it; false where it does not, or where t' is thin (two corners on nearly one ray from
/// ĉ, an edge pointing at the light: a plane dominated by rounding, still a valid bound but a
/// useless one), and the triangle's plane stays the cap.
DH_FUNC bool stsvTPrimeCap(vec3 q0, vec3 q1, vec3 q2, vec3 ch, float rh, float slack, DH_OUT(vec4) cap) {
    cap = vec4(0.0f);
    vec3 nT = cross(q1 - q0, q2 - q0);
    float nTLength = length(nT);
    float qScale = max(length(q1 - q0), length(q2 - q0));
    if (!(nTLength > 1e-3f * qScale * qScale)) return false;
    nT = nT / nTLength;
    float dT = dot(nT, ch - q0);
    if (dT < 0.0f) {
        nT = -nT;
        dT = -dT;
    }
    if (!(dT > rh)) return false;
    cap = vec4(-nT, dot(nT, q0) + slack);
    return true;
}

/// Steps 1–3 of stsvBuildVolume: the volume's planes in its frame (StsvVolumeFrame), and what
/// the strip is built from.
struct StsvVolumeCore {
    StsvVolume vol;        ///< planes in the frame, planeCount, flags; world space and final when done
    StsvVolumeFrame frame; ///< of the triangle and the box
    vec3 n;                ///< the side's normal
    vec3 p1;               ///< v1 − v0 in the frame (v0 is its origin)
    vec3 p2;               ///< v2 − v0 in the frame
    vec3 q[3];             ///< the front cap t' (or the triangle)
    vec4 outer[3];         ///< outer planes of t''s edges, where hasOuter
    bool hasOuter[3];
    vec4 front; ///< the front cap's plane
    uint done;  ///< 1: vol is an empty volume, in world space, and nothing follows
};

DH_FUNC StsvVolumeCore stsvVolumeCore(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere, vec3 boundsLo,
                                      vec3 boundsHi, uint side) {
    StsvVolumeCore core;
    core.done = 1u;
    vec3 e1 = v1 - v0;
    vec3 e2 = v2 - v0;
    bool finiteInput = stsvFiniteVec(v0) && stsvFiniteVec(v1) && stsvFiniteVec(v2) &&
                       stsvFiniteVec(vec3(lightSphere)) && !isnan(lightSphere.w) && !isinf(lightSphere.w) &&
                       stsvFiniteVec(boundsLo) && stsvFiniteVec(boundsHi);
    if (!finiteInput || stsvTriangleIsDegenerate(v0, v1, v2)) {
        core.vol = stsvEmptyVolume(finiteInput ? v0 : vec3(0.0f), STSV_VOLUME_DEGENERATE);
        return core;
    }

    // Work relative to v0 in units of the box diagonal (StsvVolumeFrame).
    StsvVolumeFrame frame = stsvVolumeFrame(v0, v1, v2, boundsLo, boundsHi);
    float invScale = frame.invScale;
    float slack = frame.slack;
    vec3 p0 = vec3(0.0f);
    vec3 p1 = e1 * invScale;
    vec3 p2 = e2 * invScale;
    vec3 cc = (vec3(lightSphere) - v0) * invScale;
    float rr = abs(lightSphere.w) * invScale;

    // 1. Side normal and the light region that shines on this side.
    vec3 n = normalize(cross(p1, p2));
    float dc = dot(n, cc);
    if (dc < 0.0f) {
        n = -n;
        dc = -dc;
    }
    if (side == 1u) {
        n = -n;
        dc = -dc;
        if (!(dc > -rr)) {
            core.vol = stsvEmptyVolume(v0, 0u);
            return core;
        }
    }
    vec3 ch = cc;
    float rh = rr;
    if (dc < 0.0f) {
        ch = cc - dc * n; // the disk where the sphere crosses the plane bounds the lit part
        rh = sqrt(max(rr * rr - dc * dc, 0.0f));
    }
    rh = rh * (1.0f + 1e-5f) + slack;

    StsvVolume vol;
    vol.flags = 0u;
    vol.pad0 = 0u;
    vol.pad1 = 0u;
    vec4 triPlane = vec4(-n, slack); // behind t (p0 = 0), STSV §2.3
    vol.planes[0] = triPlane;
    uint count = 1u;

    // 2. Front cap t': the vertex closest to ĉ is kept, the others pulled towards ĉ (§2.2).
    float d0 = length(p0 - ch);
    float d1 = length(p1 - ch);
    float d2 = length(p2 - ch);
    float R = min(d0, min(d1, d2));
    bool tPrimeOk = R > rh;
    vec3 q[3];
    q[0] = p0;
    q[1] = p1;
    q[2] = p2;
    if (tPrimeOk) {
        if (d0 > R) q[0] = ch + (p0 - ch) * (R / d0);
        if (d1 > R) q[1] = ch + (p1 - ch) * (R / d1);
        if (d2 > R) q[2] = ch + (p2 - ch) * (R / d2);
    }

    // 3. Outer planes of the edges of t' (edge i runs from q[i] to q[i+1]).
    vec4 outer[3];
    bool hasOuter[3];
    for (uint i = 0u; i < 3u; ++i) {
        hasOuter[i] =
            tPrimeOk && stsvOuterPlane(q[i], q[(i + 1u) % 3u], q[(i + 2u) % 3u], ch, rh, n, outer[i]);
        if (!hasOuter[i]) {
            outer[i] = vec4(0.0f);
            vol.flags |= STSV_VOLUME_NO_TANGENT;
        }
    }

    // Front cap: the plane of t' if the whole sphere is in front of it, else the triangle's plane.
    vec4 front = triPlane;
    vec4 tPrimePlane = vec4(0.0f);
    bool capTPrime = tPrimeOk && stsvTPrimeCap(q[0], q[1], q[2], ch, rh, slack, tPrimePlane);
    if (capTPrime) {
        front = tPrimePlane;
        vol.planes[count] = front;
        count += 1u;
    } else {
        vol.flags |= STSV_VOLUME_TRIANGLE_CAP;
    }
    for (uint i = 0u; i < 3u; ++i) {
        if (hasOuter[i]) {
            vol.planes[count] = outer[i] + vec4(0.0f, 0.0f, 0.0f, slack);
            count += 1u;
        }
    }
    vol.planeCount = count;
    for (uint i = count; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = vec4(0.0f);

    core.vol = vol;
    core.frame = frame;
    core.n = n;
    core.p1 = p1;
    core.p2 = p2;
    for (uint i = 0u; i < 3u; ++i) {
        core.q[i] = q[i];
        core.outer[i] = outer[i];
        core.hasOuter[i] = hasOuter[i];
    }
    core.front = front;
    core.done = 0u;
    return core;
}

/// The planes of one side's volume without its strip (stsvBuildVolume's planes, planeCount and
/// flags but STSV_VOLUME_CONE_STRIP and STSV_VOLUME_BOX, which describe the strip; the vertices
/// all v0): what the hull passes clip the box by.
DH_FUNC StsvVolume stsvBuildVolumePlanes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere, vec3 boundsLo,
                                         vec3 boundsHi, uint side) {
    StsvVolumeCore core = stsvVolumeCore(v0, v1, v2, lightSphere, boundsLo, boundsHi, side);
    if (core.done != 0u) return core.vol;
    StsvVolume vol = core.vol;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
        vol.planes[i] = stsvPlaneToWorld(core.frame, vol.planes[i]);
    for (uint i = 0u; i < 10u; ++i) vol.vertices[i] = vec4(v0, 1.0f);
    return vol;
}

/// Step 4 where the side planes s0, s1, s2 lean both ways across the caps (light grazing the
/// plane, an edge pointing at it): the prism closed across the whole box along the axis of their
/// cone; false where that axis or the prism degenerates.
DH_FUNC bool stsvConeStripPrism(vec4 s0, vec4 s1, vec4 s2, vec3 toLight, vec3 boxLo, vec3 boxHi, float margin,
                                DH_OUT(vec3) f0, DH_OUT(vec3) f1, DH_OUT(vec3) f2, DH_OUT(vec3) b0,
                                DH_OUT(vec3) b1, DH_OUT(vec3) b2) {
    vec3 axis = vec3(0.0f);
    vec3 apex;
    vec3 n0 = vec3(s0);
    vec3 n1 = vec3(s1);
    vec3 n2 = vec3(s2);
    if (stsvIntersectPlanes(s0, s1, s2, apex)) {
        // Opposite of the mean edge direction (edges oriented into the cone).
        vec3 r0 = cross(n2, n0);
        vec3 r1 = cross(n0, n1);
        vec3 r2 = cross(n1, n2);
        if (dot(r0, n1) < 0.0f) r0 = -r0;
        if (dot(r1, n2) < 0.0f) r1 = -r1;
        if (dot(r2, n0) < 0.0f) r2 = -r2;
        axis = -(normalize(r0) + normalize(r1) + normalize(r2));
    } else {
        // Parallel edges: along them (either way).
        vec3 r0 = cross(n2, n0);
        vec3 r1 = cross(n0, n1);
        axis = length(r0) > length(r1) ? r0 : r1;
    }
    float axisLength = length(axis);
    bool ok = axisLength > 1e-6f;
    axis = ok ? axis / axisLength : toLight;
    float hi = dot(axis, stsvBoxCorner(boxLo, boxHi, 0u));
    float lo = hi;
    for (uint k = 1u; k < 8u; ++k) {
        hi = max(hi, dot(axis, stsvBoxCorner(boxLo, boxHi, k)));
        lo = min(lo, dot(axis, stsvBoxCorner(boxLo, boxHi, k)));
    }
    return ok && stsvClosePrism(s0, s1, s2, axis, hi + margin, lo - margin, f0, f1, f2, b0, b1, b2);
}

/// Step 4's last resort: a prism around the whole box behind the triangle's plane (normal n, in
/// the volume's frame: the triangle's corners at the origin, p1 and p2), its front cap
/// `depthFront` in front of that plane.
DH_FUNC void stsvBoxPrism(vec3 n, vec3 p1, vec3 p2, vec3 boxLo, vec3 boxHi, float depthFront, float margin,
                          DH_OUT(vec3) f0, DH_OUT(vec3) f1, DH_OUT(vec3) f2, DH_OUT(vec3) b0, DH_OUT(vec3) b1,
                          DH_OUT(vec3) b2) {
    vec3 u = normalize(cross(n, abs(n.x) < 0.6f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f)));
    vec3 w = cross(n, u);
    vec2 lo2 = vec2(min(min(dot(u, p1), dot(u, p2)), 0.0f), min(min(dot(w, p1), dot(w, p2)), 0.0f));
    vec2 hi2 = vec2(max(max(dot(u, p1), dot(u, p2)), 0.0f), max(max(dot(w, p1), dot(w, p2)), 0.0f));
    float depthBack = depthFront - 0.01f;
    for (uint k = 0u; k < 8u; ++k) {
        vec3 corner = stsvBoxCorner(boxLo, boxHi, k);
        vec2 uw = vec2(dot(u, corner), dot(w, corner));
        lo2 = min(lo2, uw);
        hi2 = max(hi2, uw);
        depthBack = min(depthBack, dot(n, corner));
    }
    lo2 -= vec2(margin);
    hi2 += vec2(margin);
    depthBack -= margin;
    vec2 span = 2.0f * (hi2 - lo2); // triangle (0,0), (2W,0), (0,2H) holds the rectangle W×H
    vec3 base = lo2.x * u + lo2.y * w;
    vec3 c0 = base;
    vec3 c1 = base + span.x * u;
    vec3 c2 = base + span.y * w;
    f0 = c0 + depthFront * n;
    f1 = c1 + depthFront * n;
    f2 = c2 + depthFront * n;
    b0 = c0 + depthBack * n;
    b1 = c1 + depthBack * n;
    b2 = c2 + depthBack * n;
}

/// Builds the volume of one side of triangle (v0, v1, v2): side 0 faces the light centre, side 1
/// is the opposite face (only meaningful when stsvSideCount is 2; otherwise it is empty). The box
/// [boundsLo, boundsHi] (the scene's bounds; grown to hold the triangle) limits the extrusion.
DH_FUNC StsvVolume stsvBuildVolume(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere, vec3 boundsLo, vec3 boundsHi,
                                   uint side) {
    StsvVolumeCore core = stsvVolumeCore(v0, v1, v2, lightSphere, boundsLo, boundsHi, side);
    if (core.done != 0u) return core.vol;
    StsvVolume vol = core.vol;
    StsvVolumeFrame frame = core.frame;
    vec3 n = core.n;
    vec3 p1 = core.p1;
    vec3 p2 = core.p2;
    vec3 q[3];
    vec4 outer[3];
    bool hasOuter[3];
    for (uint i = 0u; i < 3u; ++i) {
        q[i] = core.q[i];
        outer[i] = core.outer[i];
        hasOuter[i] = core.hasOuter[i];
    }
    vec4 front = core.front;
    float slack = frame.slack;
    float margin = STSV_STRIP_MARGIN;
    // The strip's planes lie this much (box diagonals) outside the stored ones: more than the
    // rounding stsvClosePrism tolerates in its corners (≤ 2e-4), so the strip encloses the volume.
    float stripExpansion = slack + STSV_STRIP_EXPANSION;
    vec3 boxLo = frame.boxLo;
    vec3 boxHi = frame.boxHi;

    // 4. The strip's prism: front cap, three side planes, back cap, each one more slack outwards
    // so that it strictly encloses the stored planes' region inside the box.
    vec3 toLight = -vec3(front);
    vec4 stripFront = front + vec4(0.0f, 0.0f, 0.0f, stripExpansion - slack);
    // Side planes: the outer planes, and for each edge a plane perpendicular to the front cap along
    // it, outside the box (used where the outer plane is missing, or too flat to close a prism).
    vec4 lateral[3];
    vec4 upright[3];
    bool hasLateral = true; // false if an upright plane could not be oriented (degenerate t')
    for (uint i = 0u; i < 3u; ++i) {
        vec3 a = q[i];
        vec3 m = cross(toLight, q[(i + 1u) % 3u] - a);
        float ml = length(m);
        if (!(ml > 0.0f)) {
            hasLateral = false;
            m = toLight;
        } else {
            m = m / ml;
        }
        if (dot(m, q[(i + 2u) % 3u] - a) < 0.0f) m = -m;
        float lowest = min(dot(m, a), dot(m, q[(i + 1u) % 3u]));
        for (uint k = 0u; k < 8u; ++k) lowest = min(lowest, dot(m, stsvBoxCorner(boxLo, boxHi, k)));
        upright[i] = vec4(m, margin - lowest);
        lateral[i] = hasOuter[i] ? outer[i] + vec4(0.0f, 0.0f, 0.0f, stripExpansion) : upright[i];
    }
    // The paper's prism: front cap t' (or the triangle's plane), back cap parallel to it beyond the
    // box. Corners on the side edges, i.e. along cross(n_a, n_b) of adjacent side planes (§2.2).
    float frontLevel = stripFront.w; // front cap: dot(toLight, x) ≤ frontLevel
    float backLevel = frontLevel - 0.01f;
    for (uint k = 0u; k < 8u; ++k) backLevel = min(backLevel, dot(toLight, stsvBoxCorner(boxLo, boxHi, k)));
    vec3 f[3];
    vec3 b[3];
    bool ok = hasLateral && stsvClosePrism(lateral[0], lateral[1], lateral[2], toLight, frontLevel,
                                           backLevel - margin, f[0], f[1], f[2], b[0], b[1], b[2]);
    if (!ok && hasLateral) {
        // Outer planes nearly parallel to the caps (the sphere reaching close to the plane of t')
        // put the corners far outside the box: bound those sides by the upright planes instead.
        bool changed = false;
        vec4 sides[3];
        for (uint i = 0u; i < 3u; ++i) {
            sides[i] = lateral[i];
            if (hasOuter[i] && abs(dot(vec3(outer[i]), toLight)) > 0.8f) {
                sides[i] = upright[i];
                changed = true;
            }
        }
        ok = changed && stsvClosePrism(sides[0], sides[1], sides[2], toLight, frontLevel, backLevel - margin,
                                       f[0], f[1], f[2], b[0], b[1], b[2]);
    }
    if (!ok && hasLateral) {
        // The side planes lean both ways across the caps: the cone strip.
        vol.flags |= STSV_VOLUME_CONE_STRIP;
        ok = stsvConeStripPrism(lateral[0], lateral[1], lateral[2], toLight, boxLo, boxHi, margin, f[0], f[1],
                                f[2], b[0], b[1], b[2]);
    }
    if (!ok) {
        vol.flags = (vol.flags & ~STSV_VOLUME_CONE_STRIP) | STSV_VOLUME_BOX;
        stsvBoxPrism(n, p1, p2, boxLo, boxHi, stripExpansion, margin, f[0], f[1], f[2], b[0], b[1], b[2]);
    }
    // Both ends no farther than the box: the back cap (and, for the cone strip and the box
    // fallback, the front cap too) on the face where the prism leaves the box.
    stsvCutPrismAtBox(f[0], f[1], f[2], b[0], b[1], b[2], boxLo, boxHi, margin);
    stsvCutPrismAtBox(b[0], b[1], b[2], f[0], f[1], f[2], boxLo, boxHi, margin);
    // A cut cap need not face along toLight; every cross section of the prism turns the same way
    // about its side edges, so the front cap's outward normal is taken against them.
    vec3 outward = -((b[0] - f[0]) + (b[1] - f[1]) + (b[2] - f[2]));
    stsvWriteStrip(vol, f[0], f[1], f[2], b[0], b[1], b[2], outward);

    // Back to world space: x_world = v0 + scale·x; a plane (m, d) becomes (m, d·scale − m·v0).
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = stsvPlaneToWorld(frame, vol.planes[i]);
    for (uint i = 0u; i < 10u; ++i) vol.vertices[i] = vec4(v0 + frame.scale * vec3(vol.vertices[i]), 1.0f);
    return vol;
}

/// Side `side`'s volume of triangle (v0, v1, v2) (stsvBuildVolume, or without `strip` only its
/// planes, stsvBuildVolumePlanes): false past the sides the light sees (stsvSideCount) or when the
/// volume is empty. The one rule of both backends' STSV volumes and wedge bounds for which sides
/// have a volume.
DH_FUNC bool stsvSideVolume(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere, vec3 boundsLo, vec3 boundsHi,
                            uint side, bool strip, DH_OUT(StsvVolume) vol) {
    if (side >= stsvSideCount(v0, v1, v2, lightSphere)) {
        vol = stsvEmptyVolume(v0, 0u);
        return false;
    }
    vol = strip ? stsvBuildVolume(v0, v1, v2, lightSphere, boundsLo, boundsHi, side)
                : stsvBuildVolumePlanes(v0, v1, v2, lightSphere, boundsLo, boundsHi, side);
    return (vol.flags & STSV_VOLUME_EMPTY) == 0u;
}

/// STSV §2.3: p is inside iff it is on the inner side of every plane of the volume. The plane
/// loops of these tests run a fixed number of times, so that a shader compiler unrolls them and
/// keeps the planes in registers (lavapipe turns an array indexed by a loop of varying length
/// into memory accesses lane by lane).
DH_FUNC bool stsvPointInVolume(StsvVolume v, vec3 p) {
    bool inside = true;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
        inside = inside && (i >= v.planeCount || !(dot(vec3(v.planes[i]), p) + v.planes[i].w < 0.0f));
    return inside;
}

/// True when the whole box [lo, hi] lies on the outer side of `plane` (n, d): a plane's value is
/// linear in p, so its maximum over the box is at the corner its normal points to. The margin,
/// 1e-6 of |p|₁ + |d| over the box, is five times the float rounding of the per-point test
/// (three products and three sums, each within 2⁻²⁴ of |n·p| + |d|), so a box it rejects holds
/// no point that the per-point test would accept.
DH_FUNC bool stsvPlaneMissesBox(vec4 plane, vec3 lo, vec3 hi) {
    vec3 far = max(abs(lo), abs(hi));
    float extent = far.x + far.y + far.z;
    vec3 n = vec3(plane);
    vec3 corner = vec3(n.x >= 0.0f ? hi.x : lo.x, n.y >= 0.0f ? hi.y : lo.y, n.z >= 0.0f ? hi.z : lo.z);
    return dot(n, corner) + plane.w < -1e-6f * (extent + abs(plane.w));
}

/// True when no point of the box [lo, hi] passes stsvPointInVolume: the whole box lies on the outer
/// side of one of the volume's planes (stsvPlaneMissesBox), so culling with it changes no result.
DH_FUNC bool stsvVolumeMissesBox(StsvVolume v, vec3 lo, vec3 hi) {
    bool misses = false;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
        misses = misses || (i < v.planeCount && stsvPlaneMissesBox(v.planes[i], lo, hi));
    return misses;
}

DH_END

#endif // STSV_VOLUMES_VOLUME_DH_H
