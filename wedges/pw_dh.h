// Penumbra wedges (Assarsson & Akenine-Möller 2003; STSV paper §3.1; DESIGN §4.5): the signed
// fraction of the light behind one silhouette edge projected from the receiver p, analytic for
// the square (rectangle light) and the unit disk (disk, sphere and directional lights) in frame
// coordinates. Same projection as wedges/dcs_dh.h. Compiles as C++ and as GLSL 4.50.
//
// Integrating the DCS identity over the light gives the mean depth complexity
//   mean D = D(r) + Σ_e k_e · sign(ℓ_e·X beyond) · |L ∩ V_e| / |L|,
// V_e = the points x whose segment from r crosses the projected edge (the angular sector from r
// spanned by the edge, beyond the edge). Penumbra wedges keep only the boolean hard shadow at
// r and one unit per silhouette edge: occlusion = clamp([D(r) > 0] + Σ_e sign(k_e)·f_e, 0, 1).
// Exact for one silhouette loop of a closed object or one open surface; where loops overlap the
// fractions add up twice (the method's known over-darkening).
#ifndef STSV_WEDGES_PW_DH_H
#define STSV_WEDGES_PW_DH_H

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"

DH_BEGIN

/// A convex polygon in frame coordinates (up to 8 vertices: a square clipped by 3 half-planes).
struct PwPolygon {
    vec2 v[8];
    int n;
};

/// Keeps the part of `poly` where dot(line, (x, y, 1)) ≥ 0 (Sutherland–Hodgman, one plane).
DH_FUNC PwPolygon pwClipPolygon(PwPolygon poly, vec3 line) {
    PwPolygon outPoly;
    outPoly.n = 0;
    for (int i = 0; i < 8; ++i) outPoly.v[i] = vec2(0.0f);
    for (int i = 0; i < poly.n; ++i) {
        vec2 a = poly.v[i];
        vec2 b = poly.v[(i + 1) % poly.n];
        float da = line.x * a.x + line.y * a.y + line.z;
        float db = line.x * b.x + line.y * b.y + line.z;
        if (da >= 0.0f && outPoly.n < 8) {
            outPoly.v[outPoly.n] = a;
            outPoly.n += 1;
        }
        if ((da >= 0.0f) != (db >= 0.0f) && outPoly.n < 8) {
            outPoly.v[outPoly.n] = a + (b - a) * (da / (da - db));
            outPoly.n += 1;
        }
    }
    return outPoly;
}

/// Area of a convex polygon (shoelace, absolute value).
DH_FUNC float pwPolygonArea(PwPolygon poly) {
    float sum = 0.0f;
    for (int i = 0; i < poly.n; ++i) {
        vec2 a = poly.v[i];
        vec2 b = poly.v[(i + 1) % poly.n];
        sum += a.x * b.y - a.y * b.x;
    }
    return 0.5f * abs(sum);
}

/// Signed area of the unit sector between directions u and v (angle from u to v, radius 1).
DH_FUNC float pwSector(vec2 u, vec2 v) {
    return 0.5f * atan(u.x * v.y - u.y * v.x, u.x * v.x + u.y * v.y);
}

/// Signed area of (unit disk ∩ triangle (0, a, b)): the circle–polygon area formula's term.
DH_FUNC float pwDiskTriangleArea(vec2 a, vec2 b) {
    vec2 d = b - a;
    float qa = dot(d, d);
    if (!(qa > 0.0f)) return 0.0f;
    float qb = dot(a, d);
    float qc = dot(a, a) - 1.0f;
    float disc = qb * qb - qa * qc;
    if (disc <= 0.0f) return pwSector(a, b); // the line misses the disk
    float s = sqrt(disc);
    float t0 = (-qb - s) / qa;
    float t1 = (-qb + s) / qa;
    if (t1 <= 0.0f || t0 >= 1.0f) return pwSector(a, b); // the segment misses the disk
    vec2 p0 = a + d * max(t0, 0.0f);
    vec2 p1 = a + d * min(t1, 1.0f);
    float inner = 0.5f * (p0.x * p1.y - p0.y * p1.x);
    return (t0 > 0.0f ? pwSector(a, p0) : 0.0f) + inner + (t1 < 1.0f ? pwSector(p1, b) : 0.0f);
}

/// Area of (unit disk ∩ convex polygon), as the sum of the per-edge signed terms.
DH_FUNC float pwDiskPolygonArea(PwPolygon poly) {
    float sum = 0.0f;
    for (int i = 0; i < poly.n; ++i) sum += pwDiskTriangleArea(poly.v[i], poly.v[(i + 1) % poly.n]);
    return abs(sum);
}

/// The wedge term of one clipped projected edge a → b (homogeneous, w > 0) with unclipped line
/// l (as dcsSampleCrossing): sign(l·X) of the points beyond the edge times the fraction of the
/// light domain (DOMAIN_SQUARE: [−1,1]², DOMAIN_DISK: the unit disk) whose segment from the
/// centre crosses the edge. Multiply by sign(k_e) and sum over edges.
DH_FUNC float pwEdgeCoverage(vec3 l, vec3 a, vec3 b, uint domain) {
    if (l.z == 0.0f) return 0.0f; // the centre is on the edge's line: an empty sector
    // Sector from r = (0,0,1) between a and b: the side of line (r, a) holding b, and vice versa.
    vec3 ra = vec3(-a.y, a.x, 0.0f);
    vec3 rb = vec3(-b.y, b.x, 0.0f);
    float sa = dot(ra, b);
    float sb = dot(rb, a);
    if (sa == 0.0f || sb == 0.0f) return 0.0f;
    PwPolygon poly;
    poly.n = 4;
    for (int i = 4; i < 8; ++i) poly.v[i] = vec2(0.0f);
    poly.v[0] = vec2(-1.0f, -1.0f);
    poly.v[1] = vec2(1.0f, -1.0f);
    poly.v[2] = vec2(1.0f, 1.0f);
    poly.v[3] = vec2(-1.0f, 1.0f);
    poly = pwClipPolygon(poly, sa > 0.0f ? ra : -ra);
    poly = pwClipPolygon(poly, sb > 0.0f ? rb : -rb);
    float sideR = l.z > 0.0f ? 1.0f : -1.0f;
    poly = pwClipPolygon(poly, -sideR * l); // beyond the edge, away from r
    if (poly.n < 3) return 0.0f;
    float fraction = domain == DOMAIN_SQUARE ? pwPolygonArea(poly) * 0.25f
                                             : pwDiskPolygonArea(poly) * (1.0f / SAMPLING_PI);
    return -sideR * fraction;
}

/// PW's occlusion at a pixel starts from the hard shadow at the light centre: 1 when the
/// segment to it crosses D(r) > 0 layers (Algorithm 2, line 5).
DH_FUNC float pwCenterOcclusion(int centerLayers) {
    return centerLayers > 0 ? 1.0f : 0.0f;
}

/// One silhouette edge's term of PW's occlusion: its wedge coverage (pwEdgeCoverage) with the
/// sign of the edge's weight k_e.
DH_FUNC float pwWedgeTerm(int k, float coverage) {
    return float(k > 0 ? 1 : -1) * coverage;
}

/// v_coef from PW's summed occlusion (the centre's, then every wedge term), clamped to [0, 1].
DH_FUNC float pwVisibility(float occlusion) {
    return 1.0f - clamp(occlusion, 0.0f, 1.0f);
}

/// pw+stsv (STSV paper §3.1): the fraction of the light samples the perforated triangles occlude
/// (their STSV bits) is added to PW's occlusion.
DH_FUNC float pwVisibilityWithStsv(float pwV, float stsvOccluded) {
    return clamp(pwV - stsvOccluded, 0.0f, 1.0f);
}

DH_END

#endif // STSV_WEDGES_PW_DH_H
