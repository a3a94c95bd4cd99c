// CPU STSV mirror against the Embree ground truth: at equal light samples, the
// occlusion bits must agree except where a sample's segment passes within float round-off of a
// triangle edge or an alpha-texel boundary (tests/support/boundary.h).
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/load.h"
#include "tests/support/boundary.h"
#include "volumes/cpu/cpu_stsv.h"
#include "volumes/stsv_dh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

namespace stsv {
namespace {

using test::allowedDifferingBits;

/// `measured`: the differing bits of each light when the test was written.
void compareOnScene(const std::string& name, int samples, const std::vector<std::size_t>& measured) {
    Scene scene = loadScene(name);
    constexpr int W = 160, H = 120; // small enough for a unit test, large enough for real shadows
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(W, H);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 7u, 1, true);
    const float far = farDistanceFor(scene.bounds());
    ASSERT_EQ(measured.size(), scene.lights.size()) << name;
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        LightSampleBuffer reference(W, H, samples, BufferKind::Bitmask);
        LightSampleBuffer mirror(W, H, samples, BufferKind::Bitmask);
        traceReferenceSamples(embree, g, scene.lights[l], plan, far, reference);
        stsvCpuSamples(scene, g, scene.lights[l], plan, far, mirror);

        std::size_t total = 0, differing = 0, occludedRef = 0, unexplained = 0;
        double worst = 0.0; // the largest distance, in units of round-off, of an explained bit
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
                    const double units = test::boundaryDistanceAt(scene, g, x, y, s, frame.center).nearest();
                    if (units <= test::ROUND_OFF_UNITS) worst = std::max(worst, units);
                    if (units > test::ROUND_OFF_UNITS) {
                        if (++unexplained <= 10)
                            where << "\n  pixel (" << x << "," << y << ") sample " << k
                                  << " reference=" << reference.occluded(x, y, k) << ", " << units
                                  << " units of round-off from a boundary, p=(" << g.position[i].x << ","
                                  << g.position[i].y << "," << g.position[i].z << ") s=(" << s.x << "," << s.y
                                  << "," << s.z << ")";
                    }
                }
            }
        const double agreement = 1.0 - double(differing) / double(total);
        ::testing::Test::RecordProperty(name + "_agreement", std::to_string(agreement));
        std::cout << name << " light " << l << ": " << total << " pairs, " << occludedRef << " occluded, "
                  << differing << " differ (" << 100.0 * (1.0 - agreement) << " %), " << unexplained
                  << " away from boundaries; worst explained " << worst << " units of round-off\n";
        // The scenes must actually cast shadows, or agreement is meaningless.
        EXPECT_GT(occludedRef, total / 50) << name << ": too few occluded samples to test anything";
        EXPECT_LE(differing, allowedDifferingBits(measured[l]))
            << name << " light " << l << ": " << measured[l] << " measured";
        EXPECT_EQ(unexplained, 0u) << name << " light " << l
                                   << ": differing bits away from boundaries:" << where.str();
    }
}

TEST(MirrorVsReference, Fence64) {
    compareOnScene("fence", 64, {2}); // measured 2 of 901 376
}
TEST(MirrorVsReference, Foliage64) {
    compareOnScene("foliage", 64, {0}); // measured 0 of 953 536
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
    LightSampleBuffer reference(W, H, N, BufferKind::Counters);
    LightSampleBuffer mirror(W, H, N, BufferKind::Counters);
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
    // Layer counts are integers: the mirror and the ray tracer count the same crossings.
    EXPECT_EQ(equal, total);
}

} // namespace
} // namespace stsv
