// dcs and dcs+stsv (CPU mirror) against Embree shadow rays at equal light samples, on closed
// meshes (sphere, torus, torus knot, a loaded 10k+ triangle OBJ) with and without perforated
// triangles: at least 99.9 % identical occlusion bits. Differences come from samples
// whose segment grazes an edge or a vertex within float round-off.
#include "core/progress.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu_wedges.h"
#include "sampling/light_bounds.h"
#include "scene/geometry.h"
#include "scene/load.h"
#include "scene/procedural.h"
#include "wedge_test_util.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace stsv {
namespace {

/// A chain-link quad (perforated, double-sided) between the mesh and its light.
void addPerforatedQuad(Scene& scene) {
    const Bounds b = scene.bounds();
    const vec3 c = 0.5f * (vec3(scene.lights[0].position) + b.center());
    Material fence;
    fence.name = "chainlink";
    fence.alphaTexture = addTexture(scene, makeChainLinkTexture(64));
    fence.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, fence);
    const float size = 0.6f * length(vec3(b.extent()) * vec3(1.0f, 0.0f, 1.0f)) * 0.25f;
    mat4 placement = glm::translate(mat4(1.0f), c) * glm::rotate(mat4(1.0f), 1.2f, vec3(1.0f, 0.0f, 0.2f));
    appendMesh(scene, makeQuad(vec2(size), vec2(3.0f)), placement, "fence", int(m));
    scene.validate();
}

struct Agreement {
    std::size_t compared = 0;
    std::size_t differing = 0;
    std::size_t occluded = 0;
    double fraction() const { return compared ? 1.0 - double(differing) / double(compared) : 0.0; }
};

Agreement compareWithReference(const Scene& scene, int size, int samples, bool withStsv,
                               WedgeCpuStats* statsOut = nullptr) {
    Progress::setEnabled(false);
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 3);
    const float farDistance = farDistanceFor(scene.bounds());
    const OpaqueOccluders occ(scene);
    Agreement a;
    for (const Light& light : scene.lights) {
        LightSampleBuffer dcs(size, size, samples, BufferKind::Counters);
        const WedgeCpuStats stats = withStsv ? dcsStsvCpuSamples(occ, g, light, plan, farDistance, dcs)
                                             : dcsCpuSamples(occ, g, light, plan, farDistance, dcs);
        if (statsOut) *statsOut = stats;
        LightSampleBuffer ref(size, size, samples, BufferKind::Bitmask);
        traceReferenceSamples(embree, g, light, plan, farDistance, ref);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                if (!g.covered(g.index(x, y))) continue;
                for (int k = 0; k < samples; ++k) {
                    ++a.compared;
                    a.occluded += ref.occluded(x, y, k) ? 1 : 0;
                    if (ref.occluded(x, y, k) != dcs.occluded(x, y, k)) ++a.differing;
                }
            }
    }
    return a;
}

void expectAgreement(const char* name, const Scene& scene, bool withStsv, double minFraction = 0.999,
                     int size = 80, int samples = 32) {
    WedgeCpuStats stats;
    const Agreement a = compareWithReference(scene, size, samples, withStsv, &stats);
    std::printf(
        "%-28s %s: %zu of %zu samples differ (%.4f %% identical), %zu occluded; %zu edges, %zu potential "
        "silhouettes, %zu negative counts\n",
        name, withStsv ? "dcs+stsv" : "dcs     ", a.differing, a.compared, 100.0 * a.fraction(), a.occluded,
        stats.edges, stats.potentialSilhouettes, stats.negativeCounts);
    EXPECT_GE(a.fraction(), minFraction) << name;
    // Not vacuous: a real shadow is in view.
    EXPECT_GT(a.occluded, a.compared / 50) << name;
}

Scene meshScene(const MeshData& mesh, const char* name, bool perforated) {
    Scene scene = makeMeshScene(mesh, name);
    if (perforated) addPerforatedQuad(scene);
    return scene;
}

TEST(DcsVsReference, Sphere) {
    for (bool perforated : {false, true})
        expectAgreement("sphere 32x16", meshScene(test::makeSphereMesh(32, 16), "sphere", perforated),
                        perforated);
}

TEST(DcsVsReference, Torus) {
    for (bool perforated : {false, true})
        expectAgreement("torus 48x16",
                        meshScene(test::makeTorusMesh(48, 16, 1.0f, 0.35f), "torus", perforated), perforated);
}

TEST(DcsVsReference, TorusKnot) {
    for (bool perforated : {false, true})
        expectAgreement("torus knot 256x12",
                        meshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "knot", perforated), perforated);
}

TEST(DcsVsReference, OtherLightShapes) {
    for (int shape = 0; shape < 3; ++shape) {
        Scene scene = meshScene(test::makeTorusMesh(40, 12, 1.0f, 0.35f), "torus", shape == 1);
        const Light rect = scene.lights[0];
        if (shape == 0) scene.lights[0] = makeDiskLight(rect.position, rect.normal, 0.6f, rect.radiance);
        if (shape == 1) scene.lights[0] = makeSphereLight(rect.position, 0.5f, rect.radiance);
        if (shape == 2) scene.lights[0] = makeDirectionalLight(-rect.normal, 0.1f, vec3(1.0f));
        const char* names[] = {"torus, disk light", "torus+fence, sphere light", "torus, directional"};
        expectAgreement(names[shape], scene, shape == 1, 0.999);
    }
}

TEST(DcsVsReference, LoadedObjOver10kTriangles) {
    const MeshData knot = test::makeTorusKnotMesh(480, 12, 0.12f, 3, 4); // 11,520 triangles
    const auto dir = std::filesystem::temp_directory_path() / "stsv_wedges_obj";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "knot.obj").string();
    {
        std::ofstream out(path);
        for (const vec3& p : knot.positions) out << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        for (const uvec3& t : knot.triangles)
            out << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
    }
    Scene scene = loadScene(path);
    std::filesystem::remove_all(dir);
    ASSERT_GE(scene.triangleCount(), 10000u);
    expectAgreement("loaded knot.obj (11.5k)", scene, false);
    addPerforatedQuad(scene);
    expectAgreement("loaded knot.obj + fence", scene, true);
}

} // namespace
} // namespace stsv
