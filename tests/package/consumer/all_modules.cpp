// Links every library the installed package exports (stsv::core, scene, sampling, volumes,
// wedges, shadowmaps, reference, gpu, render) and uses each: a built-in scene rendered on the CPU
// by STSV and by the Embree reference, the two agreeing on every light sample, plus one call into
// each module that the frame does not make itself. Exit 0 when every check holds.
#include "core/error.h"
#include "core/memory_budget.h"
#include "gpu/device.h"
#include "reference/embree_scene.h"
#include "render/renderer.h"
#include "sampling/pattern.h"
#include "scene/load.h"
#include "shadowmaps/shadow_map.h"
#include "wedges/adjacency.h"

#include <cstdio>

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what);
    if (!ok) ++failures;
}

} // namespace

int main() {
    using namespace stsv;
    check(formatBytes(2048.0) == "2.0 KiB", "core: formatBytes");
    const Scene scene = loadScene("fence");
    check(scene.triangleCount() == 4 && scene.lights.size() == 1, "scene: the built-in fence");
    check(makeSamplePlan(PatternKind::Poisson, 16, 1u).points.size() == 16, "sampling: a plan of 16 samples");
    check(buildEdgeAdjacency(scene).edges.size() > 0, "wedges: edge adjacency");
    check(fitShadowMap(scene.lights[0], scene.bounds(), 256).size == 256u, "shadowmaps: a fitted map");
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(8, 6);
    std::size_t covered = 0;
    for (std::size_t i = 0; i < g.triangle.size(); ++i) covered += g.covered(i) ? 1 : 0;
    check(covered > 24, "reference: a traced G-buffer sees the scene");
    try {
        check(!listDevices().empty(), "gpu: Vulkan devices listed");
    } catch (const Error& e) {
        std::printf("skip: gpu: no Vulkan driver here (%s)\n", e.what());
    }
    RenderOptions options;
    options.backend = Backend::Cpu;
    options.width = 24;
    options.height = 16;
    options.samples = 16;
    options.method = Method::Stsv;
    const Frame stsv = renderFrame(scene, options);
    options.method = Method::Reference;
    const Frame reference = renderFrame(scene, options);
    std::size_t differing = 0, occluded = 0;
    const LightSampleBuffer& a = stsv.lightSamples.at(0);
    const LightSampleBuffer& b = reference.lightSamples.at(0);
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int k = 0; k < a.samples(); ++k) {
                differing += a.occluded(x, y, k) != b.occluded(x, y, k) ? 1 : 0;
                occluded += b.occluded(x, y, k) ? 1 : 0;
            }
    check(occluded > 0, "render: the fence casts a shadow");
    check(differing == 0, "render: STSV and the Embree reference agree on every light sample");
    return failures == 0 ? 0 : 1;
}
