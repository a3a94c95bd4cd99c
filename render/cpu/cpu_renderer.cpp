#include "render/cpu/cpu_renderer.h"

#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "render/cpu/cpu_techniques.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"

namespace stsv {

void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility, const ImageF* vcoef) {
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) {
            visibility.at(x, y, 0) += weight;
            return;
        }
        const vec3 albedo = scene.materialOf(gbuffer.triangle[i]).albedo;
        const float v = vcoef ? vcoef->at(x, y, 0) : samples.visibleFraction(x, y);
        // A visibility-only method's v_coef modulates the unshadowed direct lighting.
        const vec3 direct = resolveDirect(samples, plan, x, y, light, gbuffer.position[i], gbuffer.normal[i],
                                          albedo, farDistance, vcoef ? v : 1.0f);
        for (int c = 0; c < 3; ++c) color.at(x, y, c) += direct[c];
        visibility.at(x, y, 0) += weight * v;
    });
}

namespace {

/// Embree G-buffer, then per light the row's techniques and the resolve.
class CpuRenderer final : public FrameRenderer {
  public:
    CpuRenderer(const Scene& scene, const RenderOptions& options)
        : m_scene(scene), m_requested(options), m_options(frameOptions(options)),
          m_method(methodInfo(options.method)), m_plan(samplePlanOf(options)),
          m_farDistance(farDistanceFor(scene.bounds())),
          m_embree(scene), m_context{scene, m_options, m_method, m_plan, m_farDistance, m_embree},
          m_techniques(makeCpuTechniques(m_context)), m_startupMs(m_startup.milliseconds()) {}

    Frame render() override {
        Frame frame;
        nlohmann::json passes = nlohmann::json::object();
        Timer total;
        Timer timer;
        frame.gbuffer = m_embree.traceGBuffer(m_options.width, m_options.height);
        passes["gbuffer"] = timer.milliseconds();
        initFrameImages(m_scene, frame.gbuffer, m_options.ambient, frame);

        const bool visibilityOnly = m_method.output == MethodOutput::Visibility;
        const BufferKind kind = m_options.buffer; // the method's kind (frameOptions)
        std::size_t bufferBytes = 0;
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
            const Light& light = m_scene.lights[l];
            LightSampleBuffer& samples =
                frame.lightSamples.emplace_back(m_options.width, m_options.height, m_options.samples, kind);
            bufferBytes = std::max(bufferBytes, samples.memoryBytes());
            ImageF vcoef = visibilityOnly ? ImageF(m_options.width, m_options.height, 1) : ImageF();
            CpuLightWork work{frame.gbuffer, light, l, samples, vcoef, frame, passes};
            // Algorithm 2 per light: each technique of the row, then what combines them.
            for (const std::unique_ptr<CpuTechnique>& technique : m_techniques) technique->run(work);
            for (const std::unique_ptr<CpuTechnique>& technique : m_techniques) technique->combine(work);
            timer.reset();
            // A visibility-only method shades with every sample lit, scaled by its v_coef.
            LightSampleBuffer allLit;
            if (visibilityOnly)
                allLit = LightSampleBuffer(m_options.width, m_options.height, m_options.samples,
                                           BufferKind::Bitmask);
            resolveLight(m_scene, frame.gbuffer, light, m_plan, m_farDistance,
                         visibilityOnly ? allLit : samples, 1.0f / float(m_scene.lights.size()), frame.color,
                         frame.visibility, visibilityOnly ? &vcoef : nullptr);
            passes[work.pass("resolve")] = timer.milliseconds();
        }
        frame.stats = {{"options", toJson(m_options)},
                       {"scene", sceneStats(m_scene)},
                       {"startup_ms", m_startupMs},
                       {"frame_ms", total.milliseconds()},
                       {"passes", passes},
                       {"light_sample_buffer_bytes", bufferBytes}};
        frame.stats.update(methodSceneNotes(m_scene, m_method));
        if (!m_scene.lights.empty())
            for (const std::unique_ptr<CpuTechnique>& technique : m_techniques)
                technique->takeStats(frame.stats);
        resolveSupersampling(frame, m_requested);
        return frame;
    }

  private:
    const Scene& m_scene;
    RenderOptions m_requested;
    RenderOptions m_options;
    const MethodInfo& m_method;
    Timer m_startup;
    SamplePlan m_plan;
    float m_farDistance;
    EmbreeScene m_embree;
    CpuTechniqueContext m_context;
    std::vector<std::unique_ptr<CpuTechnique>> m_techniques;
    double m_startupMs;
};

} // namespace

std::unique_ptr<FrameRenderer> makeCpuRenderer(const Scene& scene, const RenderOptions& options) {
    validate(options);
    return std::make_unique<CpuRenderer>(scene, options);
}

} // namespace stsv
