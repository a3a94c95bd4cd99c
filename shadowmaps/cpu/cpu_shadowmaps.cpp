#include "shadowmaps/cpu/cpu_shadowmaps.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "render/cpu/cpu_techniques.h"
#include "shadowmaps/filtered_lookup.h"
#include "shadowmaps/filtered_map.h"
#include "shadowmaps/kept_maps.h"
#include "shadowmaps/shadow_filter.h"
#include "shadowmaps/shadow_fit.h"
#include "shadowmaps/shadow_map_stats.h"
#include "wedges/adjacency.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

namespace stsv {

ShadowMap traceShadowMap(const EmbreeScene& embree, const ShadowMapView& view) {
    ShadowMap map;
    map.view = view;
    const std::size_t size = view.size;
    map.depth.assign(std::size_t(view.faces) * size * size, SHADOW_MAP_EMPTY);
    for (uint face = 0; face < view.faces; ++face) {
        float* depth = map.depth.data() + std::size_t(face) * size * size;
        parallelForPixels(int(size), int(size), [&](int x, int y) {
            vec3 o, d;
            shadowMapTexelRay(view, face, ivec2(x, y), o, d);
            Hit hit;
            // d·Z = 1: the ray parameter is the axial depth, clipped to [near, far] as the rasteriser clips.
            if (embree.intersect(o, d, view.near, view.far, hit))
                depth[std::size_t(y) * size + std::size_t(x)] = shadowMapDepthAlong(view, d, hit.t);
        });
    }
    return map;
}

DepthGrid traceDepthGrid(const EmbreeScene& embree, const ShadowMapView& view, uint bins) {
    DepthGrid grid(view, bins);
    const Scene& scene = embree.scene();
    const int size = int(view.size);
    for (uint face = 0; face < view.faces; ++face) {
        parallelForTiles(size, size, [&](const PixelTile& tile) {
            std::vector<Hit> hits;
            std::vector<GridSurface> surfaces;
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) {
                    vec3 o, d;
                    shadowMapTexelRay(view, face, ivec2(x, y), o, d);
                    // d·Z = 1: the ray parameter is the axial depth, clipped to [near, far] as the
                    // rasteriser clips.
                    embree.allHits(o, d, view.near, view.far, hits);
                    surfaces.clear();
                    for (const Hit& h : hits) {
                        const uvec3 idx = scene.triangles[h.triangle];
                        const vec3 n = cross(scene.positions[idx.y] - scene.positions[idx.x],
                                             scene.positions[idx.z] - scene.positions[idx.x]);
                        surfaces.push_back({shadowMapDepthAlong(view, d, h.t), dot(n, d) < 0.0f});
                    }
                    fillDepthGridTexel(grid.texel(face, ivec2(x, y)), bins, surfaces);
                }
        });
    }
    return grid;
}

PeelMarchCounts peelMarchSamples(const DepthGrid& grid, const GBuffer& gbuffer, const Light& light,
                                 const SamplePlan& plan, float farDistance, const ShadowMapSettings& settings,
                                 LightSampleBuffer& out) {
    const bool counting = out.kind() == BufferKind::Counters;
    const PeelGridSource src{&grid};
    const uint maxSteps = uint(settings.peelMaxSteps);
    std::atomic<std::uint64_t> rays{0}, steps{0}, capped{0};
    std::atomic<std::uint32_t> longest{0};
    Progress progress("peel march", std::size_t(tilesAcross(gbuffer.width)) * tilesAcross(gbuffer.height));
    parallelForTiles(gbuffer.width, gbuffer.height, [&](const PixelTile& tile) {
        std::uint64_t tileRays = 0, tileSteps = 0, tileCapped = 0;
        std::uint32_t tileLongest = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const std::size_t i = gbuffer.index(x, y);
                if (!gbuffer.covered(i)) continue;
                const vec3 p = gbuffer.position[i];
                const LightFrame frame = lightFrame(light, p, farDistance);
                const ShadowReceiver r = shadowReceiver(grid.view, p, gbuffer.normal[i], settings.bias,
                                                        settings.normalOffset, vec2(1.0f, 0.0f));
                for (int k = 0; k < plan.count; ++k) {
                    const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
                    const PeelMarch m =
                        peelRayMarch(src, grid.view, grid.bins, maxSteps, r, s, counting ? 1u : 0u);
                    ++tileRays;
                    tileSteps += m.steps;
                    tileCapped += m.capped;
                    tileLongest = std::max(tileLongest, m.steps);
                    if (m.occluded == 0u) continue;
                    if (counting)
                        out.addCount(x, y, k, int(m.crossings));
                    else
                        out.setOccluded(x, y, k);
                }
            }
        rays += tileRays;
        steps += tileSteps;
        capped += tileCapped;
        for (std::uint32_t seen = longest.load();
             seen < tileLongest && !longest.compare_exchange_weak(seen, tileLongest);) {
        }
        progress.advance();
    });
    PeelMarchCounts counts;
    counts.rays = rays;
    counts.steps = steps;
    counts.capped = capped;
    counts.longest = longest;
    counts.maxSteps = maxSteps;
    return counts;
}

PeelCpuStats peelCpuSamples(const EmbreeScene& embree, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, const ShadowMapView& view,
                            const ShadowMapSettings& settings, LightSampleBuffer& out, DepthGrid* keep) {
    PeelCpuStats stats;
    Timer timer;
    DepthGrid grid = traceDepthGrid(embree, view, uint(settings.peelBins));
    stats.gridMs = timer.milliseconds();
    stats.gridBytes = depthGridBytes(view, settings);
    timer.reset();
    stats.march = peelMarchSamples(grid, gbuffer, light, plan, farDistance, settings, out);
    stats.marchMs = timer.milliseconds();
    if (keep) *keep = std::move(grid);
    return stats;
}

void shadowMapFilterPixels(const ShadowMap& map, const std::vector<vec2>& taps, const GBuffer& gbuffer,
                           const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate,
                           ImageF& vcoef, ShadowMapCpuStats* stats, int supersample) {
    const ShadowMapView& view = map.view;
    const ShadowMapSource src{&map, taps.data()};
    auto receiver = [&](int x, int y, std::size_t i) {
        return shadowReceiver(view, gbuffer.position[i], gbuffer.normal[i], settings.bias,
                              settings.normalOffset,
                              shadowTapRotation(uvec2(unsigned(x / supersample), unsigned(y / supersample)),
                                                seed, decorrelate));
    };
    Timer timer;
    // A filtered representation is built first (channels and their tables or mips).
    std::optional<FilteredShadowMap> filtered;
    if (isFilteredRepresentation(settings.filter)) {
        filtered.emplace(map, settings);
        if (stats) {
            stats->buildMs = timer.milliseconds();
            stats->representationBytes = filteredMapBytes(view, settings);
        }
        timer.reset();
    }
    // The blocker search, as on the GPU: PCSS, and the filtered maps with fm_kernel=1. It leaves
    // the kernel radius (uv) or −1 (no blocker: lit) in `vcoef`; the filter replaces it with the
    // visibility.
    const bool search = searchesBlockers(settings);
    const uint blockerTaps = uint(settings.blockerTaps), filterTaps = uint(settings.filterTaps);
    std::atomic<std::uint64_t> kernelClamped{0}, searchClamped{0};
    if (search) {
        parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
            const std::size_t i = gbuffer.index(x, y);
            if (!gbuffer.covered(i)) return;
            const ShadowReceiver r = receiver(x, y, i);
            const PcssBlockerStep step =
                pcssBlockerStep(view, r, pcssAverageBlocker(view, src, r, blockerTaps, settings.maxSearch),
                                settings.maxSearch, settings.maxKernel);
            vcoef.at(x, y, 0) = step.radius;
            if (step.searchClamped != 0u) searchClamped.fetch_add(1, std::memory_order_relaxed);
            if (step.kernelClamped != 0u) kernelClamped.fetch_add(1, std::memory_order_relaxed);
        });
        if (stats) stats->blockerMs = timer.milliseconds();
        timer.reset();
    }
    const bool fixedKernel = filtersFixedDepthKernel(settings.filter);
    const ShadowFilterParams params = shadowFilterParams(settings);
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) return;
        float& v = vcoef.at(x, y, 0);
        const ShadowReceiver r = receiver(x, y, i);
        if (fixedKernel) {
            bool strided = false;
            v = depthKernelVisibility(view, src, r, params, strided);
            if (strided) kernelClamped.fetch_add(1, std::memory_order_relaxed);
        } else if (!filtered) {
            v = v < 0.0f ? 1.0f : pcssFilter(view, src, r, v, blockerTaps, filterTaps);
        } else {
            // The lookup takes texels.
            const float radius = search ? v * float(view.size) : filteredFixedRadius(r, settings.worldRadius);
            v = radius < 0.0f ? 1.0f : filtered->visibility(r, radius);
        }
    });
    if (stats) {
        stats->filterMs = timer.milliseconds();
        stats->kernelClamped = kernelClamped.load();
        stats->searchClamped = searchClamped.load();
    }
}

AvsmMap traceAvsm(const EmbreeScene& embree, const ShadowMapView& view, uint maxNodes) {
    AvsmMap map(view, maxNodes);
    const int size = int(view.size);
    for (uint face = 0; face < view.faces; ++face) {
        parallelForTiles(size, size, [&](const PixelTile& tile) {
            std::vector<SurfaceCrossing> crossings;
            std::vector<AvsmSurface> surfaces;
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) {
                    vec3 o, d;
                    shadowMapTexelRay(view, face, ivec2(x, y), o, d);
                    // d·Z = 1: the ray parameter is the axial depth, clipped to [near, far] as the
                    // rasteriser clips.
                    embree.surfaceCrossings(o, d, view.near, view.far, crossings);
                    surfaces.clear();
                    for (const SurfaceCrossing& c : crossings)
                        surfaces.push_back({shadowMapDepthAlong(view, d, c.t), c.units});
                    map.store(map.texel(face, ivec2(x, y)), buildAvsmTexel(surfaces, maxNodes));
                }
        });
    }
    return map;
}

void avsmFilterPixels(const AvsmMap& map, const std::vector<vec2>& taps, const GBuffer& gbuffer,
                      const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate, ImageF& vcoef,
                      AvsmCpuStats* stats, int supersample) {
    const ShadowMapView& view = map.view;
    const AvsmSource src{&map, taps.data()};
    auto receiver = [&](int x, int y, std::size_t i) {
        return shadowReceiver(view, gbuffer.position[i], gbuffer.normal[i], settings.bias,
                              settings.normalOffset,
                              shadowTapRotation(uvec2(unsigned(x / supersample), unsigned(y / supersample)),
                                                seed, decorrelate));
    };
    const bool vpcss = settings.filter == ShadowMapMethod::Vpcss;
    const uint n = uint(settings.vpcssTaps);
    Timer timer;
    // vpcss's blocker search leaves the kernel radius (uv) or −1 (no light lost: lit) in `vcoef`.
    if (vpcss) {
        std::atomic<std::uint64_t> clamped{0}, searchClamped{0};
        parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
            const std::size_t i = gbuffer.index(x, y);
            if (!gbuffer.covered(i)) return;
            const ShadowReceiver r = receiver(x, y, i);
            const PcssBlockerStep step =
                pcssBlockerStep(view, r, vpcssAverageBlocker(view, src, r, n, settings.maxSearch),
                                settings.maxSearch, settings.maxKernel);
            vcoef.at(x, y, 0) = step.radius;
            if (step.searchClamped != 0u) searchClamped.fetch_add(1, std::memory_order_relaxed);
            if (step.kernelClamped != 0u) clamped.fetch_add(1, std::memory_order_relaxed);
        });
        if (stats) {
            stats->kernelClamped = clamped.load();
            stats->searchClamped = searchClamped.load();
            stats->blockerMs = timer.milliseconds();
        }
        timer.reset();
    }
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) return;
        float& v = vcoef.at(x, y, 0);
        if (!vpcss)
            v = avsmVisibility(view, src, receiver(x, y, i));
        else
            v = v < 0.0f ? 1.0f : vpcssFilter(view, src, receiver(x, y, i), v, n, n);
    });
    if (stats) stats->filterMs = timer.milliseconds();
}

AvsmCpuStats avsmCpuVisibility(const EmbreeScene& embree, const GBuffer& gbuffer, const ShadowMapView& view,
                               const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate,
                               ImageF& vcoef, AvsmMap* keep, int supersample) {
    AvsmCpuStats stats;
    Timer timer;
    AvsmMap map = traceAvsm(embree, view, uint(settings.avsmNodes));
    stats.mapMs = timer.milliseconds();
    stats.map = avsmStats(map);
    stats.bytes = avsmBytes(view, settings);
    avsmFilterPixels(map, shadowFilterTaps(settings), gbuffer, settings, seed, decorrelate, vcoef, &stats,
                     supersample);
    if (keep) *keep = std::move(map);
    return stats;
}

ShadowMapCpuStats shadowMapCpuVisibility(const EmbreeScene& embree, const GBuffer& gbuffer,
                                         const ShadowMapView& view, const ShadowMapSettings& settings,
                                         std::uint32_t seed, bool decorrelate, ImageF& vcoef, ShadowMap* keep,
                                         int supersample) {
    ShadowMapCpuStats stats;
    Timer timer;
    ShadowMap map = traceShadowMap(embree, view);
    stats.mapMs = timer.milliseconds();
    shadowMapFilterPixels(map, shadowFilterTaps(settings), gbuffer, settings, seed, decorrelate, vcoef,
                          &stats, supersample);
    if (keep) *keep = std::move(map);
    return stats;
}

namespace {

/// The light-centre map and its filter (v_coef per pixel), or the depth grid marched per light
/// sample (`peel`: the light's bits).
class ShadowMapsTechnique final : public CpuTechnique {
  public:
    explicit ShadowMapsTechnique(const CpuTechniqueContext& c)
        : m_c(c), m_settings(shadowMapSettings(c.options)),
          m_receivers(
              shadowReceiverBounds(c.embree.scene(), float(c.options.width) / float(c.options.height))) {
        if (m_settings.filter == ShadowMapMethod::Peel)
            m_openEdges = buildEdgeAdjacency(c.embree.scene()).openEdges;
    }
    void run(CpuLightWork& work) override {
        if (m_settings.filter == ShadowMapMethod::Peel) return runPeel(work);
        if (readsTransmittanceFunctions(m_settings.filter)) return runAvsm(work);
        ShadowMap* keep =
            m_c.options.keepShadowMaps ? &keepMapsIn(work.frame.keptMaps).shadowMaps.emplace_back() : nullptr;
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        const ShadowMapCpuStats s =
            shadowMapCpuVisibility(m_c.embree, work.gbuffer, view, m_settings, m_c.options.seed,
                                   m_c.options.decorrelate, work.vcoef, keep, m_c.options.supersample);
        work.passes[work.pass("shadow_map")] = s.mapMs;
        const bool filtered = isFilteredRepresentation(m_settings.filter);
        if (filtered) work.passes[work.pass("filtered_map")] = s.buildMs;
        if (searchesBlockers(m_settings)) work.passes[work.pass("pcss_blocker")] = s.blockerMs;
        work.passes[work.pass("shadow_filter")] = s.filterMs;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        if (filtered) map["representation_bytes"] = s.representationBytes;
        map.update(filtersFixedDepthKernel(m_settings.filter)
                       ? kernelStrideStats(s.kernelClamped, work.gbuffer)
                       : kernelClampStats(s.kernelClamped, work.gbuffer));
        if (searchesBlockers(m_settings)) map.update(searchClampStats(s.searchClamped, work.gbuffer));
        m_stats.push_back(map);
    }
    void takeStats(nlohmann::json& stats) override {
        stats["shadow_maps"] = std::exchange(m_stats, nlohmann::json::array());
    }

  private:
    void runPeel(CpuLightWork& work) {
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        DepthGrid* keep =
            m_c.options.keepShadowMaps ? &keepMapsIn(work.frame.keptMaps).depthGrids.emplace_back() : nullptr;
        const PeelCpuStats s = peelCpuSamples(m_c.embree, work.gbuffer, work.light, m_c.plan, m_c.farDistance,
                                              view, m_settings, work.samples, keep);
        work.passes[work.pass("depth_grid")] = s.gridMs;
        work.passes[work.pass("peel_march")] = s.marchMs;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        map["grid_bytes"] = s.gridBytes;
        map["open_edges"] = m_openEdges;
        map.update(peelMarchStats(s.march));
        m_stats.push_back(map);
    }

    void runAvsm(CpuLightWork& work) {
        const Scene& scene = m_c.embree.scene();
        const ShadowMapView view = fitFrameShadowMap(scene, work.light, m_receivers, m_settings);
        AvsmMap* keep =
            m_c.options.keepShadowMaps ? &keepMapsIn(work.frame.keptMaps).avsmMaps.emplace_back() : nullptr;
        const AvsmCpuStats s =
            avsmCpuVisibility(m_c.embree, work.gbuffer, view, m_settings, m_c.options.seed,
                              m_c.options.decorrelate, work.vcoef, keep, m_c.options.supersample);
        work.passes[work.pass("avsm")] = s.mapMs;
        if (m_settings.filter == ShadowMapMethod::Vpcss)
            work.passes[work.pass("vpcss_blocker")] = s.blockerMs;
        work.passes[work.pass("shadow_filter")] = s.filterMs;
        nlohmann::json map = shadowMapViewStats(view, m_settings, scene.camera, work.gbuffer);
        map["avsm"] = avsmStatsJson(s.map, s.bytes);
        if (m_settings.filter == ShadowMapMethod::Vpcss) {
            map.update(kernelClampStats(s.kernelClamped, work.gbuffer));
            map.update(searchClampStats(s.searchClamped, work.gbuffer));
        }
        m_stats.push_back(map);
    }

    const CpuTechniqueContext& m_c;
    ShadowMapSettings m_settings;
    /// peel: the scene's edges with one triangle (the grid's closed-object assumption fails there)
    std::size_t m_openEdges = 0;
    Bounds m_receivers; ///< what the camera sees (the view fit's receivers)
    nlohmann::json m_stats = nlohmann::json::array();
};

} // namespace

std::unique_ptr<CpuTechnique> makeShadowMapsCpuTechnique(const CpuTechniqueContext& context) {
    return std::make_unique<ShadowMapsTechnique>(context);
}

} // namespace stsv
