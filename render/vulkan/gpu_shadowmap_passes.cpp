#include "render/vulkan/gpu_shadowmap_passes.h"

#include "core/error.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"
#include "render/options.h"
#include "shadowmaps/filtered_lookup.h"
#include "shadowmaps/filtered_map.h"
#include "shadowmaps/shadow_fit.h"

#include <cstring>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

} // namespace

std::vector<DescriptorBinding> ShadowMapResources::bindings() {
    return {{GPU_BINDING_SHADOW_MAP, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_SHADOW_VIEWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_SHADOW_TAPS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

ShadowMapResources::ShadowMapResources(const Device& device, const Scene& scene, const RenderOptions& options)
    : m_settings(shadowMapSettings(options)) {
    if (scene.lights.empty()) throw Error("internal error: shadow maps of a scene without lights");
    const ShadowFilterParams params = shadowFilterParams(m_settings);
    const Bounds receivers = m_settings.fit == 0
                                 ? Bounds{}
                                 : shadowReceiverBounds(scene, float(options.width) / float(options.height));
    for (const Light& light : scene.lights) {
        m_views.push_back(fitFrameShadowMap(scene, light, receivers, m_settings));
        depth.emplace_back(device, shadowMapBytes(m_views.back()), STORAGE, MemoryUsage::DeviceLocal);
        if (m_settings.filter == ShadowFilter::Peel) {
            // A cube map's grid outgrows a storage buffer's range (512², 16 subintervals: 214 MB).
            if (!device.info().shaderInt64 || !device.info().bufferDeviceAddress)
                throw UsageError(
                    "peel on Vulkan needs 64-bit integers in shaders and buffer device addresses, "
                    "which " +
                    device.info().name + " lacks: use --backend cpu");
            const std::size_t bytes = depthGridBytes(m_views.back(), m_settings);
            if (bytes > device.info().maxMemoryAllocationSize)
                throw UsageError("the depth grid of light " + std::to_string(m_views.size() - 1) + " needs " +
                                 std::to_string(bytes >> 20) + " MiB, more than one allocation of " +
                                 device.info().name + " may hold (" +
                                 std::to_string(device.info().maxMemoryAllocationSize >> 20) +
                                 " MiB): lower peel_size or peel_bins");
            grid.emplace_back(device, bytes, STORAGE | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                              MemoryUsage::DeviceLocal);
            const VkDeviceAddress address = grid.back().deviceAddress();
            m_views.back().filteredLow = uint(address & 0xffffffffu);
            m_views.back().filteredHigh = uint(address >> 32);
        }
        if (isFilteredRepresentation(m_settings.filter)) {
            // The planes outgrow a storage buffer's range (MSM's at 2048²: 134 MB, lavapipe's range
            // 128 MiB): the shaders reach them by device address.
            if (!device.info().shaderInt64 || !device.info().bufferDeviceAddress)
                throw UsageError(
                    "the filtered shadow maps on Vulkan need 64-bit integers in shaders and buffer "
                    "device addresses, which " +
                    device.info().name + " lacks: use --backend cpu");
            const std::size_t bytes = filteredMapBytes(m_views.back(), m_settings);
            if (bytes > device.info().maxMemoryAllocationSize)
                throw UsageError(
                    "the " + std::string(methodInfo(options.method).name) + " representation of light " +
                    std::to_string(m_views.size() - 1) + " needs " + std::to_string(bytes >> 20) +
                    " MiB, more than one allocation of " + device.info().name + " may hold (" +
                    std::to_string(device.info().maxMemoryAllocationSize >> 20) + " MiB): lower sm_size" +
                    (m_settings.filter == ShadowFilter::Csm ? " or csm_terms" : "") +
                    (filteredUsesMip(m_settings) ? "" : ", or use fm_mip=1 (4-byte mips)"));
            filtered.emplace_back(device, bytes, STORAGE | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                  MemoryUsage::DeviceLocal);
            const VkDeviceAddress address = filtered.back().deviceAddress();
            m_views.back().filteredLow = uint(address & 0xffffffffu);
            m_views.back().filteredHigh = uint(address >> 32);
        }
    }
    const std::vector<vec2> tapPoints = shadowFilterTaps(m_settings);
    std::vector<std::byte> table(sizeof(ShadowFilterParams) + sizeof(ShadowMapView) * m_views.size());
    std::memcpy(table.data(), &params, sizeof params);
    std::memcpy(table.data() + sizeof params, m_views.data(), sizeof(ShadowMapView) * m_views.size());
    views = createBuffer(device, std::span<const std::byte>(table), STORAGE);
    taps = createBuffer(device, std::span<const vec2>(tapPoints), STORAGE);
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

void ShadowMapResources::writeDescriptors(DescriptorSet& set, std::size_t light) const {
    set.writeBuffer(GPU_BINDING_SHADOW_MAP, depth[light]);
    set.writeBuffer(GPU_BINDING_SHADOW_VIEWS, views);
    set.writeBuffer(GPU_BINDING_SHADOW_TAPS, taps);
}

ShadowMapPass::ShadowMapPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                             const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    const ShaderCompiler compiler;
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("shadowmaps/shadowmap.vert", defines)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("shadowmaps/shadowmap.frag", defines)}};
    // A triangle blocks light whichever face the light sees: no culling.
    desc.cullMode = VK_CULL_MODE_NONE;
    m_pipeline = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
}

PassAccesses ShadowMapPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->depth[light], ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void ShadowMapPass::record(VkCommandBuffer cmd, std::size_t light) const {
    const ShadowMapView& view = m_maps->view(light);
    beginRendering(cmd, VkExtent2D{view.size, view.size});
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    if (m_triangleCount > 0) vkCmdDraw(cmd, 3 * m_triangleCount, view.faces, 0, 0);
    endRendering(cmd);
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
                                  compiler.compileFile("shadowmaps/filtered_map.comp", withStep)));
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
    const ShaderCompiler compiler;
    Pipeline* pipelines[] = {&m_range, &m_bins};
    for (int step = 0; step < 2; ++step) {
        std::vector<ShaderDefine> withStep = defines;
        withStep.push_back({"DEPTH_GRID_STEP", std::to_string(step)});
        GraphicsPipelineDesc desc;
        desc.stages = {
            {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("shadowmaps/shadowmap.vert", withStep)},
            {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("shadowmaps/depth_grid.frag", withStep)}};
        // Every surface counts, front and back: no culling.
        desc.cullMode = VK_CULL_MODE_NONE;
        *pipelines[step] = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
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
        beginRendering(cmd, VkExtent2D{view.size, view.size});
        pipeline->bind(cmd);
        m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
        m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
        if (m_triangleCount > 0) vkCmdDraw(cmd, 3 * m_triangleCount, view.faces, 0, 0);
        endRendering(cmd);
    }
}

PeelMarchPass::PeelMarchPass(const Device& device, const RenderOptions& options, ShadowMapResources& maps,
                             FrameResources& frame, const FamilyDescriptors& descriptors,
                             const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_frame(&frame), m_descriptors(&descriptors),
      m_counters(options.buffer == BufferKind::Counters), m_width(static_cast<uint32_t>(options.width)),
      m_height(static_cast<uint32_t>(options.height)) {
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("shadowmaps/peel_march.comp", defines));
}

PassAccesses PeelMarchPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_maps->grid[light], ResourceUse::storageRead(COMPUTE));
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
    dispatchPerPixel(cmd, m_width, m_height);
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
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("shadowmaps/shadow_filter.comp", withStep));
}

PassAccesses ShadowFilterPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_maps->depth[light], ResourceUse::storageRead(COMPUTE))
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
