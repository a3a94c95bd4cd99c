// Shared set-up of the Vulkan renderer tests: one validated device (synchronisation validation
// on) for the whole binary, renders on it, and the comparisons against the CPU mirror (fed the
// GPU's own G-buffer) and Embree (boundary classifier after tests/render/mirror_vs_reference_test.cpp).
#pragma once

#include "gpu/device.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu/cpu_renderer.h"
#include "render/renderer.h"
#include "render/vulkan/gpu_renderer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/geometry.h"
#include "tests/support/boundary.h"
#include "volumes/cpu/cpu_stsv.h"
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
        RenderOptions o = options;
        if (extrusion != ExtrusionStage::Auto) o.extrusion = extrusion;
        VulkanRenderer renderer(scene, o, {&device()});
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
    LightSampleBuffer out(o.width, o.height, o.samples, o.buffer);
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

/// The (pixel, sample) pairs where two buffers differ, one line each (up to `maxLines`): the
/// pixel, the sample, both values (counts with `counts`: layers, or optical depths of two
/// transmittance buffers), the visible triangle and point of the G-buffer.
inline std::string describeDifferences(const LightSampleBuffer& gpu, const LightSampleBuffer& mirror,
                                       const GBuffer& g, bool counts, std::size_t maxLines = 12) {
    std::ostringstream out;
    std::size_t lines = 0;
    const bool depths = counts && transmittanceBoth(gpu, mirror);
    auto value = [&](const LightSampleBuffer& b, int x, int y, int k) -> std::int64_t {
        if (depths) return b.opticalDepth(x, y, k);
        return counts ? b.count(x, y, k) : int(b.occluded(x, y, k));
    };
    for (int y = 0; y < gpu.height() && lines < maxLines; ++y)
        for (int x = 0; x < gpu.width() && lines < maxLines; ++x)
            for (int k = 0; k < gpu.samples() && lines < maxLines; ++k) {
                const std::int64_t a = value(gpu, x, y, k);
                const std::int64_t b = value(mirror, x, y, k);
                if (a == b) continue;
                const std::size_t i = g.index(x, y);
                out << "\n  pixel (" << x << "," << y << ") sample " << k << ": gpu " << a << ", mirror " << b
                    << ", triangle " << g.triangle[i] << ", p=(" << g.position[i].x << "," << g.position[i].y
                    << "," << g.position[i].z << ")";
                ++lines;
            }
    return out.str();
}

/// GPU vs mirror, both running volumes/stsv_fragment_dh.h on the same G-buffer: every
/// (pixel, sample) pair with the same occlusion state and (counters) the same count or
/// (transmittance) the same optical depth.
inline void expectMirrorExact(const Scene& scene, const Frame& frame, const RenderOptions& o, std::size_t l,
                              const std::string& what) {
    const LightSampleBuffer mirror = mirrorSamples(scene, frame, l, o);
    const bool counters = o.buffer != BufferKind::Bitmask;
    const LightSampleDiff diff = compareLightSamples(frame.lightSamples[l], mirror, 8, counters);
    std::cout << what << " light " << l << ": " << diff.comparedSamples << " pairs, " << occludedCount(mirror)
              << " occluded (mirror), " << diff.differingSamples << " differ\n";
    EXPECT_EQ(diff.differingSamples, 0u)
        << what << " light " << l << ": differing pairs"
        << describeDifferences(frame.lightSamples[l], mirror, frame.gbuffer, counters);
}

/// GPU vs mirror where exact agreement is out of reach for the reason `why`: ≥ minAgreement of
/// (pixel, sample) pairs with the same occlusion state and (counters) the same counts; the
/// differing pairs are printed with the reason. Returns the agreement.
inline double expectMatchesMirror(const Scene& scene, const Frame& frame, const RenderOptions& o,
                                  std::size_t l, double minAgreement, const std::string& what,
                                  const std::string& why) {
    const LightSampleBuffer mirror = mirrorSamples(scene, frame, l, o);
    const bool counters = o.buffer == BufferKind::Counters;
    const LightSampleDiff diff = compareLightSamples(frame.lightSamples[l], mirror, 8, counters);
    const double agreement = 1.0 - double(diff.differingSamples) / double(diff.comparedSamples);
    const std::string differences =
        describeDifferences(frame.lightSamples[l], mirror, frame.gbuffer, counters);
    std::cout << what << " light " << l << ": " << diff.comparedSamples << " pairs, " << occludedCount(mirror)
              << " occluded (mirror), " << diff.differingSamples << " differ, agreement " << agreement
              << "\n";
    if (diff.differingSamples > 0) std::cout << "  not exact: " << why << differences << "\n";
    EXPECT_GE(agreement, minAgreement) << what << " light " << l << ": differing pairs" << differences;
    return agreement;
}

/// GPU vs Embree on the GPU's G-buffer positions: at most allowedDifferingBits(measuredDiffering)
/// differing bits (the count measured when the call was written), every one within round-off of a
/// boundary (tests/support/boundary.h). With `centreToo` (DCS: every sample's count is D(r) plus
/// edge crossings, so a tie on the segment to the light centre r moves the whole pixel), a bit also
/// counts as explained when p → r is at a boundary, or when a triangle lies in the start gap.
inline void expectMatchesEmbree(const Scene& scene, const Frame& frame, const RenderOptions& o, std::size_t l,
                                std::size_t measuredDiffering, const std::string& what,
                                bool centreToo = false) {
    const EmbreeScene embree(scene);
    const float far = farDistanceFor(scene.bounds());
    const SamplePlan plan = planOf(o);
    LightSampleBuffer reference(o.width, o.height, o.samples, BufferKind::Bitmask);
    traceReferenceSamples(embree, frame.gbuffer, scene.lights[l], plan, far, reference);
    const LightSampleBuffer& gpu = frame.lightSamples[l];
    const GBuffer& g = frame.gbuffer;
    std::size_t total = 0, differing = 0, unexplained = 0, occluded = 0;
    double worst = 0.0;         // the largest distance, in units of round-off, of an explained bit
    std::size_t inStartGap = 0; // DCS bits with a triangle in the segment's start gap
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
                const test::BoundaryDistance sample = test::boundaryDistanceAt(scene, g, x, y, s, lf.center);
                const test::BoundaryDistance centre =
                    centreToo ? test::boundaryDistanceAt(scene, g, x, y, lf.center, lf.center)
                              : test::BoundaryDistance{};
                const double nearest = std::min(sample.nearest(), centre.nearest());
                if (centreToo && sample.startGap <= 2.0) {
                    ++inStartGap;
                } else if (nearest <= (centreToo ? test::DCS_ROUND_OFF_UNITS : test::ROUND_OFF_UNITS)) {
                    worst = std::max(worst, nearest);
                } else if (++unexplained <= 10) {
                    where << "\n  pixel (" << x << "," << y << ") sample " << k
                          << " embree=" << reference.occluded(x, y, k) << ", " << nearest
                          << " units of round-off from a boundary (sample: edge " << sample.edge << " texel "
                          << sample.texel << " gap " << sample.gap << " start gap " << sample.startGap
                          << "; centre: edge " << centre.edge << " texel " << centre.texel << " gap "
                          << centre.gap << " start gap " << centre.startGap << "), p=(" << g.position[i].x
                          << "," << g.position[i].y << "," << g.position[i].z << ")";
                }
            }
        }
    std::cout << what << " vs Embree light " << l << ": " << total << " pairs, " << occluded << " occluded, "
              << differing << " differ, " << unexplained << " away from boundaries; worst explained " << worst
              << " units of round-off";
    if (centreToo) std::cout << "; " << inStartGap << " with a triangle in the start gap";
    std::cout << "\n";
    EXPECT_GT(occluded, total / 100) << what << ": too few occluded samples to test anything";
    EXPECT_LE(differing, allowedDifferingBits(measuredDiffering))
        << what << " light " << l << ": " << measuredDiffering << " measured";
    EXPECT_EQ(unexplained, 0u) << what << ": differing bits away from boundaries:" << where.str();
}

/// Ground y = 0 (x, z ∈ [−3, 3]), a perforated double-sided checker quad at y = 1, an opaque
/// triangle at y = 0.6, camera above and in front.
inline Scene testScene() {
    Scene s;
    s.source = "gpu test scene";
    Material ground;
    ground.name = "ground";
    ground.albedo = vec3(0.7f);
    const std::uint32_t groundMaterial = addMaterial(s, ground);
    Texture tex;
    tex.name = "checker";
    tex.width = 8;
    tex.height = 8;
    tex.rgba.assign(8 * 8 * 4, 255);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            tex.rgba[std::size_t(y * 8 + x) * 4 + 3] = ((x / 2 + y / 2) % 2) ? 255 : 0;
    Material perforated;
    perforated.name = "checker";
    perforated.albedo = vec3(0.3f, 0.6f, 0.2f);
    perforated.alphaTexture = addTexture(s, tex);
    perforated.doubleSided = true;
    const std::uint32_t fenceMaterial = addMaterial(s, perforated);
    Material opaque;
    opaque.name = "opaque";
    opaque.albedo = vec3(0.8f, 0.3f, 0.3f);
    const std::uint32_t opaqueMaterial = addMaterial(s, opaque);
    const vec2 t(0.0f);
    s.addTriangle({-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, t, t, t, groundMaterial);
    s.addTriangle({-3, 0, -3}, {3, 0, 3}, {3, 0, -3}, t, t, t, groundMaterial);
    s.addTriangle({-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {0, 0}, {0, 2}, {2, 2}, fenceMaterial);
    s.addTriangle({-1, 1, -1}, {1, 1, 1}, {1, 1, -1}, {0, 0}, {2, 2}, {2, 0}, fenceMaterial);
    s.addTriangle({0.5f, 0.6f, 0.8f}, {1.5f, 0.6f, 1.6f}, {1.8f, 0.6f, 0.4f}, t, t, t, opaqueMaterial);
    s.camera.eye = vec3(0.0f, 4.5f, 5.0f);
    s.camera.target = vec3(0.0f, 0.0f, 0.3f);
    s.camera.fovY = 50.0f;
    return s;
}

} // namespace stsv::test
