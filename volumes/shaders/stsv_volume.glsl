// The data an STSV fragment needs about its volume (STSV paper §3): the triangle constants of
// Eq. 2–5, the volume's planes and the light planes, packed as flat varyings by the extrusion
// stage or as a record by the hull pass; and the volume's set-up, shared by all three.
#ifndef STSV_SHADERS_STSV_VOLUME_GLSL
#define STSV_SHADERS_STSV_VOLUME_GLSL

#include "volumes/extrusion_dh.h"
#include "volumes/vulkan/gpu_stsv_dh.h"
#include "volumes/stsv_cull_dh.h"

/// The record of a volume (volumes/vulkan/gpu_stsv_dh.h GpuStsvRecord): flat varyings of the geometry
/// and mesh shaders (72 components; Vulkan guarantees 64 per geometry-shader vertex, lavapipe
/// and NVIDIA allow 128), or a record of the hull pass.
GpuStsvRecord stsvPackRecord(StsvTriangle t, StsvVolume v, StsvLightPlanes lp, uint side) {
    GpuStsvRecord o;
    o.m0 = t.m0;
    o.m1 = t.m1;
    o.m2 = t.m2;
    o.uv0E1 = vec4(t.uv0, t.uvE1);
    o.uvE2 = vec4(t.uvE2, 0.0, 0.0);
    o.ids = uvec4(t.texture, t.flags, t.triangle, side | (v.planeCount << 8u) | (lp.count << 16u));
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) o.planes[i] = v.planes[i];
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) o.lightPlanes[i] = lp.planes[i];
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
    t.material = 0u;
    t.pad1 = 0u;
    t.pad2 = 0u;
    return t;
}

/// The triangle constants, volume and light planes of (triangle, side) for light `lightIndex`:
/// the same dh calls as volumes/cpu/cpu_stsv.cpp (stsvSetupTriangle, stsvSideVolume,
/// stsvTriangleLightPlanes), after the culling only the GPU does (stsv_cull_dh.h); with `strip`
/// the volume's ten vertices too (the prisms), else only its planes (the hulls). False when this
/// side has no volume (degenerate triangle, unlit side, empty or culled volume).
bool stsvSetupVolume(uint tri, uint side, uint lightIndex, bool strip, out StsvTriangle t, out StsvVolume vol,
                     out StsvLightPlanes lp) {
    GpuTriangle g = triangles[tri];
    vol.planeCount = 0u;
    vol.flags = STSV_VOLUME_EMPTY;
    lp = stsvNoLightPlanes();
    // Algorithm 2 with wedges: the opaque triangles are not STSV's.
    if ((pc.flags & GPU_PUSH_PERFORATED_ONLY) != 0u && gpuOpaqueOccluder(g.flags)) return false;
    vec4 sphere = lights[lightIndex].sphere;
    vec3 v0 = vec3(g.v0);
    vec3 v1 = vec3(g.v1);
    vec3 v2 = vec3(g.v2);
    vec3 lo = vec3(frame.boxLo);
    vec3 hi = vec3(frame.boxHi);
    t = stsvSetupTriangle(v0, v1, v2, g.t0, g.t1, g.t2, vec3(sphere), g.texture, g.flags & GPU_STSV_FLAG_MASK, tri);
    if ((t.flags & STSV_FLAG_DEGENERATE) != 0u) return false;
    if (side == 0u && stsvSideCount(v0, v1, v2, sphere) == 1u &&
        stsvVolumeCannotShadowBox(t, sphere, lights[lightIndex].light, lo, hi, frame.farDistance))
        return false;
    if (!stsvSideVolume(v0, v1, v2, sphere, lo, hi, side, strip, vol)) return false;
    lp = stsvTriangleLightPlanes(v0, v1, v2, lights[lightIndex].light, frame.farDistance, lo, hi);
    return true;
}

#endif
