#include "render/vulkan/gpu_frame_resources.h"

#include "render/frame.h"
#include "render/methods.h"
#include "render/vulkan/gpu_renderer.h"
#include "sampling/light_bounds.h"
#include "scene/camera.h"
#include "scene/geometry.h"
#include "volumes/stsv.h"

#include <algorithm>
#include <cstring>

namespace stsv {

namespace {

constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr VkBufferUsageFlags UNIFORM = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;

/// One GpuTriangle per scene triangle (at least one). A transmittance frame's translucent
/// triangles read their blend textures (stsvTextureFor).
std::vector<GpuTriangle> gpuTriangles(const Scene& scene, bool transmittance) {
    std::vector<GpuTriangle> tris(std::max<std::size_t>(scene.triangleCount(), 1));
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const uvec3 idx = scene.triangles[t];
        const Material& material = scene.materialOf(t);
        const StsvTexture texture = stsvTextureFor(material, transmittance);
        GpuTriangle& g = tris[t];
        g = {};
        g.v0 = vec4(scene.positions[idx.x], 1.0f);
        g.v1 = vec4(scene.positions[idx.y], 1.0f);
        g.v2 = vec4(scene.positions[idx.z], 1.0f);
        g.t0 = scene.texcoords[idx.x];
        g.t1 = scene.texcoords[idx.y];
        g.t2 = scene.texcoords[idx.z];
        g.texture = texture.texture;
        g.flags = texture.flags | (material.doubleSided ? GPU_TRIANGLE_DOUBLE_SIDED : 0u) |
                  (material.translucent() ? GPU_TRIANGLE_TRANSLUCENT : 0u);
        g.albedo = material.albedo;
        g.material = scene.triangleMaterial[t];
    }
    return tris;
}

/// The optical-depth tables of every material (at least one), 256 uints each; a frame without
/// transmittance binds one empty table.
std::vector<std::uint32_t> depthTables(const Scene& scene, bool transmittance) {
    std::vector<std::uint32_t> tables(256, 0u);
    if (!transmittance) return tables;
    tables.clear();
    for (const Material& m : scene.materials) {
        const OpticalDepthTable table = opticalDepthTable(m);
        tables.insert(tables.end(), table.begin(), table.end());
    }
    tables.resize(std::max<std::size_t>(tables.size(), 256), 0u);
    return tables;
}

/// Binary alpha (alphaBlocks per texel, volumes/stsv_dh.h) of every texture as bits in a
/// uniform buffer of uvec4, when they fit MAX_UNIFORM_TABLE_BYTES; else alpha bytes in a storage
/// buffer. Returns the uvec4 words (empty when they do not fit); GpuTexture::offset then counts bits.
std::vector<std::uint32_t> alphaBitWords(const Scene& scene, std::vector<GpuTexture>& table) {
    std::size_t bits = 0;
    for (const Texture& tex : scene.textures) bits += std::size_t(tex.width) * std::size_t(tex.height);
    const std::size_t vec4s = std::max<std::size_t>((bits + 127) / 128, 1);
    if (vec4s * 16 > MAX_UNIFORM_TABLE_BYTES) return {};
    std::vector<std::uint32_t> words(4 * vec4s, 0u);
    std::size_t bit = 0;
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& tex = scene.textures[i];
        table[i] = {static_cast<uint>(bit), tex.width, tex.height, 0u};
        for (int y = 0; y < tex.height; ++y)
            for (int x = 0; x < tex.width; ++x, ++bit)
                if (alphaBlocks(tex.alpha(x, y))) words[bit / 32] |= 1u << (bit % 32);
    }
    return words;
}

/// Alpha bytes of every texture, 4 per word (GpuTexture::offset counts bytes).
std::vector<std::uint32_t> alphaByteWords(const Scene& scene, std::vector<GpuTexture>& table) {
    std::vector<std::uint8_t> bytes;
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& tex = scene.textures[i];
        table[i] = {static_cast<uint>(bytes.size()), tex.width, tex.height, 0u};
        for (int y = 0; y < tex.height; ++y)
            for (int x = 0; x < tex.width; ++x) bytes.push_back(tex.alpha(x, y));
    }
    bytes.resize(std::max<std::size_t>((bytes.size() + 3) / 4 * 4, 4), 0);
    std::vector<std::uint32_t> words(bytes.size() / 4);
    std::memcpy(words.data(), bytes.data(), bytes.size());
    return words;
}

/// GpuFrame then one GpuLight per light (at least one).
std::vector<std::byte> frameConstants(const Scene& scene, const RenderOptions& options) {
    const std::size_t lightCount = scene.lights.size();
    const Bounds box = scene.bounds();
    const float farDistance = farDistanceFor(box);
    GpuFrame frame{};
    frame.clipFromWorld = gpuClipFromWorld(scene, options.width, options.height);
    frame.eye = vec4(scene.camera.eye, 1.0f);
    frame.boxLo = vec4(box.lo, 0.0f);
    frame.boxHi = vec4(box.hi, 0.0f);
    frame.farDistance = farDistance;
    frame.ambient = options.ambient;
    frame.background = vec4(BACKGROUND, 1.0f);
    frame.width = static_cast<uint>(options.width);
    frame.height = static_cast<uint>(options.height);
    frame.sampleCount = static_cast<uint>(options.samples);
    frame.interleave = static_cast<uint>(options.interleave);
    frame.seed = options.seed;
    frame.decorrelate = options.decorrelate ? 1u : 0u;
    frame.supersample = uint(options.supersample);
    frame.lightCount = static_cast<uint>(lightCount);
    frame.lightWeight = lightCount > 0 ? 1.0f / float(lightCount) : 0.0f;
    std::vector<std::byte> bytes(sizeof(GpuFrame) + sizeof(GpuLight) * std::max<std::size_t>(lightCount, 1));
    std::memcpy(bytes.data(), &frame, sizeof(frame));
    for (std::size_t l = 0; l < lightCount; ++l) {
        const GpuLight light{scene.lights[l], lightBoundingSphere(scene.lights[l], box, farDistance)};
        std::memcpy(bytes.data() + sizeof(GpuFrame) + l * sizeof(GpuLight), &light, sizeof(light));
    }
    return bytes;
}

} // namespace

void setBehindVisiblePointDepth(GraphicsPipelineDesc& desc) {
    desc.depthFormat = DEPTH_FORMAT;
    desc.depthTest = true;
    desc.depthWrite = false;
    desc.depthCompare = VK_COMPARE_OP_LESS;
    desc.depthClamp = true;
    desc.depthBiasConstant = -256.0f;
    desc.depthBiasSlope = -1.0f;
}

int maskAttachmentCount(int samples) {
    return (samples + 63) / 64;
}

GpuSceneTables::GpuSceneTables(const Device& device, const Scene& scene, const RenderOptions& options,
                               const SamplePlan& plan) {
    // A transmittance frame, and the transmittance functions of avsm and vpcss, read the
    // translucent triangles' blend textures and the materials' optical-depth tables.
    const bool transmittance = options.buffer == BufferKind::Transmittance ||
                               readsTransmittanceFunctions(methodInfo(options.method).shadowMap);
    triangles =
        createBuffer(device, std::span<const GpuTriangle>(gpuTriangles(scene, transmittance)), STORAGE);
    depthTables = createBuffer(
        device, std::span<const std::uint32_t>(stsv::depthTables(scene, transmittance)), STORAGE);

    // Translucent triangles read alpha bytes, not bits, in a transmittance frame.
    std::vector<GpuTexture> table(std::max<std::size_t>(scene.textures.size(), 1), GpuTexture{0, 1, 1, 0});
    const std::vector<std::uint32_t> bitWords =
        transmittance && scene.hasTranslucent() ? std::vector<std::uint32_t>{} : alphaBitWords(scene, table);
    layout.alphaBitVec4s = bitWords.size() / 4;
    alpha = layout.alphaBitVec4s > 0
                ? createBuffer(device, std::span<const std::uint32_t>(bitWords), UNIFORM)
                : createBuffer(device, std::span<const std::uint32_t>(alphaByteWords(scene, table)), STORAGE);
    textures = createBuffer(device, std::span<const GpuTexture>(table), STORAGE);

    layout.patternVec4s = patternVec4Count(plan);
    std::vector<vec2> points = plan.points;
    points.resize(std::max<std::size_t>(2 * ((points.size() + 1) / 2), 2), vec2(0.0f)); // whole vec4s
    pattern =
        createBuffer(device, std::span<const vec2>(points), layout.patternVec4s > 0 ? UNIFORM : STORAGE);

    frame = createBuffer(device, std::span<const std::byte>(frameConstants(scene, options)), STORAGE);
}

Image& LightSampleBuffers::mask(std::size_t light, std::size_t i) {
    return i < masks[light].size() ? masks[light][i] : unusedMask;
}

FrameResources::FrameResources(const Device& device, const Scene& scene, const RenderOptions& options,
                               const SamplePlan& plan)
    : tables(device, scene, options, plan) {
    const std::size_t lightCount = scene.lights.size();
    const std::size_t setCount = std::max<std::size_t>(lightCount, 1);

    const auto w = static_cast<uint32_t>(options.width), h = static_cast<uint32_t>(options.height);
    const VkImageUsageFlags attachment = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
    gbuffer.position = Image(device, {w, h, POSITION_FORMAT, attachment});
    gbuffer.triangleId = Image(device, {w, h, TRIANGLE_FORMAT, attachment});
    gbuffer.depth = Image(device, {w, h, DEPTH_FORMAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT});
    color = Image(device, {w, h, COLOR_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
    visibility = Image(device, {w, h, VISIBILITY_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});

    // Bits in bitmask and transmittance frames, counters where layers are counted, optical depths
    // in transmittance frames; a 16-byte stand-in for each buffer the frame does not write.
    samples.masks.resize(setCount);
    if (options.buffer != BufferKind::Counters)
        for (std::size_t l = 0; l < lightCount; ++l)
            for (int i = 0; i < maskAttachmentCount(options.samples); ++i)
                samples.masks[l].emplace_back(device, ImageDesc{w, h, MASK_FORMAT, attachment});
    const std::size_t pixelSamples = std::size_t(w) * h * std::size_t(options.samples);
    const std::size_t counterBytes = frameCountsLayers(options) ? pixelSamples * 2 : 16;
    const std::size_t depthBytes = options.buffer == BufferKind::Transmittance ? pixelSamples * 4 : 16;
    for (std::size_t l = 0; l < setCount; ++l) {
        samples.counters.emplace_back(device, counterBytes, STORAGE, MemoryUsage::DeviceLocal);
        samples.depths.emplace_back(device, depthBytes, STORAGE, MemoryUsage::DeviceLocal);
    }
    samples.unusedMask = Image(device, {1, 1, MASK_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
    const bool vcoef = methodInfo(options.method).output == MethodOutput::Visibility;
    samples.vcoef = Image(device, {vcoef ? w : 1u, vcoef ? h : 1u, VCOEF_FORMAT, attachment});
}

std::vector<DescriptorBinding> FrameResources::bindings() const {
    std::vector<DescriptorBinding> bindings;
    for (uint32_t b : {GPU_BINDING_TRIANGLES, GPU_BINDING_TEXTURES, GPU_BINDING_FRAME, GPU_BINDING_COUNTERS,
                       GPU_BINDING_DEPTH_TABLES, GPU_BINDING_DEPTHS})
        bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1});
    auto tableType = [](std::size_t uniformVec4s) {
        return uniformVec4s > 0 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    };
    bindings.push_back({GPU_BINDING_ALPHA, tableType(tables.layout.alphaBitVec4s), VK_SHADER_STAGE_ALL, 1});
    bindings.push_back({GPU_BINDING_PATTERN, tableType(tables.layout.patternVec4s), VK_SHADER_STAGE_ALL, 1});
    for (uint32_t b : {GPU_BINDING_POSITION, GPU_BINDING_TRIANGLE_ID, GPU_BINDING_VCOEF})
        bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1});
    bindings.push_back(
        {GPU_BINDING_MASKS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, GPU_MAX_MASK_IMAGES});
    return bindings;
}

void FrameResources::writeDescriptors(DescriptorSet& set, std::size_t light) {
    set.writeBuffer(GPU_BINDING_TRIANGLES, tables.triangles);
    set.writeBuffer(GPU_BINDING_ALPHA, tables.alpha);
    set.writeBuffer(GPU_BINDING_TEXTURES, tables.textures);
    set.writeBuffer(GPU_BINDING_PATTERN, tables.pattern);
    set.writeBuffer(GPU_BINDING_FRAME, tables.frame);
    set.writeBuffer(GPU_BINDING_COUNTERS, samples.counters[light]);
    set.writeBuffer(GPU_BINDING_DEPTH_TABLES, tables.depthTables);
    set.writeBuffer(GPU_BINDING_DEPTHS, samples.depths[light]);
    set.writeStorageImage(GPU_BINDING_POSITION, gbuffer.position);
    set.writeStorageImage(GPU_BINDING_TRIANGLE_ID, gbuffer.triangleId);
    set.writeStorageImage(GPU_BINDING_VCOEF, samples.vcoef);
    for (uint32_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i)
        set.writeStorageImage(GPU_BINDING_MASKS, samples.mask(light, i), VK_IMAGE_LAYOUT_GENERAL, i);
}

FrameDescriptors::FrameDescriptors(const Device& device, std::vector<DescriptorBinding> bindings,
                                   std::size_t setCount)
    : m_setLayout(device, std::move(bindings)),
      m_pipelineLayout(device, {m_setLayout.handle()}, sizeof(GpuPush)) {
    for (std::size_t l = 0; l < setCount; ++l) m_sets.emplace_back(device, m_setLayout);
}

void FrameDescriptors::bind(VkCommandBuffer cmd, VkPipelineBindPoint point, std::size_t light) const {
    VkDescriptorSet handle = m_sets.at(light).handle();
    vkCmdBindDescriptorSets(cmd, point, m_pipelineLayout.handle(), GPU_SET_FRAME, 1, &handle, 0, nullptr);
}

void FrameDescriptors::push(VkCommandBuffer cmd, const GpuPush& constants) const {
    m_pipelineLayout.push(cmd, &constants, sizeof(constants));
}

namespace {

std::vector<DescriptorBinding> withStats(std::vector<DescriptorBinding> bindings, std::size_t statsBytes) {
    if (statsBytes > 0)
        bindings.push_back(
            {GPU_BINDING_FAMILY_STATS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1});
    return bindings;
}

} // namespace

FamilyDescriptors::FamilyDescriptors(const Device& device, const FrameDescriptors& frame,
                                     std::vector<DescriptorBinding> bindings, std::size_t statsBytes)
    : m_frame(&frame), m_setLayout(device, withStats(std::move(bindings), statsBytes)),
      m_pipelineLayout(device, {frame.setLayout().handle(), m_setLayout.handle()}, sizeof(GpuPush)),
      m_statsStride(statsBytes) {
    static_assert(GPU_SET_FRAME == 0 && GPU_SET_FAMILY == 1, "the pipeline layout lists the sets in order");
    if (statsBytes > 0)
        m_stats = Buffer(device, statsBytes * frame.setCount(), STORAGE, MemoryUsage::DeviceLocal);
    for (std::size_t l = 0; l < frame.setCount(); ++l) {
        m_sets.emplace_back(device, m_setLayout);
        if (statsBytes > 0) m_sets.back().writeBuffer(GPU_BINDING_FAMILY_STATS, m_stats);
    }
}

void FamilyDescriptors::bind(VkCommandBuffer cmd, VkPipelineBindPoint point, std::size_t light) const {
    const VkDescriptorSet handles[] = {m_frame->set(light).handle(), m_sets.at(light).handle()};
    vkCmdBindDescriptorSets(cmd, point, m_pipelineLayout.handle(), GPU_SET_FRAME, 2, handles, 0, nullptr);
}

void FamilyDescriptors::push(VkCommandBuffer cmd, const GpuPush& constants) const {
    m_pipelineLayout.push(cmd, &constants, sizeof(constants));
}

} // namespace stsv
