#include "render/frame.h"

#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "sampling/light_sampling.h"
#include "reference/reference_visibility.h"
#include "render/cpu_stsv.h"
#include "render/gpu_renderer.h"
#include "sampling/light_bounds.h"


namespace stsv {

namespace {
const vec3 BACKGROUND(0.02f, 0.02f, 0.03f);
}

void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility) {
    parallelFor(std::size_t(gbuffer.width) * gbuffer.height, [&](std::size_t i) {
        const int x = static_cast<int>(i % std::size_t(gbuffer.width)), y = static_cast<int>(i / std::size_t(gbuffer.width));
        if (!gbuffer.covered(i)) {
            visibility.at(x, y, 0) += weight;
            return;
        }
        const vec3 albedo = scene.materialOf(gbuffer.triangle[i]).albedo;
        const vec3 direct =
            resolveDirect(samples, plan, x, y, light, gbuffer.position[i], gbuffer.normal[i], albedo, farDistance);
        for (int c = 0; c < 3; ++c) color.at(x, y, c) += direct[c];
        visibility.at(x, y, 0) += weight * samples.visibleFraction(x, y);
    }, 256);
}

void initFrameImages(const Scene& scene, const GBuffer& gbuffer, float ambient, Frame& frame) {
    frame.color = ImageF(gbuffer.width, gbuffer.height, 3);
    frame.visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) {
        const int x = static_cast<int>(i % std::size_t(gbuffer.width)), y = static_cast<int>(i / std::size_t(gbuffer.width));
        const vec3 c = gbuffer.covered(i) ? ambient * scene.materialOf(gbuffer.triangle[i]).albedo : BACKGROUND;
        for (int k = 0; k < 3; ++k) frame.color.at(x, y, k) = c[k];
    }
}

nlohmann::json sceneStats(const Scene& scene) {
    std::size_t perforated = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) perforated += scene.perforated(t) ? 1 : 0;
    return {{"source", scene.source},
            {"triangles", scene.triangleCount()},
            {"perforated_triangles", perforated},
            {"skipped_faces", scene.skippedFaces},
            {"lights", scene.lights.size()}};
}

namespace {

/// The CPU backend: Embree G-buffer, then per light the reference rays or the STSV mirror.
class CpuRenderer final : public FrameRenderer {
  public:
    CpuRenderer(const Scene& scene, const RenderOptions& options)
        : m_scene(scene), m_options(options),
          m_plan(makeSamplePlan(options.pattern, options.samples, options.seed, options.interleave,
                                options.decorrelate)),
          m_farDistance(farDistanceFor(scene.bounds())), m_embree((validate(options), scene)),
          m_startupMs(m_startup.milliseconds()) {}

    Frame render() override {
        Frame frame;
        nlohmann::json passes = nlohmann::json::object();
        Timer total;
        Timer timer;
        frame.gbuffer = m_embree.traceGBuffer(m_options.width, m_options.height);
        passes["gbuffer"] = timer.milliseconds();
        initFrameImages(m_scene, frame.gbuffer, m_options.ambient, frame);

        nlohmann::json stsvStats = nlohmann::json::array();
        const auto kind = m_options.buffer == BufferKind::Bitmask ? LightSampleBuffer::Kind::Bitmask
                                                                  : LightSampleBuffer::Kind::Counters;
        std::size_t bufferBytes = 0;
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
            const Light& light = m_scene.lights[l];
            const std::string prefix = "light" + std::to_string(l) + "/";
            LightSampleBuffer& buffer =
                frame.lightSamples.emplace_back(m_options.width, m_options.height, m_options.samples, kind);
            bufferBytes = std::max(bufferBytes, buffer.memoryBytes());
            timer.reset();
            if (m_options.method == Method::Reference) {
                traceReferenceSamples(m_embree, frame.gbuffer, light, m_plan, m_farDistance, buffer);
                passes[prefix + "reference"] = timer.milliseconds();
            } else {
                const StsvCpuStats s = stsvCpuSamples(m_scene, frame.gbuffer, light, m_plan, m_farDistance, buffer);
                passes[prefix + "stsv_bin"] = s.bin_ms;
                passes[prefix + "stsv_shade"] = s.shade_ms;
                stsvStats.push_back({{"volumes", s.volumes},
                                     {"degenerate_skipped", s.degenerateSkipped},
                                     {"tile_entries", s.tileEntries},
                                     {"point_in_volume_tests", s.pixelVolumeTests},
                                     {"fragments", s.pixelVolumeHits}});
            }
            timer.reset();
            resolveLight(m_scene, frame.gbuffer, light, m_plan, m_farDistance, buffer,
                         1.0f / float(m_scene.lights.size()), frame.color, frame.visibility);
            passes[prefix + "resolve"] = timer.milliseconds();
        }
        frame.stats = {{"options", toJson(m_options)},
                       {"scene", sceneStats(m_scene)},
                       {"startup_ms", m_startupMs},
                       {"frame_ms", total.milliseconds()},
                       {"passes", passes},
                       {"light_sample_buffer_bytes", bufferBytes}};
        if (!stsvStats.empty()) frame.stats["stsv"] = stsvStats;
        return frame;
    }

  private:
    const Scene& m_scene;
    RenderOptions m_options;
    Timer m_startup;
    SamplePlan m_plan;
    float m_farDistance;
    EmbreeScene m_embree;
    double m_startupMs;
};

} // namespace

std::unique_ptr<FrameRenderer> makeRenderer(const Scene& scene, const RenderOptions& options) {
    validate(options);
    // The Embree reference is CPU-only; the Vulkan backend renders the STSV method.
    if (options.backend == Backend::Vulkan && options.method == Method::Stsv)
        return std::make_unique<VulkanRenderer>(scene, options);
    return std::make_unique<CpuRenderer>(scene, options);
}

Frame renderFrame(const Scene& scene, const RenderOptions& options) { return makeRenderer(scene, options)->render(); }

} // namespace stsv
