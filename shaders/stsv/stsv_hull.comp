#version 450
// STSV volumes as their hulls (DESIGN §4.2; volumes/extrusion_dh.h stsvVolumeHullSetup): an
// invocation per queued side of an S-triangle (hull_queue.glsl) builds the volume with the
// same dh functions as the geometry shader and the CPU mirror, then the closed polyhedron of
// what its fragment accepts (the volume's and the light's planes inside the scene box), and appends the polyhedron's
// triangles and the volume's record (GpuStsvRecord) for the indirect draw of hull.vert +
// stsv.frag. Where the ten-vertex prism of stsv.geom reaches far beyond the accepted region (a
// large light, a leaf edge-on), the hull costs no fragment that only rejects.
#extension GL_GOOGLE_include_directive : require
// Threads per workgroup, set by render/vulkan/gpu_hulls.cpp to what shared memory holds: the clipping
// keeps its polyhedron there (clip_box_dh.h).
#ifndef CLIP_SHARED_INVOCATIONS
#define CLIP_SHARED_INVOCATIONS 8
#endif
#include "common/frame_bindings.glsl"
#include "stsv/stsv_volume.glsl"
#include "common/hull_append.glsl"

layout(local_size_x = CLIP_SHARED_INVOCATIONS) in;

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };

/// Item `item` (a side of a triangle: every side 0, then every side 1, for most triangles
/// have one) and whether it may have a volume: the tests of stsvSetupVolume that build nothing.
bool hullItem(uint item, out uint tri, out uint side) {
    uint triangleCount = uint(triangles.length());
    side = item >= triangleCount ? 1u : 0u;
    tri = item - side * triangleCount;
    if (side > 1u || tri >= triangleCount) return false;
    GpuTriangle g = triangles[tri];
    if ((pc.flags & GPU_PUSH_PERFORATED_ONLY) != 0u && gpuOpaqueOccluder(g.flags)) return false;
    return side < stsvSideCount(vec3(g.v0), vec3(g.v1), vec3(g.v2), lights[pc.light].sphere);
}

/// The volume of side `side` of triangle `tri`: its hull appended, its record written.
void buildHull(uint tri, uint side) {
    StsvTriangle t;
    StsvVolume vol;
    StsvLightPlanes lp;
    if (!stsvSetupVolume(tri, side, pc.light, false, t, vol, lp)) return;
    GpuTriangle g = triangles[tri];
    uint drawn;
    uint record = appendHull(stsvVolumeHullSetup(vol, lp, vec3(g.v0), vec3(g.v1), vec3(g.v2), vec3(frame.boxLo),
                                                 vec3(frame.boxHi)),
                             drawn);
    if (drawn == 0u) return;
    atomicAdd(stats[pc.light].hull.volumes, 1u);
    atomicAdd(stats[pc.light].hull.triangles, drawn);
    if (record == HULL_NO_RECORD) return;
    GpuStsvRecord r = stsvPackRecord(t, vol, lp, side);
    uint base = record * GPU_HULL_RECORD_TEXELS;
    hullRecords[base] = floatBitsToUint(r.m0);
    hullRecords[base + 1u] = floatBitsToUint(r.m1);
    hullRecords[base + 2u] = floatBitsToUint(r.m2);
    hullRecords[base + 3u] = floatBitsToUint(r.uv0E1);
    hullRecords[base + 4u] = floatBitsToUint(r.uvE2);
    hullRecords[base + GPU_STSV_RECORD_IDS] = r.ids;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
        hullRecords[base + GPU_STSV_RECORD_PLANES + i] = floatBitsToUint(r.planes[i]);
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        hullRecords[base + GPU_STSV_RECORD_LIGHT_PLANES + i] = floatBitsToUint(r.lightPlanes[i]);
}

#include "common/hull_queue.glsl"
