// Test scenes of translucent (Blend) occluders: a ground under a small square light, seen from
// straight above, and horizontal quads ("veils") over it.
#pragma once

#include "scene/geometry.h"
#include "scene/scene.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace stsv::test {

/// Ground [−2, 2]² at y = 0 and a camera straight above it; a square light of side `lightSize`
/// at y = 3 facing down.
inline Scene groundScene(float lightSize) {
    Scene s;
    s.source = "transmittance-test";
    s.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    const vec3 a(-2, 0, -2), b(2, 0, -2), c(2, 0, 2), d(-2, 0, 2);
    s.addTriangle(a, c, b, vec2(0, 0), vec2(1, 1), vec2(1, 0), 0);
    s.addTriangle(a, d, c, vec2(0, 0), vec2(0, 1), vec2(1, 1), 0);
    s.lights.push_back(makeRectangleLight(vec3(0.0f, 3.0f, 0.0f), vec3(0.0f, -1.0f, 0.0f), vec2(lightSize),
                                          vec3(1.0f), vec3(1.0f, 0.0f, 0.0f)));
    // Slightly off the quads' diagonals: a segment exactly through the edge two triangles share
    // crosses both (the inclusive rule every method shares), so a pixel centre on it would count
    // the surface twice; the set-up keeps pixel centres off it.
    s.camera.eye = vec3(0.0137f, 2.5f, 0.0071f);
    s.camera.target = vec3(0.0137f, 0.0f, 0.0071f);
    s.camera.up = vec3(0.0f, 0.0f, -1.0f);
    s.camera.fovY = 60.0f;
    return s;
}

/// A horizontal quad [−h, h]² at height y with uv over [0, 1]² (u along x, v along z).
inline void addVeil(Scene& s, float y, float h, std::uint32_t material) {
    const vec3 a(-h, y, -h), b(h, y, -h), c(h, y, h), d(-h, y, h);
    s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), material);
    s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), material);
}

inline std::uint32_t addBlend(Scene& s, float factor, int texture = -1) {
    Material m{"veil", vec3(0.5f), -1, WrapMode::Clamp, true};
    setMaterialAlpha(m, s.textures, AlphaMode::Blend, texture, factor, 0.5f);
    return addMaterial(s, m);
}

/// Two veils of constant α = 0.5 and 0.3 over the ground (light side 0.2), and an opaque tile
/// over part of them.
inline Scene veilsAndTile() {
    Scene s = groundScene(0.2f);
    addVeil(s, 1.0f, 0.9f, addBlend(s, 0.5f));
    addVeil(s, 1.4f, 0.6f, addBlend(s, 0.3f));
    Material tile{"tile", vec3(0.4f), -1, WrapMode::Repeat, false};
    const std::uint32_t m = addMaterial(s, tile);
    const vec3 a(0.1f, 1.8f, 0.1f), b(0.5f, 1.8f, 0.1f), c(0.5f, 1.8f, 0.5f), d(0.1f, 1.8f, 0.5f);
    s.addTriangle(a, b, c, vec2(0), vec2(0), vec2(0), m);
    s.addTriangle(a, c, d, vec2(0), vec2(0), vec2(0), m);
    s.validate();
    return s;
}

/// `scene` with its triangles in a random order (mt19937 of `seed`): the same surfaces, other
/// triangle indices.
inline Scene shuffledTriangles(const Scene& scene, unsigned seed) {
    Scene shuffled = scene;
    std::vector<std::size_t> order(scene.triangleCount());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::shuffle(order.begin(), order.end(), std::mt19937(seed));
    shuffled.triangles.clear();
    shuffled.triangleMaterial.clear();
    for (std::size_t t : order) {
        shuffled.triangles.push_back(scene.triangles[t]);
        shuffled.triangleMaterial.push_back(scene.triangleMaterial[t]);
    }
    shuffled.validate();
    return shuffled;
}

} // namespace stsv::test
