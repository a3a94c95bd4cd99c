#include "render/frame.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu_shadowmaps.h"
#include "render/cpu_stsv.h"
#include "render/cpu_wedges.h"
#include "render/gpu_renderer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"

namespace stsv {

void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility, const ImageF* coverage) {
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) {
            visibility.at(x, y, 0) += weight;
            return;
        }
        const vec3 albedo = scene.materialOf(gbuffer.triangle[i]).albedo;
        const float v = coverage ? coverage->at(x, y, 0) : samples.visibleFraction(x, y);
        // PW: v_coef modulates the unshadowed direct lighting.
        const vec3 direct = resolveDirect(samples, plan, x, y, light, gbuffer.position[i], gbuffer.normal[i],
                                          albedo, farDistance, coverage ? v : 1.0f);
        for (int c = 0; c < 3; ++c) color.at(x, y, c) += direct[c];
        visibility.at(x, y, 0) += weight * v;
    });
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
        : m_scene(scene), m_requested(options), m_options(frameOptions(options)),
          m_method(methodInfo(options.method)), m_plan(samplePlanOf(options)),
          m_farDistance(farDistanceFor(scene.bounds())), m_embree((validate(options), scene)),
          m_shadowMaps(shadowMapSettings(m_options)), m_startupMs(0.0) {
        if (m_method.opaque != OpaqueTechnique::None) occluders();
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
        nlohmann::json stsvStats = nlohmann::json::array(); // the STSV part of pw+stsv, dcs+stsv
        const BufferKind kind = m_options.buffer;
        std::size_t bufferBytes = 0;
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
            const Light& light = m_scene.lights[l];
            const std::string prefix = "light" + std::to_string(l) + "/";
            LightSampleBuffer& buffer =
                frame.lightSamples.emplace_back(m_options.width, m_options.height, m_options.samples, kind);
            bufferBytes = std::max(bufferBytes, buffer.memoryBytes());
            ImageF coverage;
            timer.reset();
            // Algorithm 2 per light: rays (ground truth), or the opaque pass and then STSV over the
            // triangles the method sends through it.
            if (m_method.traced) {
                traceReferenceSamples(m_embree, frame.gbuffer, light, m_plan, m_farDistance, buffer);
                passes[prefix + "reference"] = timer.milliseconds();
            } else if (m_method.shadowMap != ShadowFilter::None) {
                // Image-based: the light-centre map and its filter give v_coef per pixel.
                coverage = ImageF(m_options.width, m_options.height, 1);
                ShadowMap* keep = m_options.keepShadowMaps ? &frame.shadowMaps.emplace_back() : nullptr;
                const ShadowMapCpuStats s =
                    shadowMapCpuVisibility(m_embree, frame.gbuffer, light, m_shadowMaps, m_options.seed,
                                           m_options.decorrelate, coverage, keep, m_options.supersample);
                passes[prefix + "shadow_map"] = s.map_ms;
                if (m_shadowMaps.filter == ShadowFilter::Pcss) passes[prefix + "pcss_blocker"] = s.blocker_ms;
                passes[prefix + "shadow_filter"] = s.filter_ms;
                nlohmann::json mapStats = toJson(s);
                mapStats.update(kernelClampStats(s.kernelClamped, frame.gbuffer));
                methodStats.push_back(mapStats);
            } else if (m_method.opaque == OpaqueTechnique::None) {
                const StsvCpuStats s = stsvCpuSamples(m_scene, frame.gbuffer, light, m_plan, m_farDistance,
                                                      buffer, stsvFilter(m_scene, m_method.stsv));
                passes[prefix + "stsv_bin"] = s.bin_ms;
                passes[prefix + "stsv_shade"] = s.shade_ms;
                methodStats.push_back(toJson(s));
            } else {
                const bool withStsv = m_method.stsv != StsvTriangles::None;
                StsvCpuStats stsv;
                WedgeCpuStats w;
                if (m_method.opaque == OpaqueTechnique::Dcs) {
                    w = withStsv
                            ? dcsStsvCpuSamples(occluders(), frame.gbuffer, light, m_plan, m_farDistance,
                                                buffer, &stsv)
                            : dcsCpuSamples(occluders(), frame.gbuffer, light, m_plan, m_farDistance, buffer);
                } else {
                    // PW yields a v_coef per pixel; the bitmask keeps the STSV part of pw+stsv.
                    coverage = ImageF(m_options.width, m_options.height, 1);
                    w = withStsv
                            ? pwStsvCpuVisibility(occluders(), frame.gbuffer, light, m_plan, m_farDistance,
                                                  coverage, buffer, &stsv)
                            : pwCpuVisibility(occluders(), frame.gbuffer, light, m_farDistance, coverage);
                }
                passes[prefix + m_method.name] = timer.milliseconds();
                methodStats.push_back(toJson(w));
                if (withStsv) stsvStats.push_back(toJson(stsv));
            }
            timer.reset();
            // PW shades with all samples lit, scaled by its v_coef.
            const LightSampleBuffer* resolveBuffer = &buffer;
            LightSampleBuffer allLit;
            const bool visibilityOnly = m_method.output == MethodOutput::Visibility;
            if (visibilityOnly) {
                allLit = LightSampleBuffer(m_options.width, m_options.height, m_options.samples,
                                           BufferKind::Bitmask);
                resolveBuffer = &allLit;
            }
            resolveLight(m_scene, frame.gbuffer, light, m_plan, m_farDistance, *resolveBuffer,
                         1.0f / float(m_scene.lights.size()), frame.color, frame.visibility,
                         visibilityOnly ? &coverage : nullptr);
            passes[prefix + "resolve"] = timer.milliseconds();
        }
        frame.stats = {{"options", toJson(m_options)},
                       {"scene", sceneStats(m_scene)},
                       {"startup_ms", m_startupMs},
                       {"frame_ms", total.milliseconds()},
                       {"passes", passes},
                       {"light_sample_buffer_bytes", bufferBytes}};
        frame.stats.update(methodSceneNotes(m_scene, m_method));
        if (!methodStats.empty())
            frame.stats[m_method.shadowMap != ShadowFilter::None   ? "shadow_maps"
                        : m_method.opaque == OpaqueTechnique::None ? "stsv"
                                                                   : "wedges"] = methodStats;
        if (!stsvStats.empty()) frame.stats["stsv"] = stsvStats;
        resolveSupersampling(frame, m_requested);
        return frame;
    }

  private:
    /// Adjacency and silhouette data of the opaque meshes, built on first use (wedge methods).
    const OpaqueOccluders& occluders() {
        if (!m_occluders) m_occluders = std::make_unique<OpaqueOccluders>(m_scene);
        return *m_occluders;
    }

    const Scene& m_scene;
    RenderOptions m_requested;
    RenderOptions m_options;
    const MethodInfo& m_method;
    Timer m_startup;
    SamplePlan m_plan;
    float m_farDistance;
    EmbreeScene m_embree;
    std::unique_ptr<OpaqueOccluders> m_occluders;
    ShadowMapSettings m_shadowMaps;
    double m_startupMs;
};

} // namespace

std::unique_ptr<FrameRenderer> makeRenderer(const Scene& scene, const RenderOptions& options) {
    validate(options);
    const MethodInfo& method = methodInfo(options.method);
    if (!method.implementedOn(options.backend))
        throw UsageError("method " + method.name + " does not run on " + toString(options.backend) +
                         " (it runs on " + toString(method.backends.front()) + ")");
    if (options.backend == Backend::Vulkan) return std::make_unique<VulkanRenderer>(scene, options);
    return std::make_unique<CpuRenderer>(scene, options);
}

nlohmann::json methodSceneNotes(const Scene& scene, const MethodInfo& method) {
    nlohmann::json notes = nlohmann::json::object();
    // pw and dcs shade opaque triangles only; the traced reference and the shadow maps
    // alpha-test perforated ones, and every STSV method draws them.
    if (method.opaque != OpaqueTechnique::None && method.stsv == StsvTriangles::None) {
        std::size_t perforated = 0;
        for (std::size_t t = 0; t < scene.triangleCount(); ++t) perforated += scene.perforated(t) ? 1 : 0;
        notes["ignored_perforated_triangles"] = perforated;
        if (perforated > 0) notes["ignored_perforated_triangles_use"] = method.name + "+stsv";
    }
    return notes;
}

std::vector<std::string> frameWarnings(const nlohmann::json& stats) {
    std::vector<std::string> warnings;
    const std::string method = stats.contains("options") ? stats["options"].value("method", "") : "";
    if (stats.value("ignored_perforated_triangles", std::size_t(0)) > 0)
        warnings.push_back(method + " shades opaque triangles only: the shadows of the scene's " +
                           std::to_string(stats["ignored_perforated_triangles"].get<std::size_t>()) +
                           " perforated triangles are missing (" +
                           stats.value("ignored_perforated_triangles_use", std::string()) + " draws them)");
    if (stats.contains("shadow_maps") && stats["shadow_maps"].is_array()) {
        double worst = 0.0;
        for (const nlohmann::json& map : stats["shadow_maps"])
            worst = std::max(worst, map.value("kernel_clamped_fraction", 0.0));
        if (worst > KERNEL_CLAMP_WARNING) {
            char text[200];
            std::snprintf(
                text, sizeof text,
                "%s clamped the filter kernel of %.1f %% of the pixels to pcss_max_kernel: their "
                "penumbrae are narrower than PCSS estimates (raise it with --param pcss_max_kernel=...)",
                method.c_str(), 100.0 * worst);
            warnings.emplace_back(text);
        }
    }
    return warnings;
}

Frame renderFrame(const Scene& scene, const RenderOptions& options) {
    return makeRenderer(scene, options)->render();
}

} // namespace stsv
