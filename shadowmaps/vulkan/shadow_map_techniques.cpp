// The image family's Vulkan techniques (DESIGN §5): a depth map and its filter, the depth grid,
// or transmittance functions, for one light, behind VulkanTechnique.
#include "render/vulkan/vulkan_techniques.h"

#include "shadowmaps/filtered_map.h"
#include "shadowmaps/kept_maps.h"
#include "shadowmaps/shadow_map_stats.h"
#include "shadowmaps/vulkan/gpu_shadowmap_passes.h"
#include "wedges/adjacency.h"

namespace stsv {

namespace {

/// The filter pass's step for a row's filter.
ShadowFilterPass::Step filterStep(ShadowMapMethod f) {
    if (isFilteredRepresentation(f)) return ShadowFilterPass::FilteredLookup;
    return filtersFixedDepthKernel(f) ? ShadowFilterPass::DepthKernel : ShadowFilterPass::PcssFilter;
}

/// What the image-based techniques share: each light's maps and views (ShadowMapResources) in
/// their family set, their stats, and per light the view's stats with what the technique adds.
class ShadowMapsTechnique : public VulkanTechnique {
  public:
    void writeDescriptors() override {
        for (std::size_t l = 0; l < m_family.setCount(); ++l) m_maps.writeDescriptors(m_family.set(l), l);
    }
    ListNeeds takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuShadowMapStats>(staged, m_c.scene.lights.size());
        return {}; // its lists (AVSM's fragments) are its own: growLists
    }
    void writeStats(const GBuffer& gbuffer, nlohmann::json& stats) const override {
        nlohmann::json maps = nlohmann::json::array();
        for (std::size_t l = 0; l < m_counts.size(); ++l) {
            nlohmann::json map =
                shadowMapViewStats(m_maps.view(l), m_maps.settings(), m_c.scene.camera, gbuffer);
            addStats(l, gbuffer, map);
            maps.push_back(map);
        }
        stats["shadow_maps"] = maps;
    }

  protected:
    explicit ShadowMapsTechnique(const VulkanTechniqueContext& c)
        : VulkanTechnique(c, ShadowMapResources::bindings(c.method.shadowMap), sizeof(GpuShadowMapStats)),
          m_c(c), m_maps(c.device, c.scene, c.options) {}
    /// Light `light`'s stats beyond its view's.
    virtual void addStats(std::size_t light, const GBuffer& gbuffer, nlohmann::json& map) const = 0;

    const VulkanTechniqueContext& m_c;
    ShadowMapResources m_maps;
    std::vector<GpuShadowMapStats> m_counts; ///< per light, after the frame
};

/// The image-based baselines: per light the cleared map, its raster, then PCF, PCSS's two steps,
/// or a filtered representation (built, then looked up over a fixed kernel or one sized by PCSS's
/// blocker search) into the v_coef image.
class DepthMapTechnique final : public ShadowMapsTechnique {
  public:
    explicit DepthMapTechnique(const VulkanTechniqueContext& c)
        : ShadowMapsTechnique(c), m_map(c.device, c.scene, m_maps, m_family, c.defines),
          m_filter(c.device, c.options, filterStep(c.method.shadowMap), m_maps, c.resources, m_family,
                   c.defines) {
        for (const Buffer& depth : m_maps.depth) m_clear.push_back(ClearPass({}, {&depth}));
        const bool filtered = isFilteredRepresentation(c.method.shadowMap);
        if (filtered) m_filtered.emplace(c.device, m_maps, m_family, c.defines);
        if (searchesBlockers(m_maps.settings()))
            m_blocker.emplace(c.device, c.options, ShadowFilterPass::PcssBlocker, m_maps, c.resources,
                              m_family, c.defines);
    }

    std::uint32_t timedPassesPerLight() const override { return 4; }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        runPass(recorder, cmd, "", m_clear[light], light);
        runPass(recorder, cmd, passName(light, "shadow_map"), m_map, light);
        if (m_filtered) runPass(recorder, cmd, passName(light, "filtered_map"), *m_filtered, light);
        if (m_blocker) runPass(recorder, cmd, passName(light, "pcss_blocker"), *m_blocker, light);
        runPass(recorder, cmd, passName(light, "shadow_filter"), m_filter, light);
    }

    void readBack(Frame& frame) const override {
        if (!m_c.options.keepShadowMaps) return;
        for (std::size_t l = 0; l < m_c.scene.lights.size(); ++l)
            keepMapsIn(frame.keptMaps).shadowMaps.push_back(m_maps.download(l));
    }

  private:
    void addStats(std::size_t light, const GBuffer& gbuffer, nlohmann::json& map) const override {
        const std::uint64_t kernels = m_counts[light].kernelClamped;
        map.update(filtersFixedDepthKernel(m_c.method.shadowMap) ? kernelStrideStats(kernels, gbuffer)
                                                                 : kernelClampStats(kernels, gbuffer));
        if (m_blocker) map.update(searchClampStats(m_counts[light].searchClamped, gbuffer));
        if (m_filtered) map["representation_bytes"] = filteredMapBytes(m_maps.view(light), m_maps.settings());
    }

    std::vector<ClearPass> m_clear; ///< [light]
    ShadowMapPass m_map;
    std::optional<FilteredMapPass> m_filtered; ///< the filtered representations
    std::optional<ShadowFilterPass> m_blocker; ///< PCSS, and filtered maps with fm_kernel=1
    ShadowFilterPass m_filter;
};

/// `peel`: per light the cleared depth grid, its two draws, and the march of every sample's ray
/// into the light's bits (or counters).
class DepthGridTechnique final : public ShadowMapsTechnique {
  public:
    explicit DepthGridTechnique(const VulkanTechniqueContext& c)
        : ShadowMapsTechnique(c), m_grid(c.device, c.scene, m_maps, m_family, c.defines),
          m_march(c.device, c.options, m_maps, c.resources, m_family, c.defines),
          m_openEdges(buildEdgeAdjacency(c.scene).openEdges) {
        for (const Buffer& grid : m_maps.grid) m_clear.push_back(ClearPass({}, {&grid}));
    }

    std::uint32_t timedPassesPerLight() const override { return 2; }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        runPass(recorder, cmd, "", m_clear[light], light);
        runPass(recorder, cmd, passName(light, "depth_grid"), m_grid, light);
        runPass(recorder, cmd, passName(light, "peel_march"), m_march, light);
    }

    void readBack(Frame& frame) const override {
        if (!m_c.options.keepShadowMaps) return;
        for (std::size_t l = 0; l < m_c.scene.lights.size(); ++l)
            keepMapsIn(frame.keptMaps).depthGrids.push_back(m_maps.downloadGrid(l));
    }

  private:
    void addStats(std::size_t light, const GBuffer& gbuffer, nlohmann::json& map) const override {
        map["grid_bytes"] = depthGridBytes(m_maps.view(light), m_maps.settings());
        map["open_edges"] = m_openEdges;
        const GpuShadowMapStats& s = m_counts[light];
        std::uint64_t covered = 0;
        for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) covered += gbuffer.covered(i) ? 1 : 0;
        PeelMarchCounts march;
        march.rays = covered * std::uint64_t(m_c.options.samples);
        march.steps = (std::uint64_t(s.peelStepsHigh) << 32) | s.peelStepsLow;
        march.capped = s.peelCapped;
        march.longest = s.peelLongest;
        march.maxSteps = std::uint32_t(m_maps.settings().peelMaxSteps);
        map.update(peelMarchStats(march));
    }

    std::vector<ClearPass> m_clear; ///< [light]
    DepthGridPass m_grid;
    PeelMarchPass m_march;
    std::size_t m_openEdges; ///< the scene's edges with one triangle (not closed there)
};

/// `avsm` and `vpcss`: per light the cleared list heads, the fragment lists, the transmittance
/// functions built from them, then avsm's lookup, or vpcss's blocker search and filter, into the
/// v_coef image.
class AvsmTechnique final : public ShadowMapsTechnique {
  public:
    explicit AvsmTechnique(const VulkanTechniqueContext& c)
        : ShadowMapsTechnique(c), m_lists(c.device, c.scene, m_maps, m_family, c.defines),
          m_build(c.device, m_maps, m_family, c.defines),
          m_filter(c.device, c.options,
                   vpcss() ? ShadowFilterPass::VpcssFilter : ShadowFilterPass::AvsmLookup, m_maps,
                   c.resources, m_family, c.defines) {
        for (const Buffer& heads : m_maps.avsmHeads) m_clear.push_back(ClearPass({}, {&heads}));
        if (vpcss())
            m_blocker.emplace(c.device, c.options, ShadowFilterPass::VpcssBlocker, m_maps, c.resources,
                              m_family, c.defines);
    }

    std::uint32_t timedPassesPerLight() const override { return 4; }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        runPass(recorder, cmd, "", m_clear[light], light);
        runPass(recorder, cmd, passName(light, "avsm_fragments"), m_lists, light);
        runPass(recorder, cmd, passName(light, "avsm_build"), m_build, light);
        if (m_blocker) runPass(recorder, cmd, passName(light, "vpcss_blocker"), *m_blocker, light);
        runPass(recorder, cmd, passName(light, "shadow_filter"), m_filter, light);
    }

    bool growLists() override {
        std::uint64_t listed = 0;
        for (const GpuShadowMapStats& s : m_counts) {
            // Lost fragments with a count that fits: the 32-bit count wrapped.
            if (s.avsmLost != 0 && s.avsmFragments <= m_maps.avsmCapacity())
                throw UsageError(
                    "the transmittance functions' fragment lists need more than 2^32 fragments for "
                    "one light: lower avsm_size");
            listed = std::max<std::uint64_t>(listed, s.avsmFragments);
        }
        return m_maps.growAvsmFragments(listed);
    }

    void readBack(Frame& frame) const override {
        if (!m_c.options.keepShadowMaps) return;
        for (std::size_t l = 0; l < m_c.scene.lights.size(); ++l)
            keepMapsIn(frame.keptMaps).avsmMaps.push_back(m_maps.downloadAvsm(l));
    }

  private:
    void addStats(std::size_t light, const GBuffer& gbuffer, nlohmann::json& map) const override {
        const ShadowMapView& view = m_maps.view(light);
        const GpuShadowMapStats& counts = m_counts[light];
        AvsmStats functions;
        functions.texels = std::size_t(view.faces) * view.size * view.size;
        functions.texelsWithNodes = counts.avsmTexels;
        functions.meanNodes =
            counts.avsmTexels > 0 ? double(counts.avsmNodes) / double(counts.avsmTexels) : 0.0;
        functions.maxNodes = counts.avsmMaxNodes;
        functions.overflowedTexels = counts.avsmOverflowed;
        map["avsm"] = avsmStatsJson(functions, avsmBytes(view, m_maps.settings()));
        map["avsm"]["fragments_listed"] = counts.avsmFragments;
        map["avsm"]["fragment_capacity"] = m_maps.avsmCapacity();
        if (vpcss()) {
            map.update(kernelClampStats(counts.kernelClamped, gbuffer));
            map.update(searchClampStats(counts.searchClamped, gbuffer));
        }
    }
    bool vpcss() const { return m_c.method.shadowMap == ShadowMapMethod::Vpcss; }

    std::vector<ClearPass> m_clear; ///< [light]: the list heads
    AvsmListPass m_lists;
    AvsmBuildPass m_build;
    std::optional<ShadowFilterPass> m_blocker; ///< vpcss
    ShadowFilterPass m_filter;
};

} // namespace

std::unique_ptr<VulkanTechnique> makeShadowMapsVulkanTechnique(const VulkanTechniqueContext& context) {
    if (context.scene.lights.empty()) return nullptr;
    if (context.method.shadowMap == ShadowMapMethod::Peel)
        return std::make_unique<DepthGridTechnique>(context);
    if (readsTransmittanceFunctions(context.method.shadowMap))
        return std::make_unique<AvsmTechnique>(context);
    return std::make_unique<DepthMapTechnique>(context);
}

} // namespace stsv
