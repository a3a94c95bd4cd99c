#include "volumes/cpu/cpu_stsv.h"

#include "core/parallel.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/cpu/cpu_techniques.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/camera.h"
#include "volumes/extrusion_dh.h"
#include "volumes/light_hull_dh.h"
#include "volumes/stsv.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <memory>
#include <utility>

namespace stsv {

/// The data access of volumes/stsv_fragment_dh.h on the CPU: the pixel's sample points,
/// computed once per pixel (pixelSamplePoints), the texels from the triangle's Texture (null for
/// an opaque triangle), a translucent triangle's optical-depth table.
struct StsvSampleSource {
    const vec2* points; ///< the pixel's samples in frame coordinates, plan.count of them
    const Texture* texture;
    const std::uint32_t* depthTable; ///< 256 entries with STSV_FLAG_TRANSLUCENT, else null
};
inline vec2 stsvSourcePoint(StsvSampleSource s, uint k) {
    return s.points[k];
}
inline bool stsvSourceBlocks(StsvSampleSource s, ivec2 texel) {
    return alphaBlocks(s.texture->alpha(texel.x, texel.y));
}
inline uint stsvSourceDepth(StsvSampleSource s, const StsvTriangle& t, ivec2 texel) {
    if (t.flags & STSV_FLAG_TRANSLUCENT)
        return s.depthTable[(t.flags & STSV_FLAG_OPAQUE) ? 255u : s.texture->alpha(texel.x, texel.y)];
    return (t.flags & STSV_FLAG_OPAQUE) || stsvSourceBlocks(s, texel) ? OPTICAL_DEPTH_OPAQUE : 0u;
}

} // namespace stsv

#define STSV_SAMPLE_SOURCE
#define STSV_SAMPLE_DEPTH
#include "volumes/stsv_fragment_dh.h"

namespace stsv {

namespace {

struct VolumeRecord {
    StsvVolume volume;
    std::uint32_t triangle; ///< index into the StsvTriangle table
    std::uint32_t side;     ///< 0: shadows cast towards the far side of the light centre; 1: flipped
};

/// One light's STSV volumes (the geometry shader's work): per-triangle constants and light
/// planes, the volumes in triangle order with their triangles' balls, and the hierarchy over
/// those balls that the tiles walk.
struct StsvLightVolumes {
    std::vector<StsvTriangle> triangles;
    std::vector<StsvLightPlanes> lightPlanes;
    std::vector<VolumeRecord> volumes;
    std::vector<vec4> balls; ///< [volumes]: each volume's triangle's ball
    BallTree tree;
    std::size_t degenerate = 0;

    /// The volume's planes and its triangle's light planes: a box outside either holds no point
    /// that the fragment's test accepts.
    bool missesBox(const VolumeRecord& record, const Bounds& box) const {
        return stsvVolumeMissesBox(record.volume, box.lo, box.hi) ||
               stsvLightPlanesMissBox(lightPlanes[record.triangle], box.lo, box.hi);
    }
};

/// The volumes of the triangles `include` accepts, built on every core.
StsvLightVolumes buildLightVolumes(const Scene& scene, const Bounds& bounds, const Light& light, vec4 sphere,
                                   float farDistance, bool transmittance, const TriangleFilter& include) {
    const vec3 lightCenter = vec3(sphere);
    StsvLightVolumes lv;
    lv.triangles.resize(scene.triangleCount());
    lv.lightPlanes.assign(scene.triangleCount(), stsvNoLightPlanes());
    std::vector<VolumeRecord>& slots = lv.volumes;
    slots.resize(2 * scene.triangleCount());
    std::vector<std::uint8_t> slotUsed(2 * scene.triangleCount(), 0);
    std::atomic<std::size_t> degenerate{0};
    parallelForChunks(scene.triangleCount(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t) {
            if (include && !include(t)) continue;
            lv.triangles[t] = stsvTriangleFor(scene, t, lightCenter, transmittance);
            if (lv.triangles[t].flags & STSV_FLAG_DEGENERATE) {
                ++degenerate;
                continue;
            }
            const uvec3 idx = scene.triangles[t];
            const vec3 v0 = scene.positions[idx.x], v1 = scene.positions[idx.y], v2 = scene.positions[idx.z];
            lv.lightPlanes[t] = stsvTriangleLightPlanes(v0, v1, v2, light, farDistance, bounds.lo, bounds.hi);
            for (uint side = 0; side < 2; ++side)
                if (stsvSideVolume(v0, v1, v2, sphere, bounds.lo, bounds.hi, side, false,
                                   slots[2 * t + side].volume)) {
                    slots[2 * t + side].triangle = static_cast<std::uint32_t>(t);
                    slots[2 * t + side].side = side;
                    slotUsed[2 * t + side] = 1;
                }
        }
    });
    lv.degenerate = degenerate;
    // The used slots moved to the front, in order: the volumes.
    std::size_t used = 0;
    for (std::size_t i = 0; i < slots.size(); ++i) {
        if (!slotUsed[i]) continue;
        if (used != i) slots[used] = slots[i];
        const uvec3 idx = scene.triangles[slots[used].triangle];
        const vec3 v0 = scene.positions[idx.x], v1 = scene.positions[idx.y], v2 = scene.positions[idx.z];
        lv.balls.push_back(boxBall(min(v0, min(v1, v2)), max(v0, max(v1, v2))));
        ++used;
    }
    slots.resize(used);
    // The hierarchy the tiles walk: a volume's triangle occludes a sample of p only where it
    // meets the segment from p to the sample, so a node whose ball meets no segment from the
    // tile's visible points to the light holds nothing for the tile (volumes/light_hull_dh.h).
    lv.tree = buildBallTree(lv.balls);
    return lv;
}

/// What one tile counted, added to the frame's stats at its end.
struct TileCounts {
    std::size_t tests = 0, hits = 0, culled = 0, samples = 0;
    std::size_t nodeTests = 0, rejected = 0, entries = 0;
};

/// The volumes of the leaves whose ball meets the segments from the visible points in `box` to
/// the light, in volume order, less those with the box outside a plane.
std::vector<std::uint32_t> tileCandidates(const StsvLightVolumes& lv, const Bounds& box, vec4 sphere,
                                          TileCounts& counts) {
    std::vector<std::uint32_t> candidates;
    if (box.empty() || lv.tree.nodes.empty()) return candidates;
    const LightHull hull = lightHull(boxBall(box.lo, box.hi), sphere);
    std::vector<std::uint32_t> stack{0u}, reached;
    while (!stack.empty()) {
        const BallTree::Node& node = lv.tree.nodes[stack.back()];
        stack.pop_back();
        ++counts.nodeTests;
        if (!ballMeetsLightHull(node.ball, hull)) {
            ++counts.rejected;
        } else if (node.count > 0) {
            reached.insert(reached.end(), lv.tree.items.begin() + node.first,
                           lv.tree.items.begin() + node.first + node.count);
        } else {
            stack.push_back(node.first + 1);
            stack.push_back(node.first);
        }
    }
    std::sort(reached.begin(), reached.end());
    counts.entries += reached.size();
    candidates.reserve(reached.size());
    for (std::uint32_t v : reached) {
        if (lv.missesBox(lv.volumes[v], box))
            ++counts.culled;
        else
            candidates.push_back(v);
    }
    return candidates;
}

/// The fragment shader's work at one pixel: the samples of p that the candidate volumes'
/// triangles occlude, into `out`.
struct StsvPixelPass {
    const Scene& scene;
    const GBuffer& gbuffer;
    const Light& light;
    const SamplePlan& plan;
    float farDistance;
    float sceneDiameter;
    const StsvLightVolumes& lv;
    const std::vector<OpticalDepthTable>& depthTables;
    LightSampleBuffer& out;
    bool counters;
    uint wordCount;

    /// The sample bits of mask word w.
    uint wordBits(uint w) const {
        const uint n = std::min(32u, uint(plan.count) - 32u * w);
        return n == 32u ? ~0u : (1u << n) - 1u;
    }

    void shade(int x, int y, const std::vector<std::uint32_t>& candidates, std::array<vec2, 256>& points,
               TileCounts& counts) const {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i) || candidates.empty()) return;
        // Counted in registers, added to the tile's counts at the end.
        std::size_t tests = 0, hits = 0, samples = 0;
        const vec3 p = gbuffer.position[i];
        const LightFrame frame = lightFrame(light, p, farDistance);
        const float tMin = shadowTMin(p, frame.center, sceneDiameter);
        // The samples in an 8 × 8 grid over the frame's [−1, 1]²: a triangle tests only the
        // samples of the cells its projection (stsvSampleRegion) touches. Placed when the
        // first volume holds p (most pixels with candidates are in none).
        SampleCells cells;
        bool placed = false;
        // A bitmask keeps the union of the triangles' bits: samples already occluded are
        // not tested again, and a pixel whose samples are all occluded is done. Counters
        // need every layer.
        std::array<uint, 8> mask{};
        uint open = wordCount;
        // Transmittance: the optical depth of the translucent triangles per sample.
        std::array<std::uint32_t, 256> depth;
        bool anyDepth = false;
        for (std::uint32_t v : candidates) {
            if (open == 0) break;
            const VolumeRecord& record = lv.volumes[v];
            if (record.triangle == gbuffer.triangle[i]) continue; // self-shadowing rule
            ++tests;
            if (!stsvPointInVolume(record.volume, p) ||
                !stsvPointInLightPlanes(lv.lightPlanes[record.triangle], p))
                continue;
            ++hits;
            const StsvTriangle& tri = lv.triangles[record.triangle];
            StsvPixel px;
            if (!stsvFragmentPixel(tri, record.side, p, frame, tMin, px)) continue;
            const Texture* texture = (tri.flags & STSV_FLAG_OPAQUE) ? nullptr : &scene.textures[tri.texture];
            const ivec2 size = texture ? ivec2(texture->width, texture->height) : ivec2(1);
            vec2 regionLo, regionHi;
            if (!stsvSampleRegion(px, vec2(-1.0f), vec2(1.0f), regionLo, regionHi)) continue;
            if (!placed) {
                pixelSamplePoints(plan, x, y, frame.domain, points.data());
                for (int k = 0; k < plan.count; ++k) cells.add(points[std::size_t(k)], uint(k));
                placed = true;
            }
            const std::array<uint, 8> inRegion = cells.within(regionLo, regionHi, wordCount);
            const bool translucent = (tri.flags & STSV_FLAG_TRANSLUCENT) != 0u;
            const StsvSampleSource src{points.data(), texture,
                                       translucent ? depthTables[tri.material].data() : nullptr};
            if (translucent) {
                if (!anyDepth) depth.fill(0u);
                anyDepth = true;
                for (uint w = 0; w < wordCount; ++w) {
                    const uint before = mask[w];
                    for (uint untested = inRegion[w] & ~mask[w]; untested != 0u; untested &= untested - 1u) {
                        const uint k = 32u * w + uint(std::countr_zero(untested));
                        ++samples;
                        const uint units = stsvSampleDepth(tri, px, src, size, k);
                        std::uint32_t& d = depth[k];
                        // A sum of 2^32 units or more blocks (occlusion_rules_dh.h).
                        if (units == OPTICAL_DEPTH_OPAQUE || d + units < d)
                            mask[w] |= lsMaskBit(k);
                        else
                            d += units;
                    }
                    if (mask[w] != before && mask[w] == wordBits(w)) --open;
                }
                continue;
            }
            for (uint w = 0; w < wordCount; ++w) {
                const uint untested = counters ? inRegion[w] : inRegion[w] & ~mask[w];
                if (untested == 0u) continue;
                samples += std::size_t(std::popcount(untested));
                const uint bits = stsvOcclusionWordOf(tri, px, src, size, w, untested);
                if (counters) {
                    if (bits != 0u) out.addOccludingWord(x, y, int(w), bits);
                    continue;
                }
                mask[w] |= bits;
                if (mask[w] == wordBits(w)) --open;
            }
        }
        if (!counters)
            for (uint w = 0; w < wordCount; ++w)
                if (mask[w] != 0u) out.addOccludingWord(x, y, int(w), mask[w]);
        if (anyDepth)
            for (int k = 0; k < plan.count; ++k)
                if (depth[std::size_t(k)] != 0u && (mask[lsMaskWord(uint(k))] & lsMaskBit(uint(k))) == 0u)
                    out.addOpticalDepth(x, y, k, depth[std::size_t(k)]);
        counts.tests += tests;
        counts.hits += hits;
        counts.samples += samples;
    }
};

} // namespace

nlohmann::json toJson(const StsvCpuStats& s) {
    return {{"volumes", s.volumes},
            {"degenerate_skipped", s.degenerateSkipped},
            {"clusters", s.clusters},
            {"cluster_tests", s.clusterTests},
            {"clusters_rejected", s.clustersRejected},
            {"tile_entries", s.tileEntries},
            {"tile_entries_culled", s.tileEntriesCulled},
            {"fragments", s.pixelVolumeTests},
            {"inside_fragments", s.pixelVolumeHits},
            {"samples_tested", s.samplesTested},
            {"bin_ms", s.binMs},
            {"shade_ms", s.shadeMs}};
}

StsvCpuStats stsvCpuSamples(const Scene& scene, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& out,
                            const TriangleFilter& include) {
    StsvCpuStats stats;
    Timer timer;
    const Bounds bounds = scene.bounds();
    const vec4 sphere = lightBoundingSphere(light, bounds, farDistance);
    const bool transmittance = out.kind() == BufferKind::Transmittance;
    std::vector<OpticalDepthTable> depthTables;
    if (transmittance)
        for (const Material& m : scene.materials) depthTables.push_back(opticalDepthTable(m));
    const StsvLightVolumes lv =
        buildLightVolumes(scene, bounds, light, sphere, farDistance, transmittance, include);
    stats.degenerateSkipped = lv.degenerate;
    stats.volumes = lv.volumes.size();
    stats.binMs = timer.milliseconds();
    timer.reset();

    // The fragment shader's work, per tile and pixel.
    const StsvPixelPass pass{scene,
                             gbuffer,
                             light,
                             plan,
                             farDistance,
                             bounds.diameter(),
                             lv,
                             depthTables,
                             out,
                             out.kind() == BufferKind::Counters,
                             lsMaskWordCount(uint(plan.count))};
    std::atomic<std::size_t> tests{0}, hits{0}, culled{0}, samples{0};
    std::atomic<std::size_t> nodeTests{0}, nodesRejected{0}, entries{0};
    Progress progress("stsv (cpu)",
                      std::size_t(tilesAcross(gbuffer.width)) * std::size_t(tilesAcross(gbuffer.height)));
    parallelForTiles(gbuffer.width, gbuffer.height, [&](const PixelTile& tile) {
        TileCounts counts;
        // The tile's candidates; then the same per CPU_BLOCK × CPU_BLOCK block of pixels (a
        // smaller box culls more).
        const std::vector<std::uint32_t> candidates =
            tileCandidates(lv, tileReceiverBounds(gbuffer, tile), sphere, counts);
        std::array<std::vector<std::uint32_t>, CPU_BLOCKS * CPU_BLOCKS> blockCandidates;
        for (int by = 0; by < CPU_BLOCKS && !candidates.empty(); ++by)
            for (int bx = 0; bx < CPU_BLOCKS; ++bx) {
                const PixelTile block = tileBlock(tile, bx, by);
                if (block.x0 >= block.x1 || block.y0 >= block.y1) continue;
                const Bounds blockBox = tileReceiverBounds(gbuffer, block);
                if (blockBox.empty()) continue;
                std::vector<std::uint32_t>& list = blockCandidates[std::size_t(by * CPU_BLOCKS + bx)];
                const LightHull blockHull = lightHull(boxBall(blockBox.lo, blockBox.hi), sphere);
                for (std::uint32_t v : candidates)
                    if (ballMeetsLightHull(lv.balls[v], blockHull) && !lv.missesBox(lv.volumes[v], blockBox))
                        list.push_back(v);
            }
        std::array<vec2, 256> points;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
                pass.shade(x, y,
                           blockCandidates[std::size_t(((y - tile.y0) / CPU_BLOCK) * CPU_BLOCKS +
                                                       (x - tile.x0) / CPU_BLOCK)],
                           points, counts);
        tests += counts.tests;
        nodeTests += counts.nodeTests;
        nodesRejected += counts.rejected;
        hits += counts.hits;
        culled += counts.culled;
        samples += counts.samples;
        entries += counts.entries;
        progress.advance();
    });
    stats.pixelVolumeTests = tests;
    stats.clusters = lv.tree.nodes.empty() ? 0 : (lv.tree.nodes.size() + 1) / 2;
    stats.clusterTests = nodeTests;
    stats.clustersRejected = nodesRejected;
    stats.tileEntries = entries;
    stats.pixelVolumeHits = hits;
    stats.tileEntriesCulled = culled;
    stats.samplesTested = samples;
    stats.shadeMs = timer.milliseconds();
    return stats;
}

TriangleFilter stsvFilter(const Scene& scene, StsvTriangles which) {
    if (which == StsvTriangles::Perforated)
        return [&scene](std::size_t t) { return !scene.opaqueOccluder(t); };
    if (which == StsvTriangles::None) return [](std::size_t) { return false; };
    return {};
}

namespace {

/// STSV over the row's triangles (all, or the perforated ones), into the light's bits or counters.
class StsvTechnique final : public CpuTechnique {
  public:
    explicit StsvTechnique(const CpuTechniqueContext& c)
        : m_c(c), m_include(stsvFilter(c.scene, c.method.stsv)) {}
    void run(CpuLightWork& work) override {
        const StsvCpuStats s = stsvCpuSamples(m_c.scene, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                                              work.samples, m_include);
        work.passes[work.pass("stsv_bin")] = s.binMs;
        work.passes[work.pass("stsv_shade")] = s.shadeMs;
        m_stats.push_back(toJson(s));
    }
    void takeStats(nlohmann::json& stats) override {
        stats["stsv"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    const CpuTechniqueContext& m_c;
    TriangleFilter m_include;
    nlohmann::json m_stats = nlohmann::json::array();
};

} // namespace

std::unique_ptr<CpuTechnique> makeStsvCpuTechnique(const CpuTechniqueContext& context) {
    return std::make_unique<StsvTechnique>(context);
}

} // namespace stsv
