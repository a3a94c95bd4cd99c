// The mesh path of the volume passes (--extrusion mesh: stsv.task/.mesh, wedge.task/.mesh) against
// the compute hull pass and the geometry shader's prisms, for every object-based method. Runs
// where the device has VK_EXT_mesh_shader: ctest mesh_shaders.lavapipe_backports runs it on the
// second lavapipe (tests/drivers/mesh_shader_test.sh), where skipping is a failure.
#include "gpu_render_helpers.h"
#include "scene/load.h"
#include "tests/scene/scene_test_util.h"
#include "tests/wedges/wedge_test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace stsv::test {
namespace {

class GpuMeshShader : public GpuRenderTest {
  protected:
    /// False (the test skips, or fails under STSV_REQUIRE_MESH_SHADERS) without mesh shaders.
    bool meshShaders() {
        if (device().info().meshShader && device().info().taskShader) return true;
        if (std::getenv("STSV_REQUIRE_MESH_SHADERS"))
            ADD_FAILURE() << device().info().name
                          << " lacks VK_EXT_mesh_shader, which STSV_REQUIRE_MESH_SHADERS requires";
        return false;
    }
};

struct MeshCase {
    std::string name;
    Scene scene;
};

/// fence, foliage, knot and example.json, and the scenes of the GPU tests: the torus knot mesh
/// under a rectangle light (light planes), a sphere mesh under a sphere light (none), foliage
/// under a large disk light.
std::vector<MeshCase> meshCases() {
    std::vector<MeshCase> cases;
    for (const char* name : {"fence", "foliage", "knot"}) cases.push_back({name, loadScene(name)});
    cases.push_back({"example.json", loadScene(dataPath("example.json"))});
    cases.push_back(
        {"torus knot mesh", makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot")});
    Scene sphere = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
    sphere.lights[0] = makeSphereLight(sphere.lights[0].position, 0.3f, sphere.lights[0].radiance);
    cases.push_back({"sphere mesh, sphere light", std::move(sphere)});
    Scene disk = loadScene("foliage");
    disk.lights[0] =
        makeDiskLight(disk.lights[0].position, disk.lights[0].normal, 2.0f, disk.lights[0].radiance);
    cases.push_back({"foliage, disk light", std::move(disk)});
    return cases;
}

/// The counts of a volume family's stats ("stsv", "wedges") that the mesh path must share with
/// the compute hull path, light by light: the same dh functions build and clip the same hulls,
/// so the same volumes and triangles are drawn, and the same fragments reach the same tests.
void expectSameCounts(const Frame& mesh, const Frame& hull, const char* family, const std::string& what) {
    if (!hull.stats.contains(family)) {
        EXPECT_FALSE(mesh.stats.contains(family)) << what;
        return;
    }
    ASSERT_TRUE(mesh.stats.contains(family)) << what;
    ASSERT_EQ(mesh.stats[family].size(), hull.stats[family].size()) << what;
    for (std::size_t l = 0; l < hull.stats[family].size(); ++l) {
        const nlohmann::json& m = mesh.stats[family][l];
        const nlohmann::json& h = hull.stats[family][l];
        for (const char* key :
             {"hull_volumes", "hull_triangles", "fragments", "inside_fragments", "silhouette_fragments"}) {
            if (h.contains(key)) {
                EXPECT_EQ(m[key], h[key]) << what << " " << family << " light " << l << " " << key;
            }
        }
    }
}

TEST_F(GpuMeshShader, MeshShaderHullsGiveTheBuffersOfTheHullAndGeometryPaths) {
    if (!meshShaders())
        GTEST_SKIP() << device().info().name << " lacks VK_EXT_mesh_shader: mesh path not run";
    for (const MeshCase& c : meshCases())
        for (Method method : {Method::Stsv, Method::Dcs, Method::Pw, Method::DcsStsv, Method::PwStsv})
            for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
                // The frame's buffer is the method's (methodInfo.bufferKind); STSV alone writes either.
                if (method != Method::Stsv && kind == BufferKind::Counters) continue;
                RenderOptions o = gpuOptions(96, 72, 64, kind);
                o.method = method;
                const std::string what = c.name + " " + toString(method) + " " + toString(kind);
                const Frame mesh = renderGpu(c.scene, o, ExtrusionStage::Mesh);
                const Frame hull = renderGpu(c.scene, o, ExtrusionStage::Hull);
                const Frame prism = renderGpu(c.scene, o, ExtrusionStage::Geometry);
                EXPECT_EQ(mesh.stats["gpu"]["extrusion"], "mesh shader hull") << what;
                ASSERT_EQ(mesh.lightSamples.size(), hull.lightSamples.size()) << what;
                for (std::size_t l = 0; l < mesh.lightSamples.size(); ++l)
                    for (const Frame* other : {&hull, &prism}) {
                        EXPECT_EQ(mesh.lightSamples[l].words(), other->lightSamples[l].words())
                            << what << " light " << l;
                        EXPECT_EQ(mesh.lightSamples[l].counters(), other->lightSamples[l].counters())
                            << what << " light " << l;
                    }
                expectSameCounts(mesh, hull, "stsv", what);
                expectSameCounts(mesh, hull, "wedges", what);
                const bool pw = methodInfo(method).wedges == WedgeVariant::Pw;
                ASSERT_EQ(mesh.visibility.pixels.size(), hull.visibility.pixels.size()) << what;
                for (const Frame* other : {&hull, &prism})
                    for (std::size_t i = 0; i < mesh.visibility.pixels.size(); ++i) {
                        if (!pw) {
                            ASSERT_EQ(mesh.visibility.pixels[i], other->visibility.pixels[i])
                                << what << " pixel " << i;
                            continue;
                        }
                        // PW sums float coverages by additive blending in primitive order, which the
                        // three draws do not share: equal up to the rounding of a few dozen additions
                        // of terms ≤ 1.
                        ASSERT_NEAR(mesh.visibility.pixels[i], other->visibility.pixels[i], 1e-5f)
                            << what << " pixel " << i;
                    }
                if (pw) {
                    // The task shader hands its survivors on in item order, and a mesh workgroup emits
                    // them in that order: the primitive order, and so PW's sums, are the same in every frame.
                    const Frame again = renderGpu(c.scene, o, ExtrusionStage::Mesh);
                    EXPECT_EQ(again.visibility.pixels, mesh.visibility.pixels) << what;
                }
            }
}

TEST_F(GpuMeshShader, MeshShaderPathCullsAndDrawsFewerFragmentsThanPrisms) {
    // The task shader's culling and the clipped hulls: on the knot, DCS's mesh path draws the
    // compute path's hulls, a small fraction of the prisms' fragments (the compute path's bound
    // in the wedge tests: 2 %).
    if (!meshShaders())
        GTEST_SKIP() << device().info().name << " lacks VK_EXT_mesh_shader: mesh path not run";
    const Scene knot = makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot");
    RenderOptions o = gpuOptions(96, 72, 32, BufferKind::Counters);
    o.method = Method::Dcs;
    const Frame mesh = renderGpu(knot, o, ExtrusionStage::Mesh);
    const Frame prism = renderGpu(knot, o, ExtrusionStage::Geometry);
    const nlohmann::json& m = mesh.stats["wedges"][0];
    const nlohmann::json& p = prism.stats["wedges"][0];
    EXPECT_GT(m["hull_volumes"].get<std::size_t>(), 0u);
    // Fewer volumes than carrier sides: the task shader culled the faces without a potential
    // silhouette.
    EXPECT_LT(m["hull_volumes"].get<std::size_t>(), knot.triangleCount());
    EXPECT_EQ(m["silhouette_fragments"], p["silhouette_fragments"]);
    EXPECT_LE(double(m["fragments"].get<std::size_t>()), 0.02 * double(p["fragments"].get<std::size_t>()));
}

} // namespace
} // namespace stsv::test
