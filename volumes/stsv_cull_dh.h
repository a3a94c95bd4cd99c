// Culling of STSV volumes that cannot shadow any visible point (the ground's own-plane volume,
// say), before the volume is built: the hull and prism passes skip them, the CPU mirror builds
// them and gets no bits from them, so the buffers are the same. Compiles as C++ and as GLSL
// 4.50 (core/dh.h).
#ifndef STSV_VOLUMES_STSV_CULL_DH_H
#define STSV_VOLUMES_STSV_CULL_DH_H

#include "core/dh.h"
#include "scene/light_dh.h"
#include "scene/occlusion_rules_dh.h"
#include "volumes/stsv_dh.h"
#include "volumes/volume_dh.h"

DH_BEGIN

/// Lower bound of shadowTMin (scene/occlusion_rules_dh.h) over the receivers p in the scene box
/// [lo, hi]: the light frame's centre is the light's position (rectangle, disk, sphere), whose
/// distance to p is at most its largest distance to a box corner, or p + normal·farDistance
/// (directional), at distance farDistance. 1 % added for the rounding of the per-pixel distance.
DH_FUNC float stsvShadowTMinLowerBound(Light light, vec3 lo, vec3 hi, float farDistance) {
    float farthest = 0.0f;
    if (light.type == LIGHT_DIRECTIONAL) {
        farthest = farDistance * length(light.normal);
    } else {
        for (uint k = 0u; k < 8u; ++k)
            farthest = max(farthest, length(light.position - stsvBoxCorner(lo, hi, k)));
    }
    float sceneDiameter = length(hi - lo);
    farthest *= 1.01f;
    return farthest <= sceneDiameter ? SHADOW_T_MIN : SHADOW_T_MIN * (sceneDiameter / farthest);
}

/// True when triangle `t`'s volumes cannot shadow a point of the box [lo, hi] for the light
/// inside `sphere` (centre xyz, radius w): the sphere lies wholly on the lit side, at distance
/// L > 0 from the triangle's plane, and no corner of the box lies behind the plane by more than
/// the shadow segments' minimum start tMin·L, with tMin stsvShadowTMinLowerBound. Every visible
/// point p is in the box, so its e (its distance behind the plane) is at most that maximum (the
/// distance is linear); every light sample s has h.z = e + dist(s) ≥ e + L, so a crossing would
/// need e > tMin·h.z: impossible.
DH_FUNC bool stsvVolumeCannotShadowBox(StsvTriangle t, vec4 sphere, Light light, vec3 lo, vec3 hi,
                                       float farDistance) {
    vec3 n = vec3(t.m2);
    float lightDistance = dot(n, vec3(sphere)) + t.m2.w - sphere.w;
    float behind = -1e30f;
    for (uint k = 0u; k < 8u; ++k) behind = max(behind, -(dot(n, stsvBoxCorner(lo, hi, k)) + t.m2.w));
    vec3 far = max(abs(lo), abs(hi));
    // Round-off of e in the fragment shader (a few ulp of the coordinates), generously.
    float rounding = 4e-6f * (length(hi - lo) + max(max(far.x, far.y), far.z));
    return lightDistance > 0.0f &&
           behind + rounding <= 0.99f * stsvShadowTMinLowerBound(light, lo, hi, farDistance) * lightDistance;
}

DH_END

#endif // STSV_VOLUMES_STSV_CULL_DH_H
