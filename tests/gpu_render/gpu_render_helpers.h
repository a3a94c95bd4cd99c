// Shared set-up of the Vulkan renderer tests: one validated device (synchronisation validation
// on) for the whole binary, renders on it, and the comparisons against the CPU mirror (fed the
// GPU's own G-buffer) and Embree (boundary classifier after tests/render/mirror_vs_reference_test.cpp).
#pragma once

#include "gpu/device.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu_stsv.h"
#include "render/gpu_renderer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "volumes/stsv_dh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>

namespace stsv::test {

inline Device& sharedRenderDevice() {
    static Device device([] {
        DeviceOptions o;
        o.validation = true;
        o.synchronizationValidation = true;
        return o;
    }());
    return device;
}

/// Fails the test on any validation message.
class GpuRenderTest : public ::testing::Test {
  protected:
    Device& device() { return sharedRenderDevice(); }
    void SetUp() override {
        ASSERT_TRUE(device().validationEnabled());
        device().clearValidationMessages();
    }
    void TearDown() override {
        device().waitIdle();
        std::string text;
        for (const ValidationMessage& m : device().validationMessages()) text += "\n  " + m.text;
        EXPECT_EQ(device().validationMessageCount(), 0u) << "validation messages:" << text;
        device().clearValidationMessages();
    }
    Frame renderGpu(const Scene& scene, const RenderOptions& options,
                    ExtrusionStage extrusion = ExtrusionStage::Auto) {
        VulkanRenderer renderer(scene, options, {&device(), extrusion});
        return renderer.render();
    }
};

inline RenderOptions gpuOptions(int width, int height, int samples, BufferKind kind = BufferKind::Bitmask) {
    RenderOptions o;
    o.backend = Backend::Vulkan;
    o.width = width;
    o.height = height;
    o.samples = samples;
    o.buffer = kind;
    o.seed = 7;
    return o;
}

inline SamplePlan planOf(const RenderOptions& o) {
    return makeSamplePlan(o.pattern, o.samples, o.seed, o.interleave, o.decorrelate);
}

/// The CPU mirror's buffer for light l on the GPU's G-buffer.
inline LightSampleBuffer mirrorSamples(const Scene& scene, const Frame& frame, std::size_t l,
                                       const RenderOptions& o) {
    LightSampleBuffer out(o.width, o.height, o.samples,
                          o.buffer == BufferKind::Bitmask ? LightSampleBuffer::Kind::Bitmask
                                                          : LightSampleBuffer::Kind::Counters);
    stsvCpuSamples(scene, frame.gbuffer, scene.lights[l], planOf(o), farDistanceFor(scene.bounds()), out);
    return out;
}

inline std::size_t occludedCount(const LightSampleBuffer& b) {
    std::size_t n = 0;
    for (int y = 0; y < b.height(); ++y)
        for (int x = 0; x < b.width(); ++x)
            for (int k = 0; k < b.samples(); ++k) n += b.occluded(x, y, k) ? 1 : 0;
    return n;
}

/// GPU vs mirror: ≥ minAgreement of (pixel, sample) pairs with the same occlusion state, and
/// (counters) the same counts. Returns the agreement.
inline double expectMatchesMirror(const Scene& scene, const Frame& frame, const RenderOptions& o,
                                  std::size_t l, double minAgreement, const std::string& what) {
    const LightSampleBuffer mirror = mirrorSamples(scene, frame, l, o);
    const bool counters = o.buffer == BufferKind::Counters;
    const LightSampleDiff diff = compareLightSamples(frame.lightSamples[l], mirror, 8, counters);
    const double agreement = 1.0 - double(diff.differingSamples) / double(diff.comparedSamples);
    std::ostringstream where;
    for (ivec2 p : diff.firstPixels) where << " (" << p.x << "," << p.y << ")";
    std::cout << what << " light " << l << ": " << diff.comparedSamples << " pairs, " << occludedCount(mirror)
              << " occluded (mirror), " << diff.differingSamples << " differ, agreement " << agreement
              << "\n";
    EXPECT_GE(agreement, minAgreement) << what << " light " << l << ": first differing pixels" << where.str();
    return agreement;
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
/// different opacity (as tests/render/mirror_vs_reference_test.cpp).
inline bool atBoundary(const Scene& scene, const GBuffer& g, int x, int y, vec3 s) {
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
        if (!m.perforated()) {
            if (std::abs(edge) < 1e-3) return true;
            continue;
        }
        const Texture& tex = scene.textures[std::size_t(m.alphaTexture)];
        const dvec2 size(tex.width, tex.height);
        const double texPerBary = std::max(length((uv1 - uv0) * size), length((uv2 - uv0) * size));
        if (std::abs(edge) * texPerBary < 1.0) return true;
        const uint wrap = m.wrap == WrapMode::Clamp ? WRAP_CLAMP : WRAP_REPEAT;
        const ivec2 center = texelAt(vec2(uv), ivec2(tex.width, tex.height), wrap);
        const bool blocks = alphaBlocks(tex.alpha(center.x, center.y));
        for (int ty = -1; ty <= 1; ++ty)
            for (int tx = -1; tx <= 1; ++tx) {
                const ivec2 n = texelAt(vec2(uv + dvec2(tx, ty) / size), ivec2(tex.width, tex.height), wrap);
                if (alphaBlocks(tex.alpha(n.x, n.y)) != blocks) return true;
            }
    }
    return false;
}

/// GPU vs Embree on the GPU's G-buffer positions: ≥ minAgreement identical bits, and every
/// differing bit at a boundary.
inline void expectMatchesEmbree(const Scene& scene, const Frame& frame, const RenderOptions& o, std::size_t l,
                                double minAgreement, const std::string& what) {
    const EmbreeScene embree(scene);
    const float far = farDistanceFor(scene.bounds());
    const SamplePlan plan = planOf(o);
    LightSampleBuffer reference(o.width, o.height, o.samples, LightSampleBuffer::Kind::Bitmask);
    traceReferenceSamples(embree, frame.gbuffer, scene.lights[l], plan, far, reference);
    const LightSampleBuffer& gpu = frame.lightSamples[l];
    const GBuffer& g = frame.gbuffer;
    std::size_t total = 0, differing = 0, unexplained = 0, occluded = 0;
    std::ostringstream where;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (!g.covered(i)) continue;
            const LightFrame lf = lightFrame(scene.lights[l], g.position[i], far);
            for (int k = 0; k < o.samples; ++k) {
                ++total;
                occluded += reference.occluded(x, y, k) ? 1 : 0;
                if (reference.occluded(x, y, k) == gpu.occluded(x, y, k)) continue;
                ++differing;
                const vec3 s = lightSamplePosition(lf, pixelSamplePoint(plan, x, y, k, lf.domain));
                if (!atBoundary(scene, g, x, y, s) && ++unexplained <= 10)
                    where << "\n  pixel (" << x << "," << y << ") sample " << k
                          << " embree=" << reference.occluded(x, y, k) << " p=(" << g.position[i].x << ","
                          << g.position[i].y << "," << g.position[i].z << ")";
            }
        }
    const double agreement = total ? 1.0 - double(differing) / double(total) : 1.0;
    std::cout << what << " vs Embree light " << l << ": " << total << " pairs, " << occluded << " occluded, "
              << differing << " differ, " << unexplained << " away from boundaries\n";
    EXPECT_GT(occluded, total / 100) << what << ": too few occluded samples to test anything";
    EXPECT_GE(agreement, minAgreement) << what;
    EXPECT_EQ(unexplained, 0u) << what << ": differing bits away from boundaries:" << where.str();
}

} // namespace stsv::test
