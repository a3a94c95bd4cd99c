#include "render/vulkan/gpu_readback.h"

#include "sampling/ls_buffer_dh.h"

#include "core/parallel.h"
#include "scene/scene.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <iterator>
#include <utility>

namespace stsv {

FrameReadback::FrameReadback(const Device& device, const Scene& scene, const RenderOptions& options,
                             FrameResources& resources, std::vector<const Buffer*> stats)
    : m_scene(&scene), m_options(options), m_resources(&resources), m_stats(std::move(stats)) {
    VkDeviceSize size = 0;
    auto place = [&size](VkDeviceSize bytes) { // 16-byte aligned: a multiple of every texel size
        const VkDeviceSize offset = size;
        size += (bytes + 15) / 16 * 16;
        return offset;
    };
    m_layout.position = place(resources.gbuffer.position.byteSize());
    m_layout.color = place(resources.color.byteSize());
    m_layout.triangle = place(resources.gbuffer.triangleId.byteSize());
    m_layout.visibility = place(resources.visibility.byteSize());
    const auto& masks = resources.samples.masks;
    m_layout.masks.resize(masks.size());
    for (std::size_t l = 0; l < masks.size(); ++l)
        for (const Image& image : masks[l]) m_layout.masks[l].push_back(place(image.byteSize()));
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        if (frameCountsLayers(options))
            m_layout.counters.push_back(place(resources.samples.counters[l].size()));
        if (options.buffer == BufferKind::Transmittance)
            m_layout.depths.push_back(place(resources.samples.depths[l].size()));
    }
    for (const Buffer* buffer : m_stats) m_layout.stats.push_back(place(buffer->size()));
    m_staging = Buffer(device, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceToHost);
}

PassAccesses FrameReadback::accesses(std::size_t) const {
    FrameResources& r = *m_resources;
    PassAccesses accesses;
    accesses.use(r.gbuffer.position, ResourceUse::transferRead())
        .use(r.color, ResourceUse::transferRead())
        .use(r.gbuffer.triangleId, ResourceUse::transferRead())
        .use(r.visibility, ResourceUse::transferRead());
    for (auto& images : r.samples.masks)
        for (Image& image : images) accesses.use(image, ResourceUse::transferRead());
    for (std::size_t l = 0; l < m_layout.counters.size(); ++l)
        accesses.use(r.samples.counters[l], ResourceUse::transferRead());
    for (std::size_t l = 0; l < m_layout.depths.size(); ++l)
        accesses.use(r.samples.depths[l], ResourceUse::transferRead());
    for (const Buffer* buffer : m_stats) accesses.use(*buffer, ResourceUse::transferRead());
    accesses.use(m_staging, ResourceUse::transferWrite());
    return accesses;
}

void FrameReadback::record(VkCommandBuffer cmd, std::size_t) const {
    FrameResources& r = *m_resources;
    const VkBuffer staging = m_staging.handle();
    r.gbuffer.position.recordCopyToBuffer(cmd, staging, m_layout.position);
    r.color.recordCopyToBuffer(cmd, staging, m_layout.color);
    r.gbuffer.triangleId.recordCopyToBuffer(cmd, staging, m_layout.triangle);
    r.visibility.recordCopyToBuffer(cmd, staging, m_layout.visibility);
    for (std::size_t l = 0; l < r.samples.masks.size(); ++l)
        for (std::size_t i = 0; i < r.samples.masks[l].size(); ++i)
            r.samples.masks[l][i].recordCopyToBuffer(cmd, staging, m_layout.masks[l][i]);
    auto copyBuffer = [&](const Buffer& from, VkDeviceSize offset) {
        const VkBufferCopy region{0, offset, from.size()};
        vkCmdCopyBuffer(cmd, from.handle(), staging, 1, &region);
    };
    for (std::size_t l = 0; l < m_layout.counters.size(); ++l)
        copyBuffer(r.samples.counters[l], m_layout.counters[l]);
    for (std::size_t l = 0; l < m_layout.depths.size(); ++l)
        copyBuffer(r.samples.depths[l], m_layout.depths[l]);
    for (std::size_t i = 0; i < m_stats.size(); ++i) copyBuffer(*m_stats[i], m_layout.stats[i]);
}

PassAccesses FrameReadback::hostAccesses() const {
    PassAccesses accesses;
    accesses.use(m_staging, ResourceUse::hostRead());
    return accesses;
}

void FrameReadback::unpack(Frame& frame) const {
    const int w = m_options.width, h = m_options.height;
    const std::size_t pixels = std::size_t(w) * h;
    const std::size_t lightCount = m_scene->lights.size();
    const auto* positions = staged<vec4>(m_layout.position);
    const auto* rgba = staged<vec4>(m_layout.color);
    const auto* tris = staged<std::uint32_t>(m_layout.triangle);
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
            std::memcpy(frame.visibility.pixels.data(), staged<float>(m_layout.visibility),
                        pixels * sizeof(float));
        },
        [&] {
            for (std::size_t l = 0; l < lightCount; ++l)
                unpackLightSamples(frame.lightSamples.emplace_back(w, h, m_options.samples, m_options.buffer),
                                   l);
        }};
    parallelFor(std::size(jobs), [&](std::size_t j) { jobs[j](); });
    parallelForChunks(pixels, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (!frame.gbuffer.covered(i)) continue;
            frame.gbuffer.position[i] = vec3(positions[i]);
            frame.gbuffer.normal[i] =
                shadingNormal(*m_scene, tris[i], m_scene->camera.eye, frame.gbuffer.position[i]);
        }
    });
}

void FrameReadback::unpackLightSamples(LightSampleBuffer& buffer, std::size_t l) const {
    const std::size_t pixels = std::size_t(m_options.width) * std::size_t(m_options.height);
    if (buffer.kind() == BufferKind::Counters) {
        std::vector<std::uint16_t>& out = buffer.counters();
        std::memcpy(out.data(), staged<std::uint16_t>(m_layout.counters[l]),
                    out.size() * sizeof(std::uint16_t));
        return;
    }
    // Attachment lsMaskAttachment(w) holds word w of each pixel in channel lsMaskComponent(w).
    const auto wordsPerPixel = std::size_t(buffer.wordsPerPixel());
    std::vector<std::uint32_t>& out = buffer.words();
    const std::vector<VkDeviceSize>& masks = m_layout.masks[l];
    if (masks.size() == 1 && wordsPerPixel == 2) {
        std::memcpy(out.data(), staged<std::uint32_t>(masks[0]), pixels * 2 * sizeof(std::uint32_t));
    } else {
        for (std::size_t word = 0; word < wordsPerPixel; ++word) {
            const auto* pairs = staged<std::uint32_t>(masks[lsMaskAttachment(uint(word))]);
            for (std::size_t p = 0; p < pixels; ++p)
                out[p * wordsPerPixel + word] = pairs[p * 2 + lsMaskComponent(uint(word))];
        }
    }
    if (buffer.kind() != BufferKind::Transmittance) return;
    // A sample behind one of DCS's layers is occluded; an occluded sample's sum means nothing
    // (the shaders stop at its bit, LightSampleBuffer::addOpticalDepth) and reads 0, as the CPU's.
    const auto samples = std::size_t(m_options.samples);
    const auto* counters = m_layout.counters.empty() ? nullptr : staged<std::uint16_t>(m_layout.counters[l]);
    std::vector<std::uint32_t>& depths = buffer.depths();
    std::memcpy(depths.data(), staged<std::uint32_t>(m_layout.depths[l]),
                depths.size() * sizeof(std::uint32_t));
    parallelForChunks(pixels, [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p)
            for (std::size_t k = 0; k < samples; ++k) {
                const std::size_t slot = lsCounterSlot(uint(p), uint(samples), uint(k));
                std::uint32_t& word = out[p * wordsPerPixel + lsMaskWord(uint(k))];
                if (counters && counters[slot] != 0) word |= lsMaskBit(uint(k));
                if (word & lsMaskBit(uint(k))) depths[slot] = 0;
            }
    });
}

} // namespace stsv
