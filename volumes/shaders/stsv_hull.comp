#version 450
// STSV volumes as their hulls (DESIGN §4.2; volumes/extrusion_dh.h stsvVolumeHullSetup): an
// invocation per queued side of an S-triangle (hull_queue.glsl, stsv_hull_items.glsl) builds the volume with the
// same dh functions as the geometry shader and the CPU mirror, then the closed polyhedron of
// what its fragment accepts (the volume's and the light's planes inside the scene box), and appends the polyhedron's
// triangles and the volume's record (GpuStsvRecord) for the indirect draw of hull.vert +
// stsv.frag. Where the ten-vertex prism of stsv.geom reaches far beyond the accepted region (a
// large light, a leaf edge-on), the hull costs no fragment that only rejects.
// With STSV_HULL_RECORDS_ONLY (the cluster walk, stsv_clusters.comp) it builds the volumes'
// records only, no hull, and notes each item's record in the item table.
#extension GL_GOOGLE_include_directive : require
// Threads per workgroup, set by render/vulkan/gpu_hulls.cpp to what shared memory holds: the clipping
// keeps its polyhedron there (clip_box_dh.h).
#ifndef CLIP_SHARED_INVOCATIONS
#define CLIP_SHARED_INVOCATIONS 8
#endif
#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_hull_items.glsl"
#include "render/shaders/hull_append.glsl"

layout(local_size_x = CLIP_SHARED_INVOCATIONS) in;

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };

#ifndef STSV_HULL_RECORDS_ONLY
#define STSV_HULL_RECORDS_ONLY 0
#endif
#if STSV_HULL_RECORDS_ONLY
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_STSV_ITEM_RECORDS) writeonly buffer ItemRecords { uint itemRecords[]; };
#endif

/// The volume of side `side` of triangle `tri`: its hull appended, its record written (records
/// only: its record written and noted in the item table).
void buildHull(uint tri, uint side) {
    StsvHullSetup h;
    GpuStsvRecord r;
    if (!hullVolume(tri, side, h, r)) return;
#if STSV_HULL_RECORDS_ONLY
    // Every point the hull would enclose passes the volume's planes: the walk tests those.
    uint record = atomicAdd(draw.records, 1u);
    atomicAdd(stats[pc.light].hull.volumes, 1u);
    if ((record + 1u) * GPU_HULL_RECORD_TEXELS > uint(hullRecords.length())) return;
    itemRecords[side * uint(triangles.length()) + tri] = record + 1u;
#else
    uint drawn;
    uint record = appendHull(h, drawn);
    if (drawn == 0u) return;
    atomicAdd(stats[pc.light].hull.volumes, 1u);
    atomicAdd(stats[pc.light].hull.triangles, drawn);
    if (record == HULL_NO_RECORD) return;
#endif
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

#include "render/shaders/hull_queue.glsl"
