#include "render/gpu_renderer.h"

#include "render/cpu_shadowmaps.h"

#include "core/error.h"
#include "core/timer.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/pass_recorder.h"
#include "gpu/timer.h"
#include "render/gpu_frame_resources.h"
#include "render/gpu_gbuffer_pass.h"
#include "render/gpu_hulls.h"
#include "render/gpu_opaque_passes.h"
#include "render/gpu_readback.h"
#include "render/gpu_resolve_pass.h"
#include "render/gpu_shadowmap_passes.h"
#include "render/gpu_stsv_pass.h"
#include "scene/camera.h"

#include <algorithm>
#include <optional>
#include <string>

namespace stsv {

namespace {

/// Whether the frame draws STSV volumes: the method sends triangles through STSV and the scene
/// has some of them (Algorithm 2).
bool drawsStsv(StsvTriangles which, const Scene& scene) {
    if (which == StsvTriangles::All) return true;
    if (which == StsvTriangles::None) return false;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t)
        if (scene.perforated(t)) return true;
    return false;
}

std::vector<DescriptorBinding> frameBindings(const FrameResources& resources) {
    std::vector<DescriptorBinding> bindings = resources.bindings();
    for (const DescriptorBinding& b : OpaqueOccluderResources::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : ShadowMapResources::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : HullResources::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : DeferredFragments::bindings()) bindings.push_back(b);
    return bindings;
}

/// The clear at the start of a frame: the fragment statistics, and the sample counters the
/// passes of a counters frame add to.
ClearPass countClearPass(const FrameResources& resources, const RenderOptions& options,
                         std::size_t lightCount) {
    std::vector<const Buffer*> buffers{&resources.stats};
    if (options.buffer == BufferKind::Counters)
        for (std::size_t l = 0; l < lightCount; ++l) buffers.push_back(&resources.samples.counters[l]);
    return ClearPass({}, buffers);
}

/// The passes of a method with an opaque technique (MethodInfo::opaque): Algorithm 2 lines
/// 4–7 (centre count and wedges) and 11 (the fold, after the STSV pass).
struct OpaquePasses {
    ClearPass clearCenter;
    CenterCountPass center;
    WedgePass wedges;
    FoldPass fold;
    std::optional<WedgeSamplesPass> wedgeSamples; ///< DCS: the listed silhouette fragments
};

/// The passes of an image-based method (MethodInfo::shadowMap): per light the cleared map, its
/// raster, and PCF or PCSS's two steps.
struct ShadowMapPasses {
    std::vector<ClearPass> clear; ///< [light]
    ShadowMapPass map;
    std::optional<ShadowFilterPass> blocker; ///< PCSS
    ShadowFilterPass filter;
};

/// One frame of one method on the GPU: allocates the shared resources, builds the passes the
/// method's table row composes, orders them per light (STSV paper Algorithm 2), reads back and
/// writes the stats. Barriers come from the passes' declared accesses (gpu/pass_recorder.h).
class VulkanFrame {
  public:
    /// `deferredCapacity`: the fragments the STSV hull draw and the DCS wedge draw may list for
    /// their sample passes (the list grows when a frame needs more).
    VulkanFrame(const Device& device, const Scene& scene, const RenderOptions& options, StsvGeometry geometry,
                std::uint64_t deferredCapacity);
    Frame render(double startupMs);

  private:
    const Device& m_device;
    const Scene& m_scene;
    RenderOptions m_options;
    const MethodInfo& m_method;
    StsvGeometry m_geometry;
    SamplePlan m_plan;
    FrameResources m_resources;
    OpaqueOccluderResources m_opaqueResources;
    ShadowMapResources m_shadowResources;
    HullResources m_hullResources;
    DeferredFragments m_deferredResources;
    FrameDescriptors m_descriptors;
    ClearPass m_clearCounts;
    ClearPass m_clearHullDraw;
    ClearPass m_clearDeferred;
    ClearPass m_clearDeferredCount;
    GBufferPass m_gbuffer;
    std::optional<OpaquePasses> m_opaque;
    std::optional<StsvPass> m_stsv;               ///< when the method draws STSV volumes in this scene
    std::optional<HullPass> m_stsvHulls;          ///< when m_stsv draws hulls
    std::optional<HullPass> m_wedgeHulls;         ///< when the wedge pass draws hulls
    std::optional<StsvSamplesPass> m_stsvSamples; ///< with m_stsvHulls: the deferred fragments
    std::optional<StsvMergePass> m_stsvMerge;     ///< with m_stsvSamples in a bitmask frame
    std::optional<ShadowMapPasses> m_shadowMaps;
    ResolvePass m_resolve;
    FrameReadback m_readback;
    GpuTimer m_timer;
    PassRecorder m_recorder;
    CommandBuffer m_commands;

    void record(VkCommandBuffer cmd);
    void recordLight(VkCommandBuffer cmd, std::size_t light);
    void sizeHulls();
    bool growDeferredList(const std::vector<GpuStats>& counts);
    void checkHullCapacity(std::size_t light, const char* pass, std::uint64_t volumes,
                           std::uint64_t triangles) const;
    nlohmann::json passStats(const std::vector<GpuStats>& counts, const GBuffer& gbuffer) const;
};

VulkanFrame::VulkanFrame(const Device& device, const Scene& scene, const RenderOptions& options,
                         StsvGeometry geometry, std::uint64_t deferredCapacity)
    : m_device(device), m_scene(scene), m_options(options), m_method(methodInfo(options.method)),
      m_geometry(geometry), m_plan(samplePlanOf(options)), m_resources(device, scene, options, m_plan),
      m_opaqueResources(device, scene, options), m_shadowResources(device, scene, options),
      m_hullResources(device),
      m_deferredResources(device, options,
                          (geometry == StsvGeometry::Hull && drawsStsv(m_method.stsv, scene)) ||
                                  m_method.opaque == OpaqueTechnique::Dcs
                              ? deferredCapacity
                              : 0,
                          geometry == StsvGeometry::Hull && drawsStsv(m_method.stsv, scene) &&
                              options.buffer == BufferKind::Bitmask),
      m_descriptors(device, frameBindings(m_resources), std::max<std::size_t>(scene.lights.size(), 1)),
      m_clearCounts(countClearPass(m_resources, options, scene.lights.size())),
      m_clearHullDraw({}, {&m_hullResources.draw}),
      m_clearDeferred({}, {&m_deferredResources.count, &m_deferredResources.maskWords}),
      m_clearDeferredCount({}, {&m_deferredResources.count}),
      m_gbuffer(device, m_resources, m_descriptors, layoutDefines(m_resources.tables.layout),
                static_cast<std::uint32_t>(scene.triangleCount())),
      m_resolve(device, scene, options, m_plan, m_resources, m_descriptors),
      m_readback(device, scene, options, m_resources),
      m_timer(device, 3 + 10 * static_cast<std::uint32_t>(scene.lights.size())), m_recorder(m_timer),
      m_commands(device) {
    const std::vector<ShaderDefine> defines = sampleDefines(options, m_resources.tables.layout);
    const bool hulls = geometry == StsvGeometry::Hull;
    if (m_method.opaque != OpaqueTechnique::None) {
        m_opaque.emplace(OpaquePasses{
            ClearPass({&m_opaqueResources.center}, {}),
            CenterCountPass(device, scene, m_opaqueResources, m_resources, m_descriptors, defines),
            WedgePass(device, options, m_opaqueResources, m_resources, m_descriptors, defines,
                      hulls ? &m_hullResources : nullptr, m_deferredResources),
            FoldPass(device, options, m_opaqueResources, m_resources, m_descriptors, defines), std::nullopt});
        if (m_method.opaque == OpaqueTechnique::Dcs)
            m_opaque->wedgeSamples.emplace(device, m_resources, m_deferredResources, m_descriptors, defines);
        if (hulls && m_opaqueResources.carrierCount() > 0)
            m_wedgeHulls.emplace(device, "wedge_hull.comp", layoutDefines(m_resources.tables.layout),
                                 static_cast<std::uint32_t>(m_opaqueResources.carrierCount()), 0u,
                                 m_resources, m_hullResources, m_descriptors);
    }
    if (scene.lights.size() > 0 && drawsStsv(m_method.stsv, scene)) {
        m_stsv.emplace(device, scene, options, m_resources, m_hullResources, m_deferredResources,
                       m_descriptors, geometry);
        if (hulls) {
            m_stsvSamples.emplace(device, scene, options, m_resources, m_hullResources, m_deferredResources,
                                  m_descriptors);
            if (options.buffer == BufferKind::Bitmask)
                m_stsvMerge.emplace(device, options, m_resources, m_deferredResources, m_descriptors);
            m_stsvHulls.emplace(device, "stsv_hull.comp", layoutDefines(m_resources.tables.layout),
                                static_cast<std::uint32_t>(scene.triangleCount()),
                                m_method.stsv == StsvTriangles::Perforated ? GPU_PUSH_PERFORATED_ONLY : 0u,
                                m_resources, m_hullResources, m_descriptors);
        }
    }
    if (m_shadowResources.enabled()) {
        const bool pcss = m_method.shadowMap == ShadowFilter::Pcss;
        std::vector<ClearPass> clears;
        for (const Buffer& depth : m_shadowResources.depth) clears.push_back(ClearPass({}, {&depth}));
        m_shadowMaps.emplace(ShadowMapPasses{
            std::move(clears), ShadowMapPass(device, scene, m_shadowResources, m_descriptors, defines),
            std::nullopt,
            ShadowFilterPass(device, options, pcss ? ShadowFilterPass::PcssFilter : ShadowFilterPass::Pcf,
                             m_shadowResources, m_resources, m_descriptors, defines)});
        if (pcss)
            m_shadowMaps->blocker.emplace(device, options, ShadowFilterPass::PcssBlocker, m_shadowResources,
                                          m_resources, m_descriptors, defines);
    }
    for (std::size_t l = 0; l < m_descriptors.setCount(); ++l) {
        m_resources.writeDescriptors(m_descriptors.set(l), l);
        m_opaqueResources.writeDescriptors(m_descriptors.set(l));
        m_shadowResources.writeDescriptors(m_descriptors.set(l), l);
        m_hullResources.writeDescriptors(m_descriptors.set(l));
        m_deferredResources.writeDescriptors(m_descriptors.set(l));
    }
    if (m_stsvHulls || m_wedgeHulls) sizeHulls();
}

/// The hull passes once per light into 1-element buffers: they count every volume and triangle
/// while writing none, and the buffers get exactly the largest pass's needs (the passes are
/// deterministic: every frame appends the same counts).
void VulkanFrame::sizeHulls() {
    VkCommandBuffer cmd = m_commands.begin();
    runPass(m_recorder, cmd, "", m_clearCounts);
    for (std::size_t l = 0; l < m_scene.lights.size(); ++l)
        for (const std::optional<HullPass>* pass : {&m_wedgeHulls, &m_stsvHulls}) {
            if (!*pass) continue;
            runPass(m_recorder, cmd, "", m_clearHullDraw, l);
            runPass(m_recorder, cmd, "", **pass, l);
        }
    PassAccesses host;
    host.use(m_resources.stats, ResourceUse::hostRead());
    m_recorder.addPass(cmd, "", host, [](VkCommandBuffer) {});
    m_commands.submitAndWait();
    std::uint64_t volumes = 0, triangles = 0;
    for (const GpuStats& s : m_resources.stats.download<GpuStats>(m_scene.lights.size())) {
        volumes = std::max<std::uint64_t>({volumes, s.hullVolumes, s.wedgeHulls});
        triangles = std::max<std::uint64_t>({triangles, s.hullTriangles, s.wedgeHullTriangles});
    }
    m_hullResources.resize(volumes, triangles);
    for (std::size_t l = 0; l < m_descriptors.setCount(); ++l)
        m_hullResources.writeDescriptors(m_descriptors.set(l));
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

/// Algorithm 2 for one light: the opaque triangles through the method's technique, the
/// S-triangles through STSV (or only a cleared buffer), the fold of the two, the resolve. An
/// image-based method renders the light's map and filters it into v_coef instead.
void VulkanFrame::recordLight(VkCommandBuffer cmd, std::size_t light) {
    const std::string prefix = "light" + std::to_string(light) + "/";
    if (m_shadowMaps) {
        runPass(m_recorder, cmd, "", m_shadowMaps->clear[light], light);
        runPass(m_recorder, cmd, prefix + "shadow_map", m_shadowMaps->map, light);
        if (m_shadowMaps->blocker)
            runPass(m_recorder, cmd, prefix + "pcss_blocker", *m_shadowMaps->blocker, light);
        runPass(m_recorder, cmd, prefix + "shadow_filter", m_shadowMaps->filter, light);
    }
    if (m_opaque) {
        const std::string technique = prefix + (m_method.opaque == OpaqueTechnique::Pw ? "pw_" : "dcs_");
        runPass(m_recorder, cmd, "", m_opaque->clearCenter, light);
        runPass(m_recorder, cmd, technique + "center", m_opaque->center, light);
        if (m_wedgeHulls) {
            runPass(m_recorder, cmd, "", m_clearHullDraw, light);
            runPass(m_recorder, cmd, technique + "wedge_hulls", *m_wedgeHulls, light);
        }
        if (m_opaque->wedgeSamples) runPass(m_recorder, cmd, "", m_clearDeferredCount, light);
        runPass(m_recorder, cmd, technique + "wedges", m_opaque->wedges, light);
        if (m_opaque->wedgeSamples)
            runPass(m_recorder, cmd, technique + "wedge_samples", *m_opaque->wedgeSamples, light);
    }
    std::vector<Image*> masks;
    for (Image& image : m_resources.samples.masks[light]) masks.push_back(&image);
    if (m_stsvHulls) {
        runPass(m_recorder, cmd, "", m_clearHullDraw, light);
        runPass(m_recorder, cmd, prefix + "stsv_hulls", *m_stsvHulls, light);
    }
    if (m_stsv) {
        if (m_stsvSamples) runPass(m_recorder, cmd, "", m_clearDeferred, light);
        runPass(m_recorder, cmd, prefix + "stsv", *m_stsv, light);
        if (m_stsvSamples) runPass(m_recorder, cmd, prefix + "stsv_samples", *m_stsvSamples, light);
        if (m_stsvMerge) runPass(m_recorder, cmd, prefix + "stsv_merge", *m_stsvMerge, light);
    } else if (!masks.empty()) { // no STSV volumes: every sample lit
        runPass(m_recorder, cmd, "", ClearPass(masks, {}), light);
    }
    if (m_opaque) runPass(m_recorder, cmd, prefix + "fold", m_opaque->fold, light);
    runPass(m_recorder, cmd, prefix + "resolve", m_resolve, light);
}

/// The STSV hull draw and the DCS wedge draw list their fragments, and one the list had no room
/// for is lost: the list grows to what the frame needed (a quarter more) and the frame is
/// rendered again.
bool VulkanFrame::growDeferredList(const std::vector<GpuStats>& counts) {
    std::uint64_t listed = 0;
    for (std::size_t l = 0; l < m_scene.lights.size(); ++l)
        listed = std::max<std::uint64_t>({listed, counts[l].listed, counts[l].wedgeListed});
    if (listed <= m_deferredResources.capacity()) return false;
    if (listed > kMaxDeferredFragments)
        throw Error("a volume pass lists " + std::to_string(listed) +
                    " fragments for one light, more than the " + std::to_string(kMaxDeferredFragments) +
                    " its list may hold; render a smaller --size");
    m_deferredResources.resize(std::min(listed + listed / 4, kMaxDeferredFragments));
    for (std::size_t l = 0; l < m_descriptors.setCount(); ++l)
        m_deferredResources.writeDescriptors(m_descriptors.set(l));
    return true;
}

Frame VulkanFrame::render(double startupMs) {
    Timer total;
    Frame frame;
    std::vector<GpuStats> counts;
    double gpuMs = 0.0;
    nlohmann::json passes = nlohmann::json::object();
    Timer readback;
    do {
        frame = Frame{};
        record(m_commands.begin());
        Timer gpu;
        m_commands.submitAndWait();
        gpuMs = gpu.milliseconds();
        passes = nlohmann::json::object();
        for (const GpuTiming& t : m_timer.results()) passes[t.name] = t.milliseconds;
        readback = Timer();
        counts = m_readback.unpack(frame);
    } while (growDeferredList(counts));
    if (m_shadowMaps && m_options.keepShadowMaps)
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l)
            frame.shadowMaps.push_back(m_shadowResources.download(l));
    passes["readback"] = readback.milliseconds();

    frame.stats = passStats(counts, frame.gbuffer);
    frame.stats["options"] = toJson(m_options);
    frame.stats["scene"] = sceneStats(m_scene);
    frame.stats.update(methodSceneNotes(m_scene, m_method));
    frame.stats["startup_ms"] = startupMs;
    frame.stats["frame_ms"] = total.milliseconds();
    frame.stats["gpu_ms"] = gpuMs;
    frame.stats["passes"] = passes;
    frame.stats["light_sample_buffer_bytes"] = lightSampleBufferBytes(m_options);
    frame.stats["gpu"] = {{"device", m_device.info().name},
                          {"extrusion", toString(m_geometry)},
                          {"fragment_counts", "atomic counters in the volume passes' shaders"}};
    return frame;
}

/// A hull pass writes nothing past the buffers sized at start-up; a frame that needed more is
/// wrong, so it is an error, not a picture.
void VulkanFrame::checkHullCapacity(std::size_t light, const char* pass, std::uint64_t volumes,
                                    std::uint64_t triangles) const {
    if (volumes > m_hullResources.recordCapacity() || triangles > m_hullResources.triangleCapacity())
        throw Error("internal error: light " + std::to_string(light) + "'s " + pass + " hulls (" +
                    std::to_string(volumes) + " volumes, " + std::to_string(triangles) +
                    " triangles) outgrew the buffers sized at start-up");
}

/// Per light: "stsv" for methods that run STSV, "wedges" and "center" for methods with an opaque
/// technique, "shadow_maps" for image-based methods.
nlohmann::json VulkanFrame::passStats(const std::vector<GpuStats>& counts, const GBuffer& gbuffer) const {
    if (m_method.shadowMap != ShadowFilter::None) {
        nlohmann::json maps = nlohmann::json::array();
        for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
            const ShadowMapView& view = m_shadowResources.view(l);
            nlohmann::json map = {{"faces", view.faces},
                                  {"texels", std::size_t(view.faces) * view.size * view.size}};
            map.update(kernelClampStats(counts[l].kernelClamped, gbuffer));
            maps.push_back(map);
        }
        return {{"shadow_maps", maps}};
    }
    nlohmann::json stsvStats = nlohmann::json::array();
    nlohmann::json wedgeStats = nlohmann::json::array();
    nlohmann::json centerStats = nlohmann::json::array();
    // The sample loops of stsv.frag and wedge_samples.comp (DCS) test every sample of a fragment
    // that gets that far, so the samples tested are those fragments times N.
    const std::uint64_t n = std::uint64_t(m_options.samples);
    const bool dcs = m_method.opaque == OpaqueTechnique::Dcs;
    for (std::size_t l = 0; l < m_scene.lights.size(); ++l) {
        nlohmann::json stsv = {{"fragments", counts[l].fragments},
                               {"inside_fragments", counts[l].inside},
                               {"samples_tested", n * counts[l].inside}};
        if (m_stsvHulls) {
            checkHullCapacity(l, "STSV", counts[l].hullVolumes, counts[l].hullTriangles);
            stsv["hull_volumes"] = counts[l].hullVolumes;
            stsv["hull_triangles"] = counts[l].hullTriangles;
            stsv["listed_fragments"] = counts[l].listed;
            stsv["deferred_fragments"] = counts[l].deferred;
        }
        stsvStats.push_back(stsv);
        nlohmann::json wedge = {{"edges", m_opaqueResources.edgeCount()},
                                {"fragments", counts[l].wedgeFragments},
                                {"silhouette_fragments", counts[l].wedgeInside}};
        if (dcs) {
            wedge["listed_fragments"] = counts[l].wedgeListed;
            wedge["samples_tested"] = n * counts[l].wedgeInside;
        }
        if (m_wedgeHulls) {
            checkHullCapacity(l, "wedge", counts[l].wedgeHulls, counts[l].wedgeHullTriangles);
            wedge["hull_volumes"] = counts[l].wedgeHulls;
            wedge["hull_triangles"] = counts[l].wedgeHullTriangles;
        }
        wedgeStats.push_back(wedge);
        centerStats.push_back(
            {{"fragments", counts[l].centerFragments}, {"counted_fragments", counts[l].centerCounted}});
    }
    // A family the method does not run writes nothing (its counters would read zero).
    nlohmann::json stats = nlohmann::json::object();
    if (m_method.stsv != StsvTriangles::None) stats["stsv"] = stsvStats;
    if (m_opaque) {
        stats["wedges"] = wedgeStats;
        stats["center"] = centerStats;
    }
    return stats;
}

} // namespace

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
    StsvGeometry geometry = StsvGeometry::Hull;
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
        const ExtrusionStage stage =
            config.extrusion != ExtrusionStage::Auto ? config.extrusion : options.extrusion;
        if (stage == ExtrusionStage::Mesh && !info.meshShader)
            throw UsageError("Vulkan device " + info.name +
                             " lacks VK_EXT_mesh_shader (mesh-shader STSV extrusion)");
        if (stage == ExtrusionStage::Geometry && !info.geometryShader)
            throw UsageError("Vulkan device " + info.name + " lacks geometry shaders (--extrusion geometry)");
        geometry = stage == ExtrusionStage::Mesh       ? StsvGeometry::MeshShaderPrism
                   : stage == ExtrusionStage::Geometry ? StsvGeometry::GeometryShaderPrism
                                                       : StsvGeometry::Hull;
        // Room for two listed fragments a pixel (foliage with 16 k S-triangles lists 1.5 a
        // pixel), at most kMaxDeferredFragments; a frame that lists more grows the list and runs
        // again.
        const std::uint64_t deferred =
            config.deferredCapacity > 0
                ? config.deferredCapacity
                : std::min<std::uint64_t>(2ull * std::uint64_t(options.width) * std::uint64_t(options.height),
                                          kMaxDeferredFragments);
        frame = std::make_unique<VulkanFrame>(*device, scene, options, geometry, deferred);
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
    return m_impl->geometry == StsvGeometry::MeshShaderPrism;
}

} // namespace stsv
