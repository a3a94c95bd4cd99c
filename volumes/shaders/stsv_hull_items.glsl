// The STSV volumes as items of the hull builders — the compute hull pass (stsv_hull.comp) and the
// task and mesh shaders (stsv.task, stsv.mesh): an item is a side of an S-triangle, every side 0
// first, then every side 1 (most triangles have one).
#ifndef STSV_SHADERS_STSV_HULL_ITEMS_GLSL
#define STSV_SHADERS_STSV_HULL_ITEMS_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_volume.glsl"

/// Item `item` as (triangle, side), and whether it may have a volume: the tests of
/// stsvSetupVolume that build nothing.
bool hullItem(uint item, out uint tri, out uint side) {
    uint triangleCount = uint(triangles.length());
    side = item >= triangleCount ? 1u : 0u;
    tri = item - side * triangleCount;
    if (side > 1u || tri >= triangleCount) return false;
    GpuTriangle g = triangles[tri];
    if ((pc.flags & GPU_PUSH_PERFORATED_ONLY) != 0u && gpuOpaqueOccluder(g.flags)) return false;
    return side < stsvSideCount(vec3(g.v0), vec3(g.v1), vec3(g.v2), lights[pc.light].sphere);
}

/// The volume of side `side` of triangle `tri` as the set-up of its hull and its record; false
/// when it has none (stsvSetupVolume: degenerate, unlit, empty, or unable to shadow the
/// receivers' box).
#define HULL_RECORD GpuStsvRecord
bool hullVolume(uint tri, uint side, out StsvHullSetup h, out GpuStsvRecord r) {
    StsvTriangle t;
    StsvVolume vol;
    StsvLightPlanes lp;
    if (!stsvSetupVolume(tri, side, pc.light, false, t, vol, lp)) return false;
    GpuTriangle g = triangles[tri];
    h = stsvVolumeHullSetup(vol, lp, vec3(g.v0), vec3(g.v1), vec3(g.v2), vec3(frame.boxLo), vec3(frame.boxHi));
    r = stsvPackRecord(t, vol, lp, side);
    return h.empty == 0u;
}

#endif
