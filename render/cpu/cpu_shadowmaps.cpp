#include "render/cpu/cpu_shadowmaps.h"

#include "core/error.h"
#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "shadowmaps/filtered_map.h"
#include "shadowmaps/shadow_filter.h"

#include <atomic>
#include <cmath>

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

namespace {

/// A filtered representation's visibility per covered pixel: the representation built, the
/// kernel radius from fm_radius or the blocker search, one lookup.
template <class Receiver>
void filteredMapPixels(const ShadowMap& map, const std::vector<vec2>& taps, const GBuffer& gbuffer,
                       const ShadowMapSettings& settings, const Receiver& receiver, ImageF& vcoef,
                       ShadowMapCpuStats* stats) {
    const ShadowMapView& view = map.view;
    const ShadowMapSource src{&map, taps.data()};
    Timer timer;
    const FilteredShadowMap filtered(map, settings);
    if (stats) {
        stats->build_ms = timer.milliseconds();
        stats->representationBytes = filteredMapBytes(view, settings);
    }
    timer.reset();
    const bool search = settings.kernel != 0;
    // The blocker search leaves the kernel radius (texels) or −1 (no blocker: lit) in vcoef.
    std::atomic<std::uint64_t> clamped{0};
    if (search) {
        parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
            const std::size_t i = gbuffer.index(x, y);
            if (!gbuffer.covered(i)) return;
            const ShadowReceiver r = receiver(x, y, i);
            const float blocker =
                pcssAverageBlocker(view, src, r, uint(settings.blockerTaps), settings.maxSearch);
            vcoef.at(x, y, 0) =
                blocker < 0.0f ? -1.0f
                               : pcssFilterRadius(view, r, blocker, settings.maxKernel) * float(view.size);
            if (blocker >= 0.0f && pcssKernelClamped(view, r, blocker, settings.maxKernel))
                clamped.fetch_add(1, std::memory_order_relaxed);
        });
        if (stats) {
            stats->blocker_ms = timer.milliseconds();
            stats->kernelClamped = clamped.load();
        }
        timer.reset();
    }
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) return;
        const float radius = search ? vcoef.at(x, y, 0) : settings.radius;
        vcoef.at(x, y, 0) = radius < 0.0f ? 1.0f : filtered.visibility(receiver(x, y, i), radius);
    });
    if (stats) stats->filter_ms = timer.milliseconds();
}

} // namespace

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
    if (isFilteredRepresentation(settings.filter)) {
        filteredMapPixels(map, taps, gbuffer, settings, receiver, vcoef, stats);
        return;
    }
    if (settings.filter == ShadowFilter::Pcf) {
        parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
            const std::size_t i = gbuffer.index(x, y);
            if (!gbuffer.covered(i)) return;
            vcoef.at(x, y, 0) = pcfVisibility(view, src, receiver(x, y, i), settings.pcfRadius);
        });
        if (stats) stats->filter_ms = timer.milliseconds();
        return;
    }
    // PCSS in two passes, as on the GPU: the blocker search leaves the kernel radius (or −1:
    // no blocker, lit) in `vcoef`, the filter replaces it with the visibility.
    const uint blockerTaps = uint(settings.blockerTaps), filterTaps = uint(settings.filterTaps);
    std::atomic<std::uint64_t> clamped{0};
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) return;
        const ShadowReceiver r = receiver(x, y, i);
        const float blocker = pcssAverageBlocker(view, src, r, blockerTaps, settings.maxSearch);
        vcoef.at(x, y, 0) = blocker < 0.0f ? -1.0f : pcssFilterRadius(view, r, blocker, settings.maxKernel);
        if (blocker >= 0.0f && pcssKernelClamped(view, r, blocker, settings.maxKernel))
            clamped.fetch_add(1, std::memory_order_relaxed);
    });
    if (stats) stats->kernelClamped = clamped.load();
    if (stats) stats->blocker_ms = timer.milliseconds();
    timer.reset();
    parallelForPixels(gbuffer.width, gbuffer.height, [&](int x, int y) {
        const std::size_t i = gbuffer.index(x, y);
        if (!gbuffer.covered(i)) return;
        const float radius = vcoef.at(x, y, 0);
        vcoef.at(x, y, 0) =
            radius < 0.0f ? 1.0f : pcssFilter(view, src, receiver(x, y, i), radius, blockerTaps, filterTaps);
    });
    if (stats) stats->filter_ms = timer.milliseconds();
}

ShadowMapCpuStats shadowMapCpuVisibility(const EmbreeScene& embree, const GBuffer& gbuffer,
                                         const ShadowMapView& view, const ShadowMapSettings& settings,
                                         std::uint32_t seed, bool decorrelate, ImageF& vcoef, ShadowMap* keep,
                                         int supersample) {
    ShadowMapCpuStats stats;
    Timer timer;
    ShadowMap map = traceShadowMap(embree, view);
    stats.map_ms = timer.milliseconds();
    stats.faces = map.view.faces;
    stats.texels = map.depth.size();
    shadowMapFilterPixels(map, shadowFilterTaps(settings), gbuffer, settings, seed, decorrelate, vcoef,
                          &stats, supersample);
    if (keep) *keep = std::move(map);
    return stats;
}

} // namespace stsv
