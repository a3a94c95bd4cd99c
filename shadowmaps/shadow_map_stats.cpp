#include "shadowmaps/shadow_map_stats.h"

#include "shadowmaps/shadow_fit.h"

#include <algorithm>
#include <cstdio>

namespace stsv {

namespace {

/// {"<what>_pixels", "<what>_fraction"}: a count of the pixels with a visible surface, and its
/// fraction of them.
nlohmann::json pixelCountStats(const std::string& what, std::uint64_t pixels, const GBuffer& gbuffer) {
    std::size_t covered = 0;
    for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) covered += gbuffer.covered(i) ? 1 : 0;
    return {{what + "_pixels", pixels},
            {what + "_fraction", covered ? double(pixels) / double(covered) : 0.0}};
}

} // namespace

nlohmann::json kernelClampStats(std::uint64_t clampedPixels, const GBuffer& gbuffer) {
    return pixelCountStats("kernel_clamped", clampedPixels, gbuffer);
}

nlohmann::json kernelStrideStats(std::uint64_t stridedPixels, const GBuffer& gbuffer) {
    return pixelCountStats("kernel_strided", stridedPixels, gbuffer);
}

nlohmann::json searchClampStats(std::uint64_t clampedPixels, const GBuffer& gbuffer) {
    return pixelCountStats("search_clamped", clampedPixels, gbuffer);
}

nlohmann::json peelMarchStats(const PeelMarchCounts& c) {
    return {{"march",
             {{"rays", c.rays},
              {"steps_mean", c.rays ? double(c.steps) / double(c.rays) : 0.0},
              {"steps_max", c.longest},
              {"max_steps", c.maxSteps},
              {"capped_rays", c.capped},
              {"capped_fraction", c.rays ? double(c.capped) / double(c.rays) : 0.0}}}};
}

nlohmann::json avsmStatsJson(const AvsmStats& s, std::size_t bytes) {
    return {{"nodes_mean", s.meanNodes},
            {"nodes_max", s.maxNodes},
            {"texels", s.texels},
            {"texels_with_nodes", s.texelsWithNodes},
            {"overflowed_texels", s.overflowedTexels},
            {"bytes", bytes}};
}

nlohmann::json shadowMapViewStats(const ShadowMapView& view, const ShadowMapSettings& settings,
                                  const Camera& camera, const GBuffer& gbuffer) {
    const char* projection = view.projection == SHADOW_MAP_CUBE           ? "cube"
                             : view.projection == SHADOW_MAP_ORTHOGRAPHIC ? "orthographic"
                                                                          : "perspective";
    nlohmann::json stats = {{"projection", projection},
                            {"faces", view.faces},
                            {"texels", std::size_t(view.faces) * view.size * view.size},
                            {"fit", settings.fit == 0 ? "scene" : "view"},
                            {"near", view.near},
                            {"far", view.far}};
    stats.update(shadowTexelFootprint(view, camera, gbuffer));
    return stats;
}

std::vector<std::string> shadowMapWarnings(const std::string& method, const nlohmann::json& frameStats) {
    std::vector<std::string> warnings;
    if (!frameStats.contains("shadow_maps") || !frameStats["shadow_maps"].is_array()) return warnings;
    const nlohmann::json& maps = frameStats["shadow_maps"];
    double worstKernel = 0.0, worstSearch = 0.0, worstStride = 0.0;
    for (const nlohmann::json& map : maps) {
        worstKernel = std::max(worstKernel, map.value("kernel_clamped_fraction", 0.0));
        worstSearch = std::max(worstSearch, map.value("search_clamped_fraction", 0.0));
        worstStride = std::max(worstStride, map.value("kernel_strided_fraction", 0.0));
    }
    std::size_t openEdges = 0;
    for (const nlohmann::json& map : maps)
        openEdges = std::max(openEdges, map.value("open_edges", std::size_t(0)));
    if (openEdges > 0)
        warnings.push_back(method + " assumes closed objects, and the scene has " +
                           std::to_string(openEdges) +
                           " open edges (single quads, open meshes): behind a surface facing the light with "
                           "no back face after it everything counts as shadowed, behind a lone back face "
                           "nothing");
    char text[240];
    std::uint64_t capped = 0, rays = 0;
    std::uint32_t cap = 0;
    for (const nlohmann::json& map : maps)
        if (map.contains("march")) {
            capped += map["march"].value("capped_rays", std::uint64_t(0));
            rays += map["march"].value("rays", std::uint64_t(0));
            cap = map["march"].value("max_steps", std::uint32_t(0));
        }
    if (capped > 0) {
        std::snprintf(text, sizeof text,
                      "%s: %llu of %llu light-sample rays (%.3f %%) needed more than peel_max_steps=%u "
                      "march steps and took longer ones, which can step over thin occluders (raise "
                      "it with --param peel_max_steps=...)",
                      method.c_str(), static_cast<unsigned long long>(capped),
                      static_cast<unsigned long long>(rays), 100.0 * double(capped) / double(rays), cap);
        warnings.emplace_back(text);
    }
    // The fraction of pixels a bound cut, what that costs, and the knob that raises it.
    const struct {
        double fraction;
        const char* what;
    } cuts[] = {
        {worstKernel,
         "clamped the filter kernel of %.1f %% of the pixels to pcss_max_kernel: their penumbrae are "
         "narrower than PCSS estimates (raise it with --param pcss_max_kernel=...)"},
        {worstStride,
         "spread the kernel's taps more than three texels apart in %.1f %% of the pixels "
         "(pcf_max_radius): blockers narrower than that can fall between them (raise it with --param "
         "pcf_max_radius=...)"},
        {worstSearch,
         "cut the blocker search of %.1f %% of the pixels to pcss_max_search: blockers beyond it are "
         "missed, and wide penumbrae end early on their lit side (raise it with --param "
         "pcss_max_search=...)"},
    };
    for (const auto& cut : cuts) {
        if (!(cut.fraction > KERNEL_CLAMP_WARNING)) continue;
        std::snprintf(text, sizeof text, cut.what, 100.0 * cut.fraction);
        warnings.push_back(method + " " + text);
    }
    return warnings;
}

} // namespace stsv
