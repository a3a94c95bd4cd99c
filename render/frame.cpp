#include "render/frame.h"

#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu_stsv.h"
#include "render/cpu_wedges.h"
#include "render/gpu_renderer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"

namespace stsv {

namespace {
const vec3 BACKGROUND(0.02f, 0.02f, 0.03f);
}

void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility, const ImageF* coverage) {
    parallelFor(
        std::size_t(gbuffer.width) * gbuffer.height,
        [&](std::size_t i) {
            const int x = static_cast<int>(i % std::size_t(gbuffer.width)),
                      y = static_cast<int>(i / std::size_t(gbuffer.width));
            if (!gbuffer.covered(i)) {
                visibility.at(x, y, 0) += weight;
                return;
            }
            const vec3 albedo = scene.materialOf(gbuffer.triangle[i]).albedo;
            const float v = coverage ? coverage->at(x, y, 0) : samples.visibleFraction(x, y);
            // PW: v_coef modulates the unshadowed direct lighting.
            const vec3 direct = resolveDirect(samples, plan, x, y, light, gbuffer.position[i],
                                              gbuffer.normal[i], albedo, farDistance, coverage ? v : 1.0f);
            for (int c = 0; c < 3; ++c) color.at(x, y, c) += direct[c];
            visibility.at(x, y, 0) += weight * v;
        },
        256);
}

void initFrameImages(const Scene& scene, const GBuffer& gbuffer, float ambient, Frame& frame) {
    frame.color = ImageF(gbuffer.width, gbuffer.height, 3);
    frame.visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) {
        const int x = static_cast<int>(i % std::size_t(gbuffer.width)),
                  y = static_cast<int>(i / std::size_t(gbuffer.width));
        const vec3 c =
            gbuffer.covered(i) ? ambient * scene.materialOf(gbuffer.triangle[i]).albedo : BACKGROUND;
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
          m_startupMs(0.0) {
        if (m_options.method != Method::Reference && m_options.method != Method::Stsv) occluders();
        m_startupMs = m_startup.milliseconds();
    }

    Frame render() override {
        Frame frame;
        nlohmann::json passes = nlohmann::json::object();
        Timer total;
        Timer timer;
        frame.gbuffer = m_embree.traceGBuffer(m_options.width, m_options.height);
        passes["gbuffer"] = timer.milliseconds();
        initFrameImages(m_scene, frame.gbuffer, m_options.ambient, frame);

        nlohmann::json methodStats = nlohmann::json::array();
        const auto kind = countsLayers(m_options.method) || m_options.buffer == BufferKind::Counters
                              ? LightSampleBuffer::Kind::Counters
                              : LightSampleBuffer::Kind::Bitmask;
        std::size_t bufferBytes = 0;
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
            const Light& light = m_scene.lights[l];
            const std::string prefix = "light" + std::to_string(l) + "/";
            LightSampleBuffer& buffer =
                frame.lightSamples.emplace_back(m_options.width, m_options.height, m_options.samples, kind);
            bufferBytes = std::max(bufferBytes, buffer.memoryBytes());
            ImageF coverage;
            timer.reset();
            switch (m_options.method) {
            case Method::Reference:
                traceReferenceSamples(m_embree, frame.gbuffer, light, m_plan, m_farDistance, buffer);
                passes[prefix + "reference"] = timer.milliseconds();
                break;
            case Method::Stsv: {
                const StsvCpuStats s =
                    stsvCpuSamples(m_scene, frame.gbuffer, light, m_plan, m_farDistance, buffer);
                passes[prefix + "stsv_bin"] = s.bin_ms;
                passes[prefix + "stsv_shade"] = s.shade_ms;
                methodStats.push_back(toJson(s));
                break;
            }
            case Method::Dcs:
            case Method::DcsStsv: {
                StsvCpuStats stsv;
                const WedgeCpuStats w =
                    m_options.method == Method::Dcs
                        ? dcsCpuSamples(occluders(), frame.gbuffer, light, m_plan, m_farDistance, buffer)
                        : dcsStsvCpuSamples(occluders(), frame.gbuffer, light, m_plan, m_farDistance, buffer,
                                            &stsv);
                passes[prefix + toString(m_options.method)] = timer.milliseconds();
                methodStats.push_back({{"wedges", toJson(w)}, {"stsv", toJson(stsv)}});
                break;
            }
            case Method::Pw:
            case Method::PwStsv: {
                // PW yields a v_coef per pixel; the bitmask keeps the STSV part of pw+stsv.
                coverage = ImageF(m_options.width, m_options.height, 1);
                StsvCpuStats stsv;
                const WedgeCpuStats w =
                    m_options.method == Method::Pw
                        ? pwCpuVisibility(occluders(), frame.gbuffer, light, m_farDistance, coverage)
                        : pwStsvCpuVisibility(occluders(), frame.gbuffer, light, m_plan, m_farDistance,
                                              coverage, buffer, &stsv);
                passes[prefix + toString(m_options.method)] = timer.milliseconds();
                methodStats.push_back({{"wedges", toJson(w)}, {"stsv", toJson(stsv)}});
                break;
            }
            }
            timer.reset();
            // PW shades with all samples lit, scaled by its v_coef.
            const LightSampleBuffer* resolveBuffer = &buffer;
            LightSampleBuffer allLit;
            if (wedgeCoverage(m_options.method)) {
                allLit = LightSampleBuffer(m_options.width, m_options.height, m_options.samples,
                                           LightSampleBuffer::Kind::Bitmask);
                resolveBuffer = &allLit;
            }
            resolveLight(m_scene, frame.gbuffer, light, m_plan, m_farDistance, *resolveBuffer,
                         1.0f / float(m_scene.lights.size()), frame.color, frame.visibility,
                         wedgeCoverage(m_options.method) ? &coverage : nullptr);
            passes[prefix + "resolve"] = timer.milliseconds();
        }
        nlohmann::json options = toJson(m_options);
        options["backend"] = "cpu"; // what actually ran (the reference and the wedge methods are CPU-only)
        frame.stats = {{"options", options},        {"scene", sceneStats(m_scene)},
                       {"startup_ms", m_startupMs}, {"frame_ms", total.milliseconds()},
                       {"passes", passes},          {"light_sample_buffer_bytes", bufferBytes}};
        if (!methodStats.empty())
            frame.stats[m_options.method == Method::Stsv ? "stsv" : "wedges"] = methodStats;
        return frame;
    }

  private:
    /// Adjacency and silhouette data of the opaque meshes, built on first use (wedge methods).
    const OpaqueOccluders& occluders() {
        if (!m_occluders) m_occluders = std::make_unique<OpaqueOccluders>(m_scene);
        return *m_occluders;
    }

    const Scene& m_scene;
    RenderOptions m_options;
    Timer m_startup;
    SamplePlan m_plan;
    float m_farDistance;
    EmbreeScene m_embree;
    std::unique_ptr<OpaqueOccluders> m_occluders;
    double m_startupMs;
};

} // namespace

std::unique_ptr<FrameRenderer> makeRenderer(const Scene& scene, const RenderOptions& options) {
    validate(options);
    // The Embree reference is CPU-only; the Vulkan backend renders every other method.
    if (options.backend == Backend::Vulkan && options.method != Method::Reference)
        return std::make_unique<VulkanRenderer>(scene, options);
    return std::make_unique<CpuRenderer>(scene, options);
}

Frame renderFrame(const Scene& scene, const RenderOptions& options) {
    return makeRenderer(scene, options)->render();
}

} // namespace stsv
