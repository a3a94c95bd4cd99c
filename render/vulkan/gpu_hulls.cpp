#include "render/vulkan/gpu_hulls.h"

#include "core/error.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 VERTEX = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr VkDeviceSize TEXEL_BYTES = 16; ///< rgba32ui

/// Shared memory of one polyhedron being clipped (clip_box_dh.h with CLIP_SHARED_INVOCATIONS):
/// its corners, one face and a cut's entry and exit points, counted at 16 bytes a vec3.
constexpr std::uint32_t CLIP_SHARED_BYTES =
    ((CLIP_MAX_FACES + 1) * CLIP_MAX_FACE_VERTICES + 2 * CLIP_MAX_FACES) * 16;

/// Threads of the hull shaders' workgroups (CLIP_SHARED_INVOCATIONS): 8, a SIMD batch of
/// lavapipe, or fewer where the device's shared memory cannot hold 8 polyhedra being clipped
/// and the queue of their items.
std::uint32_t hullThreadsPerGroup(const Device& device) {
    constexpr std::uint32_t bytesPerThread = CLIP_SHARED_BYTES + GPU_HULL_MAX_ITEMS_PER_THREAD * 4;
    std::uint32_t threads = 8;
    while (threads > 1 && threads * bytesPerThread > device.limits().maxComputeSharedMemorySize) threads /= 2;
    return threads;
}

/// Items per thread of the hull passes (HULL_ITEMS_PER_THREAD): on a CPU device 16, so that a
/// workgroup of the wedge pass, where most carriers have no potential silhouette, queues two or
/// three full batches (knot: wedge hulls 68-71 ms with 8, 50-66 with 16, alternated runs); on a
/// GPU 4, for more workgroups in flight.
std::uint32_t hullItemsPerThread(const Device& device) {
    return device.info().type == VK_PHYSICAL_DEVICE_TYPE_CPU ? GPU_HULL_MAX_ITEMS_PER_THREAD : 4u;
}

/// The items a task workgroup culls (HULL_TASK_ITEMS).
constexpr std::uint32_t TASK_ITEMS = 32;

/// Volumes a mesh workgroup builds and emits (HULL_MESH_VOLUMES): 3 (the most whose corners fit the
/// compiler's 256 output vertices), or fewer where the device's
/// limits cannot hold that many hulls at their largest (render/shaders/hull_mesh.glsl: 6F − 12 corners
/// and 4F − 12 triangles of F = CLIP_MAX_FACES faces, each triangle with an 18-texel record and
/// its indices) or their clipping in shared memory (as hullThreadsPerGroup).
std::uint32_t meshVolumesPerGroup(const DeviceInfo& info) {
    constexpr std::uint32_t corners = 6 * CLIP_MAX_FACES - 12;
    constexpr std::uint32_t triangles = CLIP_MAX_TRIANGLES;
    constexpr std::uint32_t outputBytes = corners * 16 + triangles * (GPU_HULL_RECORD_TEXELS * 16 + 16);
    constexpr std::uint32_t sharedBytes = CLIP_SHARED_BYTES + 8; // and its corner and triangle counts
    const auto fits = [&](std::uint32_t k) {
        return k * corners <= info.maxMeshOutputVertices && k * triangles <= info.maxMeshOutputPrimitives &&
               k * outputBytes <= info.maxMeshOutputMemorySize &&
               k * sharedBytes <= info.maxMeshSharedMemorySize;
    };
    std::uint32_t volumes = 3;
    while (volumes > 1 && !fits(volumes)) --volumes;
    if (!fits(volumes))
        throw UsageError("Vulkan device " + info.name +
                         "'s mesh shader limits cannot hold one volume's hull; use --extrusion hull");
    return volumes;
}

} // namespace

const char* toString(VolumeGeometry geometry) {
    switch (geometry) {
    case VolumeGeometry::GeometryShaderPrism:
        return "geometry shader";
    case VolumeGeometry::MeshShaderHull:
        return "mesh shader hull";
    case VolumeGeometry::ComputeHull:
        return "hull (compute)";
    }
    return "?";
}

std::vector<ShaderStage> meshHullStages(const Device& device, const std::string& shader,
                                        const std::vector<ShaderDefine>& defines) {
    std::vector<ShaderDefine> sized = defines;
    sized.push_back({"HULL_TASK_ITEMS", std::to_string(TASK_ITEMS)});
    sized.push_back({"HULL_MESH_VOLUMES", std::to_string(meshVolumesPerGroup(device.info()))});
    const ShaderCompiler compiler;
    return {{VK_SHADER_STAGE_TASK_BIT_EXT, compiler.compileFile(shader + ".task", sized)},
            {VK_SHADER_STAGE_MESH_BIT_EXT, compiler.compileFile(shader + ".mesh", sized)}};
}

void recordMeshHullDraw(const Device& device, VkCommandBuffer cmd, std::uint32_t items) {
    // A task workgroup a TASK_ITEMS sides, in rows of at most 65535 workgroups (the minimum
    // maxTaskWorkGroupCount[0]); hull_mesh.glsl numbers them row by row.
    const std::uint64_t groups = (2ull * items + TASK_ITEMS - 1) / TASK_ITEMS;
    if (groups == 0) return;
    const auto rowLength = static_cast<std::uint32_t>(std::min<std::uint64_t>(
        {groups, 65535, std::max<std::uint32_t>(device.info().maxTaskWorkGroupCountX, 1)}));
    device.cmdDrawMeshTasks()(cmd, rowLength,
                              static_cast<std::uint32_t>((groups + rowLength - 1) / rowLength), 1);
}

HullResources::HullResources(const Device& device) : m_device(&device) {
    draw = Buffer(device, sizeof(GpuHullDraw), STORAGE | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                  MemoryUsage::DeviceLocal);
    resize(1, 1);
}

std::vector<DescriptorBinding> HullResources::bindings() {
    return {
        {GPU_BINDING_HULL_DRAW, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_HULL_RECORDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_HULL_VERTICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_HULL_RECORD_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_HULL_VERTEX_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void HullResources::writeDescriptors(DescriptorSet& set) const {
    set.writeBuffer(GPU_BINDING_HULL_DRAW, draw);
    set.writeBuffer(GPU_BINDING_HULL_RECORDS, records);
    set.writeBuffer(GPU_BINDING_HULL_VERTICES, vertices);
    set.writeTexelBuffer(GPU_BINDING_HULL_RECORD_TEXELS, recordTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_HULL_VERTEX_TEXELS, vertexTexels.handle());
}

void HullResources::resize(std::uint64_t recordCount, std::uint64_t triangles) {
    m_recordCapacity = std::max<std::uint64_t>(recordCount, 1);
    m_triangleCapacity = std::max<std::uint64_t>(triangles, 1);
    // Lengths in the shaders are 32-bit.
    if (3 * m_triangleCapacity > 0xffffffffull || m_recordCapacity * GPU_HULL_RECORD_TEXELS > 0xffffffffull)
        throw UsageError("the volumes' hulls need " + std::to_string(m_triangleCapacity) + " triangles of " +
                         std::to_string(m_recordCapacity) +
                         " volumes, more than one buffer holds; use --extrusion geometry");
    constexpr VkBufferUsageFlags TEXELS = STORAGE | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    records = Buffer(*m_device, m_recordCapacity * GPU_HULL_RECORD_TEXELS * TEXEL_BYTES, TEXELS,
                     MemoryUsage::DeviceLocal);
    vertices = Buffer(*m_device, 3 * m_triangleCapacity * TEXEL_BYTES, TEXELS, MemoryUsage::DeviceLocal);
    recordTexels = BufferView(*m_device, records, VK_FORMAT_R32G32B32A32_UINT, TEXEL_BYTES);
    vertexTexels = BufferView(*m_device, vertices, VK_FORMAT_R32G32B32A32_UINT, TEXEL_BYTES);
}

void HullResources::size(PassRecorder& recorder, CommandBuffer& commands, std::size_t lights,
                         const std::vector<const HullPass*>& passes) {
    std::vector<const Buffer*> stats;
    stats.reserve(passes.size());
    for (const HullPass* pass : passes) stats.push_back(&pass->family().stats());
    const ClearPass clearStats({}, stats);
    const ClearPass clearDraw({}, {&draw});
    VkCommandBuffer cmd = commands.begin();
    runPass(recorder, cmd, "", clearStats);
    for (std::size_t l = 0; l < lights; ++l)
        for (const HullPass* pass : passes) {
            runPass(recorder, cmd, "", clearDraw, l);
            runPass(recorder, cmd, "", *pass, l);
        }
    PassAccesses host;
    for (const Buffer* buffer : stats) host.use(*buffer, ResourceUse::hostRead());
    recorder.addPass(cmd, "", host, [](VkCommandBuffer) {});
    commands.submitAndWait();
    std::uint64_t volumes = 0, triangles = 0;
    for (const HullPass* pass : passes) {
        const FamilyDescriptors& family = pass->family();
        const std::vector<std::byte> bytes = family.stats().download<std::byte>();
        for (std::size_t l = 0; l < lights; ++l) {
            GpuHullCounts counts;
            std::memcpy(&counts, bytes.data() + l * family.statsStride(), sizeof counts);
            volumes = std::max<std::uint64_t>(volumes, counts.volumes);
            triangles = std::max<std::uint64_t>(triangles, counts.triangles);
        }
    }
    resize(volumes, triangles);
}

void HullResources::checkCapacity(std::size_t light, const char* pass, std::uint64_t volumes,
                                  std::uint64_t triangles) const {
    if (volumes > m_recordCapacity || triangles > m_triangleCapacity)
        throw Error("internal error: light " + std::to_string(light) + "'s " + pass + " hulls (" +
                    std::to_string(volumes) + " volumes, " + std::to_string(triangles) +
                    " triangles) outgrew the buffers sized at start-up");
}

void HullResources::reportCounts(VolumeGeometry geometry, std::size_t light, const char* pass,
                                 const GpuHullCounts& counts, nlohmann::json& out) const {
    switch (geometry) {
    case VolumeGeometry::GeometryShaderPrism:
        return;
    case VolumeGeometry::ComputeHull:
        checkCapacity(light, pass, counts.volumes, counts.triangles);
        break;
    case VolumeGeometry::MeshShaderHull:
        if (counts.overflow > 0)
            throw Error("light " + std::to_string(light) + "'s " + pass + " mesh shader met " +
                        std::to_string(counts.overflow) +
                        " volume hulls with more corners or triangles than a convex hull of " +
                        std::to_string(CLIP_MAX_FACES) +
                        " faces has, and drew none of them; use --extrusion hull");
        break;
    }
    out["hull_volumes"] = counts.volumes;
    out["hull_triangles"] = counts.triangles;
}

void HullResources::declareDrawReads(PassAccesses& accesses) const {
    accesses.use(draw, ResourceUse::indirectRead())
        .use(vertices, ResourceUse::sampledRead(VERTEX))
        .use(records, ResourceUse::sampledRead(FRAGMENT));
}

void HullResources::recordDraw(VkCommandBuffer cmd) const {
    vkCmdDrawIndirect(cmd, draw.handle(), 0, 1, sizeof(VkDrawIndirectCommand));
}

HullPass::HullPass(const Device& device, const std::string& shader, const std::vector<ShaderDefine>& defines,
                   std::uint32_t items, std::uint32_t pushFlags, HullResources& hulls,
                   const FamilyDescriptors& descriptors, std::vector<const Buffer*> writes)
    : m_hulls(&hulls), m_descriptors(&descriptors), m_writes(std::move(writes)), m_items(items),
      m_pushFlags(pushFlags), m_threadsPerGroup(hullThreadsPerGroup(device)),
      m_itemsPerThread(hullItemsPerThread(device)) {
    std::vector<ShaderDefine> withThreads = defines;
    withThreads.push_back({"CLIP_SHARED_INVOCATIONS", std::to_string(m_threadsPerGroup)});
    withThreads.push_back({"HULL_ITEMS_PER_THREAD", std::to_string(m_itemsPerThread)});
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile(shader, withThreads));
}

PassAccesses HullPass::accesses(std::size_t) const {
    PassAccesses accesses;
    accesses.use(m_hulls->draw, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_hulls->records, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_hulls->vertices, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    for (const Buffer* buffer : m_writes) accesses.use(*buffer, ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void HullPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, m_pushFlags, 0u});
    // m_itemsPerThread sides of items per thread, in rows of at most 65535 workgroups (the
    // minimum maxComputeWorkGroupCount[0]); the shaders number the workgroups row by row.
    const std::uint64_t perGroup = std::uint64_t(m_threadsPerGroup) * m_itemsPerThread;
    const std::uint64_t groups = (2ull * m_items + perGroup - 1) / perGroup;
    const auto rowLength = static_cast<std::uint32_t>(std::min<std::uint64_t>(groups, 65535));
    if (groups > 0)
        vkCmdDispatch(cmd, rowLength, static_cast<std::uint32_t>((groups + rowLength - 1) / rowLength), 1);
}

} // namespace stsv
