#include "scene/scene.h"

#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/occlusion_rules_dh.h"

#include <cmath>

namespace stsv {

namespace {
bool finite(vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace

bool withinSceneRange(vec3 v) {
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(v[k]) <= MAX_SCENE_COORDINATE)) return false;
    return true;
}

std::string sceneRangeText() {
    return "1e9";
}

std::string albedoProblem(vec3 albedo) {
    if (!finite(albedo)) return "must be finite";
    if (albedo.x < 0.0f || albedo.y < 0.0f || albedo.z < 0.0f) return "components must be ≥ 0";
    if (albedo.x > 1.0f || albedo.y > 1.0f || albedo.z > 1.0f)
        return "components must be ≤ 1 (a diffuse reflectance)";
    return {};
}

std::string lightProblem(const Light& l) {
    if (l.type > LIGHT_DIRECTIONAL) return "has an unknown type";
    if (!(finite(l.position) && finite(l.normal) && finite(l.axisU) && finite(l.axisV) &&
          finite(l.radiance) && std::isfinite(l.radius) && std::isfinite(l.angularRadius)))
        return "has a non-finite parameter";
    if (!withinSceneRange(l.position)) return "lies beyond ±" + sceneRangeText() + " world units";
    if (std::abs(length(l.normal) - 1.0f) > 1e-3f) return "has a non-unit normal";
    if (l.radiance.x < 0.0f || l.radiance.y < 0.0f || l.radiance.z < 0.0f) return "has a negative radiance";
    if (l.type != LIGHT_DIRECTIONAL && !(l.radius > 0.0f)) return "has no extent";
    if (l.type == LIGHT_DIRECTIONAL && !(l.angularRadius >= 0.0f && l.angularRadius < 1.5707963f))
        return "has an angular radius outside [0, 90) degrees";
    return {};
}

void checkSceneMemory(const std::string& what, double triangles) {
    checkMemory(what + ": " + std::to_string(std::llround(triangles)) + " triangles",
                triangles * SCENE_BYTES_PER_TRIANGLE, "use a coarser mesh");
}

std::uint32_t opticalDepthUnits(double alpha) {
    if (!(alpha > 0.0)) return 0u;
    if (alpha >= 1.0) return OPTICAL_DEPTH_OPAQUE;
    // α < 1 in double: the largest finite depth, α = 1 − 2^−53, is 36.7 · 65536 units.
    return static_cast<std::uint32_t>(std::llround(-std::log1p(-alpha) * double(OPTICAL_DEPTH_SCALE)));
}

OpticalDepthTable opticalDepthTable(const Material& material) {
    OpticalDepthTable table{};
    for (int a = 0; a < 256; ++a)
        table[std::size_t(a)] = opticalDepthUnits(double(a) / 255.0 * double(material.alphaFactor));
    return table;
}

bool Scene::hasTranslucent() const {
    for (const Material& m : materials)
        if (m.translucent()) return true;
    return false;
}

Bounds Scene::bounds() const {
    Bounds b;
    for (const vec3& p : positions) b.extend(p);
    return b;
}

void Scene::addTriangle(vec3 a, vec3 b, vec3 c, vec2 ta, vec2 tb, vec2 tc, std::uint32_t material) {
    const auto base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), {a, b, c});
    texcoords.insert(texcoords.end(), {ta, tb, tc});
    triangles.emplace_back(base, base + 1, base + 2);
    triangleMaterial.push_back(material);
}

void Scene::validate() const {
    if (triangles.empty()) throw InputError(source, "scene has no triangles");
    if (texcoords.size() != positions.size())
        throw InputError(source, "internal: texcoord count differs from position count");
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const vec3 p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(source, "vertex " + std::to_string(i) + " has a non-finite coordinate");
        if (!withinSceneRange(p))
            throw InputError(source, "vertex " + std::to_string(i) + " lies beyond ±" + sceneRangeText() +
                                         " world units");
        if (!std::isfinite(texcoords[i].x) || !std::isfinite(texcoords[i].y))
            throw InputError(source, "vertex " + std::to_string(i) + " has a non-finite texture coordinate");
    }
    if (triangleMaterial.size() != triangles.size())
        throw InputError(source, "internal: material count differs from triangle count");
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k)
            if (triangles[t][k] >= positions.size())
                throw InputError(source, "triangle " + std::to_string(t) + " has out-of-range vertex index " +
                                             std::to_string(triangles[t][k]));
        if (triangleMaterial[t] >= materials.size())
            throw InputError(source, "triangle " + std::to_string(t) + " has an unknown material");
    }
    for (const Material& m : materials) {
        if (m.alphaTexture >= static_cast<int>(textures.size()) ||
            m.blendTexture >= static_cast<int>(textures.size()))
            throw InputError(source, "material '" + m.name + "' refers to a missing texture");
        if (!(m.alphaFactor >= 0.0f && m.alphaFactor <= 1.0f))
            throw InputError(source, "material '" + m.name + "' alpha factor must be in [0, 1]");
        if (m.blendTexture >= 0 && !m.translucent())
            throw InputError(source,
                             "internal: material '" + m.name + "' has a blend texture but is not Blend");
        if (const std::string problem = albedoProblem(m.albedo); !problem.empty())
            throw InputError(source, "material '" + m.name + "' albedo: " + problem);
    }
    for (const Texture& t : textures)
        if (t.width <= 0 || t.height <= 0 || t.rgba.size() != std::size_t(t.width) * t.height * 4)
            throw InputError(source, "texture '" + t.name + "' is empty or has the wrong byte count");
    if (lights.empty()) throw InputError(source, "scene has no lights");
    if (lights.size() > MAX_SCENE_LIGHTS)
        throw InputError(source, "scene has " + std::to_string(lights.size()) + " lights, more than the " +
                                     std::to_string(MAX_SCENE_LIGHTS) + " a frame renders");
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (const std::string problem = lightProblem(lights[i]); !problem.empty())
            throw InputError(source, "light " + std::to_string(i) + " " + problem);
    if (!withinSceneRange(camera.eye) || !withinSceneRange(camera.target))
        throw InputError(source, "camera eye or target lies beyond ±" + sceneRangeText() + " world units");
    const vec3 forward = camera.target - camera.eye;
    if (!(finite(camera.eye) && finite(camera.target) && finite(camera.up) && length(forward) > 0.0f &&
          length(cross(forward, camera.up)) > 0.0f && camera.fovY > 0.0f && camera.fovY < 180.0f))
        throw InputError(source,
                         "camera is degenerate (eye = target, up along the view, or fovY outside (0, 180))");
}

} // namespace stsv
