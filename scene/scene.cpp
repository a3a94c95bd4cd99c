#include "scene/scene.h"

#include "core/error.h"

#include <cmath>

namespace stsv {

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
    for (const Material& m : materials)
        if (m.alphaTexture >= static_cast<int>(textures.size()))
            throw InputError(source, "material '" + m.name + "' refers to a missing texture");
    if (lights.empty()) throw InputError(source, "scene has no lights");
}

} // namespace stsv
