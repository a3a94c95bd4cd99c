// CPU mirror of the opaque-occluder passes (DESIGN §4.5, STSV paper Algorithm 2):
// depth complexity sampling (DCS) and penumbra wedges (PW) over the welded edge adjacency of the
// opaque triangles, and their combinations with STSV for the perforated ones. The per-pixel,
// per-edge math is the device/host code of wedges/dcs_dh.h and wedges/pw_dh.h; each tile finds
// its candidate edges through a tree of clusters of the light's potential silhouettes
// (wedges/edge_clusters.h), and each edge's bound is the STSV volume of one of its faces (a
// conservative bound of the region whose light segments can touch the edge).
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/cpu/cpu_binning.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/ls_buffer.h"
#include "sampling/pattern.h"
#include "scene/scene.h"
#include "wedges/adjacency.h"
#include "wedges/dcs_dh.h"
#include "wedges/layer_bvh.h"
#include "wedges/silhouette_edges.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

namespace stsv {

struct WedgeCpuStats {
    std::size_t edges = 0;                ///< welded edges of the opaque triangles
    std::size_t potentialSilhouettes = 0; ///< of those, potential silhouettes for this light
    /// STSV volumes of the carrier faces, which bound the wedges: built for a face when a pixel
    /// first tests its bound, and kept for the light's next frames (the count so far).
    std::size_t volumes = 0;
    std::size_t clusters = 0; ///< leaves of the cluster tree (EDGE_CLUSTER_LEAF edges at most)
    /// (region, node) tests of the cluster tree: each screen tile walks the tree with the ball of
    /// its visible points, each block of it tests the tile's leaves with its own ball.
    std::size_t clusterTests = 0;
    /// Of those, nodes rejected: no segment from the region to the light meets their ball, or no
    /// edge below can be a silhouette from any point of it (wedges/edge_cluster_dh.h).
    std::size_t clustersRejected = 0;
    std::size_t blockEdges = 0; ///< (block, edge) pairs the blocks' pixels test
    /// Point-in-bound tests of an edge's carrier face ("fragments"), run for the (pixel, edge)
    /// pairs that pass the silhouette and clip tests; a GPU fragment is one pair inside the bound.
    std::size_t pixelVolumeTests = 0;
    /// (pixel, edge) pairs with the edge a silhouette from p, clipped non-empty
    /// ("silhouette_fragments", as the GPU counts them; DCS tests every sample of each).
    std::size_t pixelEdgeVisits = 0;
    std::size_t negativeCounts = 0; ///< DCS counts that came out < 0 (round-off at ties), clamped to 0
    /// DCS: covered pixels whose block counted its samples through the layer tree (dcsBlockCastsRays),
    /// and those that counted D(r) and the crossings.
    std::size_t rayPixels = 0;
    std::size_t crossingPixels = 0;
    /// DCS: samples whose crossing with a silhouette edge was tested ("samples_tested"; only
    /// those in the cells of the edge's dcsSampleRegion). Empty for PW, which tests no samples.
    std::optional<std::size_t> samplesTested;
    double setupMs = 0.0; ///< potential silhouettes and their tree (the light's first frame)
    double shadeMs = 0.0; ///< per-pixel centre count and edge loop
};

nlohmann::json toJson(const WedgeCpuStats& stats);

/// The opaque triangles of a scene, prepared once (renderer start-up): their welded adjacency and
/// the tree that gives the layer count D(r) at the light centre (wedges/layer_bvh.h, the function
/// Vulkan's dcs_center.comp runs). `scene` must outlive it.
class WedgeOccluders {
  public:
    explicit WedgeOccluders(const Scene& scene);
    ~WedgeOccluders();

    const Scene& scene() const { return m_scene; }
    const EdgeAdjacency& adjacency() const { return m_adjacency; }
    /// Each edge's carrier face (edgeCarriers), whose volumes bound its wedge.
    const std::vector<std::uint32_t>& carriers() const { return m_carriers; }
    std::size_t opaqueTriangles() const { return m_opaqueCount; }

    /// Opaque triangles crossed by p → r (t ∈ [tMin, 1]), scene triangle `ignore` excluded
    /// (layer_bvh_dh.h layerCount): D(r) at the light centre, or a sample's count.
    std::uint32_t layersCrossed(vec3 p, vec3 r, float tMin, std::uint32_t ignore) const;

    /// layersCrossed(px.p, frame.center, px.tMin, ignore), D(r), and whether an opaque triangle other
    /// than `ignore` meets a gap of the segments from px.p to the light frame (layer_bvh_dh.h
    /// layerCountGaps): there D(r) and the crossings do not give every sample's count.
    std::uint32_t centreLayers(const DcsPixel& px, const LightFrame& frame, std::uint32_t ignore,
                               bool& gapMet) const;

    /// The potential silhouettes of a light with their cluster tree and their carriers' bounds:
    /// they depend on the scene and the light alone, so the first frame that asks for a light
    /// makes them and later frames reuse them (as the layer tree is built once).
    const SilhouetteEdges& silhouettes(const Light& light, float farDistance) const;

  private:
    const Scene& m_scene;
    mutable std::mutex m_silhouettesMutex;
    mutable std::vector<std::unique_ptr<SilhouetteEdges>> m_silhouettes;
    std::size_t m_opaqueCount = 0;
    LayerBvhTables m_layers;
    EdgeAdjacency m_adjacency;
    std::vector<std::uint32_t> m_carriers;
};

/// DCS: adds to `counters` (BufferKind::Counters) the exact per-sample depth complexity of the opaque
/// triangles, D(x) = D(r) + Σ_e k_e·[r → x crosses e] (wedges/dcs_dh.h), or, in a block whose edges
/// exceed `rayEdgesPerSample` per sample (dcsBlockCastsRays), each sample's segment counted through
/// the layer tree. Self-shadowing rule as STSV: the visible triangle never counts.
WedgeCpuStats dcsCpuSamples(const WedgeOccluders& occluders, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& counters,
                            float rayEdgesPerSample = DCS_RAY_EDGES_PER_SAMPLE);

/// PW: per-pixel visibility v_coef of the opaque triangles (one channel, 1 on background):
/// 1 − clamp([D(r) > 0] + Σ_e sign(k_e)·coverage_e, 0, 1), coverage analytic over the light
/// frame's square or disk (wedges/pw_dh.h).
WedgeCpuStats pwCpuVisibility(const WedgeOccluders& occluders, const GBuffer& gbuffer, const Light& light,
                              float farDistance, ImageF& visibility);

/// The fold of pw+stsv (Algorithm 2, line 14) alone: v = clamp(v − occluded fraction of
/// `stsvBits`, 0, 1) at every covered pixel of `visibility` (PW's v_coef).
void pwFoldStsv(const GBuffer& gbuffer, const LightSampleBuffer& stsvBits, ImageF& visibility);

} // namespace stsv
