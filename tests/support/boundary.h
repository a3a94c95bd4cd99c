// Test support shared by the suites that compare a method with the Embree reference: whether a
// differing (pixel, sample) bit is explained by float round-off at a boundary, by a narrow rule.
//
// Every method and the reference decide a sample in float: which side of an occluder's edge the
// segment p → s passes (a shadow-volume plane, a wedge, Embree's edge test), which texel a crossing
// falls in (uv interpolated from barycentrics), whether a crossing lies in the gaps at the
// segment's ends. Each of these computations works on coordinates of magnitude M (the largest
// |coordinate| of the points involved) and loses a few units of float round-off u = 2^−24 relative
// to M per operation, times the conditioning κ of the triangle whose planes it builds from cross
// products (1 for a right isosceles triangle, large for a sliver); so two correct implementations
// can disagree only where the exact answer is within a small multiple of u·M·(κ + 1) of the
// boundary. The rule below computes that exact distance in double precision and explains a bit
// when it is at most ROUND_OFF_UNITS such units (texel distances are first converted to world units
// by the texture's scale on the triangle). A real fault moves samples whose distance to every
// boundary is many orders of magnitude larger.
#pragma once

#include "core/gbuffer.h"
#include "scene/occlusion_rules_dh.h"
#include "scene/scene.h"
#include "volumes/stsv_dh.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace stsv::test {

/// The differing light-sample bits a comparison with Embree allows, from the count `measured`
/// on the build machine (Embree's AVX2 kernels, llvmpipe at 256 bits): that count, a quarter
/// more and two, for Embree's other instruction sets, whose rounding can move a grazing
/// segment's bit (tests/golden pins Embree's kernels for the same reason). A
/// test states each measurement beside its call, so a fault that flips a handful of bits fails.
constexpr std::size_t allowedDifferingBits(std::size_t measured) {
    return measured + (measured + 3) / 4 + 2;
}

/// Float's unit round-off, 2^−24.
constexpr double UNIT_ROUND_OFF = 0x1p-24;

/// How many units of round-off two float implementations of one decision may differ by.
/// Measured: the worst differing bit of STSV (CPU mirror and Vulkan, fence and foliage) lies 0.25
/// units from its boundary, as expected of a few rounded operations; 16 leaves a factor of 64
/// for other instruction sets' Embree kernels and compilers' contractions, and is 12 µm at
/// fence's coordinates (M ≈ 6 m, κ ≈ 1), a ten-thousandth of the light sample spacing, where a
/// fault moves samples by millimetres to metres.
constexpr double ROUND_OFF_UNITS = 16.0;

/// The same for depth complexity sampling (Forest et al.): a DCS sample's count is the centre's
/// plus the wedges its segment passes, each decided by the side of a line through points projected
/// from p onto the light's sample domain (wedges/dcs_dh.h), homogeneous coordinates that grow as the
/// edge nears p's horizon; its decisions sit farther from the exact boundary. Measured: the worst
/// differing DCS bit lies 666 units from its edge on the CPU (dcs+stsv, the sphere of
/// tests/wedges/dcs_vs_reference_test.cpp) and 79 on Vulkan (the sphere of gpu_wedges_test.cpp);
/// 2 048 leaves a factor three, a quarter of a millimetre at M = 1 for a well-shaped triangle.
constexpr double DCS_ROUND_OFF_UNITS = 2048.0;

struct Crossing {
    std::uint32_t triangle;
    dvec2 bary;
};

/// Every triangle the segment p→s crosses (double-precision Möller–Trumbore, barycentrics within
/// 1e-3 outside the triangle accepted), ignoring `self`.
inline std::vector<Crossing> crossings(const Scene& scene, vec3 pf, vec3 sf, std::uint32_t self) {
    std::vector<Crossing> out;
    const dvec3 p(pf), d = dvec3(sf) - dvec3(pf);
    for (std::uint32_t t = 0; t < scene.triangleCount(); ++t) {
        if (t == self) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 v0(scene.positions[idx.x]), e1 = dvec3(scene.positions[idx.y]) - v0,
                                                e2 = dvec3(scene.positions[idx.z]) - v0;
        const dvec3 q = cross(d, e2);
        const double det = dot(e1, q);
        if (std::abs(det) < 1e-300) continue;
        const dvec3 r = p - v0;
        const double u = dot(r, q) / det;
        const dvec3 w = cross(r, e1);
        const double v = dot(d, w) / det;
        const double t01 = dot(e2, w) / det;
        if (u < -1e-3 || v < -1e-3 || u + v > 1.0 + 1e-3 || t01 < 0.0 || t01 > 1.0) continue;
        out.push_back({t, dvec2(u, v)});
    }
    return out;
}

/// Distance between the segments [a0, a1] and [b0, b1] (closest points clamped to both; Ericson,
/// Real-Time Collision Detection, 5.1.9), in double precision.
inline double segmentDistance(dvec3 a0, dvec3 a1, dvec3 b0, dvec3 b1) {
    const dvec3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
    const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    double sParam = 0.0, tParam = 0.0;
    if (a <= 1e-30 && e <= 1e-30) return length(r);
    if (a <= 1e-30) {
        tParam = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = dot(d1, r);
        if (e <= 1e-30) {
            sParam = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = dot(d1, d2), denom = a * e - b * b;
            sParam = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            tParam = (b * sParam + f) / e;
            if (tParam < 0.0) {
                tParam = 0.0;
                sParam = std::clamp(-c / a, 0.0, 1.0);
            } else if (tParam > 1.0) {
                tParam = 1.0;
                sParam = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return length((a0 + d1 * sParam) - (b0 + d2 * tParam));
}

/// The conditioning of the triangle (a, b, c) for planes built from its edges' cross products:
/// κ = |x|·|y| / |x × y| at its worst corner (1 / the sine of that angle; 1 for a right angle,
/// large for a sliver; wedges/dcs_dh.h dcsSideRounding).
inline double conditioning(dvec3 a, dvec3 b, dvec3 c) {
    const dvec3 ab = b - a, bc = c - b, ca = a - c;
    const double area2 = length(cross(ab, ca));
    const double la = length(ab), lb = length(bc), lc = length(ca);
    return area2 > 0.0 ? std::max({la * lc, la * lb, lb * lc}) / area2 : 1e30;
}

inline double maxAbs(dvec3 v) {
    return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

/// How far a differing sample is from each kind of boundary, in units of round-off (u·M, M the
/// magnitude of the coordinates involved); infinity where there is none of that kind.
struct BoundaryDistance {
    double edge = std::numeric_limits<double>::infinity();  ///< segment to an occluder's edge
    double texel = std::numeric_limits<double>::infinity(); ///< crossing to a texel of other opacity
    double gap = std::numeric_limits<double>::infinity();   ///< crossing to the segment's end gaps
    /// The distance from p to the nearest other triangle, in units of the start gap tMin·|s − p|
    /// (not of round-off). Depth complexity sampling counts the crossings of a sample's segment
    /// as the centre's count plus the wedges it passes (Forest et al., Eq. 2), and a wedge of an
    /// edge inside the start gap counts a crossing the segment, which starts at tMin, never makes:
    /// within twice the gap (for the start point's own round-off) a DCS bit is explained.
    double startGap = std::numeric_limits<double>::infinity();
    double nearest() const { return std::min({edge, texel, gap}); }
    bool explained(double units = ROUND_OFF_UNITS) const { return nearest() <= units; }
};

/// The distance from x to the triangle (a, b, c): to its plane where the foot of the
/// perpendicular falls inside, else to its nearest edge.
inline double pointTriangleDistance(dvec3 x, dvec3 a, dvec3 b, dvec3 c) {
    double d =
        std::min({segmentDistance(x, x, a, b), segmentDistance(x, x, b, c), segmentDistance(x, x, c, a)});
    const dvec3 n = cross(b - a, c - a);
    const double n2 = dot(n, n);
    if (n2 > 0.0) {
        const dvec3 foot = x - n * (dot(x - a, n) / n2);
        if (dot(cross(b - a, foot - a), n) >= 0.0 && dot(cross(c - b, foot - b), n) >= 0.0 &&
            dot(cross(a - c, foot - c), n) >= 0.0)
            d = std::min(d, length(x - foot));
    }
    return d;
}

/// The distances of the segment p → s (the receiver's triangle `self` left out, segments from
/// tMin = shadowTMin(p, centre, D) to tMax = shadowTMax(tMin) as every method traces them) to the
/// boundaries round-off can move it across: an edge of another triangle; for each crossing of a
/// textured triangle, the nearest side of its texel beyond which the opacity changes (with
/// `transmittance`, a translucent triangle's blend texture, where any other alpha byte is another
/// opacity), converted to world units by the texture's scale on the triangle, plus the texel
/// coordinate's own round-off; a crossing at the start or end of the segment.
inline BoundaryDistance boundaryDistance(const Scene& scene, vec3 pf, vec3 sf, vec3 centre,
                                         std::uint32_t self, bool transmittance = false) {
    BoundaryDistance out;
    const double diameter = double(length(scene.bounds().extent()));
    const double tMin = double(shadowTMin(pf, centre, float(diameter))),
                 tMax = double(shadowTMax(float(tMin)));
    const dvec3 p(pf), s(sf), d = s - p;
    const double segment = length(d);
    const dvec3 a0 = p + tMin * d, a1 = p + tMax * d;
    const double ends = std::max(maxAbs(p), maxAbs(s));
    for (std::uint32_t t = 0; t < scene.triangleCount(); ++t) {
        if (t == self) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 v[3] = {dvec3(scene.positions[idx.x]), dvec3(scene.positions[idx.y]),
                            dvec3(scene.positions[idx.z])};
        const double magnitude = std::max({ends, maxAbs(v[0]), maxAbs(v[1]), maxAbs(v[2])});
        // A triangle's planes are cross products of its edges: their round-off grows with its
        // conditioning.
        const double unit = UNIT_ROUND_OFF * magnitude * (conditioning(v[0], v[1], v[2]) + 1.0);
        for (int e = 0; e < 3; ++e) {
            // The side of an edge is a plane through it and p (wedges, shadow-volume sides) or s
            // (STSV's projection): the worse of those two triangles' conditioning and its own.
            const dvec3 w0 = v[e], w1 = v[(e + 1) % 3];
            const double edgeUnit =
                std::max({unit, UNIT_ROUND_OFF * magnitude * (conditioning(p, w0, w1) + 1.0),
                          UNIT_ROUND_OFF * magnitude * (conditioning(s, w0, w1) + 1.0)});
            out.edge = std::min(out.edge, segmentDistance(a0, a1, w0, w1) / edgeUnit);
        }
        out.startGap = std::min(out.startGap, pointTriangleDistance(p, v[0], v[1], v[2]) / (tMin * segment));

        // The crossing of the line p + t·d with the triangle's plane (Möller–Trumbore).
        const dvec3 e1 = v[1] - v[0], e2 = v[2] - v[0], q = cross(d, e2);
        const double det = dot(e1, q);
        if (std::abs(det) < 1e-300) continue;
        const dvec3 r = p - v[0];
        const double u = dot(r, q) / det;
        const dvec3 w = cross(r, e1);
        const double bv = dot(d, w) / det, tc = dot(e2, w) / det;
        if (u < 0.0 || bv < 0.0 || u + bv > 1.0) continue; // outside: the edge distance covers it
        for (double end : {tMin, tMax}) out.gap = std::min(out.gap, std::abs(tc - end) * segment / unit);
        if (tc < tMin || tc > tMax) continue;

        const Material& m = scene.materialOf(t);
        const bool blend = transmittance && m.translucent();
        const int texture = blend ? m.blendTexture : m.alphaTexture;
        if (texture < 0) continue;
        const Texture& tex = scene.textures[std::size_t(texture)];
        const dvec2 size(tex.width, tex.height);
        const dvec2 t0 = dvec2(scene.texcoords[idx.x]) * size, t1 = dvec2(scene.texcoords[idx.y]) * size,
                    t2 = dvec2(scene.texcoords[idx.z]) * size;
        const dvec2 texel = t0 + u * (t1 - t0) + bv * (t2 - t0);
        // Texels per world unit on the triangle: the Frobenius norm of the linear map from the
        // plane's positions to texel coordinates, J = [Δt1 Δt2]·(GᵀG)⁻¹·Gᵀ with G = [e1 e2].
        const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2), gd = g11 * g22 - g12 * g12;
        if (gd <= 0.0) continue;
        const dvec2 dt1 = t1 - t0, dt2 = t2 - t0;
        // (GᵀG)⁻¹ = [g22 −g12; −g12 g11] / gd; J·Jᵀ = T·(GᵀG)⁻¹·Tᵀ, whose trace is ‖J‖².
        const double trace = (dot(dt1, dt1) * g22 - 2.0 * dot(dt1, dt2) * g12 + dot(dt2, dt2) * g11) / gd;
        const double texelsPerUnit = std::sqrt(std::max(trace, 0.0));
        // One unit of round-off, in texels: the position's, carried through the map, and the
        // texel coordinate's own (|texel| of magnitude).
        const double texelUnit =
            unit * texelsPerUnit + UNIT_ROUND_OFF * std::max(std::abs(texel.x), std::abs(texel.y));
        const uint wrap = m.wrap == WrapMode::Clamp ? WRAP_CLAMP : WRAP_REPEAT;
        const ivec2 dims(tex.width, tex.height);
        const dvec2 cell = glm::floor(texel);
        const ivec2 at = texelAt(vec2((cell + 0.5) / size), dims, wrap);
        const std::uint8_t a = tex.alpha(at.x, at.y);
        const auto differs = [&](int dx, int dy) {
            const ivec2 n = texelAt(vec2((cell + dvec2(dx, dy) + 0.5) / size), dims, wrap);
            const std::uint8_t b = tex.alpha(n.x, n.y);
            return blend ? a != b : alphaBlocks(a) != alphaBlocks(b);
        };
        const dvec2 f = texel - cell; // in [0, 1): distances to the four sides
        const double sides[4] = {f.x, 1.0 - f.x, f.y, 1.0 - f.y};
        const int step[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
        for (int k = 0; k < 4; ++k)
            if (differs(step[k][0], step[k][1])) out.texel = std::min(out.texel, sides[k] / texelUnit);
        // A crossing near a texel corner: the diagonal neighbour.
        for (int k = 0; k < 2; ++k)
            for (int j = 2; j < 4; ++j)
                if (differs(step[k][0], step[j][1]))
                    out.texel = std::min(out.texel, std::max(sides[k], sides[j]) / texelUnit);
    }
    return out;
}

/// The boundary distances of pixel (x, y)'s segment to sample s (light frame centred at `centre`).
inline BoundaryDistance boundaryDistanceAt(const Scene& scene, const GBuffer& g, int x, int y, vec3 s,
                                           vec3 centre, bool transmittance = false) {
    const std::size_t i = g.index(x, y);
    return boundaryDistance(scene, g.position[i], s, centre, g.triangle[i], transmittance);
}

/// True iff the differing bit of pixel (x, y), sample s is within ROUND_OFF_UNITS of round-off of
/// a boundary (boundaryDistance).
inline bool atBoundary(const Scene& scene, const GBuffer& g, int x, int y, vec3 s, vec3 centre,
                       bool transmittance = false) {
    return boundaryDistanceAt(scene, g, x, y, s, centre, transmittance).explained();
}

} // namespace stsv::test
