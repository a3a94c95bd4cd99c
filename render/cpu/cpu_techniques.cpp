#include "render/cpu/cpu_techniques.h"

#include "core/timer.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu/cpu_shadowmaps.h"
#include "render/cpu/cpu_stsv.h"
#include "render/cpu/cpu_wedges.h"
#include "render/frame.h"
#include "shadowmaps/shadow_fit.h"
#include "shadowmaps/shadow_map_stats.h"
#include "wedges/adjacency.h"

#include <optional>
#include <utility>

namespace stsv {

namespace {

/// The ground truth: Embree shadow rays to every sample.
class TracedTechnique final : public CpuTechnique {
  public:
    explicit TracedTechnique(const CpuTechniqueContext& c) : m_c(c) {}
    void run(CpuLightWork& work) override {
        Timer timer;
        traceReferenceSamples(m_c.embree, work.gbuffer, work.light, m_c.plan, m_c.farDistance, work.samples);
        work.passes[work.pass("reference")] = timer.milliseconds();
    }
    void takeStats(nlohmann::json&) override {}

  private:
    const CpuTechniqueContext& m_c;
};

/// STSV over the row's triangles (all, or the perforated ones), into the light's bits or counters.
class StsvTechnique final : public CpuTechnique {
  public:
    explicit StsvTechnique(const CpuTechniqueContext& c)
        : m_c(c), m_include(stsvFilter(c.scene, c.method.stsv)) {}
    void run(CpuLightWork& work) override {
        const StsvCpuStats s = stsvCpuSamples(m_c.scene, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                                              work.samples, m_include);
        work.passes[work.pass("stsv_bin")] = s.bin_ms;
        work.passes[work.pass("stsv_shade")] = s.shade_ms;
        m_stats.push_back(toJson(s));
    }
    void takeStats(nlohmann::json& stats) override {
        stats["stsv"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    const CpuTechniqueContext& m_c;
    TriangleFilter m_include;
    nlohmann::json m_stats = nlohmann::json::array();
};

/// The opaque triangles through DCS (signed counters added to the light's) or PW (v_coef), and
/// for pw+stsv the fold with the STSV bits of the perforated triangles (STSV paper §3.1).
class WedgeTechnique final : public CpuTechnique {
  public:
    explicit WedgeTechnique(const CpuTechniqueContext& c) : m_c(c), m_occluders(c.scene) {}
    void run(CpuLightWork& work) override {
        Timer timer;
        const bool pw = m_c.method.wedges == WedgeVariant::Pw;
        const bool transmittance = work.samples.kind() == BufferKind::Transmittance;
        // With transmittance, DCS counts into counters of its own, and a sample it finds behind
        // at least one opaque layer is occluded (STSV adds the translucent depths after it).
        std::optional<LightSampleBuffer> counts;
        if (!pw && transmittance)
            counts.emplace(work.samples.width(), work.samples.height(), work.samples.samples(),
                           BufferKind::Counters);
        const WedgeCpuStats s =
            pw ? pwCpuVisibility(m_occluders, work.gbuffer, work.light, m_c.farDistance, work.vcoef)
               : dcsCpuSamples(m_occluders, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                               counts ? *counts : work.samples);
        if (counts)
            for (int y = 0; y < counts->height(); ++y)
                for (int x = 0; x < counts->width(); ++x)
                    for (int k = 0; k < counts->samples(); ++k)
                        if (counts->count(x, y, k) != 0) work.samples.setOccluded(x, y, k);
        work.passes[work.pass(pw ? "pw" : "dcs")] = timer.milliseconds();
        m_stats.push_back(toJson(s));
    }
    void combine(CpuLightWork& work) override {
        // DCS and STSV add to the same counters; PW's v_coef loses the fraction STSV occludes.
        if (m_c.method.wedges != WedgeVariant::Pw || m_c.method.stsv == StsvTriangles::None) return;
        Timer timer;
        pwFoldStsv(work.gbuffer, work.samples, work.vcoef);
        work.passes[work.pass("fold")] = timer.milliseconds();
    }
    void takeStats(nlohmann::json& stats) override {
        stats["wedges"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    const CpuTechniqueContext& m_c;
    WedgeOccluders m_occluders;
    nlohmann::json m_stats = nlohmann::json::array();
};

/// The light-centre map and its filter (v_coef per pixel), or the depth grid marched per light
/// sample (`peel`: the light's bits).
class ShadowMapsTechnique final : public CpuTechnique {
  public:
    explicit ShadowMapsTechnique(const CpuTechniqueContext& c)
        : m_c(c), m_settings(shadowMapSettings(c.options)),
          m_receivers(
              shadowReceiverBounds(c.embree.scene(), float(c.options.width) / float(c.options.height))) {
        if (m_settings.filter == ShadowMapMethod::Peel)
            m_openEdges = buildEdgeAdjacency(c.embree.scene()).openEdges;
    }
    void run(CpuLightWork& work) override {
        if (m_settings.filter == ShadowMapMethod::Peel) return runPeel(work);
        if (readsTransmittanceFunctions(m_settings.filter)) return runAvsm(work);
        ShadowMap* keep = m_c.options.keepShadowMaps ? &work.frame.shadowMaps.emplace_back() : nullptr;
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        const ShadowMapCpuStats s =
            shadowMapCpuVisibility(m_c.embree, work.gbuffer, view, m_settings, m_c.options.seed,
                                   m_c.options.decorrelate, work.vcoef, keep, m_c.options.supersample);
        work.passes[work.pass("shadow_map")] = s.map_ms;
        const bool filtered = isFilteredRepresentation(m_settings.filter);
        if (filtered) work.passes[work.pass("filtered_map")] = s.build_ms;
        if (searchesBlockers(m_settings)) work.passes[work.pass("pcss_blocker")] = s.blocker_ms;
        work.passes[work.pass("shadow_filter")] = s.filter_ms;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        if (filtered) map["representation_bytes"] = s.representationBytes;
        map.update(m_settings.filter == ShadowMapMethod::Pcf
                       ? kernelStrideStats(s.kernelClamped, work.gbuffer)
                       : kernelClampStats(s.kernelClamped, work.gbuffer));
        if (searchesBlockers(m_settings)) map.update(searchClampStats(s.searchClamped, work.gbuffer));
        m_stats.push_back(map);
    }
    void takeStats(nlohmann::json& stats) override {
        stats["shadow_maps"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    void runPeel(CpuLightWork& work) {
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        DepthGrid* keep = m_c.options.keepShadowMaps ? &work.frame.depthGrids.emplace_back() : nullptr;
        const PeelCpuStats s = peelCpuSamples(m_c.embree, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                                              view, m_settings, work.samples, keep);
        work.passes[work.pass("depth_grid")] = s.grid_ms;
        work.passes[work.pass("peel_march")] = s.march_ms;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        map["grid_bytes"] = s.gridBytes;
        map["open_edges"] = m_openEdges;
        map.update(peelMarchStats(s.march));
        m_stats.push_back(map);
    }

    void runAvsm(CpuLightWork& work) {
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        AvsmMap* keep = m_c.options.keepShadowMaps ? &work.frame.avsmMaps.emplace_back() : nullptr;
        const AvsmCpuStats s =
            avsmCpuVisibility(m_c.embree, work.gbuffer, view, m_settings, m_c.options.seed,
                              m_c.options.decorrelate, work.vcoef, keep, m_c.options.supersample);
        work.passes[work.pass("avsm")] = s.map_ms;
        if (m_settings.filter == ShadowMapMethod::Vpcss)
            work.passes[work.pass("vpcss_blocker")] = s.blocker_ms;
        work.passes[work.pass("shadow_filter")] = s.filter_ms;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        map["avsm"] = avsmStatsJson(s.map, s.bytes);
        if (m_settings.filter == ShadowMapMethod::Vpcss) {
            map.update(kernelClampStats(s.kernelClamped, work.gbuffer));
            map.update(searchClampStats(s.searchClamped, work.gbuffer));
        }
        m_stats.push_back(map);
    }

    const CpuTechniqueContext& m_c;
    ShadowMapSettings m_settings;
    /// peel: the scene's edges with one triangle (the grid's closed-object assumption fails there)
    std::size_t m_openEdges = 0;
    Bounds m_receivers; ///< what the camera sees (the view fit's receivers)
    nlohmann::json m_stats = nlohmann::json::array();
};

} // namespace

std::vector<std::unique_ptr<CpuTechnique>> makeCpuTechniques(const CpuTechniqueContext& context) {
    std::vector<std::unique_ptr<CpuTechnique>> techniques;
    for (const TechniqueFamily family : context.method.techniques()) {
        switch (family) {
        case TechniqueFamily::Traced:
            techniques.push_back(std::make_unique<TracedTechnique>(context));
            break;
        case TechniqueFamily::Wedges:
            techniques.push_back(std::make_unique<WedgeTechnique>(context));
            break;
        case TechniqueFamily::Stsv:
            techniques.push_back(std::make_unique<StsvTechnique>(context));
            break;
        case TechniqueFamily::ShadowMaps:
            techniques.push_back(std::make_unique<ShadowMapsTechnique>(context));
            break;
        }
    }
    return techniques;
}

} // namespace stsv
