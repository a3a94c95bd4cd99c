#include "volumes/vulkan/gpu_stsv_clusters.h"

#include "gpu/device.h"
#include "volumes/ball_tree.h"
#include "volumes/light_hull_dh.h"
#include "volumes/vulkan/gpu_stsv_dh.h"

#include <algorithm>
#include <cstdint>

namespace stsv {

// A walk's invocation appends up to a leaf's items, or 16 blocks or pixels, between two flushes
// of its workgroup's shared list (render/shaders/cluster_walk.glsl groupAppend).
static_assert(BallTree::LEAF * GPU_STSV_CLUSTER_GROUP <= GPU_CLUSTER_GROUP_ENTRIES &&
              16 * GPU_STSV_CLUSTER_GROUP <= GPU_CLUSTER_GROUP_ENTRIES);

bool usesStsvClusters(const RenderOptions& options) {
    return options.extrusion == ExtrusionStage::Auto;
}

StsvClusters::StsvClusters(const Device& device, const Scene& scene, StsvTriangles which) {
    // The balls of the triangles STSV takes, as the CPU pass's (volumes/cpu/cpu_stsv.cpp).
    std::vector<vec4> balls;
    std::vector<std::uint32_t> triangleOf;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (which == StsvTriangles::None || (which == StsvTriangles::Perforated && scene.opaqueOccluder(t)))
            continue;
        const uvec3 idx = scene.triangles[t];
        const vec3 v0 = scene.positions[idx.x], v1 = scene.positions[idx.y], v2 = scene.positions[idx.z];
        balls.push_back(boxBall(min(v0, min(v1, v2)), max(v0, max(v1, v2))));
        triangleOf.push_back(static_cast<std::uint32_t>(t));
    }
    const BallTree tree = buildBallTree(balls);
    // No cone (w < 0): a node or a triangle is kept where its ball meets the segments from the
    // block's points to the light (clusterMayAdd's first test).
    const vec4 noCone(0.0f, 0.0f, 0.0f, -1.0f);
    std::vector<uvec4> nodes;
    nodes.reserve(tree.nodes.size() * GPU_CLUSTER_TEXELS);
    for (const BallTree::Node& node : tree.nodes) {
        nodes.push_back(texelBits(node.ball));
        nodes.push_back(texelBits(noCone));
        nodes.push_back(uvec4(node.first, node.count, 0u, 0u));
        if (node.count > 0) ++m_leaves;
    }
    std::vector<uvec4> items;
    items.reserve(tree.items.size() * GPU_CLUSTER_TEXELS);
    for (const std::uint32_t b : tree.items) {
        items.push_back(texelBits(balls[b]));
        items.push_back(texelBits(noCone));
        items.push_back(uvec4(triangleOf[b], 0u, 0u, 0u));
    }
    m_tables = uploadClusterTables(device, std::move(nodes), std::move(items),
                                   tree.nodes.empty() ? 0 : treeDepth(tree.nodes, 0), scene.source);
    itemRecords = Buffer(device, std::max<std::size_t>(2 * scene.triangleCount(), 1) * sizeof(uint),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         MemoryUsage::DeviceLocal);
}

std::vector<DescriptorBinding> StsvClusters::bindings() {
    return {{GPU_BINDING_STSV_ITEM_RECORDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void StsvClusters::writeDescriptors(DescriptorSet& set, const ClusterLists& lists) const {
    lists.writeDescriptors(set, &m_tables);
    set.writeBuffer(GPU_BINDING_STSV_ITEM_RECORDS, itemRecords);
}

} // namespace stsv
