#include "wedges/vulkan/gpu_wedge_clusters.h"

#include "core/error.h"
#include "core/parallel.h"
#include "gpu/device.h"
#include "render/methods.h"
#include "sampling/light_bounds.h"
#include "wedges/silhouette_edges.h"
#include "wedges/vulkan/gpu_wedges_dh.h"

#include <algorithm>
#include <bit>

namespace stsv {

// A walk's invocation appends up to a tile's 16 blocks (with CLUSTER_KEEP_TILE_BLOCKS the 16
// (block, leaf) pairs it keeps, or one kept leaf) between two flushes of its workgroup's shared list
// (render/shaders/cluster_walk.glsl groupAppend; the pixel stage appends without it), and the pixel stage
// keeps a leaf's edges as the bits of one word.
static_assert(16 * GPU_DCS_CLUSTER_GROUP <= GPU_CLUSTER_GROUP_ENTRIES && EDGE_CLUSTER_LEAF <= 32);

std::uint32_t dcsKeptPairsPerInvocation(std::uint32_t mostFaces, const std::string& source) {
    const std::uint32_t pairLoops = 1105 + 512 * std::max(mostFaces, 1u);
    if (mostFaces > 125)
        throw InputError(
            source, "an edge shared by " + std::to_string(mostFaces) +
                        " opaque triangles: the DCS cluster walk takes at most 125 (use --extrusion hull)");
    return std::clamp<std::uint32_t>(32768 / pairLoops, 1, 16);
}

bool usesWedgeClusters(const RenderOptions& options) {
    return methodInfo(options.method).wedges == WedgeVariant::Dcs &&
           options.extrusion == ExtrusionStage::Auto;
}

WedgeClusters::WedgeClusters(const Device& device, const Scene& scene, const EdgeAdjacency& adj,
                             const std::vector<std::uint32_t>& carriers, bool build) {
    uploadTexels(device, {}, m_empty.bounds, m_empty.boundTexels);
    if (!build) return;
    std::uint32_t mostFaces = 1;
    for (const MeshEdge& edge : adj.edges) mostFaces = std::max(mostFaces, edge.faceCount);
    m_keptPairsPerInvocation = dcsKeptPairsPerInvocation(mostFaces, scene.source);
    const float farDistance = farDistanceFor(scene.bounds());
    for (const Light& light : scene.lights) {
        const SilhouetteEdges sil(scene, adj, carriers, light, farDistance);
        const EdgeClusterTree& tree = sil.tree();
        Counts counts;
        counts.potentialSilhouettes = sil.potentialCount();
        counts.leaves = tree.leaves;
        counts.carriers = sil.carrierCount();
        counts.depth = tree.nodes.empty() ? 0 : treeDepth(tree.nodes, 0);
        std::vector<uvec4> nodes;
        nodes.reserve(tree.nodes.size() * GPU_CLUSTER_TEXELS);
        for (const EdgeClusterNode& node : tree.nodes) {
            nodes.push_back(texelBits(node.ball));
            nodes.push_back(texelBits(node.cone));
            nodes.push_back(uvec4(node.first, node.count, std::bit_cast<uint>(node.conditioning), 0u));
        }
        std::vector<uvec4> items(tree.items.size() * GPU_CLUSTER_TEXELS);
        parallelForChunks(tree.items.size(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const std::uint32_t item = tree.items[k];
                const EdgeClusterNode own = edgeCluster(adj, sil.edge(item), sil.carrierNormal(item));
                uvec4* t = items.data() + k * GPU_CLUSTER_TEXELS;
                t[0] = texelBits(own.ball);
                t[1] = texelBits(own.cone);
                t[2] = uvec4(sil.edge(item), sil.carrier(item), std::bit_cast<uint>(own.conditioning), 0u);
            }
        });
        std::vector<uvec4> bounds(sil.carrierCount() * GPU_CLUSTER_BOUND_TEXELS);
        parallelForChunks(sil.carrierCount(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t c = begin; c < end; ++c) {
                const FaceBound& b = sil.carrierBound(std::uint32_t(c));
                uvec4* t = bounds.data() + c * GPU_CLUSTER_BOUND_TEXELS;
                t[0] = uvec4(b.volumeCount, b.volumeCount > 0 ? b.volumes[0].planeCount : 0u,
                             b.volumeCount > 1 ? b.volumes[1].planeCount : 0u, b.lightPlanes.count);
                for (uint v = 0; v < 2; ++v)
                    for (uint i = 0; i < STSV_VOLUME_MAX_PLANES; ++i)
                        t[1 + v * STSV_VOLUME_MAX_PLANES + i] =
                            v < b.volumeCount ? texelBits(b.volumes[v].planes[i]) : uvec4(0u);
                for (uint i = 0; i < STSV_LIGHT_PLANES_MAX; ++i)
                    t[1 + 2 * STSV_VOLUME_MAX_PLANES + i] = texelBits(b.lightPlanes.planes[i]);
            }
        });
        Tables tables;
        tables.tree =
            uploadClusterTables(device, std::move(nodes), std::move(items), counts.depth, scene.source);
        uploadTexels(device, std::move(bounds), tables.bounds, tables.boundTexels);
        m_lights.push_back(std::move(tables));
        m_counts.push_back(counts);
    }
}

std::vector<DescriptorBinding> WedgeClusters::bindings() {
    return {{GPU_BINDING_CLUSTER_BOUNDS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void WedgeClusters::writeDescriptors(DescriptorSet& set, std::size_t light, const ClusterLists& lists) const {
    const Tables& t = light < m_lights.size() ? m_lights[light] : m_empty;
    lists.writeDescriptors(set, light < m_lights.size() ? &t.tree : nullptr);
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_BOUNDS, t.boundTexels.handle());
}

} // namespace stsv
