// CPU STSV mirror against the Embree ground truth (issue 2): at equal light samples, the
// occlusion bits must agree except where a sample's segment grazes a triangle edge or an
// alpha-texel boundary, or the pixel sits on a G-buffer silhouette.
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu_stsv.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/load.h"
#include "volumes/stsv_dh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace stsv {
namespace {

struct Crossing {
    std::uint32_t triangle;
    dvec2 bary;
};

/// Every triangle the segment p→s crosses (double-precision Möller–Trumbore), ignoring `self`.
std::vector<Crossing> crossings(const Scene& scene, vec3 pf, vec3 sf, std::uint32_t self) {
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
        // Generous window: near-misses count as "at an edge" candidates.
        if (u < -1e-3 || v < -1e-3 || u + v > 1.0 + 1e-3 || t01 < 0.0 || t01 > 1.0) continue;
        out.push_back({t, dvec2(u, v)});
    }
    return out;
}

/// True when the difference at (pixel, sample) is explained by a boundary within one pixel or
/// one texel: the G-buffer changes triangle next to the pixel, or a crossing lies within one
/// texel of a triangle edge or of a texel whose opacity differs.
bool atBoundary(const Scene& scene, const GBuffer& g, int x, int y, vec3 s) {
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
        if (!m.perforated()) {
            // Opaque: only the triangle's edges matter; one texel ≈ 1e-3 of the triangle here.
            const double edge = std::min({c.bary.x, c.bary.y, 1.0 - c.bary.x - c.bary.y});
            if (std::abs(edge) < 1e-3) return true;
            continue;
        }
        const Texture& tex = scene.textures[std::size_t(m.alphaTexture)];
        const dvec2 size(tex.width, tex.height);
        // Edge distance in texels: barycentric distance × the edge's texel extent.
        const double texPerBary = std::max(length((uv1 - uv0) * size), length((uv2 - uv0) * size));
        const double edge = std::min({c.bary.x, c.bary.y, 1.0 - c.bary.x - c.bary.y});
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

void compareOnScene(const std::string& name, int samples) {
    Scene scene = loadScene(name);
    constexpr int W = 160, H = 120; // small enough for a unit test, large enough for real shadows
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(W, H);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 7u, 1, true);
    const float far = farDistanceFor(scene.bounds());
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        LightSampleBuffer reference(W, H, samples, LightSampleBuffer::Kind::Bitmask);
        LightSampleBuffer mirror(W, H, samples, LightSampleBuffer::Kind::Bitmask);
        traceReferenceSamples(embree, g, scene.lights[l], plan, far, reference);
        stsvCpuSamples(scene, g, scene.lights[l], plan, far, mirror);

        std::size_t total = 0, differing = 0, occludedRef = 0, unexplained = 0;
        std::ostringstream where;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = g.index(x, y);
                if (!g.covered(i)) continue;
                const LightFrame frame = lightFrame(scene.lights[l], g.position[i], far);
                for (int k = 0; k < samples; ++k) {
                    ++total;
                    occludedRef += reference.occluded(x, y, k);
                    if (reference.occluded(x, y, k) == mirror.occluded(x, y, k)) continue;
                    ++differing;
                    const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
                    if (!atBoundary(scene, g, x, y, s)) {
                        if (++unexplained <= 10)
                            where << "\n  pixel (" << x << "," << y << ") sample " << k
                                  << " reference=" << reference.occluded(x, y, k) << " p=(" << g.position[i].x
                                  << "," << g.position[i].y << "," << g.position[i].z << ") s=(" << s.x << ","
                                  << s.y << "," << s.z << ")";
                    }
                }
            }
        const double agreement = 1.0 - double(differing) / double(total);
        ::testing::Test::RecordProperty(name + "_agreement", std::to_string(agreement));
        std::cout << name << " light " << l << ": " << total << " pairs, " << occludedRef << " occluded, "
                  << differing << " differ (" << 100.0 * (1.0 - agreement) << " %), " << unexplained
                  << " away from boundaries\n";
        // The scenes must actually cast shadows, or agreement is meaningless.
        EXPECT_GT(occludedRef, total / 50) << name << ": too few occluded samples to test anything";
        EXPECT_GE(agreement, 0.999) << name << " light " << l;
        EXPECT_EQ(unexplained, 0u) << name << " light " << l
                                   << ": differing bits away from boundaries:" << where.str();
    }
}

TEST(MirrorVsReference, Fence64) {
    compareOnScene("fence", 64);
}
TEST(MirrorVsReference, Foliage64) {
    compareOnScene("foliage", 64);
}

TEST(MirrorVsReference, CountersMatchEmbreeLayerCounts) {
    // Depth complexity: with counters, the mirror's per-sample count of blocking triangles must
    // equal Embree's count of distinct blocking triangles.
    Scene scene = loadScene("foliage");
    constexpr int W = 96, H = 72, N = 16;
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(W, H);
    const SamplePlan plan = makeSamplePlan(PatternKind::Stratified, N, 3u, 1, true);
    const float far = farDistanceFor(scene.bounds());
    LightSampleBuffer reference(W, H, N, LightSampleBuffer::Kind::Counters);
    LightSampleBuffer mirror(W, H, N, LightSampleBuffer::Kind::Counters);
    traceReferenceSamples(embree, g, scene.lights[0], plan, far, reference);
    stsvCpuSamples(scene, g, scene.lights[0], plan, far, mirror);
    std::size_t total = 0, equal = 0, multiLayer = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            for (int k = 0; k < N; ++k) {
                ++total;
                equal += reference.count(x, y, k) == mirror.count(x, y, k);
                multiLayer += reference.count(x, y, k) > 1;
            }
    std::cout << "counters: " << equal << " / " << total << " equal, " << multiLayer << " with >1 layer\n";
    EXPECT_GT(multiLayer, 0u) << "the scene should have overlapping occluders";
    EXPECT_GE(double(equal) / double(total), 0.999);
}

} // namespace
} // namespace stsv
