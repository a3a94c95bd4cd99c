#include "render/frame.h"

#include "shadowmaps/shadow_fit.h"

#include <algorithm>
#include <cstdio>

namespace stsv {

void initFrameImages(const Scene& scene, const GBuffer& gbuffer, float ambient, Frame& frame) {
    frame.color = ImageF(gbuffer.width, gbuffer.height, 3);
    frame.visibility = ImageF(gbuffer.width, gbuffer.height, 1);
    for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) {
        const int x = static_cast<int>(i % std::size_t(gbuffer.width)),
                  y = static_cast<int>(i / std::size_t(gbuffer.width));
        const vec3 c =
            gbuffer.covered(i) ? ambient * scene.materialOf(gbuffer.triangle[i]).albedo : BACKGROUND;
        for (int k = 0; k < 3; ++k) frame.color.at(x, y, k) = c[k];
    }
}

nlohmann::json sceneStats(const Scene& scene) {
    std::size_t perforated = 0, translucent = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        translucent += scene.translucent(t) ? 1 : 0;
        perforated += scene.perforated(t) && !scene.translucent(t) ? 1 : 0;
    }
    return {{"source", scene.source},
            {"triangles", scene.triangleCount()},
            {"perforated_triangles", perforated},
            {"translucent_triangles", translucent},
            {"skipped_faces", scene.skippedFaces},
            {"zero_area_triangles", scene.zeroAreaTriangles},
            {"lights", scene.lights.size()}};
}

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

nlohmann::json methodSceneNotes(const Scene& scene, const MethodInfo& method) {
    nlohmann::json notes = nlohmann::json::object();
    // pw and dcs shade opaque triangles only; the traced reference and the shadow maps
    // alpha-test perforated ones, and every STSV method draws them.
    if (method.opaque != OpaqueTechnique::None && method.stsv == StsvTriangles::None) {
        std::size_t perforated = 0;
        for (std::size_t t = 0; t < scene.triangleCount(); ++t) perforated += scene.opaqueOccluder(t) ? 0 : 1;
        notes["ignored_perforated_triangles"] = perforated;
        if (perforated > 0) notes["ignored_perforated_triangles_use"] = method.name + "+stsv";
    }
    std::size_t translucent = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) translucent += scene.translucent(t) ? 1 : 0;
    if (translucent > 0) notes["translucent_triangles"] = translucent;
    return notes;
}

std::vector<std::string> frameWarnings(const nlohmann::json& stats) {
    std::vector<std::string> warnings;
    const std::string method = stats.contains("options") ? stats["options"].value("method", "") : "";
    if (stats.value("ignored_perforated_triangles", std::size_t(0)) > 0)
        warnings.push_back(method + " shades opaque triangles only: the shadows of the scene's " +
                           std::to_string(stats["ignored_perforated_triangles"].get<std::size_t>()) +
                           " perforated and translucent triangles are missing (" +
                           stats.value("ignored_perforated_triangles_use", std::string()) + " draws them)");
    // Translucent triangles by their binary stand-in: every method but those that ignore them
    // (ignored_perforated_triangles), read transmittance functions, or write a transmittance buffer.
    const std::string buffer = stats.contains("options") ? stats["options"].value("buffer", "") : "";
    const MethodInfo* row = nullptr;
    for (const MethodInfo& m : methodTable())
        if (m.name == method) row = &m;
    const bool fractional = row && (readsTransmittanceFunctions(row->shadowMap) ||
                                    (row->writesTransmittance() && buffer == "transmittance"));
    if (stats.value("translucent_triangles", std::size_t(0)) > 0 && !fractional &&
        !stats.contains("ignored_perforated_triangles")) {
        std::string writers, readers;
        for (const MethodInfo& m : methodTable()) {
            if (m.writesTransmittance()) writers += (writers.empty() ? "" : ", ") + m.name;
            if (readsTransmittanceFunctions(m.shadowMap)) readers += (readers.empty() ? "" : ", ") + m.name;
        }
        warnings.push_back(method + " takes the scene's " +
                           std::to_string(stats["translucent_triangles"].get<std::size_t>()) +
                           " translucent triangles as blocking where alpha >= 0.5 and open elsewhere (" +
                           readers + ", and " + writers +
                           " with --buffer transmittance, let their fraction through)");
    }
    if (stats.contains("shadow_maps") && stats["shadow_maps"].is_array()) {
        double worstKernel = 0.0, worstSearch = 0.0, worstStride = 0.0;
        for (const nlohmann::json& map : stats["shadow_maps"]) {
            worstKernel = std::max(worstKernel, map.value("kernel_clamped_fraction", 0.0));
            worstSearch = std::max(worstSearch, map.value("search_clamped_fraction", 0.0));
            worstStride = std::max(worstStride, map.value("kernel_strided_fraction", 0.0));
        }
        std::size_t openEdges = 0;
        for (const nlohmann::json& map : stats["shadow_maps"])
            openEdges = std::max(openEdges, map.value("open_edges", std::size_t(0)));
        if (openEdges > 0)
            warnings.push_back(
                method + " assumes closed objects, and the scene has " + std::to_string(openEdges) +
                " open edges (single quads, open meshes): behind a surface facing the light with "
                "no back face after it everything counts as shadowed, behind a lone back face "
                "nothing");
        char text[240];
        std::uint64_t capped = 0, rays = 0;
        std::uint32_t cap = 0;
        for (const nlohmann::json& map : stats["shadow_maps"])
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
        if (worstKernel > KERNEL_CLAMP_WARNING) {
            std::snprintf(text, sizeof text,
                          "%s clamped the filter kernel of %.1f %% of the pixels to pcss_max_kernel: their "
                          "penumbrae are narrower than PCSS estimates (raise it with --param "
                          "pcss_max_kernel=...)",
                          method.c_str(), 100.0 * worstKernel);
            warnings.emplace_back(text);
        }
        if (worstStride > KERNEL_CLAMP_WARNING) {
            std::snprintf(text, sizeof text,
                          "%s spread the kernel's taps more than three texels apart in %.1f %% of the pixels "
                          "(pcf_max_radius): blockers narrower than that can fall between them (raise it "
                          "with --param pcf_max_radius=...)",
                          method.c_str(), 100.0 * worstStride);
            warnings.emplace_back(text);
        }
        if (worstSearch > KERNEL_CLAMP_WARNING) {
            std::snprintf(text, sizeof text,
                          "%s cut the blocker search of %.1f %% of the pixels to pcss_max_search: blockers "
                          "beyond it are missed, and wide penumbrae end early on their lit side (raise it "
                          "with --param pcss_max_search=...)",
                          method.c_str(), 100.0 * worstSearch);
            warnings.emplace_back(text);
        }
    }
    return warnings;
}

} // namespace stsv
