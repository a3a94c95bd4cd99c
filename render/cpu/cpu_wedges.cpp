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
#include "wedges/pw_dh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

namespace stsv {

/// The data access of wedges/wedge_fragment_dh.h on the CPU: the edge's faces in the adjacency.
struct WedgeFaces {
    const EdgeAdjacency* adjacency;
    uint first;
    uint count;
};
inline uint wedgeFaceTriangle(WedgeFaces faces, uint f) {
    return faces.adjacency->faces[f].triangle;
}
inline vec3 wedgeFaceOpposite(WedgeFaces faces, uint f) {
    return faces.adjacency->positions[faces.adjacency->faces[f].opposite];
}

} // namespace stsv

#define WEDGE_FACES
#include "wedges/wedge_fragment_dh.h"

namespace stsv {

nlohmann::json toJson(const WedgeCpuStats& s) {
    nlohmann::json j = {{"edges", s.edges},
                        {"potential_silhouettes", s.potentialSilhouettes},
                        {"volumes", s.volumes},
                        {"tile_entries", s.tileEntries},
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

std::uint32_t OpaqueOccluders::centerCount(vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                                           std::vector<std::uint32_t>& scratch) const {
    if (!m_embree) return 0;
    const std::uint32_t ignoreOpaque =
        ignore < m_sceneToOpaque.size() ? m_sceneToOpaque[ignore] : NO_TRIANGLE;
    return m_embree->countLayers(p, r, tMin, ignoreOpaque, scratch);
}

namespace {

constexpr int TILE = CPU_TILE; // screen bins are the parallel tiles (core/parallel.h)

/// One face that bounds the wedge region of the potential silhouette edges assigned to it.
struct FaceRecord {
    StsvVolume volumes[2];
    StsvLightPlanes lightPlanes; ///< of the face: a segment that touches an edge touches the face
    std::uint32_t volumeCount;
    std::uint32_t firstEdge; ///< into EdgeBins::edges
    std::uint32_t edgeCount;
};

struct EdgeBins {
    std::vector<FaceRecord> records;
    std::vector<std::uint32_t> edges;
    std::vector<std::vector<std::uint32_t>> tiles; ///< record indices per screen tile
    int tilesX = 0;
    int tilesY = 0;
};

/// Potential silhouettes of the light, grouped by a non-degenerate face each, that face's STSV
/// volumes (both sides when the light straddles it: a segment touching the edge touches the
/// closed face, which STSV bounds conservatively), binned to screen tiles.
EdgeBins binEdges(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light, float farDistance,
                  WedgeCpuStats& stats) {
    const Scene& scene = occ.scene();
    const EdgeAdjacency& adj = occ.adjacency();
    const Bounds bounds = scene.bounds();
    const vec4 sphere = lightBoundingSphere(light, bounds, farDistance);
    const std::vector<std::uint32_t> candidates = potentialSilhouetteEdges(adj, sphere);
    stats.edges = adj.edges.size();
    stats.potentialSilhouettes = candidates.size();

    auto corners = [&](std::uint32_t tri) {
        const uvec3 i = scene.triangles[tri];
        return std::array<vec3, 3>{scene.positions[i.x], scene.positions[i.y], scene.positions[i.z]};
    };
    // The potential silhouettes grouped by carrier face (wedges/adjacency.h); an edge without a
    // carrier has k_e = 0 for every p and is dropped.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> byFace; // (triangle, edge)
    byFace.reserve(candidates.size());
    for (std::uint32_t e : candidates)
        if (occ.carriers()[e] != NO_CARRIER) byFace.emplace_back(occ.carriers()[e], e);
    std::sort(byFace.begin(), byFace.end());

    EdgeBins bins;
    bins.edges.reserve(byFace.size());
    for (std::size_t i = 0; i < byFace.size();) {
        const std::uint32_t tri = byFace[i].first;
        FaceRecord record{};
        record.firstEdge = static_cast<std::uint32_t>(bins.edges.size());
        for (; i < byFace.size() && byFace[i].first == tri; ++i) bins.edges.push_back(byFace[i].second);
        record.edgeCount = static_cast<std::uint32_t>(bins.edges.size()) - record.firstEdge;
        const auto c = corners(tri);
        // The bound's rule, as wedge_bindings.glsl wedgeSetupBound: the face's volume of each
        // side the light sees, and its light planes.
        record.lightPlanes =
            stsvTriangleLightPlanes(c[0], c[1], c[2], light, farDistance, bounds.lo, bounds.hi);
        for (uint side = 0; side < 2; ++side)
            if (stsvSideVolume(c[0], c[1], c[2], sphere, bounds.lo, bounds.hi, side, true,
                               record.volumes[record.volumeCount]))
                ++record.volumeCount;
        if (record.volumeCount == 0) {
            bins.edges.resize(record.firstEdge);
            continue;
        }
        stats.volumes += record.volumeCount;
        bins.records.push_back(record);
    }

    const mat4 clipFromWorld =
        binningClipFromView(scene.camera, gbuffer.width, gbuffer.height) * viewFromWorld(scene.camera);
    bins.tilesX = tilesAcross(gbuffer.width);
    bins.tilesY = tilesAcross(gbuffer.height);
    bins.tiles.resize(std::size_t(bins.tilesX) * std::size_t(bins.tilesY));
    for (std::size_t r = 0; r < bins.records.size(); ++r) {
        ivec4 rect(std::numeric_limits<int>::max(), std::numeric_limits<int>::max(), -1, -1);
        bool any = false;
        for (std::uint32_t v = 0; v < bins.records[r].volumeCount; ++v) {
            ivec4 vr;
            if (!volumeScreenRect(bins.records[r].volumes[v], clipFromWorld, gbuffer.width, gbuffer.height,
                                  vr))
                continue;
            rect = ivec4(min(ivec2(rect.x, rect.y), ivec2(vr.x, vr.y)),
                         max(ivec2(rect.z, rect.w), ivec2(vr.z, vr.w)));
            any = true;
        }
        if (!any) continue;
        for (int ty = rect.y / TILE; ty <= rect.w / TILE; ++ty)
            for (int tx = rect.x / TILE; tx <= rect.z / TILE; ++tx) {
                bins.tiles[std::size_t(ty) * std::size_t(bins.tilesX) + std::size_t(tx)].push_back(
                    static_cast<std::uint32_t>(r));
                ++stats.tileEntries;
            }
    }
    return bins;
}

/// A face record with the edges of it that may be a silhouette from some point of a box.
struct RecordEdges {
    std::uint32_t record;
    std::uint32_t first; ///< into the list's edges
    std::uint32_t count;
};

/// The records and edges a box of visible points keeps.
struct EdgeList {
    std::vector<RecordEdges> records;
    std::vector<std::uint32_t> edges; ///< adjacency edge indices

    void clear() {
        records.clear();
        edges.clear();
    }
};

/// False when the edge's weight k_e (wedgeWorldWeight) is zero for every point of the box with
/// any receiver: every face's plane leaves the box strictly on one side (dcsBoxSide) and the
/// sides cancel. A face whose triangle is a receiver in the box has the receiver point on its
/// plane, so that face is never strict and the edge is kept.
bool edgeMayBeSilhouette(const EdgeAdjacency& adj, const MeshEdge& edge, vec3 lo, vec3 hi) {
    const vec3 v0 = adj.positions[edge.v0], v1 = adj.positions[edge.v1];
    int sum = 0;
    for (std::uint32_t f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f) {
        const int side = dcsBoxSide(v0, v1, adj.positions[adj.faces[f].opposite], lo, hi);
        if (side == 0) return true;
        sum += side;
    }
    return sum != 0;
}

/// Of `records` (their edges in `edges`), those whose bound reaches the box [lo, hi] and that may be a
/// silhouette in it, into `to`. Both tests are conservative (stsvVolumeMissesBox,
/// edgeMayBeSilhouette), so they change no result.
void keepForBox(const EdgeBins& bins, const EdgeAdjacency& adj, const std::vector<RecordEdges>& records,
                const std::vector<std::uint32_t>& edges, const Bounds& box, EdgeList& to) {
    to.clear();
    for (const RecordEdges& entry : records) {
        const FaceRecord& record = bins.records[entry.record];
        bool reaches = false;
        for (std::uint32_t v = 0; v < record.volumeCount && !reaches; ++v)
            reaches = !stsvVolumeMissesBox(record.volumes[v], box.lo, box.hi);
        if (!reaches || stsvLightPlanesMissBox(record.lightPlanes, box.lo, box.hi)) continue;
        const auto first = static_cast<std::uint32_t>(to.edges.size());
        for (std::uint32_t i = entry.first; i < entry.first + entry.count; ++i)
            if (edgeMayBeSilhouette(adj, adj.edges[edges[i]], box.lo, box.hi)) to.edges.push_back(edges[i]);
        const auto count = static_cast<std::uint32_t>(to.edges.size()) - first;
        if (count > 0) to.records.push_back({entry.record, first, count});
    }
}

/// The fragment work of one pixel: calls visit(l, a, b, k) for every edge that is a silhouette
/// from p (k ≠ 0, receiver face excluded) with a non-empty part between p and the light.
template <class Visit>
void forEachSilhouette(const OpaqueOccluders& occ, const EdgeBins& bins, const EdgeList& list,
                       const DcsPixel& px, std::uint32_t receiver, std::size_t& tests, std::size_t& visits,
                       Visit&& visit) {
    const EdgeAdjacency& adj = occ.adjacency();
    for (const RecordEdges& entry : list.records) {
        const FaceRecord& record = bins.records[entry.record];
        ++tests;
        bool inside = false;
        for (std::uint32_t v = 0; v < record.volumeCount && !inside; ++v)
            inside = stsvPointInVolume(record.volumes[v], px.p);
        if (!inside || !stsvPointInLightPlanes(record.lightPlanes, px.p)) continue;
        for (std::uint32_t i = entry.first; i < entry.first + entry.count; ++i) {
            const MeshEdge& edge = adj.edges[list.edges[i]];
            const WedgeFaces faces{&adj, edge.firstFace, edge.faceCount};
            const vec3 v0 = adj.positions[edge.v0], v1 = adj.positions[edge.v1];
            if (wedgeWorldWeight(px.p, v0, v1, faces, receiver) == 0) continue;
            vec3 l, h0, h1;
            int k;
            if (!wedgeEdgeTerm(px, v0, v1, faces, receiver, l, h0, h1, k)) continue;
            ++visits;
            visit(l, h0, h1, k);
        }
    }
}

/// Runs `pixel(x, y, i, list)` over the covered pixels, tile by tile, on every core. The list
/// holds the records and edges kept first for the tile's box of visible points and then for
/// the pixel's CPU_BLOCK × CPU_BLOCK block (keepForBox).
template <class PixelFn>
void forEachPixel(const OpaqueOccluders& occ, const GBuffer& gbuffer, const EdgeBins& bins, const char* label,
                  PixelFn&& pixel) {
    const EdgeAdjacency& adj = occ.adjacency();
    Progress progress(label, bins.tiles.size());
    parallelForTiles(gbuffer.width, gbuffer.height, [&](const PixelTile& tile) {
        const std::size_t tileIndex = std::size_t(tile.ty) * std::size_t(bins.tilesX) + std::size_t(tile.tx);
        const Bounds box = tileReceiverBounds(gbuffer, tile);
        if (box.empty()) {
            progress.advance();
            return;
        }
        thread_local std::vector<RecordEdges> binned;
        thread_local EdgeList tileList, blockList;
        binned.clear();
        for (std::uint32_t r : bins.tiles[tileIndex])
            binned.push_back({r, bins.records[r].firstEdge, bins.records[r].edgeCount});
        keepForBox(bins, adj, binned, bins.edges, box, tileList);
        // Every covered pixel is visited, with whatever its block keeps (D(r) needs no edge).
        for (int by = 0; by < CPU_BLOCKS; ++by)
            for (int bx = 0; bx < CPU_BLOCKS; ++bx) {
                const PixelTile block = tileBlock(tile, bx, by);
                if (block.x0 >= block.x1 || block.y0 >= block.y1) continue;
                const Bounds blockBox = tileReceiverBounds(gbuffer, block);
                if (blockBox.empty()) continue;
                keepForBox(bins, adj, tileList.records, tileList.edges, blockBox, blockList);
                for (int y = block.y0; y < block.y1; ++y)
                    for (int x = block.x0; x < block.x1; ++x) {
                        const std::size_t i = gbuffer.index(x, y);
                        if (gbuffer.covered(i)) pixel(x, y, i, blockList);
                    }
            }
        progress.advance();
    });
}

} // namespace

WedgeCpuStats dcsCpuSamples(const OpaqueOccluders& occ, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& counters) {
    if (counters.kind() != BufferKind::Counters)
        throw UsageError("dcs needs a counter light-sample buffer (--buffer counters)");
    WedgeCpuStats stats;
    Timer timer;
    const EdgeBins bins = binEdges(occ, gbuffer, light, farDistance, stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setup_ms = timer.milliseconds();
    timer.reset();
    std::atomic<std::size_t> tests{0}, visits{0}, negative{0}, samples{0};
    forEachPixel(occ, gbuffer, bins, "dcs (cpu)", [&](int x, int y, std::size_t i, const EdgeList& list) {
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
            forEachSilhouette(occ, bins, list, px, gbuffer.triangle[i], localTests, localVisits,
                              [&](vec3 l, vec3 a, vec3 b, int k) {
                                  vec2 lo, hi;
                                  if (!dcsSampleRegion(l, a, b, vec2(-1.0f), vec2(1.0f), lo, hi)) return;
                                  if (!sampled) {
                                      for (int s = 0; s < plan.count; ++s) {
                                          ab[std::size_t(s)] = pixelSamplePoint(plan, x, y, s, frame.domain);
                                          cells.add(ab[std::size_t(s)], uint(s));
                                      }
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
    const EdgeBins bins = binEdges(occ, gbuffer, light, farDistance, stats);
    const float sceneDiameter = occ.scene().bounds().diameter();
    stats.setup_ms = timer.milliseconds();
    timer.reset();
    visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    std::fill(visibility.pixels.begin(), visibility.pixels.end(), 1.0f);
    std::atomic<std::size_t> tests{0}, visits{0};
    forEachPixel(occ, gbuffer, bins, "pw (cpu)", [&](int x, int y, std::size_t i, const EdgeList& list) {
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
            forEachSilhouette(occ, bins, list, px, gbuffer.triangle[i], localTests, localVisits,
                              [&](vec3 l, vec3 a, vec3 b, int k) {
                                  occlusion += pwWedgeTerm(k, pwEdgeCoverage(l, a, b, frame.domain));
                              });
        visibility.at(x, y, 0) = pwVisibility(occlusion);
        tests += localTests;
        visits += localVisits;
    });
    stats.pixelVolumeTests = tests;
    stats.pixelEdgeVisits = visits;
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
