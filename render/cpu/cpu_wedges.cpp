#include "render/cpu/cpu_wedges.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/timer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/camera.h"
#include "volumes/extrusion.h"
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
#include <thread>

#include <tbb/task_arena.h>

namespace stsv {

/// A face of an edge, copied next to it (PackedEdge).
struct PackedFace {
    vec3 opposite; ///< the face's vertex opposite the edge
    uint triangle; ///< scene triangle
};

/// The data access of wedges/wedge_fragment_dh.h on the CPU: the edge's faces copied next to it
/// (`local`, two at most) or, for an edge with more, in the adjacency.
struct WedgeFaces {
    const EdgeAdjacency* adjacency;
    const PackedFace* local; ///< null: the faces first … first + count − 1 of the adjacency
    uint first;
    uint count;
};
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

/// One non-degenerate face that bounds the wedges of the potential silhouette edges it carries
/// (wedges/adjacency.h edgeCarriers), by the rule of wedge_bindings.glsl wedgeSetupBound: its
/// STSV volume of each side the light sees, and its light planes. A segment that touches an edge
/// touches the closed face, which STSV bounds conservatively. Trivial, so that storage for every
/// carrier costs no page until a pixel needs its bound.
struct FaceBound {
    StsvVolume volumes[2];
    StsvLightPlanes lightPlanes;
    std::uint32_t volumeCount;

    bool contains(vec3 p) const {
        bool inside = false;
        for (std::uint32_t v = 0; v < volumeCount && !inside; ++v) inside = stsvPointInVolume(volumes[v], p);
        return inside && stsvPointInLightPlanes(lightPlanes, p);
    }
};

/// One potential silhouette edge as a pixel reads it: its vertices and, for two faces at most,
/// the faces themselves.
struct PackedEdge {
    vec3 v0, v1;
    std::uint32_t item; ///< the edge's index in (carrier, edge) order
    std::uint32_t faceCount;
    std::uint32_t firstFace; ///< into the adjacency's faces
    PackedFace faces[2];     ///< the first two (unused ones: NO_TRIANGLE)

    WedgeFaces wedgeFaces(const EdgeAdjacency& adj) const {
        return faceCount <= 2 ? WedgeFaces{&adj, faces, 0u, faceCount}
                              : WedgeFaces{&adj, nullptr, firstFace, faceCount};
    }
};

/// The potential silhouettes of one light with a carrier, in (carrier, edge) order — the order
/// every pixel visits them in (PW sums in it) — the tree of clusters over them, and their
/// carriers' bounds, each built when a pixel first tests it: most carriers never hold a pixel's
/// silhouette edge that crosses its light.
class SilhouetteEdges {
  public:
    SilhouetteEdges(const OpaqueOccluders& occ, const Light& light, float farDistance)
        : m_scene(occ.scene()), m_lightSource(light), m_farDistance(farDistance) {
        const EdgeAdjacency& adj = occ.adjacency();
        m_sceneBounds = m_scene.bounds();
        light_ = lightBoundingSphere(light, m_sceneBounds, farDistance);
        const std::vector<std::uint32_t> candidates = potentialSilhouetteEdges(adj, light_);
        m_edgeCount = adj.edges.size();
        m_potential = candidates.size();
        // Grouped by carrier face; an edge without a carrier has k_e = 0 for every p and is dropped.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> byFace; // (triangle, edge)
        byFace.reserve(candidates.size());
        for (std::uint32_t e : candidates)
            if (occ.carriers()[e] != NO_CARRIER) byFace.emplace_back(occ.carriers()[e], e);
        std::sort(byFace.begin(), byFace.end());
        std::vector<vec3> turn; // the carriers' own normals, which orient the clusters' cones
        turn.reserve(byFace.size());
        edges_.reserve(byFace.size());
        carrier_.reserve(byFace.size());
        vec3 normal(0.f);
        for (std::size_t i = 0; i < byFace.size(); ++i) {
            if (i == 0 || byFace[i].first != byFace[i - 1].first) {
                m_carrierTriangle.push_back(byFace[i].first);
                const uvec3 t = m_scene.triangles[byFace[i].first];
                const vec3 c0 = m_scene.positions[t.x];
                normal = cross(m_scene.positions[t.y] - c0, m_scene.positions[t.z] - c0);
            }
            edges_.push_back(byFace[i].second);
            carrier_.push_back(std::uint32_t(m_carrierTriangle.size() - 1));
            turn.push_back(normal);
        }
        m_bounds = std::make_unique_for_overwrite<FaceBound[]>(m_carrierTriangle.size());
        m_state = std::make_unique<std::atomic<std::uint8_t>[]>(m_carrierTriangle.size());
        tree_ = buildEdgeClusters(adj, edges_, turn, m_sceneBounds.diameter());

        // What a pixel reads of each edge, leaf after leaf.
        packed_.resize(tree_.items.size());
        parallelForChunks(packed_.size(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const MeshEdge& edge = adj.edges[edges_[tree_.items[k]]];
                PackedEdge& e = packed_[k];
                e.v0 = adj.positions[edge.v0];
                e.v1 = adj.positions[edge.v1];
                e.item = tree_.items[k];
                e.faceCount = edge.faceCount;
                e.firstFace = edge.firstFace;
                for (uint f = 0; f < 2; ++f) {
                    const bool has = f < edge.faceCount;
                    const EdgeFace& face = adj.faces[edge.firstFace + (has ? f : 0)];
                    e.faces[f] = {has ? adj.positions[face.opposite] : vec3(0.f),
                                  has ? face.triangle : NO_TRIANGLE};
                }
            }
        });
    }

    /// Edge `position` of the tree's items (EdgeClusterTree::items order).
    const PackedEdge& packed(std::uint32_t position) const { return packed_[position]; }

    const EdgeClusterTree& tree() const { return tree_; }
    vec4 light() const { return light_; } ///< the light's bounding ball (sampling/light_bounds.h)

    /// The bound of item `item`'s carrier, built by the first thread that asks.
    const FaceBound& bound(std::uint32_t item) const {
        const std::uint32_t f = carrier_[item];
        std::atomic<std::uint8_t>& state = m_state[f];
        if (state.load(std::memory_order_acquire) == READY) return m_bounds[f];
        std::uint8_t expected = UNBUILT;
        if (state.compare_exchange_strong(expected, BUILDING, std::memory_order_acq_rel)) {
            build(f);
            state.store(READY, std::memory_order_release);
        } else {
            while (state.load(std::memory_order_acquire) != READY) std::this_thread::yield();
        }
        return m_bounds[f];
    }

    /// Volumes of the bounds built so far.
    std::size_t volumesBuilt() const { return m_volumes.load(); }

    /// Whether these are the silhouettes of `light` at `farDistance` (its geometry; not its radiance).
    bool isFor(const Light& light, float farDistance) const {
        const Light& l = m_lightSource;
        return l.type == light.type && l.position == light.position && l.normal == light.normal &&
               l.radius == light.radius && l.axisU == light.axisU && l.axisV == light.axisV &&
               l.angularRadius == light.angularRadius && m_farDistance == farDistance;
    }

    /// The counts of the setup into `stats`.
    void report(WedgeCpuStats& stats) const {
        stats.edges = m_edgeCount;
        stats.potentialSilhouettes = m_potential;
        stats.clusters = tree_.leaves;
    }

  private:
    static constexpr std::uint8_t UNBUILT = 0, BUILDING = 1, READY = 2;

    void build(std::uint32_t f) const {
        const uvec3 i = m_scene.triangles[m_carrierTriangle[f]];
        const vec3 c0 = m_scene.positions[i.x], c1 = m_scene.positions[i.y], c2 = m_scene.positions[i.z];
        FaceBound& b = m_bounds[f];
        b.volumeCount = 0;
        b.lightPlanes = stsvTriangleLightPlanes(c0, c1, c2, m_lightSource, m_farDistance, m_sceneBounds.lo,
                                                m_sceneBounds.hi);
        for (uint side = 0; side < 2; ++side)
            if (stsvSideVolume(c0, c1, c2, light_, m_sceneBounds.lo, m_sceneBounds.hi, side, false,
                               b.volumes[b.volumeCount]))
                ++b.volumeCount;
        m_volumes += b.volumeCount;
    }

    const Scene& m_scene;
    Light m_lightSource;
    float m_farDistance;
    std::size_t m_edgeCount = 0;
    std::size_t m_potential = 0;
    Bounds m_sceneBounds;
    vec4 light_;
    std::vector<std::uint32_t> edges_;
    std::vector<std::uint32_t> carrier_; ///< per item, its carrier's index
    std::vector<std::uint32_t> m_carrierTriangle;
    EdgeClusterTree tree_;
    std::vector<PackedEdge> packed_;
    std::unique_ptr<FaceBound[]> m_bounds;
    std::unique_ptr<std::atomic<std::uint8_t>[]> m_state;
    mutable std::atomic<std::size_t> m_volumes{0};
};

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
                        {"setup_ms", s.setup_ms},
                        {"shade_ms", s.shade_ms}};
    if (s.samplesTested) j["samples_tested"] = *s.samplesTested;
    return j;
}

OpaqueOccluders::OpaqueOccluders(const Scene& scene) : m_scene(scene) {
    m_opaque.source = scene.source + " (opaque triangles)";
    m_opaque.positions = scene.positions;
    m_opaque.texcoords = scene.texcoords;
    m_opaque.materials = scene.materials;
    m_opaque.textures = scene.textures;
    m_sceneToOpaque.assign(scene.triangleCount(), NO_TRIANGLE);
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        if (!scene.opaqueOccluder(t)) continue;
        m_sceneToOpaque[t] = static_cast<std::uint32_t>(m_opaque.triangles.size());
        m_opaqueToScene.push_back(static_cast<std::uint32_t>(t));
        m_opaque.triangles.push_back(scene.triangles[t]);
        m_opaque.triangleMaterial.push_back(scene.triangleMaterial[t]);
    }
    if (!m_opaqueToScene.empty()) m_embree = std::make_unique<EmbreeScene>(m_opaque);
    m_adjacency = buildEdgeAdjacency(scene, [&](std::size_t t) { return scene.opaqueOccluder(t); });
    m_carriers = edgeCarriers(m_adjacency, scene);
}

OpaqueOccluders::~OpaqueOccluders() = default;

const SilhouetteEdges& OpaqueOccluders::silhouettes(const Light& light, float farDistance) const {
    const std::lock_guard<std::mutex> lock(m_silhouettesMutex);
    for (const auto& s : m_silhouettes)
        if (s->isFor(light, farDistance)) return *s;
    // Built in an isolated arena: the build's parallel loops must not take another task that
    // waits for this lock.
    tbb::this_task_arena::isolate(
        [&] { m_silhouettes.push_back(std::make_unique<SilhouetteEdges>(*this, light, farDistance)); });
    return *m_silhouettes.back();
}

std::uint32_t OpaqueOccluders::centerCount(vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                                           std::vector<std::uint32_t>& scratch) const {
    if (!m_embree) return 0;
    const std::uint32_t ignoreOpaque =
        ignore < m_sceneToOpaque.size() ? m_sceneToOpaque[ignore] : NO_TRIANGLE;
    return m_embree->countLayers(p, r, tMin, ignoreOpaque, scratch);
}

namespace {

/// A ball of receiver points and the segments from it to the light.
struct Region {
    vec4 ball;
    LightHull hull;

    Region(vec4 region, vec4 light) : ball(region), hull(lightHull(region, light)) {}
    Region(const Bounds& box, vec4 light) : Region(boxBall(box.lo, box.hi), light) {}
};

/// A node of the tree against a region: false when no edge below it can add to any of its
/// points (edge_cluster_dh.h). The cone test's margin grows by the rounding of the per-point
/// orientation test (dcsWorldSide): its determinant, of differences up to M long, is off by at
/// most about 16·2⁻²⁴·M³ (10⁻⁶·M³), the margin twice that over |n| in distance from a face's plane.
bool nodeMayAdd(const EdgeClusterNode& node, const Region& region) {
    if (!ballMeetsLightHull(node.ball, region.hull)) return false;
    if (node.cone.w < 0.f) return true;
    const float m = stsv::length(vec3(region.ball) - vec3(node.ball)) + region.ball.w + node.faceReach;
    return clusterMayHaveSilhouette(node.ball, node.cone, region.ball,
                                    2e-6f * m * m * m * node.inverseNormal);
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
};

/// The fragment work of one pixel: calls visit(l, a, b, k) for every edge of the block that is a
/// silhouette from p (k ≠ 0, receiver face excluded), whose ball meets the segments from p to the
/// light (edgeBall, ballMeetsLightHull), with a non-empty part between p and the light, and
/// whose carrier's bound holds p: the pairs a GPU fragment counts (wedge_term.glsl). The block's
/// leaves' balls are tested with p first; a leaf's ball holds its edges' balls, so a leaf p
/// rejects holds no such edge (the silhouette test is exact per edge). `tests` counts the bound tests,
/// `visits` the edges visited. `ordered`: in item order, else leaf by leaf.
template <class Visit>
void forEachSilhouette(const OpaqueOccluders& occ, const SilhouetteEdges& sil, BlockEdges& block,
                       bool ordered, const DcsPixel& px, std::uint32_t receiver, std::size_t& tests,
                       std::size_t& visits, Visit&& visit) {
    const EdgeAdjacency& adj = occ.adjacency();
    const EdgeClusterTree& tree = sil.tree();
    const Region point(vec4(px.p, 0.f), sil.light());
    bool any = false;
    for (std::size_t s = 0; s < block.leaves.size(); ++s) {
        block.leafKept[s] = ballMeetsLightHull(tree.nodes[block.leaves[s]].ball, point.hull);
        any = any || block.leafKept[s];
    }
    if (!any) return;
    const auto edgeTerm = [&](std::uint32_t position) {
        const PackedEdge& edge = sil.packed(position);
        const WedgeFaces faces = edge.wedgeFaces(adj);
        const vec3 v0 = edge.v0, v1 = edge.v1;
        if (wedgeWorldWeight(px.p, v0, v1, faces, receiver) == 0) return;
        if (!ballMeetsLightHull(edgeBall(v0, v1), point.hull)) return;
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
    for (std::size_t s = 0; s < block.leaves.size(); ++s) {
        if (!block.leafKept[s]) continue;
        const EdgeClusterNode& leaf = tree.nodes[block.leaves[s]];
        for (std::uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k) edgeTerm(k);
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
                for (std::uint32_t index : tileLeaves) {
                    ++tests;
                    if (!nodeMayAdd(tree.nodes[index], region)) {
                        ++rejected;
                        continue;
                    }
                    const EdgeClusterNode& leaf = tree.nodes[index];
                    entries += leaf.count;
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

WedgeCpuStats dcsCpuSamples(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& counters) {
    if (counters.kind() != BufferKind::Counters)
        throw UsageError("dcs needs a counter light-sample buffer (--buffer counters)");
    WedgeCpuStats stats;
    Timer timer;
    const SilhouetteEdges& sil = occ.silhouettes(light, farDistance);
    sil.report(stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setup_ms = timer.milliseconds();
    timer.reset();
    std::atomic<std::size_t> tests{0}, visits{0}, negative{0}, samples{0};
    forEachPixel(
        gbuffer, sil, false, "dcs (cpu)", stats, [&](int x, int y, std::size_t i, BlockEdges& block) {
            thread_local std::vector<std::uint32_t> scratch;
            thread_local std::vector<vec2> ab;
            thread_local std::vector<int> count;
            const vec3 p = gbuffer.position[i];
            const LightFrame frame = lightFrame(light, p, farDistance);
            const float tMin = shadowTMin(p, frame.center, sceneDiameter);
            const DcsPixel px = dcsSetupPixel(p, frame.center, frame.T, frame.B, tMin);
            // D(r): the layer count at the light centre (DESIGN §4.5).
            const int base =
                static_cast<int>(occ.centerCount(p, frame.center, tMin, gbuffer.triangle[i], scratch));
            count.assign(std::size_t(plan.count), base);
            ab.resize(std::size_t(plan.count));
            // The samples in a grid of cells, made when the first edge needs them: an edge tests
            // only those of the cells its crossing region (dcsSampleRegion) touches.
            SampleCells cells;
            bool sampled = false;
            const uint wordCount = uint(plan.count + 31) / 32u;
            std::size_t localTests = 0, localVisits = 0, localNegative = 0, localSamples = 0;
            if (px.valid != 0.0f)
                forEachSilhouette(occ, sil, block, false, px, gbuffer.triangle[i], localTests, localVisits,
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
    stats.volumes = sil.volumesBuilt();
    stats.shade_ms = timer.milliseconds();
    return stats;
}

/// Algorithm 2, lines 9 and 13: the perforated triangles through STSV, into `out`.
StsvCpuStats perforatedStsvSamples(const Scene& scene, const GBuffer& gbuffer, const Light& light,
                                   const SamplePlan& plan, float farDistance, LightSampleBuffer& out) {
    return stsvCpuSamples(scene, gbuffer, light, plan, farDistance, out,
                          stsvFilter(scene, StsvTriangles::Perforated));
}

WedgeCpuStats dcsStsvCpuSamples(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light,
                                const SamplePlan& plan, float farDistance, LightSampleBuffer& counters,
                                StsvCpuStats* stsvStats) {
    WedgeCpuStats stats = dcsCpuSamples(occ, gbuffer, light, plan, farDistance, counters);
    const StsvCpuStats s = perforatedStsvSamples(occ.scene(), gbuffer, light, plan, farDistance, counters);
    if (stsvStats) *stsvStats = s;
    return stats;
}

WedgeCpuStats pwCpuVisibility(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light,
                              float farDistance, ImageF& visibility) {
    WedgeCpuStats stats;
    Timer timer;
    const SilhouetteEdges& sil = occ.silhouettes(light, farDistance);
    sil.report(stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setup_ms = timer.milliseconds();
    timer.reset();
    visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    std::fill(visibility.pixels.begin(), visibility.pixels.end(), 1.0f);
    std::atomic<std::size_t> tests{0}, visits{0};
    forEachPixel(gbuffer, sil, true, "pw (cpu)", stats, [&](int x, int y, std::size_t i, BlockEdges& block) {
        thread_local std::vector<std::uint32_t> scratch;
        const vec3 p = gbuffer.position[i];
        const LightFrame frame = lightFrame(light, p, farDistance);
        const float tMin = shadowTMin(p, frame.center, sceneDiameter);
        const DcsPixel px = dcsSetupPixel(p, frame.center, frame.T, frame.B, tMin);
        // Hard shadow from the light centre, then one signed wedge term per silhouette edge.
        float occlusion =
            pwCenterOcclusion(int(occ.centerCount(p, frame.center, tMin, gbuffer.triangle[i], scratch)));
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
    stats.shade_ms = timer.milliseconds();
    return stats;
}

WedgeCpuStats pwStsvCpuVisibility(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light,
                                  const SamplePlan& plan, float farDistance, ImageF& visibility,
                                  LightSampleBuffer& stsvBits, StsvCpuStats* stsvStats) {
    WedgeCpuStats stats = pwCpuVisibility(occ, gbuffer, light, farDistance, visibility);
    const StsvCpuStats s = perforatedStsvSamples(occ.scene(), gbuffer, light, plan, farDistance, stsvBits);
    if (stsvStats) *stsvStats = s;
    pwFoldStsv(gbuffer, stsvBits, visibility);
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

} // namespace stsv
