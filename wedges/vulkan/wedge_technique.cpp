// The wedge family's Vulkan technique (DESIGN §5): DCS's or PW's passes for one light, behind
// VulkanTechnique.
#include "render/vulkan/vulkan_techniques.h"

#include "wedges/adjacency.h"
#include "wedges/layer_bvh_dh.h"
#include "wedges/vulkan/gpu_wedge_passes.h"

namespace stsv {

namespace {

/// D(r)'s pass: for DCS it also marks the pixels whose segments' gaps meet a triangle.
std::vector<ShaderDefine> centerDefines(const VulkanTechniqueContext& c) {
    std::vector<ShaderDefine> defines = c.defines;
    defines.push_back({"DCS_GAP_BLOCKS", c.method.wedges == WedgeVariant::Pw ? "0" : "1"});
    return defines;
}

/// The opaque triangles through DCS or PW (Algorithm 2 lines 4–7): the layer count at the light
/// centre (dcs_center.comp); for DCS with the auto extrusion the cluster pass (dcs_clusters.comp), else the
/// wedge bounds (hulls, mesh-shader hulls or wedge.geom prisms) drawn; for DCS the samples of the
/// (pixel, edge) pairs either listed; DCS then folds D(r) into its counters; PW folds (line 11)
/// after the other techniques of the row.
class WedgeTechnique final : public VulkanTechnique {
  public:
    explicit WedgeTechnique(const VulkanTechniqueContext& c)
        : VulkanTechnique(c, volumeFamilyBindings(WedgeResources::bindings()), sizeof(GpuWedgeStats)), m_c(c),
          m_pw(c.method.wedges == WedgeVariant::Pw), m_resources(c.device, c.scene, c.options),
          m_clearHullDraw({}, {&c.hulls->draw}), m_clearDeferredCount({}, {&c.deferred->count}),
          m_clearDcsBlocks({}, {&m_resources.dcsBlocks}),
          m_center(c.device, m_resources, c.resources, m_family, centerDefines(c),
                   static_cast<std::uint32_t>(c.options.width), static_cast<std::uint32_t>(c.options.height)),
          m_fold(c.device, c.options, m_resources, c.resources, m_family, c.defines) {
        if (!m_pw) {
            // The walk lists each pair with its edge term; the wedge draw lists the pair alone.
            const bool walks = usesWedgeClusters(c.options);
            c.deferred->use(false, walks);
            // The sample loop over listed terms unrolls on the baked sample set (measured there).
            std::vector<ShaderDefine> defines = walks ? c.patternDefines : c.defines;
            defines.push_back({"WEDGE_LISTED_TERMS", walks ? "1" : "0"});
            m_samples.emplace(c.device, c.scene, c.options, m_resources, c.resources, *c.deferred, m_family,
                              defines);
            // The blocks that cast rays: those whose pixels' gaps meet a triangle (dcs_center.comp) and,
            // after the walk, those whose edges outnumber their rays.
            m_rayBlocks.emplace(c.device, c.options, m_resources, c.resources, m_family, c.defines, 0u);
            m_rays.emplace(c.device, c.options, m_resources, c.resources, m_family, c.defines, 1u);
        }
        if (usesWedgeClusters(c.options)) {
            c.clusterLists->use();
            std::vector<ShaderDefine> defines = c.defines;
            defines.push_back({"CLUSTER_KEPT_ENTRIES_PER_INVOCATION",
                               std::to_string(m_resources.clusters().keptPairsPerInvocation()) + "u"});
            defines.push_back(dcsRayEdgesDefine(c.options));
            // Stage 2 adds up each block's kept edges, stage 3 reads them (the blocks that cast rays).
            m_clusters.emplace(c.device, "wedges/shaders/dcs_clusters.comp", 5, c.resources, *c.deferred,
                               *c.clusterLists, m_family, defines,
                               std::vector<std::pair<const Buffer*, ResourceUse>>{
                                   {&m_resources.dcsBlocks,
                                    ResourceUse::storageReadWrite(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)}});
            return;
        }
        m_wedges.emplace(c.device, c.options, m_resources, c.resources, m_family, c.defines, c.geometry,
                         *c.hulls, *c.deferred);
        if (c.geometry == VolumeGeometry::ComputeHull && m_resources.carrierCount() > 0) {
            m_hullPass.emplace(
                c.device, "wedges/shaders/wedge_hull.comp", layoutDefines(c.resources.tables.layout),
                static_cast<std::uint32_t>(m_resources.carrierCount()), 0u, *c.hulls, m_family);
            m_hullPasses = {&*m_hullPass};
        }
    }

    void writeDescriptors() override {
        for (std::size_t l = 0; l < m_family.setCount(); ++l) {
            DescriptorSet& set = m_family.set(l);
            m_c.hulls->writeDescriptors(set);
            m_c.deferred->writeDescriptors(set);
            m_resources.writeDescriptors(set, l, *m_c.clusterLists);
        }
    }
    /// The walk and the samples time each part, the rays' two passes once.
    std::uint32_t timedPassesPerLight() const override { return 7 + 2 * (m_c.clusterLists->parts() - 1); }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        const std::string technique = passName(light, m_pw ? "pw_" : "dcs_");
        if (!m_pw) runPass(recorder, cmd, "", m_clearDcsBlocks, light);
        runPass(recorder, cmd, technique + "center", m_center, light);
        if (m_hullPass) {
            runPass(recorder, cmd, "", m_clearHullDraw, light);
            runPass(recorder, cmd, technique + "wedge_hulls", *m_hullPass, light);
        }
        if (m_samples) runPass(recorder, cmd, "", m_clearDeferredCount, light);
        const std::string samples = technique + "wedge_samples";
        if (m_clusters) {
            const auto& counts = m_resources.clusters().counts();
            m_clusters->record(recorder, cmd, light, light < counts.size() ? counts[light].depth : 0,
                               technique + "clusters", *m_samples, samples);
        }
        if (m_wedges) runPass(recorder, cmd, technique + "wedges", *m_wedges, light);
        if (m_samples && !m_clusters) runPass(recorder, cmd, samples, *m_samples, light);
        if (m_rays) {
            // The blocks that cast rays count their samples through the layer tree.
            runPass(recorder, cmd, technique + "rays", *m_rayBlocks, light);
            runPass(recorder, cmd, technique + "rays", *m_rays, light);
        }
        // DCS's count is clamped at 0 before another technique adds its layers (dcs+stsv), as
        // on the CPU (wedges/cpu/cpu_wedges.cpp dcsCpuSamples).
        if (!m_pw) runPass(recorder, cmd, passName(light, "fold"), m_fold, light);
    }

    void recordCombine(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        // PW's v_coef loses the fraction of the samples the other techniques occlude (pw+stsv).
        if (m_pw) runPass(recorder, cmd, passName(light, "fold"), m_fold, light);
    }

    ListNeeds takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuWedgeStats>(staged, m_c.scene.lights.size());
        // A segment whose count stopped short would leave D(r) too low: no picture then.
        for (std::size_t l = 0; l < m_counts.size(); ++l)
            if (m_counts[l].centerCutShort > 0)
                throw Error(m_c.scene.source + ": light " + std::to_string(l) +
                            ": the layer count at the light centre or at a sample stopped after " +
                            std::to_string(LAYER_BVH_MAX_VISITS) + " tree nodes on " +
                            std::to_string(m_counts[l].centerCutShort) +
                            " segments (lavapipe's loop limit); render with --backend cpu");
        return volumeListNeeds(m_counts, m_samples.has_value());
    }

    void writeStats(const GBuffer& gbuffer, nlohmann::json& stats) const override {
        std::size_t covered = 0;
        for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) covered += gbuffer.covered(i) ? 1 : 0;
        // wedge_samples.comp (DCS) tests every sample of a listed silhouette fragment.
        const std::uint64_t n = std::uint64_t(m_c.options.samples);
        nlohmann::json wedges = nlohmann::json::array();
        for (std::size_t l = 0; l < m_counts.size(); ++l) {
            const GpuWedgeStats& s = m_counts[l];
            nlohmann::json wedge = {{"edges", m_resources.edgeCount()}, {"silhouette_fragments", s.inside}};
            if (m_clusters) {
                // The tree's tables and the walk's (block, node) and (block, edge) tests;
                // "fragments": the bound tests of the (pixel, edge) pairs that reach them, as on
                // the CPU.
                const WedgeClusters::Counts& t = m_resources.clusters().counts()[l];
                wedge["path"] = "clusters";
                wedge["potential_silhouettes"] = t.potentialSilhouettes;
                wedge["clusters"] = t.leaves;
                wedge["cluster_depth"] = t.depth;
                wedge["list_capacity"] = m_c.clusterLists->capacity();
                wedge["parts"] = m_c.clusterLists->parts();
                wedge["bounds"] = t.carriers; // the carriers' bounds uploaded
                wedge["cluster_tests"] = s.walk.tests;
                wedge["clusters_rejected"] = s.walk.rejected;
                wedge["fragments"] = s.fragments;
            } else {
                wedge["path"] = "volumes";
                wedge["fragments"] = s.fragments;
                m_c.hulls->reportCounts(m_c.geometry, l, "wedge", s.hull, wedge);
            }
            if (!m_pw) {
                wedge["listed_fragments"] = s.listed;
                wedge["samples_tested"] = n * s.inside;
                // The walk's blocks that counted their samples through the layer tree (dcs_rays.comp).
                wedge["ray_pixels"] = s.rayPixels;
                wedge["crossing_pixels"] = covered - s.rayPixels;
            }
            // The layer count at the light centre (dcs_center.comp): the tree's nodes, the visits
            // and triangle tests of its segments (the CPU mirror does not count them).
            wedge["center"] = {{"nodes", m_resources.layerNodeCount()},
                               {"node_visits", s.centerVisits},
                               {"triangle_tests", s.centerTests}};
            wedges.push_back(wedge);
        }
        stats["wedges"] = wedges;
    }

  private:
    const VulkanTechniqueContext& m_c;
    bool m_pw;
    WedgeResources m_resources;
    ClearPass m_clearHullDraw;
    ClearPass m_clearDeferredCount;
    ClearPass m_clearDcsBlocks; ///< DCS's blocks' words, before each light
    CenterCountPass m_center;
    FoldPass m_fold;
    std::optional<ClusterWalkPasses> m_clusters; ///< DCS with the auto extrusion: lists the pairs
    std::optional<WedgePass> m_wedges;           ///< else the wedge bounds drawn
    std::optional<WedgeSamplesPass> m_samples;   ///< DCS: the listed (pixel, edge) pairs
    std::optional<HullPass> m_hullPass;          ///< with hulls, when the scene has carriers
    std::optional<DcsRaysPass> m_rayBlocks;      ///< DCS: the blocks that cast rays
    std::optional<DcsRaysPass> m_rays;           ///< and their samples' segments
    std::vector<GpuWedgeStats> m_counts;         ///< per light, after the frame
};

} // namespace

std::unique_ptr<VulkanTechnique> makeWedgesVulkanTechnique(const VulkanTechniqueContext& context) {
    return std::make_unique<WedgeTechnique>(context);
}

} // namespace stsv
