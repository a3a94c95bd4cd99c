#include "render/gpu_renderer.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "gpu/buffer.h"
#include "gpu/commands.h"
#include "gpu/descriptors.h"
#include "gpu/device.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"
#include "gpu/timer.h"
#include "reference/embree_scene.h"
#include "render/gpu_frame_dh.h"
#include "render/gpu_wedges.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/pattern.h"
#include "scene/camera.h"
#include "volumes/stsv_dh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <iterator>
#include <string>

namespace stsv {

namespace {

const vec3 BACKGROUND(0.02f, 0.02f, 0.03f); // as render/frame.cpp

constexpr VkFormat POSITION_FORMAT = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat TRIANGLE_FORMAT = VK_FORMAT_R32_UINT;
constexpr VkFormat DEPTH_FORMAT = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat MASK_FORMAT = VK_FORMAT_R32G32_UINT;
constexpr VkFormat COLOR_FORMAT = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat VISIBILITY_FORMAT = VK_FORMAT_R32_SFLOAT;

/// RG32UI attachments of a bitmask of N samples: 64 samples each.
int maskAttachmentCount(int samples) {
    return (samples + 63) / 64;
}

/// The pattern buffer is a uniform buffer when it fits the minimum maxUniformBufferRange that
/// every Vulkan device guarantees; else a storage buffer (shaders/frame_bindings.glsl).
constexpr std::size_t MAX_UNIFORM_PATTERN_BYTES = 16384;

/// vec4 count of the uniform pattern buffer (two points each), 0 when it is a storage buffer.
std::size_t patternVec4Count(const SamplePlan& plan) {
    const std::size_t vec4s = (plan.points.size() + 1) / 2;
    return vec4s * 16 <= MAX_UNIFORM_PATTERN_BYTES ? vec4s : 0;
}

/// Binary alpha (alphaBlocks per texel, volumes/stsv_dh.h) of every texture as bits in a
/// uniform buffer of uvec4, when they fit the same 16 KiB; else alpha bytes in a storage buffer.
/// Returns the uvec4 words (empty when they do not fit); GpuTexture::offset then counts bits.
std::vector<std::uint32_t> alphaBitWords(const Scene& scene, std::vector<GpuTexture>& table) {
    std::size_t bits = 0;
    for (const Texture& tex : scene.textures) bits += std::size_t(tex.width) * std::size_t(tex.height);
    const std::size_t vec4s = std::max<std::size_t>((bits + 127) / 128, 1);
    if (vec4s * 16 > MAX_UNIFORM_PATTERN_BYTES) return {};
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

/// Defines every shader of the frame needs to match the descriptor set layout.
std::vector<ShaderDefine> layoutDefines(const SamplePlan& plan, std::size_t alphaBitVec4s) {
    std::vector<ShaderDefine> defines;
    if (patternVec4Count(plan) > 0)
        defines.push_back({"STSV_PATTERN_VEC4S", std::to_string(patternVec4Count(plan))});
    if (alphaBitVec4s > 0) defines.push_back({"STSV_ALPHA_BIT_VEC4S", std::to_string(alphaBitVec4s)});
    return defines;
}

std::vector<ShaderDefine> sampleDefines(const RenderOptions& options, const SamplePlan& plan,
                                        std::size_t alphaBitVec4s) {
    std::vector<ShaderDefine> defines = layoutDefines(plan, alphaBitVec4s);
    defines.push_back({"SAMPLE_COUNT", std::to_string(options.samples)});
    defines.push_back({"STSV_COUNTERS", options.buffer == BufferKind::Counters ? "1" : "0"});
    return defines;
}

/// `defines` plus STSV_PATTERN_Q when the plan has one sample set (no interleaving) whose points
/// are all exact multiples of 2^-24 in [0,1): the set as 24-bit fixed-point integers baked into
/// the resolve (shaders/frame_bindings.glsl). Otherwise the shader reads the pattern buffer.
/// The resolve unrolls its sample loop with it (the constants need constant indices): 3x faster
/// at 64 and 128 samples on lavapipe (fence 1024²), but at 256 samples llvmpipe's lazy compile
/// of the unrolled shader made the first frame 4x slower, so not above 128 samples.
/// Only for the resolve: in stsv.frag the unrolled loop (texel tests, early continues) measured
/// 2-3x slower on lavapipe.
std::vector<ShaderDefine> withPatternDefine(std::vector<ShaderDefine> defines, const SamplePlan& plan) {
    if (plan.setCount() != 1 || plan.points.size() != std::size_t(plan.count) || plan.count > 128)
        return defines;
    std::string array = "uvec2[" + std::to_string(plan.points.size()) + "](";
    for (std::size_t k = 0; k < plan.points.size(); ++k) {
        const vec2 q = plan.points[k] * SAMPLING_FIXED_ONE;
        for (int c = 0; c < 2; ++c)
            if (!(q[c] >= 0.0f && q[c] < SAMPLING_FIXED_ONE && q[c] == std::floor(q[c]))) return defines;
        array += (k > 0 ? ",uvec2(" : "uvec2(") + std::to_string(std::uint32_t(q.x)) + "u," +
                 std::to_string(std::uint32_t(q.y)) + "u)";
    }
    defines.push_back({"STSV_PATTERN_Q", array + ")"});
    return defines;
}

/// The defines above plus FIXED_LIGHT_TYPE (sampling/light_sampling_dh.h): one resolve and one
/// STSV fragment shader per light type in the scene, with the type tests folded.
std::vector<ShaderDefine> lightTypeDefines(std::vector<ShaderDefine> defines, uint lightType) {
    defines.push_back({"FIXED_LIGHT_TYPE", std::to_string(lightType) + "u"});
    return defines;
}

/// The options the Vulkan frame runs with: the buffer kind the method writes.
RenderOptions vulkanOptions(RenderOptions options) {
    options.buffer = methodInfo(options.method).bufferKind(options.buffer);
    return options;
}

/// Whether the frame draws STSV volumes: the method sends triangles through STSV and the scene
/// has some of them (Algorithm 2).
bool drawsStsv(StsvTriangles which, const Scene& scene) {
    if (which == StsvTriangles::All) return true;
    if (which == StsvTriangles::None) return false;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t)
        if (scene.perforated(t)) return true;
    return false;
}

} // namespace

std::size_t lightSampleBufferBytes(const RenderOptions& options) {
    return LightSampleBuffer::payloadBytes(options.width, options.height, options.samples, options.buffer);
}

vec2 gpuDepthRange(const Scene& scene) {
    const Bounds box = scene.bounds();
    const float radius = 0.5f * length(box.extent());
    const float distance = length(box.center() - scene.camera.eye);
    const float zFar = std::max((distance + radius) * 1.01f, 1e-3f);
    const float zNear = std::max(0.99f * (distance - radius), 1e-3f * zFar);
    return {zNear, zFar};
}

mat4 gpuClipFromWorld(const Scene& scene, int width, int height) {
    const vec2 range = gpuDepthRange(scene);
    return clipFromView(scene.camera, float(width) / float(height), range.x, range.y) *
           viewFromWorld(scene.camera);
}

struct VulkanRenderer::Impl {
    const Scene& scene;
    RenderOptions options;
    std::unique_ptr<Device> ownDevice;
    Device* device = nullptr;
    bool mesh = false;
    SamplePlan plan;
    std::size_t lightCount = 0;
    std::uint32_t triangleCount = 0;
    std::size_t alphaBitVec4s = 0; ///< > 0: alpha as bits in a uniform buffer (alphaBitWords)

    DescriptorSetLayout setLayout;
    PipelineLayout pipelineLayout;
    Pipeline gbufferPipeline;
    /// Per light type (LIGHT_*): created for the types the scene has. resolvePipelines[0] also
    /// writes the ambient term of a scene without lights.
    std::array<Pipeline, 4> stsvPipelines;
    std::array<Pipeline, 4> resolvePipelines;
    GpuWedgePasses wedges;
    bool stsvPass = false; ///< drawsStsv

    Buffer triangles, alpha, textures, pattern, frameData, stats;
    std::vector<Buffer> counters; ///< per light (counters mode), else one dummy
    Image position, triangleId, depth, color, visibility, dummyMask;
    std::vector<std::vector<Image>> masks; ///< per light, maskAttachmentCount images (bitmask mode)
    std::vector<DescriptorSet> sets;       ///< per light (at least one)
    GpuTimer timer;
    CommandBuffer commands;
    double startupMs = 0.0;

    /// Readback: every output is copied into one host-visible buffer at the end of the frame's
    /// command buffer (no submit per image); byte offsets of each part.
    Buffer staging;
    struct StagingLayout {
        VkDeviceSize position = 0, color = 0, triangle = 0, visibility = 0, stats = 0;
        std::vector<std::vector<VkDeviceSize>> masks; ///< [light][attachment]
        std::vector<VkDeviceSize> counters;           ///< [light]
    } layout;

    Impl(const Scene& s, const RenderOptions& o, const VulkanRendererConfig& config)
        : scene(s), options(vulkanOptions(o)) {
        Timer startup;
        validate(options);
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
        if (config.extrusion == ExtrusionStage::Mesh && !info.meshShader)
            throw UsageError("Vulkan device " + info.name +
                             " lacks VK_EXT_mesh_shader (mesh-shader STSV extrusion)");
        mesh = config.extrusion == ExtrusionStage::Mesh ||
               (config.extrusion == ExtrusionStage::Auto && info.meshShader);
        if (!mesh && !info.geometryShader)
            throw UsageError("Vulkan device " + info.name + " has neither geometry nor mesh shaders");
        plan = makeSamplePlan(options.pattern, options.samples, options.seed, options.interleave,
                              options.decorrelate);
        lightCount = scene.lights.size();
        triangleCount = static_cast<std::uint32_t>(scene.triangleCount());
        stsvPass = drawsStsv(methodInfo(options.method).stsv, scene);

        uploadScene();
        createImages();
        createPipelines();
        writeDescriptors();
        createStaging();
        timer = GpuTimer(*device, 2 + 4 * std::uint32_t(lightCount) + 4);
        commands = CommandBuffer(*device);
        startupMs = startup.milliseconds();
    }

    void uploadScene() {
        const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        std::vector<GpuTriangle> tris(std::max<std::size_t>(scene.triangleCount(), 1));
        for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
            const uvec3 idx = scene.triangles[t];
            const Material& material = scene.materialOf(t);
            GpuTriangle& g = tris[t];
            g = {};
            g.v0 = vec4(scene.positions[idx.x], 1.0f);
            g.v1 = vec4(scene.positions[idx.y], 1.0f);
            g.v2 = vec4(scene.positions[idx.z], 1.0f);
            g.t0 = scene.texcoords[idx.x];
            g.t1 = scene.texcoords[idx.y];
            g.t2 = scene.texcoords[idx.z];
            // As volumes/stsv.cpp's stsvTriangleFor: texture 0 and STSV_FLAG_OPAQUE when not perforated.
            g.texture = material.perforated() ? static_cast<uint>(material.alphaTexture) : 0u;
            g.flags = (material.wrap == WrapMode::Clamp ? STSV_FLAG_CLAMP : 0u) |
                      (material.perforated() ? 0u : STSV_FLAG_OPAQUE) |
                      (material.doubleSided ? GPU_TRIANGLE_DOUBLE_SIDED : 0u);
            g.albedo = vec4(material.albedo, 0.0f);
        }
        triangles = createBuffer(*device, std::span<const GpuTriangle>(tris), storage);

        std::vector<GpuTexture> table(std::max<std::size_t>(scene.textures.size(), 1),
                                      GpuTexture{0, 1, 1, 0});
        const std::vector<std::uint32_t> bitWords = alphaBitWords(scene, table);
        alphaBitVec4s = bitWords.size() / 4;
        std::vector<std::uint8_t> bytes;
        for (std::size_t i = 0; i < scene.textures.size() && alphaBitVec4s == 0; ++i) {
            const Texture& tex = scene.textures[i];
            table[i] = {static_cast<uint>(bytes.size()), tex.width, tex.height, 0u};
            for (int y = 0; y < tex.height; ++y)
                for (int x = 0; x < tex.width; ++x) bytes.push_back(tex.alpha(x, y));
        }
        bytes.resize(std::max<std::size_t>((bytes.size() + 3) / 4 * 4, 4), 0);
        std::vector<std::uint32_t> words(bytes.size() / 4);
        std::memcpy(words.data(), bytes.data(), bytes.size());
        alpha = alphaBitVec4s > 0 ? createBuffer(*device, std::span<const std::uint32_t>(bitWords),
                                                 VkBufferUsageFlags(VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT))
                                  : createBuffer(*device, std::span<const std::uint32_t>(words), storage);
        textures = createBuffer(*device, std::span<const GpuTexture>(table), storage);
        std::vector<vec2> points = plan.points;
        points.resize(std::max<std::size_t>(2 * ((points.size() + 1) / 2), 2), vec2(0.0f)); // whole vec4s
        pattern = createBuffer(
            *device, std::span<const vec2>(points),
            patternVec4Count(plan) > 0 ? VkBufferUsageFlags(VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT) : storage);

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
        frame.lightCount = static_cast<uint>(lightCount);
        frame.lightWeight = lightCount > 0 ? 1.0f / float(lightCount) : 0.0f;
        std::vector<std::byte> frameBytes(sizeof(GpuFrame) +
                                          sizeof(GpuLight) * std::max<std::size_t>(lightCount, 1));
        std::memcpy(frameBytes.data(), &frame, sizeof(frame));
        for (std::size_t l = 0; l < lightCount; ++l) {
            const GpuLight light{scene.lights[l], lightBoundingSphere(scene.lights[l], box, farDistance)};
            std::memcpy(frameBytes.data() + sizeof(GpuFrame) + l * sizeof(GpuLight), &light, sizeof(light));
        }
        frameData = createBuffer(*device, std::span<const std::byte>(frameBytes), storage);
        stats = Buffer(*device, sizeof(GpuStats) * std::max<std::size_t>(lightCount, 1), storage,
                       MemoryUsage::DeviceLocal);
        const std::size_t counterBytes =
            options.buffer == BufferKind::Counters ? lightSampleBufferBytes(options) : 16;
        for (std::size_t l = 0; l < std::max<std::size_t>(lightCount, 1); ++l)
            counters.emplace_back(*device, counterBytes, storage, MemoryUsage::DeviceLocal);
    }

    void createImages() {
        const auto w = static_cast<uint32_t>(options.width), h = static_cast<uint32_t>(options.height);
        const VkImageUsageFlags attachment = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT;
        position = Image(*device, {w, h, POSITION_FORMAT, attachment});
        triangleId = Image(*device, {w, h, TRIANGLE_FORMAT, attachment});
        depth = Image(*device, {w, h, DEPTH_FORMAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT});
        color = Image(*device, {w, h, COLOR_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
        visibility = Image(*device, {w, h, VISIBILITY_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
        dummyMask = Image(*device, {1, 1, MASK_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
        masks.resize(std::max<std::size_t>(lightCount, 1));
        if (options.buffer == BufferKind::Bitmask)
            for (std::size_t l = 0; l < lightCount; ++l)
                for (int i = 0; i < maskAttachmentCount(options.samples); ++i)
                    masks[l].emplace_back(*device, ImageDesc{w, h, MASK_FORMAT, attachment});
    }

    void createStaging() {
        VkDeviceSize size = 0;
        auto place = [&size](VkDeviceSize bytes) { // 16-byte aligned: a multiple of every texel size
            const VkDeviceSize offset = size;
            size += (bytes + 15) / 16 * 16;
            return offset;
        };
        layout.position = place(position.byteSize());
        layout.color = place(color.byteSize());
        layout.triangle = place(triangleId.byteSize());
        layout.visibility = place(visibility.byteSize());
        layout.masks.resize(masks.size());
        for (std::size_t l = 0; l < masks.size(); ++l)
            for (const Image& image : masks[l]) layout.masks[l].push_back(place(image.byteSize()));
        if (options.buffer == BufferKind::Counters)
            for (std::size_t l = 0; l < lightCount; ++l) layout.counters.push_back(place(counters[l].size()));
        layout.stats = place(stats.size());
        staging = Buffer(*device, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceToHost);
    }

    /// Copies of every output into `staging`, then the barrier for the host reads.
    void recordReadback(VkCommandBuffer cmd) {
        position.recordCopyToBuffer(cmd, staging.handle(), layout.position);
        color.recordCopyToBuffer(cmd, staging.handle(), layout.color);
        triangleId.recordCopyToBuffer(cmd, staging.handle(), layout.triangle);
        visibility.recordCopyToBuffer(cmd, staging.handle(), layout.visibility);
        for (std::size_t l = 0; l < masks.size(); ++l)
            for (std::size_t i = 0; i < masks[l].size(); ++i)
                masks[l][i].recordCopyToBuffer(cmd, staging.handle(), layout.masks[l][i]);
        auto copyBuffer = [&](const Buffer& from, VkDeviceSize offset) {
            const VkBufferCopy region{0, offset, from.size()};
            vkCmdCopyBuffer(cmd, from.handle(), staging.handle(), 1, &region);
        };
        for (std::size_t l = 0; l < layout.counters.size(); ++l) copyBuffer(counters[l], layout.counters[l]);
        copyBuffer(stats, layout.stats);
        hostReadBarrier(cmd);
    }

    /// Light `l`'s staged bitmask attachments or counters into `buffer`.
    void unpackLightSamples(LightSampleBuffer& buffer, std::size_t l) const {
        const std::size_t pixels = std::size_t(options.width) * std::size_t(options.height);
        if (buffer.kind() == BufferKind::Counters) {
            std::vector<std::uint16_t>& out = buffer.counters();
            std::memcpy(out.data(), staged<std::uint16_t>(layout.counters[l]),
                        out.size() * sizeof(std::uint16_t));
            return;
        }
        // Attachment lsMaskAttachment(w) holds word w of each pixel in channel lsMaskComponent(w).
        const auto wordsPerPixel = std::size_t(buffer.wordsPerPixel());
        std::vector<std::uint32_t>& out = buffer.words();
        if (masks[l].size() == 1 && wordsPerPixel == 2) {
            std::memcpy(out.data(), staged<std::uint32_t>(layout.masks[l][0]),
                        pixels * 2 * sizeof(std::uint32_t));
            return;
        }
        for (std::size_t word = 0; word < wordsPerPixel; ++word) {
            const auto* pairs = staged<std::uint32_t>(layout.masks[l][lsMaskAttachment(uint(word))]);
            for (std::size_t p = 0; p < pixels; ++p)
                out[p * wordsPerPixel + word] = pairs[p * 2 + lsMaskComponent(uint(word))];
        }
    }

    template <class T> const T* staged(VkDeviceSize offset) const {
        return reinterpret_cast<const T*>(static_cast<const std::byte*>(staging.mapped()) + offset);
    }

    void createPipelines() {
        std::vector<DescriptorBinding> bindings;
        for (uint32_t b : {GPU_BINDING_TRIANGLES, GPU_BINDING_TEXTURES, GPU_BINDING_FRAME,
                           GPU_BINDING_COUNTERS, GPU_BINDING_STATS})
            bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1});
        bindings.push_back(
            {GPU_BINDING_ALPHA,
             alphaBitVec4s > 0 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
             VK_SHADER_STAGE_ALL, 1});
        bindings.push_back({GPU_BINDING_PATTERN,
                            patternVec4Count(plan) > 0 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                                                       : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                            VK_SHADER_STAGE_ALL, 1});
        for (uint32_t b :
             {GPU_BINDING_POSITION, GPU_BINDING_TRIANGLE_ID, GPU_BINDING_COLOR, GPU_BINDING_VISIBILITY})
            bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1});
        bindings.push_back(
            {GPU_BINDING_MASKS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, GPU_MAX_MASK_IMAGES});
        for (const DescriptorBinding& b : GpuWedgePasses::bindings()) bindings.push_back(b);
        setLayout = DescriptorSetLayout(*device, bindings);
        pipelineLayout = PipelineLayout(*device, {setLayout.handle()}, sizeof(GpuPush));

        const ShaderCompiler compiler;
        const std::vector<ShaderDefine> defines = sampleDefines(options, plan, alphaBitVec4s);
        const std::vector<ShaderDefine> common = layoutDefines(plan, alphaBitVec4s);

        GraphicsPipelineDesc gbuffer;
        gbuffer.stages = {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("gbuffer.vert", common)},
                          {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("gbuffer.frag", common)}};
        gbuffer.colorFormats = {POSITION_FORMAT, TRIANGLE_FORMAT};
        gbuffer.depthFormat = DEPTH_FORMAT;
        gbuffer.depthTest = true;
        gbuffer.depthWrite = true;
        gbuffer.depthCompare = VK_COMPARE_OP_LESS;
        gbufferPipeline = createGraphicsPipeline(*device, pipelineLayout, gbuffer);

        // STSV pass (DESIGN §4.2): back faces of the convex volume behind the visible point, no
        // depth write, depth clamp (the far extrusion may pass the far plane): one fragment per
        // pixel and volume.
        GraphicsPipelineDesc stsv;
        std::vector<ShaderDefine> fragmentDefines = defines;
        if (mesh) {
            fragmentDefines.push_back({"STSV_MESH_PATH", "1"});
            stsv.stages = {{VK_SHADER_STAGE_MESH_BIT_EXT, compiler.compileFile("stsv.mesh", common)}};
        } else {
            stsv.stages = {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("stsv.vert", common)},
                           {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("stsv.geom", common)}};
        }
        stsv.stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, {}});
        if (options.buffer == BufferKind::Bitmask) {
            stsv.colorFormats.assign(std::size_t(maskAttachmentCount(options.samples)), MASK_FORMAT);
            stsv.logicOpEnable = true;
            stsv.logicOp = VK_LOGIC_OP_OR;
        }
        stsv.depthFormat = DEPTH_FORMAT;
        stsv.depthTest = true;
        stsv.depthWrite = false;
        stsv.depthCompare = VK_COMPARE_OP_GREATER;
        stsv.depthClamp = true;
        // The strip faces outward (counter-clockwise seen from outside, extrusion_dh.h); the
        // y-down clip space keeps that orientation in framebuffer coordinates, so the back faces
        // are the clockwise ones.
        stsv.cullMode = VK_CULL_MODE_FRONT_BIT;
        stsv.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
        std::vector<ShaderDefine> resolveDefines = defines;
        resolveDefines.push_back(
            {"RESOLVE_COVERAGE", methodInfo(options.method).output == MethodOutput::Visibility ? "1" : "0"});
        std::array<bool, 4> used{};
        for (const Light& light : scene.lights) used.at(light.type) = true;
        if (lightCount == 0) used[0] = true;
        for (uint type = 0; type < used.size(); ++type) {
            if (!used[type]) continue;
            if (lightCount > 0) {
                stsv.stages.back().spirv =
                    compiler.compileFile("stsv.frag", lightTypeDefines(fragmentDefines, type));
                stsvPipelines[type] = createGraphicsPipeline(*device, pipelineLayout, stsv);
            }
            resolvePipelines[type] = createComputePipeline(
                *device, pipelineLayout,
                compiler.compileFile("resolve.comp",
                                     lightTypeDefines(withPatternDefine(resolveDefines, plan), type)));
        }
        wedges = GpuWedgePasses(*device, scene, options, pipelineLayout, defines);
    }

    void writeDescriptors() {
        for (std::size_t l = 0; l < std::max<std::size_t>(lightCount, 1); ++l) {
            DescriptorSet& set = sets.emplace_back(*device, setLayout);
            set.writeBuffer(GPU_BINDING_TRIANGLES, triangles);
            set.writeBuffer(GPU_BINDING_ALPHA, alpha);
            set.writeBuffer(GPU_BINDING_TEXTURES, textures);
            set.writeBuffer(GPU_BINDING_PATTERN, pattern);
            set.writeBuffer(GPU_BINDING_FRAME, frameData);
            set.writeBuffer(GPU_BINDING_COUNTERS, counters[l]);
            set.writeBuffer(GPU_BINDING_STATS, stats);
            set.writeStorageImage(GPU_BINDING_POSITION, position);
            set.writeStorageImage(GPU_BINDING_TRIANGLE_ID, triangleId);
            set.writeStorageImage(GPU_BINDING_COLOR, color);
            set.writeStorageImage(GPU_BINDING_VISIBILITY, visibility);
            for (uint32_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i) {
                const Image& image = i < masks[l].size() ? masks[l][i] : dummyMask;
                set.writeStorageImage(GPU_BINDING_MASKS, image, VK_IMAGE_LAYOUT_GENERAL, i);
            }
            wedges.writeDescriptors(set);
        }
    }

    void bind(VkCommandBuffer cmd, VkPipelineBindPoint point, std::size_t light) {
        VkDescriptorSet handle = sets[light].handle();
        vkCmdBindDescriptorSets(cmd, point, pipelineLayout.handle(), 0, 1, &handle, 0, nullptr);
    }

    void push(VkCommandBuffer cmd, uint light, uint initialize, uint flags = 0u) {
        const GpuPush p{light, initialize, flags, 0u};
        pipelineLayout.push(cmd, &p, sizeof(p));
    }

    void drawVolumes(VkCommandBuffer cmd) {
        if (triangleCount == 0) return;
        if (!mesh) {
            vkCmdDraw(cmd, 3 * triangleCount, 1, 0, 0);
            return;
        }
        // Workgroups in rows of at most 65535 (the minimum maxMeshWorkGroupCount[0]).
        const uint32_t rowLength = std::min<uint32_t>(triangleCount, 65535u);
        device->cmdDrawMeshTasks()(cmd, rowLength, (triangleCount + rowLength - 1) / rowLength, 1);
    }

    void record(VkCommandBuffer cmd) {
        timer.reset(cmd);
        vkCmdFillBuffer(cmd, stats.handle(), 0, VK_WHOLE_SIZE, 0);
        if (options.buffer == BufferKind::Counters)
            for (std::size_t l = 0; l < lightCount; ++l)
                vkCmdFillBuffer(cmd, counters[l].handle(), 0, VK_WHOLE_SIZE, 0);
        fullBarrier(cmd);

        // Pass 0: G-buffer (ambient is written by the first resolve).
        timer.begin(cmd, "gbuffer");
        {
            VkClearColorValue noTriangle{};
            noTriangle.uint32[0] = NO_TRIANGLE;
            const ColorTarget targets[] = {{&position, true, {}}, {&triangleId, true, noTriangle}};
            beginRendering(cmd, targets, DepthTarget{&depth, true, 1.0f, false});
            gbufferPipeline.bind(cmd);
            bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, 0);
            push(cmd, 0u, 0u);
            if (triangleCount > 0) vkCmdDraw(cmd, 3 * triangleCount, 1, 0, 0);
            endRendering(cmd);
        }
        timer.end(cmd);
        position.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        triangleId.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        color.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        visibility.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        dummyMask.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
        wedges.prepare(cmd);
        fullBarrier(cmd);

        // resolve.comp works on 16 × 16 tiles (fewer, larger workgroups: lavapipe pays per workgroup).
        const uint32_t groupsX = (uint32_t(options.width) + 15) / 16,
                       groupsY = (uint32_t(options.height) + 15) / 16;
        for (std::size_t l = 0; l < lightCount; ++l) {
            const std::string prefix = "light" + std::to_string(l) + "/";
            if (wedges.enabled()) {
                // Algorithm 2, lines 4–7 and 11: the opaque triangles through DCS or PW.
                bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, l);
                push(cmd, uint(l), 0u);
                wedges.recordOcclusion(
                    cmd, depth, triangleCount, timer,
                    prefix + (methodInfo(options.method).opaque == OpaqueTechnique::Pw ? "pw_" : "dcs_"));
            }
            std::vector<ColorTarget> targets; // bitmask attachments, cleared by the pass
            for (Image& image : masks[l]) targets.push_back({&image, true, {}});
            if (stsvPass) {
                timer.begin(cmd, prefix + "stsv");
                beginRendering(cmd, targets, DepthTarget{&depth, false, 1.0f, true});
                stsvPipelines.at(scene.lights[l].type).bind(cmd);
                bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, l);
                push(cmd, uint(l), 0u,
                     methodInfo(options.method).stsv == StsvTriangles::Perforated ? GPU_PUSH_PERFORATED_ONLY
                                                                                  : 0u);
                drawVolumes(cmd);
                endRendering(cmd);
                timer.end(cmd);
            } else if (!targets.empty()) {
                // No STSV volumes to draw: the buffer is only cleared (pw: every sample lit).
                beginRendering(cmd, targets, DepthTarget{&depth, false, 1.0f, true});
                endRendering(cmd);
            }
            for (Image& image : masks[l]) image.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
            fullBarrier(cmd);
            if (wedges.enabled()) {
                timer.begin(cmd, prefix + "fold");
                bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, l);
                push(cmd, uint(l), 0u);
                wedges.recordFold(cmd);
                timer.end(cmd);
            }

            timer.begin(cmd, prefix + "resolve");
            resolvePipelines.at(scene.lights[l].type).bind(cmd);
            bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, l);
            push(cmd, uint(l), l == 0 ? 1u : 0u);
            vkCmdDispatch(cmd, groupsX, groupsY, 1);
            timer.end(cmd);
            fullBarrier(cmd);
        }
        if (lightCount == 0) {
            timer.begin(cmd, "ambient");
            resolvePipelines[0].bind(cmd);
            bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, 0);
            push(cmd, 0xffffffffu, 1u);
            vkCmdDispatch(cmd, groupsX, groupsY, 1);
            timer.end(cmd);
            fullBarrier(cmd);
        }
        timer.begin(cmd, "copy");
        recordReadback(cmd);
        timer.end(cmd);
    }

    Frame render() {
        Timer total;
        Frame frame;
        VkCommandBuffer cmd = commands.begin();
        record(cmd);
        Timer gpu;
        commands.submitAndWait();
        const double gpuMs = gpu.milliseconds();

        nlohmann::json passes = nlohmann::json::object();
        for (const GpuTiming& t : timer.results()) passes[t.name] = t.milliseconds;

        Timer readback;
        const int w = options.width, h = options.height;
        const std::size_t pixels = std::size_t(w) * h;
        const auto* positions = staged<vec4>(layout.position);
        const auto* rgba = staged<vec4>(layout.color);
        const auto* tris = staged<std::uint32_t>(layout.triangle);
        // The outputs are fresh allocations whose first touch (page faults) costs more than the
        // copying: build them on all cores, one output per task, then the normals per pixel.
        const std::function<void()> jobs[] = {
            [&] {
                frame.gbuffer = GBuffer(w, h);
                std::memcpy(frame.gbuffer.triangle.data(), tris, pixels * sizeof(std::uint32_t));
            },
            [&] {
                frame.color = ImageF(w, h, 3);
                for (std::size_t i = 0; i < pixels; ++i)
                    for (int c = 0; c < 3; ++c) frame.color.pixels[3 * i + std::size_t(c)] = rgba[i][c];
            },
            [&] {
                frame.visibility = ImageF(w, h, 1);
                std::memcpy(frame.visibility.pixels.data(), staged<float>(layout.visibility),
                            pixels * sizeof(float));
            },
            [&] {
                for (std::size_t l = 0; l < lightCount; ++l)
                    unpackLightSamples(frame.lightSamples.emplace_back(w, h, options.samples, options.buffer),
                                       l);
            }};
        parallelFor(std::size(jobs), [&](std::size_t j) { jobs[j](); });
        parallelForChunks(pixels, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                if (!frame.gbuffer.covered(i)) continue;
                frame.gbuffer.position[i] = vec3(positions[i]);
                frame.gbuffer.normal[i] =
                    shadingNormal(scene, tris[i], scene.camera.eye, frame.gbuffer.position[i]);
            }
        });
        const auto* statsBegin = staged<GpuStats>(layout.stats);
        const std::vector<GpuStats> counts(statsBegin, statsBegin + std::max<std::size_t>(lightCount, 1));
        passes["readback"] = readback.milliseconds();

        nlohmann::json stsvStats = nlohmann::json::array();
        nlohmann::json wedgeStats = nlohmann::json::array();
        for (std::size_t l = 0; l < lightCount; ++l) {
            stsvStats.push_back({{"fragments", counts[l].fragments}, {"inside_fragments", counts[l].inside}});
            wedgeStats.push_back({{"edges", wedges.edgeCount()},
                                  {"fragments", counts[l].wedgeFragments},
                                  {"silhouette_fragments", counts[l].wedgeInside}});
        }
        frame.stats = {{"options", toJson(options)},
                       {"scene", sceneStats(scene)},
                       {"startup_ms", startupMs},
                       {"frame_ms", total.milliseconds()},
                       {"gpu_ms", gpuMs},
                       {"passes", passes},
                       {"light_sample_buffer_bytes", lightSampleBufferBytes(options)},
                       {"stsv", stsvStats},
                       {"gpu",
                        {{"device", device->info().name},
                         {"extrusion", mesh ? "mesh shader" : "geometry shader"},
                         {"fragment_counts", "atomic counters in stsv.frag"}}}};
        if (wedges.enabled()) frame.stats["wedges"] = wedgeStats;
        return frame;
    }
};

VulkanRenderer::VulkanRenderer(const Scene& scene, const RenderOptions& options,
                               const VulkanRendererConfig& config)
    : m_impl(std::make_unique<Impl>(scene, options, config)) {}

VulkanRenderer::~VulkanRenderer() {
    if (m_impl && m_impl->device) m_impl->device->waitIdle();
}

Frame VulkanRenderer::render() {
    return m_impl->render();
}

const Device& VulkanRenderer::device() const {
    return *m_impl->device;
}

bool VulkanRenderer::usesMeshShader() const {
    return m_impl->mesh;
}

} // namespace stsv
