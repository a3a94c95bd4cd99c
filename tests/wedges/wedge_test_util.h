// Shared helpers of the wedges tests: random soups and closed meshes, exact counting.
#pragma once

#include "core/dh.h"
#include "scene/geometry.h"
#include "scene/scene.h"

#include <glm/gtx/string_cast.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

namespace stsv::test {

inline std::string str(vec3 v) {
    return glm::to_string(v);
}
inline std::string str(vec2 v) {
    return glm::to_string(v);
}

class Rng {
  public:
    explicit Rng(std::uint64_t seed) : m_engine(seed) {}
    float uniform(float lo = 0.0f, float hi = 1.0f) {
        return static_cast<float>(std::uniform_real_distribution<double>(lo, hi)(m_engine));
    }
    int index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(m_engine); }
    vec3 inBox(vec3 lo, vec3 hi) {
        return vec3(uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z));
    }

  private:
    std::mt19937_64 m_engine;
};

/// A scene of one mesh, untransformed.
inline Scene sceneOf(const MeshData& mesh) {
    Scene scene;
    appendMesh(scene, mesh, mat4(1.0f), "m");
    return scene;
}

/// Appends triangle (a, b, c) with material `material` (texture coordinates 0).
inline void addTri(Scene& s, vec3 a, vec3 b, vec3 c, std::uint32_t material = 0) {
    s.addTriangle(a, b, c, vec2(0.0f), vec2(0.0f), vec2(0.0f), material);
}

/// Number of triangles the segment p → s crosses at t ∈ (tMin, 1), `ignore` excluded, by
/// double-precision Möller–Trumbore (the independent brute-force depth complexity).
inline int countCrossings(const Scene& scene, vec3 pf, vec3 sf, double tMin,
                          std::uint32_t ignore = 0xffffffffu) {
    const dvec3 p(pf), d = dvec3(sf) - dvec3(pf);
    int count = 0;
    for (std::uint32_t t = 0; t < scene.triangleCount(); ++t) {
        if (t == ignore || scene.perforated(t)) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 v0(scene.positions[idx.x]), e1 = dvec3(scene.positions[idx.y]) - v0,
                                                e2 = dvec3(scene.positions[idx.z]) - v0;
        const dvec3 q = cross(d, e2);
        const double det = dot(e1, q);
        if (det == 0.0) continue;
        const dvec3 r = p - v0;
        const double u = dot(r, q) / det;
        const dvec3 w = cross(r, e1);
        const double v = dot(d, w) / det;
        const double tt = dot(e2, w) / det;
        if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && tt > tMin && tt < 1.0) ++count;
    }
    return count;
}

/// A UV sphere (closed, consistently wound outwards), welded at the poles and the seam only by
/// position: every ring vertex is emitted per triangle (unindexed) so welding has work to do.
inline MeshData makeSphereMesh(int slices, int stacks) {
    MeshData m;
    auto point = [&](int i, int j) {
        if (j == 0) return vec3(0.0f, 1.0f, 0.0f);
        if (j == stacks) return vec3(0.0f, -1.0f, 0.0f);
        const float th = 3.14159265f * float(j) / float(stacks),
                    ph = 6.2831853f * float(i % slices) / float(slices);
        return vec3(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
    };
    auto tri = [&](vec3 a, vec3 b, vec3 c) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        m.positions.insert(m.positions.end(), {a, b, c});
        m.texcoords.insert(m.texcoords.end(), 3, vec2(0.0f));
        m.triangles.push_back(uvec3(base, base + 1, base + 2));
        m.triangleMaterial.push_back(0);
    };
    for (int j = 0; j < stacks; ++j)
        for (int i = 0; i < slices; ++i) {
            const vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
            if (j != 0) tri(a, b, c);
            if (j != stacks - 1) tri(a, c, d);
        }
    Material mat;
    mat.name = "sphere";
    m.materials.push_back(mat);
    return m;
}

inline MeshData makeTorusMesh(int segments, int sides, float major, float minor) {
    return makeTubeMesh(segments, sides, minor, [&](float u) {
        const float a = 6.2831853f * u;
        return vec3(major * std::cos(a), 0.0f, major * std::sin(a));
    });
}

/// (p, q) torus knot of tube radius `minor` (scene/geometry.h).
inline MeshData makeTorusKnotMesh(int segments, int sides, float minor, int p = 2, int q = 3) {
    return stsv::makeTorusKnotMesh(segments, sides, minor, p, q);
}

} // namespace stsv::test
