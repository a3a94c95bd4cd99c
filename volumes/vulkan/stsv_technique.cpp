// STSV's Vulkan technique (DESIGN §5): its passes for one light, behind VulkanTechnique.
#include "render/vulkan/vulkan_techniques.h"

#include "volumes/vulkan/gpu_stsv_clusters.h"
#include "volumes/vulkan/gpu_stsv_pass.h"

namespace stsv {

namespace {

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
            m_hullPass.emplace(c.device, "volumes/shaders/stsv_hull.comp", hullDefines, triangles, pushFlags,
                               *c.hulls, m_family, std::vector<const Buffer*>{&m_clusters->itemRecords});
            m_hullPasses = {&*m_hullPass};
            m_walk.emplace(
                c.device, "volumes/shaders/stsv_clusters.comp", 5, c.resources, *c.deferred, *c.clusterLists,
                m_family, c.defines,
                std::vector<std::pair<const Buffer*, ResourceUse>>{
                    {&c.hulls->records, ResourceUse::sampledRead(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)},
                    {&m_clusters->itemRecords,
                     ResourceUse::storageRead(VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)}});
        } else {
            if (c.geometry == VolumeGeometry::ComputeHull) c.deferred->use(bitmask);
            m_stsv.emplace(c.device, c.scene, c.options, c.resources, *c.hulls, *c.deferred, m_family,
                           c.geometry);
            // The volumes' draw sets the masks whole (its attachments are cleared as it begins);
            // the walk's merge ORs its bits into masks the frame cleared.
            m_writesSampleMasks = true;
            if (c.geometry != VolumeGeometry::ComputeHull) return;
            m_hullPass.emplace(c.device, "volumes/shaders/stsv_hull.comp", hullDefines, triangles, pushFlags,
                               *c.hulls, m_family);
            m_hullPasses = {&*m_hullPass};
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

    /// The walk and the samples time each part.
    std::uint32_t timedPassesPerLight() const override { return 4 + 2 * (m_c.clusterLists->parts() - 1); }

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

    ListNeeds takeStats(const std::byte* staged) override {
        m_counts = stagedStats<GpuStsvStats>(staged, m_c.scene.lights.size());
        return volumeListNeeds(m_counts, m_samples.has_value());
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

} // namespace

std::unique_ptr<VulkanTechnique> makeStsvVulkanTechnique(const VulkanTechniqueContext& context) {
    return std::make_unique<StsvTechnique>(context);
}

} // namespace stsv
