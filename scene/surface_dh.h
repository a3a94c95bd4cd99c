// The visible surface's rules, one text for the Embree G-buffer and the Vulkan passes: the point
// at barycentrics (b1, b2) of a triangle, and its shading normal. Compiles as C++ and as GLSL
// (see core/dh.h).
#ifndef STSV_SCENE_SURFACE_DH_H
#define STSV_SCENE_SURFACE_DH_H

#include "core/dh.h"

DH_BEGIN

/// The point of triangle (v0, v1, v2) at barycentrics (b1, b2): the weights of v1 and v2.
DH_FUNC vec3 trianglePoint(vec3 v0, vec3 v1, vec3 v2, vec2 bary) {
    return v0 + bary.x * (v1 - v0) + bary.y * (v2 - v0);
}

/// The shading normal at p: the winding normal of (v0, v1, v2), turned towards the eye for a
/// double-sided material (lit from both sides).
DH_FUNC vec3 triangleShadingNormal(vec3 v0, vec3 v1, vec3 v2, bool doubleSided, vec3 eye, vec3 p) {
    vec3 n = normalize(cross(v1 - v0, v2 - v0));
    if (doubleSided && dot(n, eye - p) < 0.0f) n = -n;
    return n;
}

DH_END

#endif
