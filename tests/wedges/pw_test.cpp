// Penumbra wedges (CPU mirror) against the Embree reference visibility: exact (up to the
// reference's Monte-Carlo noise) for one convex occluder, for every light shape; the
// over-darkening where two occluders' silhouettes overlap is measured and printed.
#include "core/progress.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "sampling/light_bounds.h"
#include "scene/geometry.h"
#include "wedge_test_util.h"
#include "wedges/cpu/cpu_wedges.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdio>

namespace stsv {
namespace {

struct PwError {
    double meanAbs = 0.0;    ///< over pixels where either image is below 0.995
    double meanSigned = 0.0; ///< v_reference − v_pw (positive = PW too dark)
    double maxAbs = 0.0;
    std::size_t pixels = 0;
    std::size_t darker = 0;  ///< pixels with v_pw < v_reference − 0.05
    std::size_t lighter = 0; ///< pixels with v_pw > v_reference + 0.05
};

PwError comparePw(const Scene& scene, int size, int samples) {
    Progress::setEnabled(false);
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Stratified, samples, 5);
    const float farDistance = farDistanceFor(scene.bounds());
    const WedgeOccluders occ(scene);
    ImageF pw;
    pwCpuVisibility(occ, g, scene.lights[0], farDistance, pw);
    LightSampleBuffer ref(size, size, samples, BufferKind::Bitmask);
    traceReferenceSamples(embree, g, scene.lights[0], plan, farDistance, ref);
    // Receivers on the ground only: on the occluder itself the receiver's own face is left out
    // (self-shadowing rule), which leaves a hole whose edges PW cannot normalise.
    std::uint32_t groundFirst = 0, groundCount = 0;
    for (const Mesh& m : scene.meshes)
        if (m.name == "ground") groundFirst = m.firstTriangle, groundCount = m.triangleCount;
    PwError e;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::uint32_t tri = g.triangle[g.index(x, y)];
            if (tri == NO_TRIANGLE || tri < groundFirst || tri >= groundFirst + groundCount) continue;
            const double vr = ref.visibleFraction(x, y), vp = pw.at(x, y, 0);
            if (vr > 0.995 && vp > 0.995) continue;
            ++e.pixels;
            e.meanAbs += std::abs(vr - vp);
            e.meanSigned += vr - vp;
            e.maxAbs = std::max(e.maxAbs, std::abs(vr - vp));
            e.darker += vp < vr - 0.05 ? 1 : 0;
            e.lighter += vp > vr + 0.05 ? 1 : 0;
        }
    if (e.pixels) {
        e.meanAbs /= double(e.pixels);
        e.meanSigned /= double(e.pixels);
    }
    return e;
}

TEST(PenumbraWedges, SingleConvexOccluderAllLightShapes) {
    const char* names[] = {"rectangle", "disk", "sphere", "directional"};
    for (int shape = 0; shape < 4; ++shape) {
        Scene scene = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
        const Light rect = scene.lights[0];
        if (shape == 1) scene.lights[0] = makeDiskLight(rect.position, rect.normal, 0.35f, rect.radiance);
        if (shape == 2) scene.lights[0] = makeSphereLight(rect.position, 0.3f, rect.radiance);
        if (shape == 3) scene.lights[0] = makeDirectionalLight(-rect.normal, 0.08f, vec3(1.0f));
        const PwError e = comparePw(scene, 96, 256);
        std::printf(
            "pw vs reference (256 stratified samples), convex sphere, %-11s light: mean |dv| %.4f, max %.3f "
            "over %zu shadowed pixels\n",
            names[shape], e.meanAbs, e.maxAbs, e.pixels);
        // PW is exact for one convex occluder; what remains is the reference's Monte-Carlo noise
        // (256 stratified samples: per-pixel standard deviation ≲ 0.01 in the penumbra) plus a
        // pixel-edge effect where the G-buffer sees the sphere's silhouette.
        EXPECT_LT(e.meanAbs, 0.01) << names[shape];
        EXPECT_GT(e.pixels, 200u) << "no shadow in view";
    }
}

TEST(PenumbraWedges, OverlappingOccludersOverDarkenMeasured) {
    // Two spheres, one above the other on the light's axis: their silhouettes overlap as seen
    // from the receivers, so PW counts the overlap twice (the STSV paper's §3.1 artifact).
    MeshData a = test::makeSphereMesh(32, 16);
    Scene scene = makeMeshScene(a, "spheres");
    const vec3 towardLight = normalize(scene.lights[0].position - vec3(0.0f));
    appendMesh(scene, a,
               glm::translate(mat4(1.0f), towardLight * 1.2f + vec3(0.35f, 0.0f, 0.0f)) *
                   glm::scale(mat4(1.0f), vec3(0.6f)),
               "upper", 0);
    scene.validate();
    const PwError e = comparePw(scene, 96, 256);
    std::printf(
        "pw, two overlapping spheres: mean (v_ref - v_pw) %.4f, mean |dv| %.4f, max %.3f over %zu shadowed "
        "pixels; %zu pixels darker than the reference by > 0.05, %zu lighter by > 0.05\n",
        e.meanSigned, e.meanAbs, e.maxAbs, e.pixels, e.darker, e.lighter);
    // Measured, not hidden. Where the centre sees neither sphere, both silhouettes' coverages add
    // (over-darkening, the paper's §3.1 artifact); where the centre is behind both, both loops
    // subtract their uncovered parts from one hard shadow (too light). Both must show up here,
    // far above the convex case's noise level.
    EXPECT_GT(e.darker, 20u);
    EXPECT_GT(e.meanAbs, 0.02);
}

} // namespace
} // namespace stsv
