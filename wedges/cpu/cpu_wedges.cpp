#include "wedges/cpu/cpu_wedges.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/cpu/cpu_techniques.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/camera.h"
#include "volumes/stsv_dh.h"
#include "wedges/dcs_dh.h"
#include "wedges/edge_cluster_dh.h"
#include "wedges/edge_clusters.h"
#include "wedges/pw_dh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#include <tbb/task_arena.h>

namespace stsv {

inline uint wedgeFaceTriangle(WedgeFaces faces, uint f) {
    return faces.local ? faces.local[f].triangle : faces.adjacency->faces[f].triangle;
}
inline vec3 wedgeFaceOpposite(WedgeFaces faces, uint f) {
    return faces.local ? faces.local[f].opposite
                       : faces.adjacency->positions[faces.adjacency->faces[f].opposite];
}

} // namespace stsv

#define WEDGE_FACES
#include "wedges/wedge_fragment_dh.h"

namespace stsv {

namespace {

/// The counts of the light's setup into `stats`.
void reportSetup(const SilhouetteEdges& sil, WedgeCpuStats& stats) {
    stats.edges = sil.edgeCount();
    stats.potentialSilhouettes = sil.potentialCount();
    stats.clusters = sil.tree().leaves;
}

} // namespace

nlohmann::json toJson(const WedgeCpuStats& s) {
    nlohmann::json j = {{"edges", s.edges},
                        {"potential_silhouettes", s.potentialSilhouettes},
                        {"volumes", s.volumes},
                        {"block_edges", s.blockEdges},
                        {"clusters", s.clusters},
                        {"cluster_tests", s.clusterTests},
                        {"clusters_rejected", s.clustersRejected},
                        {"fragments", s.pixelVolumeTests},
                        {"silhouette_fragments", s.pixelEdgeVisits},
                        {"negative_counts", s.negativeCounts},
                        {"ray_pixels", s.rayPixels},
                        {"crossing_pixels", s.crossingPixels},
                        {"setup_ms", s.setupMs},
                        {"shade_ms", s.shadeMs}};
    if (s.samplesTested) j["samples_tested"] = *s.samplesTested;
    return j;
}

WedgeOccluders::WedgeOccluders(const Scene& scene) : m_scene(scene), m_layers(buildLayerBvh(scene)) {
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) m_opaqueCount += scene.opaqueOccluder(t) ? 1 : 0;
    m_adjacency = buildEdgeAdjacency(scene, [&](std::size_t t) { return scene.opaqueOccluder(t); });
    m_carriers = edgeCarriers(m_adjacency, scene);
}

WedgeOccluders::~WedgeOccluders() = default;

const SilhouetteEdges& WedgeOccluders::silhouettes(const Light& light, float farDistance) const {
    const std::lock_guard<std::mutex> lock(m_silhouettesMutex);
    for (const auto& s : m_silhouettes)
        if (s->isFor(light, farDistance)) return *s;
    // Built in an isolated arena: the build's parallel loops must not take another task that
    // waits for this lock.
    tbb::this_task_arena::isolate([&] {
        m_silhouettes.push_back(
            std::make_unique<SilhouetteEdges>(m_scene, m_adjacency, m_carriers, light, farDistance));
    });
    return *m_silhouettes.back();
}

std::uint32_t WedgeOccluders::layersCrossed(vec3 p, vec3 r, float tMin, std::uint32_t ignore) const {
    // No loop limit on the CPU: the count runs to its end.
    LayerCountWork work{};
    return layerCount(m_layers, p, r, tMin, ignore, work, 0xffffffffu);
}

std::uint32_t WedgeOccluders::centreLayers(const DcsPixel& px, const LightFrame& frame, std::uint32_t ignore,
                                           bool& gapMet) const {
    LayerCountWork work{};
    const LayerGaps gaps = px.valid != 0.0f ? layerGapsOf(px.p, frame.center, frame.T, frame.B, px.row0,
                                                          px.row1, px.row2, px.tMin)
                                            : layerNoGaps();
    return layerCountGaps(m_layers, px.p, frame.center, px.tMin, ignore, gaps, work, gapMet, 0xffffffffu);
}

namespace {

/// A ball of receiver points and the segments from it to the light.
struct Region {
    vec4 ball;
    LightHull hull;

    Region(vec4 region, vec4 light) : ball(region), hull(lightHull(region, light)) {}
    Region(const Bounds& box, vec4 light) : Region(boxBall(box.lo, box.hi), light) {}
};

/// A node of the tree against a region (edge_cluster_dh.h clusterMayAdd).
bool nodeMayAdd(const EdgeClusterNode& node, const Region& region) {
    return clusterMayAdd(node.ball, node.cone, node.conditioning, region.ball, region.hull);
}

/// An edge of a block's leaves, where the visit order matters.
struct BlockItem {
    std::uint32_t item;     ///< (carrier, edge) order
    std::uint32_t position; ///< in the tree's items
    std::uint32_t slot;     ///< its leaf's slot in BlockEdges::leaves

    bool operator<(const BlockItem& other) const { return item < other.item; }
};

/// The edges a block of pixels tests: the leaves its region keeps and, where the visit order
/// matters (PW sums floats), their edges in (carrier, edge) order.
struct BlockEdges {
    std::vector<std::uint32_t> leaves; ///< node indices
    std::vector<BlockItem> items;      ///< ordered only
    std::vector<char> leafKept;        ///< per slot, for the current pixel
    std::uint32_t edgeCount = 0;       ///< the edges of `leaves` (dcsBlockCastsRays)
};

/// The fragment work of one pixel: calls visit(l, a, b, k) for every edge of the block that is a
/// silhouette from p (k ≠ 0, receiver face excluded), whose ball meets the cone from p to the
/// light's ball (edgeBall, ballMeetsLightCone: it holds the segments from p to the light), with a
/// non-empty part between p and the light, and whose carrier's bound holds p: the pairs a GPU
/// fragment counts (wedge_term.glsl). The block's leaves' balls are tested with p's cone first; a
/// leaf's ball holds its edges' balls and the test is monotone, so a leaf p rejects holds no such
/// edge (the silhouette test is exact per edge). `tests` counts the bound tests, `visits` the
/// edges visited. `ordered`: in item order (PW, which sums floats), edge by edge; else leaf by
/// leaf, the silhouette test four edges at a time (silhouetteCandidates).
template <class Visit>
void forEachSilhouette(const WedgeOccluders& occ, const SilhouetteEdges& sil, BlockEdges& block, bool ordered,
                       const DcsPixel& px, std::uint32_t receiver, std::size_t& tests, std::size_t& visits,
                       Visit&& visit) {
    const EdgeAdjacency& adj = occ.adjacency();
    const EdgeClusterTree& tree = sil.tree();
    const LightCone cone = lightCone(px.p, sil.light());
    bool any = false;
    for (std::size_t s = 0; s < block.leaves.size(); ++s) {
        block.leafKept[s] = ballMeetsLightCone(tree.nodes[block.leaves[s]].ball, cone);
        any = any || block.leafKept[s];
    }
    if (!any) return;
    const auto edgeTerm = [&](std::uint32_t position) {
        const PackedEdge& edge = sil.packed(position);
        const WedgeFaces faces = edge.wedgeFaces(adj);
        const vec3 v0 = edge.v0, v1 = edge.v1;
        const int weight = edge.faceCount <= 2
                               ? dcsTwoFaceWeight(px.p, v0, edge.faces[0].normal, edge.faces[0].triangle,
                                                  edge.faces[1].normal, edge.faces[1].triangle, receiver)
                               : wedgeWorldWeight(px.p, v0, v1, faces, receiver);
        if (weight == 0) return;
        if (!ballMeetsLightCone(edgeBall(v0, v1), cone)) return;
        vec3 l, h0, h1;
        int k;
        if (!wedgeEdgeTerm(px, v0, v1, faces, receiver, l, h0, h1, k)) return;
        ++tests;
        if (!sil.bound(edge.item).contains(px.p)) return;
        ++visits;
        visit(l, h0, h1, k);
    };
    if (ordered) {
        for (const BlockItem& entry : block.items)
            if (block.leafKept[entry.slot]) edgeTerm(entry.position);
        return;
    }
    const EdgeSideLanes& lanes = sil.sideLanes();
    for (std::size_t s = 0; s < block.leaves.size(); ++s) {
        if (!block.leafKept[s]) continue;
        const EdgeClusterNode& leaf = tree.nodes[block.leaves[s]];
        const std::uint32_t end = leaf.first + leaf.count;
        for (std::uint32_t k = leaf.first; k < end; k += EdgeSideLanes::LANES) {
            std::uint32_t bits = silhouetteCandidates(lanes, k, px.p, receiver);
            if (end - k < EdgeSideLanes::LANES) bits &= (1u << (end - k)) - 1u;
            for (; bits != 0u; bits &= bits - 1u) edgeTerm(k + std::uint32_t(std::countr_zero(bits)));
        }
    }
}

/// Runs `pixel(x, y, i, block)` over the covered pixels, tile by tile, on every core. Each tile
/// walks the cluster tree with the region of its visible points and keeps the leaves that may
/// add to them (nodeMayAdd); each CPU_BLOCK × CPU_BLOCK block of it keeps those of the tile's
/// leaves that pass for its own region, and forEachSilhouette those that pass for the pixel's
/// point. The tests are conservative, so they change no result; `stats` counts the tile and
/// block ones. `ordered`: the block lists its edges in item order too (forEachSilhouette).
template <class PixelFn>
void forEachPixel(const GBuffer& gbuffer, const SilhouetteEdges& sil, bool ordered, const char* label,
                  WedgeCpuStats& stats, PixelFn&& pixel) {
    Progress progress(label,
                      std::size_t(tilesAcross(gbuffer.width)) * std::size_t(tilesAcross(gbuffer.height)));
    std::atomic<std::size_t> testCount{0}, rejectedCount{0}, entryCount{0};
    const EdgeClusterTree& tree = sil.tree();
    parallelForTiles(gbuffer.width, gbuffer.height, [&](const PixelTile& tile) {
        const Bounds box = tileReceiverBounds(gbuffer, tile);
        if (box.empty()) {
            progress.advance();
            return;
        }
        thread_local std::vector<std::uint32_t> tileLeaves, stack;
        thread_local BlockEdges block;
        tileLeaves.clear();
        std::size_t tests = 0, rejected = 0, entries = 0;
        if (!tree.nodes.empty()) {
            const Region region(box, sil.light());
            stack.assign(1, 0u);
            while (!stack.empty()) {
                const std::uint32_t index = stack.back();
                stack.pop_back();
                const EdgeClusterNode& node = tree.nodes[index];
                ++tests;
                if (!nodeMayAdd(node, region)) {
                    ++rejected;
                } else if (node.count > 0) {
                    tileLeaves.push_back(index);
                } else {
                    stack.push_back(node.first + 1);
                    stack.push_back(node.first);
                }
            }
        }
        // Every covered pixel is visited, with whatever its block keeps (D(r) needs no edge).
        for (int by = 0; by < CPU_BLOCKS; ++by)
            for (int bx = 0; bx < CPU_BLOCKS; ++bx) {
                const PixelTile sub = tileBlock(tile, bx, by);
                if (sub.x0 >= sub.x1 || sub.y0 >= sub.y1) continue;
                const Bounds blockBox = tileReceiverBounds(gbuffer, sub);
                if (blockBox.empty()) continue;
                const Region region(blockBox, sil.light());
                block.leaves.clear();
                block.items.clear();
                block.edgeCount = 0;
                for (std::uint32_t index : tileLeaves) {
                    ++tests;
                    if (!nodeMayAdd(tree.nodes[index], region)) {
                        ++rejected;
                        continue;
                    }
                    const EdgeClusterNode& leaf = tree.nodes[index];
                    entries += leaf.count;
                    block.edgeCount += leaf.count;
                    if (ordered)
                        for (std::uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k)
                            block.items.push_back({tree.items[k], k, std::uint32_t(block.leaves.size())});
                    block.leaves.push_back(index);
                }
                if (ordered) std::sort(block.items.begin(), block.items.end());
                block.leafKept.resize(block.leaves.size());
                for (int y = sub.y0; y < sub.y1; ++y)
                    for (int x = sub.x0; x < sub.x1; ++x) {
                        const std::size_t i = gbuffer.index(x, y);
                        if (gbuffer.covered(i)) pixel(x, y, i, block);
                    }
            }
        testCount += tests;
        rejectedCount += rejected;
        entryCount += entries;
        progress.advance();
    });
    stats.clusterTests = testCount;
    stats.clustersRejected = rejectedCount;
    stats.blockEdges = entryCount;
}

} // namespace

WedgeCpuStats dcsCpuSamples(const WedgeOccluders& occ, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& counters,
                            float rayEdgesPerSample) {
    if (counters.kind() != BufferKind::Counters)
        throw UsageError("dcs needs a counter light-sample buffer (--buffer counters)");
    WedgeCpuStats stats;
    Timer timer;
    const SilhouetteEdges& sil = occ.silhouettes(light, farDistance);
    reportSetup(sil, stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setupMs = timer.milliseconds();
    timer.reset();
    std::atomic<std::size_t> tests{0}, visits{0}, negative{0}, samples{0}, rayPixels{0}, crossingPixels{0};
    forEachPixel(
        gbuffer, sil, false, "dcs (cpu)", stats, [&](int x, int y, std::size_t i, BlockEdges& block) {
            thread_local std::vector<vec2> ab;
            thread_local std::vector<int> count;
            const vec3 p = gbuffer.position[i];
            const std::uint32_t receiver = gbuffer.triangle[i];
            const LightFrame frame = lightFrame(light, p, farDistance);
            const float tMin = shadowTMin(p, frame.center, sceneDiameter);
            const DcsPixel px = dcsSetupPixel(p, frame.center, frame.T, frame.B, tMin);
            // D(r), the layer count at the light centre (DESIGN §4.5), and whether a triangle meets the
            // segments' gaps, where the crossings would miss a change of D: then the samples' segments.
            bool gapMet = false;
            const int base = static_cast<int>(occ.centreLayers(px, frame, receiver, gapMet));
            ab.resize(std::size_t(plan.count));
            if (gapMet || dcsBlockCastsRays(block.edgeCount, uint(plan.count), rayEdgesPerSample)) {
                // Each sample's segment through the layer tree: N rays cost less than the crossings.
                pixelSamplePoints(plan, x, y, frame.domain, ab.data());
                for (int k = 0; k < plan.count; ++k) {
                    const vec3 s = lightSamplePosition(frame, ab[std::size_t(k)]);
                    if (const std::uint32_t c = occ.layersCrossed(p, s, tMin, receiver))
                        counters.addCount(x, y, k, int(c));
                }
                ++rayPixels;
                return;
            }
            ++crossingPixels;
            count.assign(std::size_t(plan.count), base);
            // The samples in a grid of cells, made when the first edge needs them: an edge tests
            // only those of the cells its crossing region (dcsSampleRegion) touches.
            SampleCells cells;
            bool sampled = false;
            const uint wordCount = uint(plan.count + 31) / 32u;
            std::size_t localTests = 0, localVisits = 0, localNegative = 0, localSamples = 0;
            if (px.valid != 0.0f)
                forEachSilhouette(occ, sil, block, false, px, receiver, localTests, localVisits,
                                  [&](vec3 l, vec3 a, vec3 b, int k) {
                                      vec2 lo, hi;
                                      if (!dcsSampleRegion(l, a, b, vec2(-1.0f), vec2(1.0f), lo, hi)) return;
                                      if (!sampled) {
                                          pixelSamplePoints(plan, x, y, frame.domain, ab.data());
                                          for (int s = 0; s < plan.count; ++s)
                                              cells.add(ab[std::size_t(s)], uint(s));
                                          sampled = true;
                                      }
                                      const std::array<uint, 8> tested = cells.within(lo, hi, wordCount);
                                      for (uint w = 0; w < wordCount; ++w)
                                          for (uint bits = tested[w]; bits != 0u; bits &= bits - 1u) {
                                              const std::size_t s = 32u * w + uint(std::countr_zero(bits));
                                              ++localSamples;
                                              count[s] += k * dcsSampleCrossing(l, a, b, ab[s]);
                                          }
                                  });
            for (int k = 0; k < plan.count; ++k) {
                int c = count[std::size_t(k)];
                if (c < 0) {
                    ++localNegative;
                    c = 0;
                }
                if (c) counters.addCount(x, y, k, c);
            }
            tests += localTests;
            visits += localVisits;
            negative += localNegative;
            samples += localSamples;
        });
    stats.pixelVolumeTests = tests;
    stats.pixelEdgeVisits = visits;
    stats.negativeCounts = negative;
    stats.samplesTested = samples.load();
    stats.rayPixels = rayPixels;
    stats.crossingPixels = crossingPixels;
    stats.volumes = sil.volumesBuilt();
    stats.shadeMs = timer.milliseconds();
    return stats;
}

WedgeCpuStats pwCpuVisibility(const WedgeOccluders& occ, const GBuffer& gbuffer, const Light& light,
                              float farDistance, ImageF& visibility) {
    WedgeCpuStats stats;
    Timer timer;
    const SilhouetteEdges& sil = occ.silhouettes(light, farDistance);
    reportSetup(sil, stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setupMs = timer.milliseconds();
    timer.reset();
    visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    std::fill(visibility.pixels.begin(), visibility.pixels.end(), 1.0f);
    std::atomic<std::size_t> tests{0}, visits{0};
    forEachPixel(gbuffer, sil, true, "pw (cpu)", stats, [&](int x, int y, std::size_t i, BlockEdges& block) {
        const vec3 p = gbuffer.position[i];
        const LightFrame frame = lightFrame(light, p, farDistance);
        const float tMin = shadowTMin(p, frame.center, sceneDiameter);
        const DcsPixel px = dcsSetupPixel(p, frame.center, frame.T, frame.B, tMin);
        // Hard shadow from the light centre, then one signed wedge term per silhouette edge.
        float occlusion =
            pwCenterOcclusion(int(occ.layersCrossed(p, frame.center, tMin, gbuffer.triangle[i])));
        std::size_t localTests = 0, localVisits = 0;
        if (px.valid != 0.0f)
            forEachSilhouette(occ, sil, block, true, px, gbuffer.triangle[i], localTests, localVisits,
                              [&](vec3 l, vec3 a, vec3 b, int k) {
                                  occlusion += pwWedgeTerm(k, pwEdgeCoverage(l, a, b, frame.domain));
                              });
        visibility.at(x, y, 0) = pwVisibility(occlusion);
        tests += localTests;
        visits += localVisits;
    });
    stats.pixelVolumeTests = tests;
    stats.pixelEdgeVisits = visits;
    stats.volumes = sil.volumesBuilt();
    stats.shadeMs = timer.milliseconds();
    return stats;
}

void pwFoldStsv(const GBuffer& gbuffer, const LightSampleBuffer& stsvBits, ImageF& visibility) {
    for (int y = 0; y < gbuffer.height; ++y)
        for (int x = 0; x < gbuffer.width; ++x) {
            if (!gbuffer.covered(gbuffer.index(x, y))) continue;
            visibility.at(x, y, 0) =
                pwVisibilityWithStsv(visibility.at(x, y, 0), 1.0f - stsvBits.visibleFraction(x, y));
        }
}

namespace {

/// The opaque triangles through DCS (signed counters added to the light's) or PW (v_coef), and
/// for pw+stsv the fold with the STSV bits of the perforated triangles (STSV paper §3.1).
class WedgeTechnique final : public CpuTechnique {
  public:
    explicit WedgeTechnique(const CpuTechniqueContext& c) : m_c(c), m_occluders(c.scene) {}
    void run(CpuLightWork& work) override {
        Timer timer;
        const bool pw = m_c.method.wedges == WedgeVariant::Pw;
        const bool transmittance = work.samples.kind() == BufferKind::Transmittance;
        // With transmittance, DCS counts into counters of its own, and a sample it finds behind
        // at least one opaque layer is occluded (STSV adds the translucent depths after it).
        std::optional<LightSampleBuffer> counts;
        if (!pw && transmittance)
            counts.emplace(work.samples.width(), work.samples.height(), work.samples.samples(),
                           BufferKind::Counters);
        const WedgeCpuStats s =
            pw ? pwCpuVisibility(m_occluders, work.gbuffer, work.light, m_c.farDistance, work.vcoef)
               : dcsCpuSamples(m_occluders, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                               counts ? *counts : work.samples, float(methodKnob(m_c.options, "ray_edges")));
        if (counts)
            for (int y = 0; y < counts->height(); ++y)
                for (int x = 0; x < counts->width(); ++x)
                    for (int k = 0; k < counts->samples(); ++k)
                        if (counts->count(x, y, k) != 0) work.samples.setOccluded(x, y, k);
        work.passes[work.pass(pw ? "pw" : "dcs")] = timer.milliseconds();
        m_stats.push_back(toJson(s));
    }
    void combine(CpuLightWork& work) override {
        // DCS and STSV add to the same counters; PW's v_coef loses the fraction STSV occludes.
        if (m_c.method.wedges != WedgeVariant::Pw || m_c.method.stsv == StsvTriangles::None) return;
        Timer timer;
        pwFoldStsv(work.gbuffer, work.samples, work.vcoef);
        work.passes[work.pass("fold")] = timer.milliseconds();
    }
    void takeStats(nlohmann::json& stats) override {
        stats["wedges"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    const CpuTechniqueContext& m_c;
    WedgeOccluders m_occluders;
    nlohmann::json m_stats = nlohmann::json::array();
};

} // namespace

std::unique_ptr<CpuTechnique> makeWedgesCpuTechnique(const CpuTechniqueContext& context) {
    return std::make_unique<WedgeTechnique>(context);
}

} // namespace stsv
