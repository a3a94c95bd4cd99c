#include "render/vulkan/vulkan_techniques.h"

#include "shadowmaps/filtered_map.h"
#include "shadowmaps/shadow_map_stats.h"
#include "wedges/adjacency.h"
#include "wedges/layer_bvh_dh.h"

#include "render/vulkan/gpu_shadowmap_passes.h"
#include "render/vulkan/gpu_stsv_clusters.h"
#include "render/vulkan/gpu_wedge_passes.h"
#include "shadowmaps/filtered_map.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>

namespace stsv {

namespace {

std::string passName(std::size_t light, const std::string& name) {
    return "light" + std::to_string(light) + "/" + name;
}

/// The bindings a volume family's set shares with the other volume family (gpu_volumes_dh.h),
/// then `own`.
std::vector<DescriptorBinding> volumeFamilyBindings(std::vector<DescriptorBinding> own) {
    std::vector<DescriptorBinding> bindings = HullResources::bindings();
    for (const DescriptorBinding& b : DeferredFragments::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : ClusterLists::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : own) bindings.push_back(b);
    return bindings;
}

/// The most fragments one list held for a sample pass: one light's draw, or one part of its walk
/// (a volume family's stats).
template <class Stats> std::uint64_t mostListed(const std::vector<Stats>& counts) {
    std::uint64_t listed = 0;
    for (const Stats& s : counts) listed = std::max<std::uint64_t>(listed, s.listedPart);
    return listed;
}

/// A family's stats per light, from the bytes of its stats buffer.
template <class Stats> std::vector<Stats> stagedStats(const std::byte* staged, std::size_t lights) {
    std::vector<Stats> stats(lights);
    std::memcpy(stats.data(), staged, lights * sizeof(Stats));
    return stats;
}

/// Whether the frame draws STSV volumes: the row sends triangles through STSV and the scene has
/// some of them (Algorithm 2).
bool drawsStsv(StsvTriangles which, const Scene& scene) {
    if (which == StsvTriangles::All) return true;
    if (which == StsvTriangles::None) return false;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t)
        if (!scene.opaqueOccluder(t)) return true;
    return false;
}

/// STSV over the row's triangles (Algorithm 2 lines 8–10): with the auto extrusion the volumes'
/// records built by a compute pass and the cluster walk over the triangles' tree
/// (stsv_clusters.comp), else the volumes' hulls built by a compute pass and drawn; their listed
/// fragments' samples and, for bits, the merge into the masks; or the prisms of the geometry
/// shader or the hulls of the mesh shader, whose fragments test the samples. Without S-triangles
/// in the scene it records nothing, and the frame clears the masks (every sample lit).
class StsvTechnique final : public VulkanTechnique {
  public:
    explicit StsvTechnique(const VulkanTechniqueContext& c)
        : VulkanTechnique(c,
                          volumeFamilyBindings({{GPU_BINDING_STSV_MASK_WORDS,
                                                 VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
                                                StsvClusters::bindings()[0]}),
                          sizeof(GpuStsvStats)),
          m_c(c), m_clearHullDraw({}, {&c.hulls->draw}),
          m_clearDeferred({}, {&c.deferred->count, &c.deferred->maskWords}),
          m_itemRecordsStandIn(c.device, sizeof(uint), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               MemoryUsage::DeviceLocal) {
        if (c.scene.lights.empty() || !drawsStsv(c.method.stsv, c.scene)) return;
        const bool bitmask = c.options.buffer != BufferKind::Counters; // occlusion bits
        const bool walks = usesStsvClusters(c.options);
        const std::uint32_t pushFlags =
            c.method.stsv == StsvTriangles::Perforated ? GPU_PUSH_PERFORATED_ONLY : 0u;
        const auto triangles = static_cast<std::uint32_t>(c.scene.triangleCount());
        std::vector<ShaderDefine> hullDefines = layoutDefines(c.resources.tables.layout);
        if (walks) {
            c.deferred->use(bitmask);
            c.clusterLists->use();
            m_clusters.emplace(c.device, c.scene, c.method.stsv);
            m_clearItemRecords.emplace(std::vector<Image*>{},
                                       std::vector<const Buffer*>{&m_clusters->itemRecords});
            hullDefines.push_back({"STSV_HULL_RECORDS_ONLY", "1"});
            m_hullPass.emplace(c.device, "stsv/stsv_hull.comp", hullDefines, triangles, pushFlags, *c.hulls,
                               m_family, std::vector<const Buffer*>{&m_clusters->itemRecords});
            m_walk.emplace(
                c.device, "stsv/stsv_clusters.comp", 5, c.resources, *c.deferred, *c.clusterLists, m_family,
                c.defines,
                std::vector<std::pair<const Buffer*, ResourceUse>>{
                    {&c.hulls->records, ResourceUse::sampledRead(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)},
                    {&m_clusters->itemRecords,
                     ResourceUse::storageRead(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)}});
        } else {
            if (c.geometry == VolumeGeometry::ComputeHull) c.deferred->use(bitmask);
            m_stsv.emplace(c.device, c.scene, c.options, c.resources, *c.hulls, *c.deferred, m_family,
                           c.geometry);
            if (c.geometry != VolumeGeometry::ComputeHull) return;
            m_hullPass.emplace(c.device, "stsv/stsv_hull.comp", hullDefines, triangles, pushFlags, *c.hulls,
                               m_family);
        }
        m_samples.emplace(c.device, c.scene, c.options, c.resources, *c.hulls, *c.deferred, m_family);
        if (bitmask) m_merge.emplace(c.device, c.options, c.resources, *c.deferred, m_family);
    }

    void writeDescriptors() override {
        for (std::size_t l = 0; l < m_family.setCount(); ++l) {
            DescriptorSet& set = m_family.set(l);
            m_c.hulls->writeDescriptors(set);
            m_c.deferred->writeDescriptors(set);
            set.writeBuffer(GPU_BINDING_STSV_MASK_WORDS, m_c.deferred->maskWords);
            if (m_clusters) {
                m_clusters->writeDescriptors(set, *m_c.clusterLists);
            } else {
                m_c.clusterLists->writeDescriptors(set, nullptr);
                set.writeBuffer(GPU_BINDING_STSV_ITEM_RECORDS, m_itemRecordsStandIn);
            }
        }
    }

    /// The volumes' draw sets the masks whole (its attachments are cleared as it begins); the
    /// walk's merge ORs its bits into masks the frame cleared.
    bool writesSampleMasks() const override { return m_stsv.has_value(); }
    /// The walk and the samples time each part.
    std::uint32_t timedPassesPerLight() const override { return 4 + 2 * (m_c.clusterLists->parts() - 1); }
    std::vector<const HullPass*> hullPasses() const override {
        if (!m_hullPass) return {};
        return {&*m_hullPass};
    }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        if (!m_stsv && !m_walk) return;
        if (m_hullPass) {
            runPass(recorder, cmd, "", m_clearHullDraw, light);
            if (m_clearItemRecords) runPass(recorder, cmd, "", *m_clearItemRecords, light);
            runPass(recorder, cmd, passName(light, m_walk ? "stsv_volumes" : "stsv_hulls"), *m_hullPass,
                    light);
        }
        if (m_samples) runPass(recorder, cmd, "", m_clearDeferred, light);
        const std::string samples = passName(light, "stsv_samples");
        if (m_walk) // the mask words add up over the walk's parts until the merge
            m_walk->record(recorder, cmd, light, m_clusters->depth(), passName(light, "stsv_clusters"),
                           *m_samples, samples);
        if (m_stsv) runPass(recorder, cmd, passName(light, "stsv"), *m_stsv, light);
        if (m_samples && !m_walk) runPass(recorder, cmd, samples, *m_samples, light);
        if (m_merge) runPass(recorder, cmd, passName(light, "stsv_merge"), *m_merge, light);
    }

    void takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuStsvStats>(staged, m_c.scene.lights.size());
    }

    std::uint64_t listedFragments() const override { return m_samples ? mostListed(m_counts) : 0; }

    std::uint64_t clusterPairsNeeded() const override {
        std::uint64_t needed = 0;
        for (const GpuStsvStats& s : m_counts) needed = std::max<std::uint64_t>(needed, s.walk.pairsNeeded);
        return needed;
    }

    void writeStats(const GBuffer&, nlohmann::json& stats) const override {
        // stsv.frag and stsv_samples.comp test every sample of a fragment inside its volume.
        const std::uint64_t n = std::uint64_t(m_c.options.samples);
        nlohmann::json lights = nlohmann::json::array();
        for (std::size_t l = 0; l < m_counts.size(); ++l) {
            const GpuStsvStats& s = m_counts[l];
            nlohmann::json light = {
                {"fragments", s.fragments}, {"inside_fragments", s.inside}, {"samples_tested", n * s.inside}};
            if (m_walk) {
                // The walk's (block, node) and (block, triangle) tests; "fragments": the
                // (pixel, volume) plane tests of the candidates (the (block, volume) pairs whose
                // volume the block's box does not miss), as the CPU's pixel tests.
                m_c.hulls->checkCapacity(l, "STSV", s.hull.volumes, 0);
                light["path"] = "clusters";
                light["volumes"] = s.hull.volumes;
                light["clusters"] = m_clusters->leaves();
                light["cluster_depth"] = m_clusters->depth();
                light["cluster_tests"] = s.walk.tests;
                light["clusters_rejected"] = s.walk.rejected;
                light["list_capacity"] = m_c.clusterLists->capacity();
                light["parts"] = m_c.clusterLists->parts();
            } else {
                light["path"] = "volumes";
                m_c.hulls->reportCounts(m_c.geometry, l, "STSV", s.hull, light);
            }
            if (m_samples) {
                light["listed_fragments"] = s.listed;
                light["deferred_fragments"] = s.deferred;
            }
            lights.push_back(light);
        }
        stats["stsv"] = lights;
    }

  private:
    const VulkanTechniqueContext& m_c;
    ClearPass m_clearHullDraw;
    ClearPass m_clearDeferred;
    Buffer m_itemRecordsStandIn;                 ///< the item table's binding without the walk
    std::optional<StsvClusters> m_clusters;      ///< with the walk
    std::optional<ClearPass> m_clearItemRecords; ///< with the walk
    std::optional<HullPass> m_hullPass;          ///< with the walk (records only) or the hulls
    std::optional<ClusterWalkPasses> m_walk;     ///< with the auto extrusion
    std::optional<StsvPass> m_stsv;              ///< the volumes drawn
    std::optional<StsvSamplesPass> m_samples;    ///< with the walk or the hulls: the listed fragments
    std::optional<StsvMergePass> m_merge;        ///< with m_samples in a bitmask frame
    std::vector<GpuStsvStats> m_counts;          ///< per light, after the frame
};

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
          m_center(c.device, m_resources, c.resources, m_family, c.defines,
                   static_cast<std::uint32_t>(c.options.width), static_cast<std::uint32_t>(c.options.height)),
          m_fold(c.device, c.options, m_resources, c.resources, m_family, c.defines) {
        if (!m_pw) {
            // The walk lists each pair with its edge term; the wedge draw lists the pair alone.
            const bool walks = usesWedgeClusters(c.options);
            c.deferred->use(false, walks);
            // The sample loop over listed terms unrolls on the baked sample set (measured there).
            std::vector<ShaderDefine> defines = walks ? c.patternDefines : c.defines;
            defines.push_back({"WEDGE_LISTED_TERMS", walks ? "1" : "0"});
            m_samples.emplace(c.device, c.scene, c.options, c.resources, *c.deferred, m_family, defines);
        }
        if (usesWedgeClusters(c.options)) {
            c.clusterLists->use();
            std::vector<ShaderDefine> defines = c.defines;
            defines.push_back({"CLUSTER_KEPT_ENTRIES_PER_INVOCATION",
                               std::to_string(m_resources.clusters().keptPairsPerInvocation()) + "u"});
            m_clusters.emplace(c.device, "wedges/dcs_clusters.comp", 5, c.resources, *c.deferred,
                               *c.clusterLists, m_family, defines);
            return;
        }
        m_wedges.emplace(c.device, c.options, m_resources, c.resources, m_family, c.defines, c.geometry,
                         *c.hulls, *c.deferred);
        if (c.geometry == VolumeGeometry::ComputeHull && m_resources.carrierCount() > 0)
            m_hullPass.emplace(c.device, "wedges/wedge_hull.comp", layoutDefines(c.resources.tables.layout),
                               static_cast<std::uint32_t>(m_resources.carrierCount()), 0u, *c.hulls,
                               m_family);
    }

    void writeDescriptors() override {
        for (std::size_t l = 0; l < m_family.setCount(); ++l) {
            DescriptorSet& set = m_family.set(l);
            m_c.hulls->writeDescriptors(set);
            m_c.deferred->writeDescriptors(set);
            m_resources.writeDescriptors(set, l, *m_c.clusterLists);
        }
    }
    /// The walk and the samples time each part.
    std::uint32_t timedPassesPerLight() const override { return 5 + 2 * (m_c.clusterLists->parts() - 1); }
    std::vector<const HullPass*> hullPasses() const override {
        if (!m_hullPass) return {};
        return {&*m_hullPass};
    }

    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        const std::string technique = passName(light, m_pw ? "pw_" : "dcs_");
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
        // DCS's count is clamped at 0 before another technique adds its layers (dcs+stsv), as
        // on the CPU (render/cpu/cpu_wedges.cpp dcsCpuSamples).
        if (!m_pw) runPass(recorder, cmd, passName(light, "fold"), m_fold, light);
    }

    void recordCombine(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) override {
        // PW's v_coef loses the fraction of the samples the other techniques occlude (pw+stsv).
        if (m_pw) runPass(recorder, cmd, passName(light, "fold"), m_fold, light);
    }

    void takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuWedgeStats>(staged, m_c.scene.lights.size());
        // A segment whose count stopped short would leave D(r) too low: no picture then.
        for (std::size_t l = 0; l < m_counts.size(); ++l)
            if (m_counts[l].centerCutShort > 0)
                throw Error(m_c.scene.source + ": light " + std::to_string(l) +
                            ": the layer count at the light centre stopped after " +
                            std::to_string(LAYER_BVH_MAX_VISITS) + " tree nodes on " +
                            std::to_string(m_counts[l].centerCutShort) +
                            " pixels' segments (lavapipe's loop limit); render with --backend cpu");
    }

    std::uint64_t listedFragments() const override { return m_samples ? mostListed(m_counts) : 0; }

    std::uint64_t clusterPairsNeeded() const override {
        std::uint64_t needed = 0;
        for (const GpuWedgeStats& s : m_counts) needed = std::max<std::uint64_t>(needed, s.walk.pairsNeeded);
        return needed;
    }

    void writeStats(const GBuffer&, nlohmann::json& stats) const override {
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
    CenterCountPass m_center;
    FoldPass m_fold;
    std::optional<ClusterWalkPasses> m_clusters; ///< DCS with the auto extrusion: lists the pairs
    std::optional<WedgePass> m_wedges;           ///< else the wedge bounds drawn
    std::optional<WedgeSamplesPass> m_samples;   ///< DCS: the listed (pixel, edge) pairs
    std::optional<HullPass> m_hullPass;          ///< with hulls, when the scene has carriers
    std::vector<GpuWedgeStats> m_counts;         ///< per light, after the frame
};

/// The filter pass's step for a row's filter.
ShadowFilterPass::Step filterStep(ShadowMapMethod f) {
    if (f == ShadowMapMethod::Pcss) return ShadowFilterPass::PcssFilter;
    return isFilteredRepresentation(f) ? ShadowFilterPass::FilteredLookup : ShadowFilterPass::Pcf;
}

/// What the image-based techniques share: each light's maps and views (ShadowMapResources) in
/// their family set, their stats, and per light the view's stats with what the technique adds.
class ShadowMapsTechnique : public VulkanTechnique {
  public:
    void writeDescriptors() override {
        for (std::size_t l = 0; l < m_family.setCount(); ++l) m_maps.writeDescriptors(m_family.set(l), l);
    }
    void takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuShadowMapStats>(staged, m_c.scene.lights.size());
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
            frame.shadowMaps.push_back(m_maps.download(l));
    }

  private:
    void addStats(std::size_t light, const GBuffer& gbuffer, nlohmann::json& map) const override {
        const std::uint64_t kernels = m_counts[light].kernelClamped;
        map.update(m_c.method.shadowMap == ShadowMapMethod::Pcf ? kernelStrideStats(kernels, gbuffer)
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
            frame.depthGrids.push_back(m_maps.downloadGrid(l));
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
            frame.avsmMaps.push_back(m_maps.downloadAvsm(l));
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

std::vector<std::unique_ptr<VulkanTechnique>> makeVulkanTechniques(const VulkanTechniqueContext& context) {
    std::vector<std::unique_ptr<VulkanTechnique>> techniques;
    for (const TechniqueFamily family : context.method.techniques()) {
        switch (family) {
        case TechniqueFamily::Traced:
            throw UsageError(context.method.name + " has no Vulkan technique (its rays run on the CPU)");
        case TechniqueFamily::Wedges:
            techniques.push_back(std::make_unique<WedgeTechnique>(context));
            break;
        case TechniqueFamily::Stsv:
            techniques.push_back(std::make_unique<StsvTechnique>(context));
            break;
        case TechniqueFamily::ShadowMaps:
            if (context.scene.lights.empty()) break;
            if (context.method.shadowMap == ShadowMapMethod::Peel)
                techniques.push_back(std::make_unique<DepthGridTechnique>(context));
            else if (readsTransmittanceFunctions(context.method.shadowMap))
                techniques.push_back(std::make_unique<AvsmTechnique>(context));
            else
                techniques.push_back(std::make_unique<DepthMapTechnique>(context));
            break;
        }
    }
    return techniques;
}

} // namespace stsv
