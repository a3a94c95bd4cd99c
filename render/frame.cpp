#include "render/frame.h"

#include "shadowmaps/shadow_map_stats.h"

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

Method autoMethod(const Scene& scene) {
    for (std::size_t t = 0; t < scene.triangleCount(); ++t)
        if (scene.opaqueOccluder(t)) return Method::DcsStsv;
    return Method::Stsv;
}

nlohmann::json methodSceneNotes(const Scene& scene, const MethodInfo& method) {
    nlohmann::json notes = nlohmann::json::object();
    // pw and dcs shade opaque triangles only; the traced reference and the shadow maps
    // alpha-test perforated ones, and every STSV method draws them.
    if (method.wedges != WedgeVariant::None && method.stsv == StsvTriangles::None) {
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
    const bool fractional = row && (row->readsTransmittanceFunctions() ||
                                    (row->writesTransmittance() && buffer == "transmittance"));
    if (stats.value("translucent_triangles", std::size_t(0)) > 0 && !fractional &&
        !stats.contains("ignored_perforated_triangles")) {
        std::string writers, readers;
        for (const MethodInfo& m : methodTable()) {
            if (m.writesTransmittance()) writers += (writers.empty() ? "" : ", ") + m.name;
            if (m.readsTransmittanceFunctions()) readers += (readers.empty() ? "" : ", ") + m.name;
        }
        warnings.push_back(method + " takes the scene's " +
                           std::to_string(stats["translucent_triangles"].get<std::size_t>()) +
                           " translucent triangles as blocking where alpha >= 0.5 and open elsewhere (" +
                           readers + ", and " + writers +
                           " with --buffer transmittance, let their fraction through)");
    }
    for (std::string& warning : shadowMapWarnings(method, stats)) warnings.push_back(std::move(warning));
    return warnings;
}

} // namespace stsv
