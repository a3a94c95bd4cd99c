#include "scene/scene.h"

#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/occlusion_rules_dh.h"
#include "scene/surface_dh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace stsv {

namespace {
bool finite(vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The shortest text that reads back as the float `value` ("1e+38", "0.0625").
std::string shortText(float value) {
    char buffer[32];
    const char* end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    return std::string(static_cast<const char*>(buffer), end);
}

/// The shortest text of `value` to 3 significant digits ("2.6e+40", "0.0022").
std::string roundText(double value) {
    char buffer[32];
    const char* end = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 3).ptr;
    return std::string(static_cast<const char*>(buffer), end);
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

std::string lightSizeRangeText() {
    return "[" + shortText(MIN_LIGHT_SIZE) + ", " + shortText(MAX_LIGHT_SIZE) + "]";
}

std::string lightProblem(const Light& l) {
    if (l.type > LIGHT_DIRECTIONAL) return "has an unknown type";
    if (!(finite(l.position) && finite(l.normal) && finite(l.axisU) && finite(l.axisV) &&
          finite(l.radiance) && std::isfinite(l.angularRadius)))
        return "has a non-finite parameter";
    if (l.type != LIGHT_DIRECTIONAL) {
        // Its sizes: a rectangle's full edges (in double: the square of a huge axis overflows a
        // float), a disk's or sphere's radius.
        const auto edge = [](vec3 axis) { return 2.0 * glm::length(glm::dvec3(axis)); };
        const bool rectangle = l.type == LIGHT_RECTANGLE;
        for (const double size :
             {rectangle ? edge(l.axisU) : double(l.radius), rectangle ? edge(l.axisV) : double(l.radius)})
            if (!(size >= double(MIN_LIGHT_SIZE) && size <= double(MAX_LIGHT_SIZE)))
                return std::string("has ") + (rectangle ? "an edge" : "a radius") + " of " + roundText(size) +
                       " world units, outside the accepted " + lightSizeRangeText() +
                       " (the samplers need its area as a normal float)";
    }
    if (!std::isfinite(l.radius)) return "has a non-finite parameter";
    if (!withinSceneRange(l.position)) return "lies beyond ±" + sceneRangeText() + " world units";
    if (std::abs(length(l.normal) - 1.0f) > 1e-3f) return "has a non-unit normal";
    if (l.radiance.x < 0.0f || l.radiance.y < 0.0f || l.radiance.z < 0.0f) return "has a negative radiance";
    if (l.type != LIGHT_DIRECTIONAL && !(l.radius > 0.0f)) return "has no extent";
    if (l.type == LIGHT_DIRECTIONAL && !(l.angularRadius >= 0.0f && l.angularRadius < 1.5707963f))
        return "has an angular radius outside [0, 90) degrees";
    return {};
}

std::string texcoordProblem(vec2 uv, const Texture& texture) {
    const int size[2] = {texture.width, texture.height};
    for (int k = 0; k < 2; ++k) {
        const double texels = std::abs(double(uv[k])) * double(size[k]);
        if (!(texels < MAX_TEXEL_COORDINATE))
            return std::string(k == 0 ? "u" : "v") + " = " + shortText(uv[k]) + " is " + roundText(texels) +
                   " texels of texture '" + texture.name + "' (" + std::to_string(size[k]) +
                   (k == 0 ? " wide" : " high") +
                   "), beyond the 2^24 texels where a float texel coordinate is exact (past it "
                   "consecutive floats are two or more texels apart)";
    }
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

namespace {

/// The spacing of floats just above |x|: how finely a coordinate of that size is resolved.
double floatSpacing(float x) {
    const float a = std::abs(x);
    return double(std::nextafter(a, std::numeric_limits<float>::infinity())) - double(a);
}

/// Whether triangle t's vertices, as the floats the scene holds, span no area (coincide or lie on
/// one line). In double: the differences of floats and their products are then exact enough
/// that only a truly flat triangle gives zero.
bool collapsed(const Scene& scene, std::size_t t) {
    const glm::dvec3 a(scene.positions[scene.triangles[t].x]), b(scene.positions[scene.triangles[t].y]),
        c(scene.positions[scene.triangles[t].z]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

/// Scene::validate's last step: the float precision left where the scene lies.
void checkPrecision(Scene& scene) {
    // Float spacing at the largest |coordinate| against the bounding-box diagonal: far from the
    // origin a float coordinate keeps only the bits its offset leaves (MIN_SCENE_PRECISION).
    float largest = 0.0f;
    for (const vec3& p : scene.positions)
        largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    const Bounds box = scene.bounds();
    const double diagonal = glm::length(glm::dvec3(box.hi) - glm::dvec3(box.lo));
    const double spacing = floatSpacing(largest);
    // (A scene of one point has no extent to lose: its triangles are degenerate wherever it is.)
    if (!(diagonal > 0.0) || spacing <= MIN_SCENE_PRECISION * diagonal) return;
    std::size_t flat = 0;
    for (std::size_t t = 0; t < scene.triangles.size(); ++t) flat += collapsed(scene, t) ? 1 : 0;
    const vec3 centre = box.center();
    const std::string where = "the scene lies far from the origin (coordinates up to " + roundText(largest) +
                              " world units), where floats are " + roundText(spacing) + " apart, " +
                              roundText(spacing / diagonal) + " of its " + roundText(diagonal) +
                              "-unit diagonal";
    const auto shift = [](float c) { return roundText(0.0 - double(c)); }; // no "-0"
    const std::string fix = "recentre the scene near the origin (translate it by [" + shift(centre.x) + ", " +
                            shift(centre.y) + ", " + shift(centre.z) + "])";
    if (flat > 0)
        throw InputError(scene.source, where + ": " + std::to_string(flat) + " of its " +
                                           std::to_string(scene.triangles.size()) +
                                           " triangles have collapsed to lines or points; " + fix);
    const std::string warning =
        where + " (more than " + roundText(MIN_SCENE_PRECISION) + "): edges and shadows may shift; " + fix;
    if (std::find(scene.warnings.begin(), scene.warnings.end(), warning) == scene.warnings.end())
        scene.warnings.push_back(warning);
}

} // namespace

void Scene::validate() {
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
    // A textured triangle's texture coordinates must name texels (MAX_TEXEL_COORDINATE); an
    // untextured one's only need to be finite (checked above).
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Material& m = materialOf(t);
        for (const int texture : {m.alphaTexture, m.blendTexture}) {
            if (texture < 0) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = triangles[t][k];
                if (const std::string problem = texcoordProblem(texcoords[v], textures[std::size_t(texture)]);
                    !problem.empty())
                    throw InputError(source, "triangle " + std::to_string(t) + " vertex " +
                                                 std::to_string(v) + " texture coordinate: " + problem);
            }
        }
    }
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
    checkPrecision(*this);
    // Triangles whose corners coincide or lie on one line are kept and counted (no method draws
    // them, and none casts a shadow); a scene of nothing else would render as empty background.
    zeroAreaTriangles = 0;
    for (std::size_t t = 0; t < triangles.size(); ++t) zeroAreaTriangles += collapsed(*this, t) ? 1 : 0;
    if (zeroAreaTriangles == triangles.size())
        throw InputError(source, "every triangle is degenerate: the " + std::to_string(triangles.size()) +
                                     " triangle(s) have zero area (their vertices coincide or lie on one "
                                     "line), so nothing would be drawn or cast a shadow");
}

vec3 pointOnTriangle(const Scene& scene, std::uint32_t tri, vec2 bary) {
    const uvec3 idx = scene.triangles[tri];
    return trianglePoint(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z], bary);
}

vec3 shadingNormal(const Scene& scene, std::uint32_t tri, vec3 eye, vec3 p) {
    const uvec3 idx = scene.triangles[tri];
    return triangleShadingNormal(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z],
                                 scene.materialOf(tri).doubleSided, eye, p);
}

} // namespace stsv
