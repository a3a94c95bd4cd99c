// Performance measurements of the Vulkan renderer, not unit tests:
// disabled by default, run with
//   test_gpu_render --gtest_also_run_disabled_tests --gtest_filter='GpuPerf.*'
// No validation (it would dominate the timings); warm-up frame, then the median of 3 frames.
#include "render/renderer.h"
#include "render/vulkan/gpu_renderer.h"
#include "scene/load.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <iostream>

namespace stsv {
namespace {

/// CPU time of the whole process (lavapipe's and Embree's worker threads included), ms: unlike
/// wall time it does not grow when other processes share the two cores.
double processCpuMs() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return 1e3 * double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-3 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

nlohmann::json medianFrame(FrameRenderer& renderer, int repeat, Frame* keep = nullptr) {
    renderer.render(); // warm-up
    std::vector<nlohmann::json> stats;
    for (int i = 0; i < repeat; ++i) {
        const double cpu = processCpuMs();
        Frame f = renderer.render();
        f.stats["process_cpu_ms"] = processCpuMs() - cpu;
        stats.push_back(f.stats);
        if (keep && i == 0) *keep = std::move(f);
    }
    std::sort(stats.begin(), stats.end(), [](const auto& a, const auto& b) {
        return a["frame_ms"].template get<double>() < b["frame_ms"].template get<double>();
    });
    return stats[stats.size() / 2];
}

void print(const std::string& what, const nlohmann::json& s) {
    std::cout << what << ": frame_ms " << s["frame_ms"] << " process_cpu_ms "
              << s.value("process_cpu_ms", 0.0) << " gpu_ms " << s.value("gpu_ms", 0.0) << " passes "
              << s["passes"].dump() << " stsv " << s.value("stsv", nlohmann::json()).dump() << "\n";
}

RenderOptions options(int size, int samples) {
    RenderOptions o;
    o.backend = Backend::Vulkan;
    o.width = size;
    o.height = size;
    o.samples = samples;
    return o;
}

TEST(GpuPerf, DISABLED_FenceGpuVsEmbree1024) {
    const Scene scene = loadScene("fence");
    RenderOptions o = options(1024, 64);
    VulkanRenderer gpu(scene, o);
    Frame gpuFrame;
    const nlohmann::json g = medianFrame(gpu, 3, &gpuFrame);
    print("fence 1024 N=64 vulkan stsv", g);
    o.backend = Backend::Cpu;
    o.method = Method::Reference;
    const std::unique_ptr<FrameRenderer> cpu = makeRenderer(scene, o);
    const double cpuStart = processCpuMs();
    Frame ref = cpu->render();
    ref.stats["process_cpu_ms"] = processCpuMs() - cpuStart;
    print("fence 1024 N=64 cpu embree reference", ref.stats);
    const LightSampleDiff diff = compareLightSamples(gpuFrame.lightSamples[0], ref.lightSamples[0]);
    std::cout << "speed-up " << ref.stats["frame_ms"].get<double>() / g["frame_ms"].get<double>()
              << "x, differing bits " << diff.differingSamples << " of " << diff.comparedSamples
              << " (G-buffers differ at edges too)\n";
}

TEST(GpuPerf, DISABLED_SampleScaling) {
    const Scene scene = loadScene("fence");
    for (int n : {16, 64, 256}) {
        VulkanRenderer gpu(scene, options(1024, n));
        print("fence 1024 N=" + std::to_string(n), medianFrame(gpu, 3));
    }
}

TEST(GpuPerf, DISABLED_TriangleScaling) {
    for (const char* count : {"250", "1000", "4000"}) {
        SceneOptions so;
        so.set["count"] = count;
        const Scene scene = loadScene("foliage", so);
        VulkanRenderer gpu(scene, options(512, 64));
        print("foliage count=" + std::string(count) + " (" + std::to_string(scene.triangleCount()) +
                  " triangles) 512 N=64",
              medianFrame(gpu, 1));
    }
}

} // namespace
} // namespace stsv
