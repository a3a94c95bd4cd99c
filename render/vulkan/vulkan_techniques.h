// The Vulkan side of each family's technique (DESIGN §2): the passes of one family for one light,
// with the resources only they use, behind one small interface. A method's row lists the families
// it composes (MethodInfo::techniques); VulkanFrame records them in that order for every light,
// then lets each combine what the others wrote (the fold), then resolves. The resources the
// families share (G-buffer, light-sample buffers, the hull buffers, the deferred-fragment list)
// belong to the frame.
#pragma once

#include "gpu/pass_recorder.h"
#include "render/frame.h"
#include "render/methods.h"
#include "render/vulkan/gpu_cluster_walk.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_hulls.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace stsv {

class Device;

/// What the techniques of a frame share, constant over the frame's life.
struct VulkanTechniqueContext {
    const Device& device;
    const Scene& scene;
    const RenderOptions& options; ///< the frame's (the sub-pixel grid with --supersample)
    const MethodInfo& method;
    VolumeGeometry geometry;
    FrameResources& resources;
    const FrameDescriptors& descriptors;
    HullResources* hulls;              ///< the volume families' (STSV, wedges); null in a frame without them
    DeferredFragments* deferred;       ///< the volume families'; null in a frame without them
    ClusterLists* clusterLists;        ///< the volume families'; null in a frame without them
    std::vector<ShaderDefine> defines; ///< sampleDefines of the frame
    /// defines with the frame's sample set baked in when it is one set of at most 128 points
    /// (withPatternDefine): for the passes whose sample loops unroll.
    std::vector<ShaderDefine> patternDefines;
};

/// What a technique's lists needed in the frame just run: the frame grows the lists the volume
/// families share (DeferredFragments, ClusterLists) for the most any technique needed.
struct ListNeeds {
    /// The most fragments one list for its sample passes held: one light's draw, or one part of
    /// its walk, past the end too.
    std::uint64_t listedFragments = 0;
    /// The most pairs one of the frame's cluster lists needed in its walk, when more than it held
    /// (else 0).
    std::uint64_t clusterPairs = 0;
};

/// One family's passes on Vulkan: set up once (its set written, its hull passes sized), recorded per
/// light, then after each run of the frame its stats taken and its own lists grown; after the
/// last run, what it reads back and its stats.
class VulkanTechnique {
  public:
    virtual ~VulkanTechnique() = default;
    /// Its set GPU_SET_FAMILY (one per light), pipeline layout and stats buffer.
    const FamilyDescriptors& family() const { return m_family; }
    /// Whether its passes set the light's sample masks whole (else the frame clears them first:
    /// all lit, and passes that OR bits into them see cleared masks).
    bool writesSampleMasks() const { return m_writesSampleMasks; }
    /// Its hull passes, which HullResources::size runs once at start-up.
    const std::vector<const HullPass*>& hullPasses() const { return m_hullPasses; }

    /// Its family sets written for every light: what it owns and the shared buffers it binds
    /// (written again whenever the frame replaces those).
    virtual void writeDescriptors() = 0;
    /// The timed passes it records per light, at most (the frame sizes its timestamp pool, and
    /// sizes it again when the walk takes more parts: the walk and its sample pass time each).
    virtual std::uint32_t timedPassesPerLight() const = 0;
    /// The family's passes for one light.
    virtual void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light) = 0;
    /// After every technique of the row has recorded the light: the passes that combine them.
    virtual void recordCombine(PassRecorder&, VkCommandBuffer, std::size_t /*light*/) {}
    /// After the frame's fence: its stats buffer as the frame left it (family().stats()'s bytes),
    /// and what its lists needed.
    virtual ListNeeds takeStats(const std::byte* staged) = 0;
    /// After takeStats: when lists of its own had too little room for the frame (fragments were
    /// lost), it grows them and returns true; the frame then writes the descriptors again and
    /// runs again.
    virtual bool growLists() { return false; }
    /// After the frame's last run: what it reads back itself (the kept shadow maps).
    virtual void readBack(Frame&) const {}
    /// Its stats over the frame's lights under its family's keys (render/cpu writes the same).
    virtual void writeStats(const GBuffer& gbuffer, nlohmann::json& stats) const = 0;

  protected:
    /// `bindings`: its set's (FamilyDescriptors adds the stats); `statsBytes`: its stats struct.
    VulkanTechnique(const VulkanTechniqueContext& context, std::vector<DescriptorBinding> bindings,
                    std::size_t statsBytes)
        : m_family(context.device, context.descriptors, std::move(bindings), statsBytes) {}

    FamilyDescriptors m_family;
    bool m_writesSampleMasks = false;          ///< set by the constructor of a technique whose passes do
    std::vector<const HullPass*> m_hullPasses; ///< set by the constructor of a technique with hulls
};

/// Each family's technique, made by the family's Vulkan side (volumes/vulkan, wedges/vulkan,
/// shadowmaps/vulkan); the image family's is null in a scene without lights.
std::unique_ptr<VulkanTechnique> makeStsvVulkanTechnique(const VulkanTechniqueContext& context);
std::unique_ptr<VulkanTechnique> makeWedgesVulkanTechnique(const VulkanTechniqueContext& context);
std::unique_ptr<VulkanTechnique> makeShadowMapsVulkanTechnique(const VulkanTechniqueContext& context);

// What the families' techniques share.

/// "light<i>/<name>": a pass's key in the frame's "passes".
inline std::string passName(std::size_t light, const std::string& name) {
    return "light" + std::to_string(light) + "/" + name;
}

/// The bindings a volume family's set shares with the other volume family (gpu_volumes_dh.h),
/// then `own`.
std::vector<DescriptorBinding> volumeFamilyBindings(const std::vector<DescriptorBinding>& own);

/// What a volume family's lists needed, from its stats per light: the most fragments one list held
/// for its sample passes (when it has them) and the most pairs one walk needed.
template <class Stats> ListNeeds volumeListNeeds(const std::vector<Stats>& counts, bool samplePasses) {
    ListNeeds needs;
    for (const Stats& s : counts) {
        if (samplePasses)
            needs.listedFragments = std::max<std::uint64_t>(needs.listedFragments, s.listedPart);
        needs.clusterPairs = std::max<std::uint64_t>(needs.clusterPairs, s.walk.pairsNeeded);
    }
    return needs;
}

/// A family's stats per light, from the bytes of its stats buffer.
template <class Stats> std::vector<Stats> stagedStats(const std::byte* staged, std::size_t lights) {
    std::vector<Stats> stats(lights);
    std::memcpy(stats.data(), staged, lights * sizeof(Stats));
    return stats;
}

/// The row's techniques, in its order. `context` must outlive them.
std::vector<std::unique_ptr<VulkanTechnique>> makeVulkanTechniques(const VulkanTechniqueContext& context);

} // namespace stsv
