#version 450
// Wedge bounds as their hulls (as stsv_hull.comp): an invocation per queued side of a carrier
// face with a potential silhouette among its edges (hull_queue.glsl) builds the bound of
// wedge.geom (wedgeSetupBound), then the closed polyhedron of the carrier's volume and light
// planes inside the scene box (extrusion_dh.h stsvVolumeHullSetup), and appends its triangles
// and the carrier's record (GpuWedgeRecord) for the indirect draw of hull.vert + wedge.frag.
#extension GL_GOOGLE_include_directive : require
// Threads per workgroup, set by render/vulkan/gpu_hulls.cpp to what shared memory holds: the clipping
// keeps its polyhedron there (clip_box_dh.h).
#ifndef CLIP_SHARED_INVOCATIONS
#define CLIP_SHARED_INVOCATIONS 8
#endif
#include "wedges/shaders/wedge_hull_items.glsl"
#include "render/shaders/hull_append.glsl"

layout(local_size_x = CLIP_SHARED_INVOCATIONS) in;

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };

/// The bound of side `side` of carrier `c`: its hull appended, its record written.
void buildHull(uint c, uint side) {
    StsvHullSetup h;
    GpuWedgeRecord r;
    if (!hullVolume(c, side, h, r)) return;
    uint drawn;
    uint record = appendHull(h, drawn);
    if (drawn == 0u) return;
    atomicAdd(stats[pc.light].hull.volumes, 1u);
    atomicAdd(stats[pc.light].hull.triangles, drawn);
    if (record == HULL_NO_RECORD) return;
    uint base = record * GPU_HULL_RECORD_TEXELS;
    hullRecords[base] = r.ids;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) {
        hullRecords[base + GPU_WEDGE_RECORD_PLANES + i] = floatBitsToUint(r.planes[i]);
        hullRecords[base + GPU_WEDGE_RECORD_PLANES_SIDE0 + i] = floatBitsToUint(r.planesSide0[i]);
    }
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        hullRecords[base + GPU_WEDGE_RECORD_LIGHT_PLANES + i] = floatBitsToUint(r.lightPlanes[i]);
}

#include "render/shaders/hull_queue.glsl"
