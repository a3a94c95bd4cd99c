// The data an STSV fragment needs about its volume (STSV paper §3: passed from the extrusion
// stage as flat varyings): the triangle constants of Eq. 2–5 and the volume's planes.
#ifndef STSV_SHADERS_STSV_VOLUME_GLSL
#define STSV_SHADERS_STSV_VOLUME_GLSL

#include "volumes/extrusion_dh.h"

/// Per-volume values as flat varyings: 11 vec4 (44 components, lavapipe allows 128).
struct StsvVaryings {
    vec4 m0;
    vec4 m1;
    vec4 m2;
    vec4 uv0E1;  ///< uv0 (xy), uvE1 (zw)
    vec4 uvE2;   ///< uvE2 (xy), zw unused
    uvec4 ids;   ///< texture, flags, triangle, side | planeCount << 8
    vec4 planes[5];
};

StsvVaryings stsvPackVaryings(StsvTriangle t, StsvVolume v, uint side) {
    StsvVaryings o;
    o.m0 = t.m0;
    o.m1 = t.m1;
    o.m2 = t.m2;
    o.uv0E1 = vec4(t.uv0, t.uvE1);
    o.uvE2 = vec4(t.uvE2, 0.0, 0.0);
    o.ids = uvec4(t.texture, t.flags, t.triangle, side | (v.planeCount << 8u));
    for (int i = 0; i < 5; ++i) o.planes[i] = v.planes[i];
    return o;
}

StsvTriangle stsvUnpackTriangle(vec4 m0, vec4 m1, vec4 m2, vec4 uv0E1, vec4 uvE2, uvec4 ids) {
    StsvTriangle t;
    t.m0 = m0;
    t.m1 = m1;
    t.m2 = m2;
    t.uv0 = uv0E1.xy;
    t.uvE1 = uv0E1.zw;
    t.uvE2 = uvE2.xy;
    t.texture = ids.x;
    t.flags = ids.y;
    t.triangle = ids.z;
    t.pad0 = 0u;
    t.pad1 = 0u;
    t.pad2 = 0u;
    return t;
}

/// The triangle constants and volume of (triangle, side) for light `lightIndex`: the same dh
/// calls as render/cpu_stsv.cpp (stsvTriangleFor, stsvSideCount, stsvBuildVolume). False when
/// this side has no volume (degenerate triangle, unlit side, empty volume).
bool stsvSetupVolume(uint tri, uint side, uint lightIndex, out StsvTriangle t, out StsvVolume vol) {
    GpuTriangle g = triangles[tri];
    vec4 sphere = lights[lightIndex].sphere;
    vec3 v0 = vec3(g.v0);
    vec3 v1 = vec3(g.v1);
    vec3 v2 = vec3(g.v2);
    t = stsvSetupTriangle(v0, v1, v2, g.t0, g.t1, g.t2, vec3(sphere), g.texture, g.flags & GPU_STSV_FLAG_MASK, tri);
    vol.planeCount = 0u;
    vol.flags = STSV_VOLUME_EMPTY;
    if ((t.flags & STSV_FLAG_DEGENERATE) != 0u) return false;
    if (side >= stsvSideCount(v0, v1, v2, sphere)) return false;
    vol = stsvBuildVolume(v0, v1, v2, sphere, vec3(frame.boxLo), vec3(frame.boxHi), side);
    return (vol.flags & STSV_VOLUME_EMPTY) == 0u;
}

#endif
