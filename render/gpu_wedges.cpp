#include "render/gpu_wedges.h"

#include "core/error.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "volumes/extrusion_dh.h"
#include "wedges/adjacency.h"

#include <algorithm>

namespace stsv {

namespace {
constexpr VkFormat CENTER_FORMAT = VK_FORMAT_R32_SINT;
constexpr VkFormat COVERAGE_FORMAT = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat DEPTH_FORMAT = VK_FORMAT_D32_SFLOAT; // as render/gpu_renderer.cpp
} // namespace

GpuEdgeTables buildGpuEdgeTables(const Scene& scene) {
    const EdgeAdjacency adj = buildEdgeAdjacency(scene, [&](std::size_t t) { return !scene.perforated(t); });
    GpuEdgeTables tables;
    tables.faces.reserve(adj.faces.size());
    for (const EdgeFace& f : adj.faces)
        tables.faces.push_back({adj.positions[f.opposite], f.triangle, f.forward ? 1u : 0u, 0u, 0u, 0u});
    tables.edges.reserve(adj.edges.size());
    for (const MeshEdge& e : adj.edges) {
        GpuEdge g{};
        g.v0 = adj.positions[e.v0];
        g.v1 = adj.positions[e.v1];
        g.firstFace = e.firstFace;
        g.faceCount = e.faceCount;
        g.carrier = GPU_NO_TRIANGLE;
        // Edges whose faces are all degenerate have k_e = 0 everywhere (their third vertices lie
        // on the edge's line): no carrier, no wedge.
        for (std::uint32_t f = e.firstFace; f < e.firstFace + e.faceCount; ++f) {
            const uvec3 i = scene.triangles[adj.faces[f].triangle];
            if (stsvTriangleIsDegenerate(scene.positions[i.x], scene.positions[i.y], scene.positions[i.z]))
                continue;
            g.carrier = adj.faces[f].triangle;
            break;
        }
        tables.edges.push_back(g);
    }
    return tables;
}

std::vector<DescriptorBinding> GpuWedgePasses::bindings() {
    return {{GPU_BINDING_EDGES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_EDGE_FACES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CENTER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_COVERAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1}};
}

GpuWedgePasses::GpuWedgePasses(const Device& device, const Scene& scene, const RenderOptions& options,
                               const PipelineLayout& layout, const std::vector<ShaderDefine>& defines)
    : m_enabled(methodInfo(options.method).opaque != OpaqueTechnique::None),
      m_pw(methodInfo(options.method).opaque == OpaqueTechnique::Pw) {
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    GpuEdgeTables tables;
    if (m_enabled) tables = buildGpuEdgeTables(scene);
    m_edgeCount = tables.edges.size();
    if (tables.edges.empty()) tables.edges.push_back({});
    if (tables.faces.empty()) tables.faces.push_back({});
    m_edges = createBuffer(device, std::span<const GpuEdge>(tables.edges), storage);
    m_faces = createBuffer(device, std::span<const GpuEdgeFace>(tables.faces), storage);
    m_width = m_enabled ? static_cast<uint32_t>(options.width) : 1u;
    m_height = m_enabled ? static_cast<uint32_t>(options.height) : 1u;
    m_center = Image(device, {m_width, m_height, CENTER_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
    m_coverage = Image(device, {m_width, m_height, COVERAGE_FORMAT,
                                VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT});
    if (!m_enabled) return;

    VkFormatProperties coverageFormat{};
    vkGetPhysicalDeviceFormatProperties(device.physicalDevice(), COVERAGE_FORMAT, &coverageFormat);
    if (m_pw && !(coverageFormat.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
        throw UsageError("Vulkan device " + device.info().name +
                         " cannot blend into R32_SFLOAT attachments (penumbra-wedge coverage)");

    const ShaderCompiler compiler;
    std::vector<ShaderDefine> wedgeDefines = defines;
    wedgeDefines.push_back({"WEDGE_PW", m_pw ? "1" : "0"});
    wedgeDefines.push_back(
        {"WEDGE_STSV", m_pw && methodInfo(options.method).stsv != StsvTriangles::None ? "1" : "0"});
    const std::vector<uint32_t> vertex = compiler.compileFile("stsv.vert", defines);

    // Centre count: every face of the volumes behind the visible point, both facings, no writes
    // but the atomics; depth clamp keeps the far caps (beyond the far plane) in.
    GraphicsPipelineDesc center;
    center.stages = {{VK_SHADER_STAGE_VERTEX_BIT, vertex},
                     {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("dcs_center.geom", defines)},
                     {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("dcs_center.frag", defines)}};
    center.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    center.depthFormat = DEPTH_FORMAT;
    center.depthTest = true;
    center.depthWrite = false;
    center.depthCompare = VK_COMPARE_OP_GREATER;
    center.depthClamp = true;
    center.cullMode = VK_CULL_MODE_NONE;
    center.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE; // outward faces are CCW (dcs_center.geom)
    m_centerPipeline = createGraphicsPipeline(device, layout, center);

    // Wedge pass: the back faces of the bound behind the visible point, as the STSV pass.
    GraphicsPipelineDesc wedge;
    wedge.stages = {{VK_SHADER_STAGE_VERTEX_BIT, vertex},
                    {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("wedge.geom", defines)},
                    {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("wedge.frag", wedgeDefines)}};
    wedge.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    if (m_pw) {
        wedge.colorFormats = {COVERAGE_FORMAT};
        wedge.blend = {additiveBlend()};
    }
    wedge.depthFormat = DEPTH_FORMAT;
    wedge.depthTest = true;
    wedge.depthWrite = false;
    wedge.depthCompare = VK_COMPARE_OP_GREATER;
    wedge.depthClamp = true;
    wedge.cullMode = VK_CULL_MODE_FRONT_BIT;
    wedge.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    m_wedgePipeline = createGraphicsPipeline(device, layout, wedge);

    m_foldPipeline =
        createComputePipeline(device, layout, compiler.compileFile("wedge_fold.comp", wedgeDefines));
}

void GpuWedgePasses::writeDescriptors(DescriptorSet& set) const {
    set.writeBuffer(GPU_BINDING_EDGES, m_edges);
    set.writeBuffer(GPU_BINDING_EDGE_FACES, m_faces);
    set.writeStorageImage(GPU_BINDING_CENTER, m_center);
    set.writeStorageImage(GPU_BINDING_COVERAGE, m_coverage);
}

void GpuWedgePasses::prepare(VkCommandBuffer cmd) {
    m_center.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
    m_coverage.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
}

void GpuWedgePasses::recordOcclusion(VkCommandBuffer cmd, Image& depth, uint32_t triangleCount,
                                     GpuTimer& timer, const std::string& prefix) {
    if (!m_enabled) return;
    const VkClearColorValue zero{};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, m_center.handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
    fullBarrier(cmd);

    timer.begin(cmd, prefix + "center");
    beginRendering(cmd, {}, DepthTarget{&depth, false, 1.0f, true});
    m_centerPipeline.bind(cmd);
    vkCmdDraw(cmd, triangleCount + static_cast<uint32_t>(m_edgeCount), 1, 0, 0);
    endRendering(cmd);
    timer.end(cmd);
    fullBarrier(cmd);

    timer.begin(cmd, prefix + "wedges");
    std::vector<ColorTarget> targets;
    if (m_pw) targets.push_back({&m_coverage, true, {}});
    beginRendering(cmd, targets, DepthTarget{&depth, false, 1.0f, true});
    m_wedgePipeline.bind(cmd);
    if (m_edgeCount > 0) vkCmdDraw(cmd, static_cast<uint32_t>(m_edgeCount), 1, 0, 0);
    endRendering(cmd);
    timer.end(cmd);
    m_coverage.transition(cmd, VK_IMAGE_LAYOUT_GENERAL);
    fullBarrier(cmd);
}

void GpuWedgePasses::recordFold(VkCommandBuffer cmd) {
    if (!m_enabled) return;
    m_foldPipeline.bind(cmd);
    vkCmdDispatch(cmd, (m_width + 15) / 16, (m_height + 15) / 16, 1);
    fullBarrier(cmd);
}

} // namespace stsv
