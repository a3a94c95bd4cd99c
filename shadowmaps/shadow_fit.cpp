#include "shadowmaps/shadow_fit.h"

#include "core/parallel.h"
#include "sampling/light_sampling_dh.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace stsv {

namespace {

/// A convex polygon of at most 3 + 5 vertices (a triangle clipped by five planes).
struct Polygon {
    std::array<vec3, 8> v;
    int n = 0;
};

/// The part of `poly` where dot(plane.xyz, p − eye) ≥ plane.w (Sutherland–Hodgman).
Polygon clipPolygon(const Polygon& poly, vec3 eye, vec4 plane) {
    Polygon out;
    for (int i = 0; i < poly.n; ++i) {
        const vec3 a = poly.v[std::size_t(i)], b = poly.v[std::size_t((i + 1) % poly.n)];
        const float da = dot(vec3(plane), a - eye) - plane.w, db = dot(vec3(plane), b - eye) - plane.w;
        if (da >= 0.0f) out.v[std::size_t(out.n++)] = a;
        if ((da >= 0.0f) != (db >= 0.0f) && out.n < 8)
            out.v[std::size_t(out.n++)] = a + (b - a) * (da / (da - db));
    }
    return out;
}

/// The union of two boxes (the join of the parallel reductions).
Bounds unite(Bounds a, const Bounds& b) {
    a.extend(b);
    return a;
}

bool overlaps(const Bounds& a, const Bounds& b) {
    return all(lessThanEqual(a.lo, b.hi)) && all(lessThanEqual(b.lo, a.hi));
}

/// Points whose convex hull holds a finite light: a rectangle's corners, the square around a
/// disk, the box around a sphere.
std::vector<vec3> lightPoints(const Light& light) {
    const vec3 c = light.position;
    if (light.type == LIGHT_RECTANGLE)
        return {c - light.axisU - light.axisV, c + light.axisU - light.axisV, c + light.axisU + light.axisV,
                c - light.axisU + light.axisV};
    if (light.type == LIGHT_DISK) {
        vec3 u, v;
        orthonormalBasis(normalize(light.normal), u, v);
        u *= light.radius;
        v *= light.radius;
        return {c - u - v, c + u - v, c + u + v, c - u + v};
    }
    std::vector<vec3> points;
    points.reserve(8);
    for (int i = 0; i < 8; ++i)
        points.push_back(c + light.radius *
                                 vec3(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f));
    return points;
}

/// Median and 90th percentile of a list (reordered).
std::pair<double, double> medianP90(std::vector<float>& values) {
    if (values.empty()) return {0.0, 0.0};
    const auto at = [&](double q) {
        const std::size_t k = std::min(values.size() - 1, std::size_t(q * double(values.size())));
        std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
        return double(values[k]);
    };
    return {at(0.5), at(0.9)};
}

} // namespace

Bounds shadowReceiverBounds(const Scene& scene, float aspect) {
    const Camera& camera = scene.camera;
    const vec3 forward = normalize(camera.target - camera.eye);
    const vec3 right = normalize(cross(forward, camera.up));
    const vec3 up = cross(right, forward);
    const float tanY = std::tan(0.5f * glm::radians(camera.fovY)), tanX = tanY * aspect;
    const float nearPlane = 1e-6f * std::max(scene.bounds().diameter(), 1e-30f);
    // Inward normals of the frustum's planes through the eye, and the near plane at nearPlane.
    const std::array<vec4, 5> planes = {vec4(forward, nearPlane), vec4(tanX * forward - right, 0.0f),
                                        vec4(tanX * forward + right, 0.0f), vec4(tanY * forward - up, 0.0f),
                                        vec4(tanY * forward + up, 0.0f)};
    const std::size_t count = scene.triangleCount();
    return parallelReduce(
        count, Bounds{},
        [&](std::size_t begin, std::size_t end) {
            Bounds b;
            for (std::size_t t = begin; t < end; ++t) {
                const uvec3 tri = scene.triangles[t];
                Polygon poly;
                poly.v = {scene.positions[tri.x], scene.positions[tri.y], scene.positions[tri.z]};
                poly.n = 3;
                for (const vec4& plane : planes) {
                    poly = clipPolygon(poly, camera.eye, plane);
                    if (poly.n == 0) break;
                }
                for (int i = 0; i < poly.n; ++i) b.extend(poly.v[std::size_t(i)]);
            }
            return b;
        },
        unite);
}

Bounds shadowCasterBounds(const Scene& scene, const Light& light, const Bounds& receivers) {
    if (receivers.empty()) return {};
    // The box a caster must meet, and the extent of the light for the plane test: for finite
    // lights its points; for a directional light the cone of directions towards it.
    Bounds reach = receivers;
    std::vector<vec3> points;
    const bool directional = light.type == LIGHT_DIRECTIONAL;
    const vec3 towardLight = normalize(light.normal);
    if (directional) {
        const float across = scene.bounds().diameter() + receivers.diameter();
        const float spread = across * std::tan(std::min(light.angularRadius, 1.5f));
        for (int i = 0; i < 8; ++i) {
            const vec3 p = receivers.corner(i) + across * towardLight;
            reach.extend(p + vec3(spread));
            reach.extend(p - vec3(spread));
        }
    } else {
        points = lightPoints(light);
        for (const vec3& p : points) reach.extend(p);
    }
    vec3 receiverCorners[8];
    for (int i = 0; i < 8; ++i) receiverCorners[i] = receivers.corner(i);
    const float eps = 1e-6f * std::max(reach.diameter(), 1e-30f);
    const std::size_t count = scene.triangleCount();
    return parallelReduce(
        count, Bounds{},
        [&](std::size_t begin, std::size_t end) {
            Bounds b;
            for (std::size_t t = begin; t < end; ++t) {
                const uvec3 tri = scene.triangles[t];
                const vec3 a = scene.positions[tri.x], e1 = scene.positions[tri.y],
                           e2 = scene.positions[tri.z];
                Bounds box;
                box.extend(a);
                box.extend(e1);
                box.extend(e2);
                if (!overlaps(box, reach)) continue;
                const vec3 cr = cross(e1 - a, e2 - a);
                const float area = length(cr);
                if (!(area > 0.0f)) continue; // a degenerate triangle blocks no segment
                const vec3 n = cr / area;
                // A segment from a receiver to the light crosses the plane only when its ends lie on
                // opposite sides.
                float rlo = 1e30f, rhi = -1e30f;
                for (const vec3& p : receiverCorners) {
                    const float d = dot(n, p - a);
                    rlo = std::min(rlo, d);
                    rhi = std::max(rhi, d);
                }
                float llo, lhi;
                if (directional) {
                    const float s = dot(n, towardLight),
                                spread = std::sin(std::min(light.angularRadius, 1.5f));
                    llo = s - spread;
                    lhi = s + spread;
                } else {
                    llo = 1e30f;
                    lhi = -1e30f;
                    for (const vec3& p : points) {
                        const float d = dot(n, p - a);
                        llo = std::min(llo, d);
                        lhi = std::max(lhi, d);
                    }
                }
                const float lightEps = directional ? 1e-6f : eps;
                if (!((rlo < -eps && lhi > lightEps) || (rhi > eps && llo < -lightEps))) continue;
                box.lo = max(box.lo, reach.lo);
                box.hi = min(box.hi, reach.hi);
                b = unite(b, box);
            }
            return b;
        },
        unite);
}

ShadowMapView fitFrameShadowMap(const Scene& scene, const Light& light, const Bounds& receivers,
                                const ShadowMapSettings& settings) {
    const int size = shadowMapSize(settings);
    if (settings.fit == 0 || receivers.empty()) return fitShadowMap(light, scene.bounds(), size);
    return fitShadowMapToRegion(light, receivers, shadowCasterBounds(scene, light, receivers), size);
}

nlohmann::json shadowTexelFootprint(const ShadowMapView& view, const Camera& camera, const GBuffer& gbuffer) {
    std::vector<float> world, perPixel;
    const vec3 forward = normalize(camera.target - camera.eye);
    // World size of a G-buffer pixel at view depth z: 2·z·tan(fovY/2)/height.
    const float pixelPerDepth =
        2.0f * std::tan(0.5f * glm::radians(camera.fovY)) / float(std::max(gbuffer.height, 1));
    for (std::size_t i = 0; i < gbuffer.triangle.size(); ++i) {
        if (!gbuffer.covered(i)) continue;
        const vec3 p = gbuffer.position[i];
        const ShadowMapCoord c = shadowMapProject(view, p);
        if (c.valid == 0.0f) continue;
        float texel = shadowMapTexelWorld(view, c.axial);
        if (view.projection == SHADOW_MAP_CUBE) texel *= c.depth / std::max(c.axial, 1e-30f);
        const float pixel = dot(p - camera.eye, forward) * pixelPerDepth;
        world.push_back(texel);
        if (pixel > 0.0f) perPixel.push_back(texel / pixel);
    }
    const auto [worldMedian, worldP90] = medianP90(world);
    const auto [ratioMedian, ratioP90] = medianP90(perPixel);
    return {{"texel_world_median", worldMedian},
            {"texel_world_p90", worldP90},
            {"texels_per_pixel_median", ratioMedian},
            {"texels_per_pixel_p90", ratioP90}};
}

} // namespace stsv
