#include "shadowmaps/vulkan/gpu_shadowmap_passes.h"

#include "core/error.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"
#include "render/options.h"
#include "render/vulkan/gpu_deferred.h"
#include "shadowmaps/filtered_lookup.h"
#include "shadowmaps/filtered_map.h"
#include "shadowmaps/shadow_fit.h"

#include <algorithm>
#include <bit>
#include <cstdint>

#include <cstring>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

} // namespace

std::vector<DescriptorBinding> ShadowMapResources::bindings(ShadowMapMethod filter) {
    std::vector<DescriptorBinding> b = {
        {GPU_BINDING_SHADOW_MAP, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_SHADOW_VIEWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_SHADOW_TAPS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
    if (readsTransmittanceFunctions(filter)) {
        b.push_back({GPU_BINDING_AVSM_HEADS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1});
        b.push_back({GPU_BINDING_AVSM_LISTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1});
    }
    return b;
}

namespace {

/// A buffer reached by device address from the shaders: the row's representation beside the
/// depth map, `bytes` of it, which `what` names in the errors.
Buffer representationBuffer(const Device& device, std::size_t bytes, const std::string& what,
                            const std::string& lower) {
    if (!device.info().shaderInt64 || !device.info().bufferDeviceAddress)
        throw UsageError(what +
                         " on Vulkan needs 64-bit integers in shaders and buffer device addresses, which " +
                         device.info().name + " lacks: use --backend cpu");
    if (bytes > device.info().maxMemoryAllocationSize)
        throw UsageError(what + " needs " + std::to_string(bytes >> 20) +
                         " MiB, more than one allocation of " + device.info().name + " may hold (" +
                         std::to_string(device.info().maxMemoryAllocationSize >> 20) + " MiB): " + lower);
    return Buffer(device, bytes, STORAGE | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                  MemoryUsage::DeviceLocal);
}

void setRepresentationAddress(ShadowMapView& view, const Buffer& buffer) {
    const VkDeviceAddress address = buffer.deviceAddress();
    view.representationLow = uint(address & 0xffffffffu);
    view.representationHigh = uint(address >> 32);
}

/// A draw of every triangle from the light (shadowmap.vert, one instance per face of its map)
/// into `fragment`. No culling: a triangle takes light whichever face the light sees.
Pipeline lightDrawPipeline(const Device& device, const FamilyDescriptors& descriptors,
                           const std::vector<ShaderDefine>& defines, const char* fragment) {
    const ShaderCompiler compiler;
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("shadowmaps/shaders/shadowmap.vert", defines)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile(fragment, defines)}};
    desc.cullMode = VK_CULL_MODE_NONE;
    return createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
}

/// Records `pipeline`'s draw of `triangles` triangles for light `light` over its map's texels.
void recordLightDraw(VkCommandBuffer cmd, const Pipeline& pipeline, const FamilyDescriptors& descriptors,
                     const ShadowMapView& view, std::size_t light, std::uint32_t triangles) {
    beginRendering(cmd, VkExtent2D{view.size, view.size});
    pipeline.bind(cmd);
    descriptors.bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    descriptors.push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    if (triangles > 0) vkCmdDraw(cmd, 3 * triangles, view.faces, 0, 0);
    endRendering(cmd);
}

} // namespace

ShadowMapResources::ShadowMapResources(const Device& device, const Scene& scene, const RenderOptions& options)
    : m_device(&device), m_settings(shadowMapSettings(options)) {
    if (scene.lights.empty()) throw Error("internal error: shadow maps of a scene without lights");
    const ShadowFilterParams params = shadowFilterParams(m_settings);
    const Bounds receivers = m_settings.fit == 0
                                 ? Bounds{}
                                 : shadowReceiverBounds(scene, float(options.width) / float(options.height));
    const ShadowMapMethod filter = m_settings.filter;
    const bool functions = readsTransmittanceFunctions(filter);
    std::size_t mostTexels = 0;
    for (const Light& light : scene.lights) {
        const std::size_t l = m_views.size();
        m_views.push_back(fitFrameShadowMap(scene, light, receivers, m_settings));
        ShadowMapView& view = m_views.back();
        const std::size_t texels = std::size_t(view.faces) * view.size * view.size;
        mostTexels = std::max(mostTexels, texels);
        // Rows that do not read the depth map bind a stand-in.
        depth.emplace_back(device, filter == ShadowMapMethod::Peel || functions ? 16 : shadowMapBytes(view),
                           STORAGE, MemoryUsage::DeviceLocal);
        if (filter == ShadowMapMethod::Peel) {
            // A cube map's grid outgrows a storage buffer's range (512², 16 subintervals: 214 MB).
            grid.push_back(representationBuffer(device, depthGridBytes(view, m_settings),
                                                "the depth grid of light " + std::to_string(l),
                                                "lower peel_size or peel_bins"));
            setRepresentationAddress(view, grid.back());
        }
        if (isFilteredRepresentation(filter)) {
            // The planes outgrow a storage buffer's range (MSM's at 2048²: 134 MB, lavapipe's range
            // 128 MiB): the shaders reach them by device address.
            filtered.push_back(representationBuffer(
                device, filteredMapBytes(view, m_settings),
                "the " + std::string(methodInfo(options.method).name) + " representation of light " +
                    std::to_string(l),
                std::string("lower sm_size") + (filter == ShadowMapMethod::Csm ? " or csm_terms" : "") +
                    (filteredUsesMip(m_settings) ? "" : ", or use fm_mip=1 (4-byte mips)")));
            setRepresentationAddress(view, filtered.back());
        }
        if (functions) {
            // The functions outgrow a storage buffer's range (2048², 8 nodes: 272 MB); their words
            // are indexed in 32 bits (gpuAvsmNodeWord).
            const std::size_t bytes = avsmBytes(view, m_settings);
            if (bytes / 4 > std::size_t(UINT32_MAX))
                throw UsageError("the transmittance functions of light " + std::to_string(l) +
                                 " hold more than 2^32 words: lower avsm_size or avsm_nodes");
            avsm.push_back(representationBuffer(device, bytes,
                                                "the transmittance functions of light " + std::to_string(l),
                                                "lower avsm_size or avsm_nodes"));
            setRepresentationAddress(view, avsm.back());
            avsmHeads.emplace_back(device, texels * AVSM_HEAD_BYTES, STORAGE, MemoryUsage::DeviceLocal);
        }
    }
    if (functions) {
        allocateAvsmFragments(std::min<std::uint64_t>(
            AVSM_INITIAL_FRAGMENTS_PER_TEXEL * std::uint64_t(mostTexels), maxAvsmFragments()));
    }
    const std::vector<vec2> tapPoints = shadowFilterTaps(m_settings);
    std::vector<std::byte> table(sizeof(ShadowFilterParams) + sizeof(ShadowMapView) * m_views.size());
    std::memcpy(table.data(), &params, sizeof params);
    std::memcpy(table.data() + sizeof params, m_views.data(), sizeof(ShadowMapView) * m_views.size());
    views = createBuffer(device, std::span<const std::byte>(table), STORAGE);
    taps = createBuffer(device, std::span<const vec2>(tapPoints), STORAGE);
}

std::uint64_t ShadowMapResources::maxAvsmFragments() const {
    return std::min<std::uint64_t>(m_device->info().maxMemoryAllocationSize / AVSM_FRAGMENT_BYTES,
                                   UINT32_MAX - 1);
}

void ShadowMapResources::allocateAvsmFragments(std::uint64_t capacity) {
    m_avsmCapacity = capacity;
    avsmFragments = representationBuffer(*m_device, capacity * AVSM_FRAGMENT_BYTES,
                                         "the transmittance functions' fragment lists", "lower avsm_size");
    const VkDeviceAddress address = avsmFragments.deviceAddress();
    const GpuAvsmLists lists{uint(address & 0xffffffffu), uint(address >> 32), uint(capacity), 0u};
    avsmLists = createBuffer(*m_device, std::span<const GpuAvsmLists>(&lists, 1), STORAGE);
}

bool ShadowMapResources::growAvsmFragments(std::uint64_t listed) {
    if (listed <= m_avsmCapacity) return false;
    const std::uint64_t most = maxAvsmFragments();
    if (listed > most)
        throw UsageError("the transmittance functions' fragment lists need " + std::to_string(listed) +
                         " fragments for one light, more than the " + std::to_string(most) +
                         " (16 bytes each) that one allocation of " + m_device->info().name +
                         " may hold: lower avsm_size");
    allocateAvsmFragments(std::min(listed + listed / 4, most));
    return true;
}

ShadowMap ShadowMapResources::download(std::size_t light) const {
    ShadowMap map;
    map.view = m_views.at(light);
    const std::vector<uint> words = depth.at(light).download<uint>();
    map.depth.resize(words.size());
    for (std::size_t i = 0; i < words.size(); ++i) map.depth[i] = gpuShadowDepthOf(words[i]);
    return map;
}

DepthGrid ShadowMapResources::downloadGrid(std::size_t light) const {
    DepthGrid out;
    out.view = m_views.at(light);
    out.bins = uint(m_settings.peelBins);
    out.words = grid.at(light).download<std::uint32_t>();
    return out;
}

AvsmMap ShadowMapResources::downloadAvsm(std::size_t light) const {
    const ShadowMapView& view = m_views.at(light);
    const uint nodes = uint(m_settings.avsmNodes);
    AvsmMap map(view, nodes);
    const std::vector<std::uint32_t> words = avsm.at(light).download<std::uint32_t>();
    const uint texels = uint(map.counts.size());
    for (uint t = 0; t < texels; ++t) {
        map.counts[t] = gpuAvsmHeaderCount(words[t]);
        map.overflowed[t] = std::uint8_t(gpuAvsmHeaderOverflowed(words[t]));
        for (uint j = 0; j < map.counts[t]; ++j) {
            const uint w = gpuAvsmNodeWord(texels, t, nodes, j);
            std::memcpy(&map.depth[std::size_t(t) * nodes + j], &words[w], 4);
            map.units[std::size_t(t) * nodes + j] = words[w + 1];
        }
    }
    return map;
}

void ShadowMapResources::writeDescriptors(DescriptorSet& set, std::size_t light) const {
    set.writeBuffer(GPU_BINDING_SHADOW_MAP, depth[light]);
    set.writeBuffer(GPU_BINDING_SHADOW_VIEWS, views);
    set.writeBuffer(GPU_BINDING_SHADOW_TAPS, taps);
    if (!avsmHeads.empty()) {
        set.writeBuffer(GPU_BINDING_AVSM_HEADS, avsmHeads[light]);
        set.writeBuffer(GPU_BINDING_AVSM_LISTS, avsmLists);
    }
}

ShadowMapPass::ShadowMapPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                             const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())),
      m_pipeline(lightDrawPipeline(device, descriptors, defines, "shadowmaps/shaders/shadowmap.frag")) {}

PassAccesses ShadowMapPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->depth[light], ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void ShadowMapPass::record(VkCommandBuffer cmd, std::size_t light) const {
    recordLightDraw(cmd, m_pipeline, *m_descriptors, m_maps->view(light), light, m_triangleCount);
}

FilteredMapPass::FilteredMapPass(const Device& device, ShadowMapResources& maps,
                                 const FamilyDescriptors& descriptors,
                                 const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors), m_mip(filteredUsesMip(maps.settings())),
      m_channels(std::uint32_t(filteredChannelCount(maps.settings()))) {
    const ShaderCompiler compiler;
    for (const int step : m_mip ? std::vector<int>{2, 3} : std::vector<int>{0, 1}) {
        std::vector<ShaderDefine> withStep = defines;
        withStep.push_back({"FILTERED_STEP", std::to_string(step)});
        m_steps.push_back(
            createComputePipeline(device, descriptors.pipelineLayout(),
                                  compiler.compileFile("shadowmaps/shaders/filtered_map.comp", withStep)));
    }
}

PassAccesses FilteredMapPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->depth[light], ResourceUse::storageRead(COMPUTE))
        .use(m_maps->filtered[light], ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void FilteredMapPass::record(VkCommandBuffer cmd, std::size_t light) const {
    const ShadowMapView& view = m_maps->view(light);
    const std::uint32_t size = view.size, planes = view.faces * m_channels;
    // Each step reads what the one before wrote in the same buffer.
    const auto barrier = [&] {
        memoryBarrier(cmd, COMPUTE, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, COMPUTE,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    };
    m_steps[0].bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    if (!m_mip) {
        // filtered_map.comp's summed-area steps: 64 rows, then 64 columns, per workgroup.
        vkCmdDispatch(cmd, (size * planes + 63) / 64, 1, 1);
        barrier();
        m_steps[1].bind(cmd);
        vkCmdDispatch(cmd, (size * planes + 63) / 64, 1, 1);
        return;
    }
    // Its mip steps: 16 × 16 texels per workgroup, one face (level 0) or plane per z.
    vkCmdDispatch(cmd, (size + 15) / 16, (size + 15) / 16, view.faces);
    m_steps[1].bind(cmd);
    for (std::uint32_t level = 1; level < filteredMipLevels(size); ++level) {
        barrier();
        m_descriptors->push(cmd, GpuPush{uint(light), level, 0u, 0u});
        const std::uint32_t n = filteredMipSize(size, level);
        vkCmdDispatch(cmd, (n + 15) / 16, (n + 15) / 16, planes);
    }
}

DepthGridPass::DepthGridPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                             const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    // Every surface counts, front and back.
    Pipeline* pipelines[] = {&m_range, &m_bins};
    for (int step = 0; step < 2; ++step) {
        std::vector<ShaderDefine> withStep = defines;
        withStep.push_back({"DEPTH_GRID_STEP", std::to_string(step)});
        *pipelines[step] =
            lightDrawPipeline(device, descriptors, withStep, "shadowmaps/shaders/depth_grid.frag");
    }
}

PassAccesses DepthGridPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->grid[light], ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void DepthGridPass::record(VkCommandBuffer cmd, std::size_t light) const {
    const ShadowMapView& view = m_maps->view(light);
    for (const Pipeline* pipeline : {&m_range, &m_bins}) {
        // The subinterval draw reads the ranges the first one wrote.
        if (pipeline == &m_bins)
            memoryBarrier(cmd, FRAGMENT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, FRAGMENT,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
        recordLightDraw(cmd, *pipeline, *m_descriptors, view, light, m_triangleCount);
    }
}

std::uint32_t peelMarchLanes(int samples, int steps, int bins) {
    const std::uint64_t perSample =
        std::uint64_t(std::max(steps, 1)) * std::uint64_t(std::max(bins, 0) + 1) + 1;
    const std::uint64_t perLane = std::max<std::uint64_t>(SAMPLE_LOOP_BUDGET / perSample, 1);
    const std::uint64_t lanes = (std::uint64_t(std::max(samples, 1)) + perLane - 1) / perLane;
    return static_cast<std::uint32_t>(std::bit_ceil(lanes));
}

PeelMarchPass::PeelMarchPass(const Device& device, const RenderOptions& options, ShadowMapResources& maps,
                             FrameResources& frame, const FamilyDescriptors& descriptors,
                             const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_frame(&frame), m_descriptors(&descriptors),
      m_counters(options.buffer == BufferKind::Counters), m_width(static_cast<uint32_t>(options.width)),
      m_height(static_cast<uint32_t>(options.height)) {
    const ShadowMapSettings settings = shadowMapSettings(options);
    const std::uint32_t lanes = peelMarchLanes(options.samples, settings.peelMaxSteps, settings.peelBins);
    const std::uint32_t group = std::max<std::uint32_t>(lanes, 64);
    if (group > device.limits().maxComputeWorkGroupInvocations ||
        group > device.limits().maxComputeWorkGroupSize[0])
        throw UsageError("peel's march needs " + std::to_string(group) + " invocations a workgroup at " +
                         std::to_string(options.samples) + " samples, peel_max_steps " +
                         std::to_string(settings.peelMaxSteps) + " and peel_bins " +
                         std::to_string(settings.peelBins) + "; Vulkan device " + device.info().name +
                         " allows " + std::to_string(device.limits().maxComputeWorkGroupInvocations) +
                         ": lower peel_max_steps, peel_bins or --samples");
    m_pixelsPerGroup = group / lanes;
    std::vector<ShaderDefine> marchDefines = defines;
    marchDefines.push_back({"PEEL_LANES", std::to_string(lanes)});
    marchDefines.push_back({"PEEL_GROUP", std::to_string(group)});
    const ShaderCompiler compiler;
    m_pipeline =
        createComputePipeline(device, descriptors.pipelineLayout(),
                              compiler.compileFile("shadowmaps/shaders/peel_march.comp", marchDefines));
}

PassAccesses PeelMarchPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_maps->grid[light], ResourceUse::storageRead(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    if (m_counters) {
        accesses.use(m_frame->samples.counters[light], ResourceUse::storageReadWrite(COMPUTE));
    } else {
        // The whole image array is bound and indexed by a loop counter: every element counts as written.
        for (std::size_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i)
            accesses.use(m_frame->samples.mask(light, i), ResourceUse::storageReadWrite(COMPUTE));
    }
    return accesses;
}

void PeelMarchPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    vkCmdDispatch(cmd, (m_width + m_pixelsPerGroup - 1) / m_pixelsPerGroup, m_height, 1);
}

AvsmListPass::AvsmListPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                           const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())),
      m_pipeline(lightDrawPipeline(device, descriptors, defines, "shadowmaps/shaders/avsm_fragments.frag")) {}

PassAccesses AvsmListPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->avsmHeads[light], ResourceUse::storageReadWrite(FRAGMENT))
        .use(m_maps->avsmFragments, ResourceUse::storageReadWrite(FRAGMENT))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void AvsmListPass::record(VkCommandBuffer cmd, std::size_t light) const {
    recordLightDraw(cmd, m_pipeline, *m_descriptors, m_maps->view(light), light, m_triangleCount);
}

AvsmBuildPass::AvsmBuildPass(const Device& device, ShadowMapResources& maps,
                             const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors) {
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("shadowmaps/shaders/avsm_build.comp", defines));
}

PassAccesses AvsmBuildPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->avsmHeads[light], ResourceUse::storageRead(COMPUTE))
        .use(m_maps->avsmFragments, ResourceUse::storageRead(COMPUTE))
        .use(m_maps->avsm[light], ResourceUse::storageReadWrite(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void AvsmBuildPass::record(VkCommandBuffer cmd, std::size_t light) const {
    const ShadowMapView& view = m_maps->view(light);
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    // avsm_build.comp: one texel a thread, 64 a workgroup; the faces along z.
    vkCmdDispatch(cmd, (view.size * view.size + 63) / 64, view.faces, 1);
}

ShadowFilterPass::ShadowFilterPass(const Device& device, const RenderOptions& options, Step step,
                                   ShadowMapResources& maps, FrameResources& frame,
                                   const FamilyDescriptors& descriptors,
                                   const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_frame(&frame), m_descriptors(&descriptors), m_step(step),
      m_width(static_cast<uint32_t>(options.width)), m_height(static_cast<uint32_t>(options.height)) {
    const ShaderCompiler compiler;
    std::vector<ShaderDefine> withStep = defines;
    withStep.push_back({"SHADOW_FILTER_STEP", std::to_string(int(step))});
    m_pipeline =
        createComputePipeline(device, descriptors.pipelineLayout(),
                              compiler.compileFile("shadowmaps/shaders/shadow_filter.comp", withStep));
}

PassAccesses ShadowFilterPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    // What the step reads of the light's: the transmittance functions, the filtered planes, or the map.
    const Buffer& map = m_step >= AvsmLookup       ? m_maps->avsm[light]
                        : m_step == FilteredLookup ? m_maps->filtered[light]
                                                   : m_maps->depth[light];
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(map, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->samples.vcoef, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void ShadowFilterPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    // shadow_filter.comp works on 16 × 16 tiles.
    dispatchPerPixel(cmd, m_width, m_height);
}

} // namespace stsv
