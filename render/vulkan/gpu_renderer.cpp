#include "render/vulkan/gpu_renderer.h"

#include "core/error.h"
#include "core/timer.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/pass_recorder.h"
#include "gpu/timer.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_gbuffer_pass.h"
#include "render/vulkan/gpu_hulls.h"
#include "render/vulkan/gpu_readback.h"
#include "render/vulkan/gpu_resolve_pass.h"
#include "render/vulkan/vulkan_techniques.h"
#include "scene/camera.h"
#include "volumes/vulkan/gpu_stsv_clusters.h"
#include "wedges/vulkan/gpu_wedge_clusters.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace stsv {

namespace {

/// The families' stats buffers, in the row's order.
std::vector<const Buffer*> statsBuffers(const std::vector<std::unique_ptr<VulkanTechnique>>& techniques) {
    std::vector<const Buffer*> buffers;
    buffers.reserve(techniques.size());
    for (const auto& technique : techniques) buffers.push_back(&technique->family().stats());
    return buffers;
}

/// The clear at the start of a frame: the families' stats, and the sample counters and optical
/// depths the passes add to.
ClearPass countClearPass(const FrameResources& resources, const RenderOptions& options,
                         std::size_t lightCount,
                         const std::vector<std::unique_ptr<VulkanTechnique>>& techniques) {
    std::vector<const Buffer*> buffers = statsBuffers(techniques);
    for (std::size_t l = 0; l < lightCount; ++l) {
        if (frameCountsLayers(options)) buffers.push_back(&resources.samples.counters[l]);
        if (options.buffer == BufferKind::Transmittance) buffers.push_back(&resources.samples.depths[l]);
    }
    return ClearPass({}, buffers);
}

/// Whether the row composes a volume family (STSV, wedges): those share the hull buffers and the
/// deferred-fragment list, which a frame without them does not allocate.
bool drawsVolumes(const MethodInfo& method) {
    for (const TechniqueFamily family : method.techniques())
        if (family == TechniqueFamily::Stsv || family == TechniqueFamily::Wedges) return true;
    return false;
}

std::optional<HullResources> hullResourcesFor(const Device& device, const MethodInfo& method) {
    if (!drawsVolumes(method)) return std::nullopt;
    return std::optional<HullResources>(std::in_place, device);
}

std::optional<ClusterLists> clusterListsFor(const Device& device, const RenderOptions& options,
                                            std::uint64_t listLimit) {
    if (!drawsVolumes(methodInfo(options.method))) return std::nullopt;
    return std::optional<ClusterLists>(std::in_place, device, options, listLimit);
}

std::optional<DeferredFragments> deferredFragmentsFor(const Device& device, const RenderOptions& options,
                                                      std::uint64_t capacity, std::uint64_t limit) {
    if (!drawsVolumes(methodInfo(options.method))) return std::nullopt;
    return std::optional<DeferredFragments>(std::in_place, device, options, capacity, limit);
}

/// What builds the frame's volumes, for its stats: the cluster walk where the auto extrusion takes
/// it (STSV, DCS), the volume stage for what still draws (PW, or every family with another
/// extrusion).
std::string extrusionLabel(const RenderOptions& options, const MethodInfo& method, VolumeGeometry geometry) {
    const bool stsvWalks = method.stsv != StsvTriangles::None && usesStsvClusters(options);
    const bool dcsWalks = usesWedgeClusters(options);
    if (!stsvWalks && !dcsWalks) return toString(geometry);
    const bool draws = method.wedges == WedgeVariant::Pw;
    return draws ? std::string("cluster walk, pw: ") + toString(geometry) : std::string("cluster walk");
}

/// Timed passes of a frame besides the lights': the G-buffer, the ambient of a frame without
/// lights, the copy into the staging buffer.
constexpr std::uint32_t FRAME_TIMED_PASSES = 3;

/// One frame of one method on the GPU: allocates the resources every family shares, builds the
/// row's techniques, orders them per light (STSV paper Algorithm 2), reads back and writes the
/// stats. Barriers come from the passes' declared accesses (gpu/pass_recorder.h).
class VulkanFrame {
  public:
    /// `deferredCapacity`: the fragments the STSV hull draw and the DCS wedge draw may list for
    /// their sample passes at first (the list grows when a frame needs more).
    /// `clusterListLimit`, `deferredLimit`: VulkanRendererConfig's.
    VulkanFrame(const Device& device, const Scene& scene, const RenderOptions& options,
                VolumeGeometry geometry, std::uint64_t deferredCapacity, std::uint64_t clusterListLimit,
                std::uint64_t deferredLimit);
    Frame render(double startupMs);

  private:
    const Device& m_device;
    const Scene& m_scene;
    RenderOptions m_options;
    const MethodInfo& m_method;
    VolumeGeometry m_geometry;
    SamplePlan m_plan;
    FrameResources m_resources;
    std::optional<HullResources> m_hulls;        ///< with a volume family
    std::optional<DeferredFragments> m_deferred; ///< with a volume family
    std::optional<ClusterLists> m_clusterLists;  ///< with a volume family
    FrameDescriptors m_descriptors;
    VulkanTechniqueContext m_context;
    std::vector<std::unique_ptr<VulkanTechnique>> m_techniques;
    bool m_techniquesWriteMasks;
    ClearPass m_clearCounts;
    GBufferPass m_gbuffer;
    ResolvePass m_resolve;
    FrameReadback m_readback;
    GpuTimer m_timer;
    PassRecorder m_recorder;
    CommandBuffer m_commands;

    void writeDescriptors();
    void record(VkCommandBuffer cmd);
    void recordLight(VkCommandBuffer cmd, std::size_t light);
    std::uint32_t timedPasses() const;
};

VulkanFrame::VulkanFrame(const Device& device, const Scene& scene, const RenderOptions& options,
                         VolumeGeometry geometry, std::uint64_t deferredCapacity,
                         std::uint64_t clusterListLimit, std::uint64_t deferredLimit)
    : m_device(device), m_scene(scene), m_options(options), m_method(methodInfo(options.method)),
      m_geometry(geometry), m_plan(samplePlanOf(options)), m_resources(device, scene, options, m_plan),
      m_hulls(hullResourcesFor(device, m_method)),
      m_deferred(deferredFragmentsFor(device, options, deferredCapacity, deferredLimit)),
      m_clusterLists(clusterListsFor(device, options, clusterListLimit)),
      m_descriptors(device, m_resources.bindings(), std::max<std::size_t>(scene.lights.size(), 1)),
      m_context{device,
                scene,
                m_options,
                m_method,
                geometry,
                m_resources,
                m_descriptors,
                m_hulls ? &*m_hulls : nullptr,
                m_deferred ? &*m_deferred : nullptr,
                m_clusterLists ? &*m_clusterLists : nullptr,
                sampleDefines(options, m_resources.tables.layout),
                withPatternDefine(sampleDefines(options, m_resources.tables.layout), m_plan)},
      m_techniques(makeVulkanTechniques(m_context)),
      m_techniquesWriteMasks(std::any_of(m_techniques.begin(), m_techniques.end(),
                                         [](const auto& t) { return t->writesSampleMasks(); })),
      m_clearCounts(countClearPass(m_resources, options, scene.lights.size(), m_techniques)),
      m_gbuffer(device, m_resources, m_descriptors, layoutDefines(m_resources.tables.layout),
                static_cast<std::uint32_t>(scene.triangleCount())),
      m_resolve(device, scene, options, m_plan, m_resources, m_descriptors),
      m_readback(device, scene, options, m_resources, statsBuffers(m_techniques)),
      m_timer(device, timedPasses()), m_recorder(m_timer), m_commands(device) {
    writeDescriptors();
    std::vector<const HullPass*> hullPasses;
    for (const auto& technique : m_techniques)
        hullPasses.insert(hullPasses.end(), technique->hullPasses().begin(), technique->hullPasses().end());
    if (!hullPasses.empty()) {
        m_hulls->size(m_recorder, m_commands, scene.lights.size(), hullPasses);
        writeDescriptors();
    }
}

std::uint32_t VulkanFrame::timedPasses() const {
    std::uint32_t perLight = 1; // the resolve
    for (const auto& technique : m_techniques) perLight += technique->timedPassesPerLight();
    return FRAME_TIMED_PASSES + perLight * static_cast<std::uint32_t>(m_scene.lights.size());
}

/// Every light's frame set, then each technique's family sets.
void VulkanFrame::writeDescriptors() {
    for (std::size_t l = 0; l < m_descriptors.setCount(); ++l)
        m_resources.writeDescriptors(m_descriptors.set(l), l);
    for (const auto& technique : m_techniques) technique->writeDescriptors();
    m_resolve.writeDescriptors();
}

void VulkanFrame::record(VkCommandBuffer cmd) {
    m_timer.reset(cmd);
    runPass(m_recorder, cmd, "", m_clearCounts);
    // Pass 0: G-buffer (ambient is written by the first resolve).
    runPass(m_recorder, cmd, "gbuffer", m_gbuffer);
    for (std::size_t l = 0; l < m_scene.lights.size(); ++l) recordLight(cmd, l);
    if (m_scene.lights.empty()) runPass(m_recorder, cmd, "ambient", m_resolve, ResolvePass::AMBIENT_ONLY);
    runPass(m_recorder, cmd, "copy", m_readback);
    m_recorder.addPass(cmd, "", m_readback.hostAccesses(), [](VkCommandBuffer) {});
}

/// Algorithm 2 for one light: the row's techniques in its order, then what combines them (the
/// fold), then the resolve. Masks no technique writes are cleared: every sample lit.
void VulkanFrame::recordLight(VkCommandBuffer cmd, std::size_t light) {
    if (!m_techniquesWriteMasks) {
        std::vector<Image*> masks;
        for (Image& image : m_resources.samples.masks[light]) masks.push_back(&image);
        if (!masks.empty()) runPass(m_recorder, cmd, "", ClearPass(masks, {}), light);
    }
    for (const auto& technique : m_techniques) technique->record(m_recorder, cmd, light);
    for (const auto& technique : m_techniques) technique->recordCombine(m_recorder, cmd, light);
    runPass(m_recorder, cmd, "light" + std::to_string(light) + "/resolve", m_resolve, light);
}

Frame VulkanFrame::render(double startupMs) {
    Timer total;
    Frame frame;
    double gpuMs = 0.0;
    nlohmann::json passes = nlohmann::json::object();
    Timer readback;
    for (;;) {
        frame = Frame{};
        record(m_commands.begin());
        Timer gpu;
        m_commands.submitAndWait();
        gpuMs = gpu.milliseconds();
        passes = nlohmann::json::object();
        // A pass timed once a part of the walk adds up.
        for (const GpuTiming& t : m_timer.results())
            passes[t.name] = passes.value(t.name, 0.0) + t.milliseconds;
        readback = Timer();
        m_readback.unpack(frame);
        ListNeeds needs;
        for (std::size_t i = 0; i < m_techniques.size(); ++i) {
            const ListNeeds n = m_techniques[i]->takeStats(m_readback.stagedStats(i));
            needs.listedFragments = std::max(needs.listedFragments, n.listedFragments);
            needs.clusterPairs = std::max(needs.clusterPairs, n.clusterPairs);
        }
        // A fragment a list had no room for is lost: the list grows and the frame runs again.
        const std::uint64_t listed = needs.listedFragments;
        // Past what the list holds, a walk takes its tiles in more parts, each part's fragments
        // sampled before the next lists its own (the walks list every deferred fragment when one
        // does: the auto extrusion).
        bool grown = false, split = false;
        if (m_deferred && listed > m_deferred->maxCapacity() && m_clusterLists && m_clusterLists->used()) {
            m_clusterLists->splitFor(listed, m_deferred->maxCapacity());
            m_deferred->growFor(m_deferred->maxCapacity());
            grown = split = true;
        } else {
            grown = m_deferred && m_deferred->growFor(listed);
        }
        // The cluster lists are shared: they grow once, for the most any walk needed (after a
        // split, the next frame's parts tell anew).
        grown = (!split && m_clusterLists && m_clusterLists->growFor(needs.clusterPairs)) || grown;
        for (const auto& technique : m_techniques) grown = technique->growLists() || grown;
        if (!grown) break;
        writeDescriptors();
        // More parts time more passes.
        if (timedPasses() > m_timer.maxScopes()) m_timer = GpuTimer(m_device, timedPasses());
    }
    for (const auto& technique : m_techniques) technique->readBack(frame);
    passes["readback"] = readback.milliseconds();

    frame.stats = nlohmann::json::object();
    if (!m_scene.lights.empty())
        for (const auto& technique : m_techniques) technique->writeStats(frame.gbuffer, frame.stats);
    frame.stats["options"] = toJson(m_options);
    frame.stats["scene"] = sceneStats(m_scene);
    frame.stats.update(methodSceneNotes(m_scene, m_method));
    frame.stats["startup_ms"] = startupMs;
    frame.stats["frame_ms"] = total.milliseconds();
    frame.stats["gpu_ms"] = gpuMs;
    frame.stats["passes"] = passes;
    frame.stats["light_sample_buffer_bytes"] = lightSampleBufferBytes(m_options);
    frame.stats["gpu"] = {{"device", m_device.info().name},
                          {"driver", m_device.info().driverName + " (" + m_device.info().driverInfo + ")"},
                          {"extrusion", extrusionLabel(m_options, m_method, m_geometry)},
                          {"fragment_counts", "atomic counters in the volume passes' shaders"}};
    return frame;
}

} // namespace

std::vector<ExtrusionStage> offeredExtrusions(const DeviceInfo& info) {
    std::vector<ExtrusionStage> stages = {ExtrusionStage::Hull};
    if (info.geometryShader) stages.push_back(ExtrusionStage::Geometry);
    if (info.meshShader && info.taskShader) stages.push_back(ExtrusionStage::Mesh);
    return stages;
}

std::size_t lightSampleBufferBytes(const RenderOptions& options) {
    return LightSampleBuffer::payloadBytes(options.width, options.height, options.samples, options.buffer);
}

float gpuNearPlane(const Scene& scene) {
    const Bounds box = scene.bounds();
    const float reach = length(box.center() - scene.camera.eye) + 0.5f * length(box.extent());
    return std::max(GPU_NEAR_FRACTION * reach, 1e-30f);
}

mat4 gpuClipFromWorld(const Scene& scene, int width, int height) {
    return clipFromViewReversedInfinite(scene.camera, float(width) / float(height), gpuNearPlane(scene)) *
           viewFromWorld(scene.camera);
}

struct VulkanRenderer::Impl {
    std::unique_ptr<Device> ownDevice;
    Device* device = nullptr;
    VolumeGeometry geometry = VolumeGeometry::ComputeHull;
    std::unique_ptr<VulkanFrame> frame;
    RenderOptions requestedOptions; ///< as asked: the frame renders the sub-pixel grid
    double startupMs = 0.0;

    Impl(const Scene& scene, const RenderOptions& requested, const VulkanRendererConfig& config) {
        Timer startup;
        validate(requested);
        requestedOptions = requested;
        const RenderOptions options = frameOptions(requested);
        if (config.device) {
            device = config.device;
        } else {
            DeviceOptions deviceOptions;
            deviceOptions.select = options.device;
            deviceOptions.validation = options.validation;
            deviceOptions.printValidation = options.validation;
            ownDevice = std::make_unique<Device>(deviceOptions);
            device = ownDevice.get();
        }
        const DeviceInfo& info = device->info();
        if (!info.depthClamp || !info.logicOp || !info.fragmentStoresAndAtomics)
            throw UsageError(
                "Vulkan device " + info.name +
                " lacks depth clamp, logic op or fragment stores/atomics needed by the STSV pass");
        const ExtrusionStage stage = options.extrusion; // the one source: --extrusion
        const std::vector<ExtrusionStage> offered = offeredExtrusions(info);
        if (stage != ExtrusionStage::Auto &&
            std::find(offered.begin(), offered.end(), stage) == offered.end())
            throw UsageError("Vulkan device " + info.name + " lacks " +
                             (stage == ExtrusionStage::Mesh ? "VK_EXT_mesh_shader" : "geometry shaders") +
                             " (--extrusion " + toString(stage) + ")");
        geometry = stage == ExtrusionStage::Mesh       ? VolumeGeometry::MeshShaderHull
                   : stage == ExtrusionStage::Geometry ? VolumeGeometry::GeometryShaderPrism
                                                       : VolumeGeometry::ComputeHull;
        const std::uint64_t deferred =
            config.deferredCapacity > 0
                ? config.deferredCapacity
                : initialDeferredFragments(std::uint64_t(options.width) * std::uint64_t(options.height));
        frame = std::make_unique<VulkanFrame>(*device, scene, options, geometry, deferred,
                                              config.clusterListLimit, config.deferredLimit);
        startupMs = startup.milliseconds();
    }
};

VulkanRenderer::VulkanRenderer(const Scene& scene, const RenderOptions& options,
                               const VulkanRendererConfig& config)
    : m_impl(std::make_unique<Impl>(scene, options, config)) {}

VulkanRenderer::~VulkanRenderer() {
    if (m_impl && m_impl->device) m_impl->device->waitIdle();
}

Frame VulkanRenderer::render() {
    Frame frame = m_impl->frame->render(m_impl->startupMs);
    resolveSupersampling(frame, m_impl->requestedOptions);
    return frame;
}

const Device& VulkanRenderer::device() const {
    return *m_impl->device;
}

bool VulkanRenderer::usesMeshShader() const {
    return m_impl->geometry == VolumeGeometry::MeshShaderHull;
}

} // namespace stsv
