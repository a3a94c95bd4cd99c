// Test support shared by the suites that compare a method with the Embree reference: where a
// differing (pixel, sample) bit is explained by a boundary within one pixel or one texel.
#pragma once

#include "core/gbuffer.h"
#include "scene/scene.h"
#include "volumes/stsv_dh.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace stsv::test {

/// The differing light-sample bits a comparison with Embree allows, from the count `measured`
/// on the build machine (Embree's AVX2 kernels, llvmpipe at 256 bits): that count, a quarter
/// more and two, for Embree's other instruction sets, whose rounding can move a grazing
/// segment's bit (tests/golden keeps one record per instruction set for the same reason). A
/// test states each measurement beside its call, so a fault that flips a handful of bits fails.
constexpr std::size_t allowedDifferingBits(std::size_t measured) {
    return measured + (measured + 3) / 4 + 2;
}

struct Crossing {
    std::uint32_t triangle;
    dvec2 bary;
};

/// Every triangle the segment p→s crosses (double-precision Möller–Trumbore), ignoring `self`.
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

/// A difference at (pixel, sample) is explained by a boundary when the G-buffer changes triangle
/// next to the pixel, or a crossing lies within one texel of a triangle edge or of a texel of
/// different opacity. With `transmittance`, a translucent triangle's texels are those of its blend
/// texture, and any other alpha byte is a different opacity.
inline bool atBoundary(const Scene& scene, const GBuffer& g, int x, int y, vec3 s,
                       bool transmittance = false) {
    const std::size_t i = g.index(x, y);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) continue;
            if (g.triangle[g.index(nx, ny)] != g.triangle[i]) return true;
        }
    for (const Crossing& c : crossings(scene, g.position[i], s, g.triangle[i])) {
        const Material& m = scene.materialOf(c.triangle);
        const uvec3 idx = scene.triangles[c.triangle];
        const dvec2 uv0(scene.texcoords[idx.x]), uv1(scene.texcoords[idx.y]), uv2(scene.texcoords[idx.z]);
        const dvec2 uv = uv0 + c.bary.x * (uv1 - uv0) + c.bary.y * (uv2 - uv0);
        const double edge = std::min({c.bary.x, c.bary.y, 1.0 - c.bary.x - c.bary.y});
        const bool blend = transmittance && m.translucent();
        const int texture = blend ? m.blendTexture : m.alphaTexture;
        if (texture < 0) {
            if (std::abs(edge) < 1e-3) return true;
            continue;
        }
        const Texture& tex = scene.textures[std::size_t(texture)];
        const dvec2 size(tex.width, tex.height);
        const double texPerBary = std::max(length((uv1 - uv0) * size), length((uv2 - uv0) * size));
        if (std::abs(edge) * texPerBary < 1.0) return true;
        const uint wrap = m.wrap == WrapMode::Clamp ? WRAP_CLAMP : WRAP_REPEAT;
        const ivec2 center = texelAt(vec2(uv), ivec2(tex.width, tex.height), wrap);
        const std::uint8_t a = tex.alpha(center.x, center.y);
        for (int ty = -1; ty <= 1; ++ty)
            for (int tx = -1; tx <= 1; ++tx) {
                const ivec2 n = texelAt(vec2(uv + dvec2(tx, ty) / size), ivec2(tex.width, tex.height), wrap);
                const std::uint8_t b = tex.alpha(n.x, n.y);
                if (blend ? a != b : alphaBlocks(a) != alphaBlocks(b)) return true;
            }
    }
    return false;
}

} // namespace stsv::test
