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
#include "wedges/wedge_bindings.glsl"
#include "common/hull_append.glsl"

layout(local_size_x = CLIP_SHARED_INVOCATIONS) in;

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };

/// Item `item` (a side of a carrier: every side 0, then every side 1) and whether it may have a
/// bound (wedgeMayHaveBound).
bool hullItem(uint item, out uint c, out uint side) {
    uint count = carrierCount();
    side = item >= count ? 1u : 0u;
    c = item - side * count;
    uint silhouettes;
    return side <= 1u && c < count && wedgeMayHaveBound(c, side, pc.light, silhouettes);
}

/// The bound of side `side` of carrier `c`: its hull appended, its record written.
void buildHull(uint c, uint side) {
    WedgeBound b;
    if (!wedgeSetupBound(c, side, pc.light, false, b)) return;
    uint drawn;
    uint record = appendHull(
        stsvVolumeHullSetup(b.vol, b.lp, b.v0, b.v1, b.v2, vec3(frame.boxLo), vec3(frame.boxHi)), drawn);
    if (drawn == 0u) return;
    atomicAdd(stats[pc.light].hull.volumes, 1u);
    atomicAdd(stats[pc.light].hull.triangles, drawn);
    if (record == HULL_NO_RECORD) return;
    uint base = record * GPU_HULL_RECORD_TEXELS;
    hullRecords[base] = b.record.ids;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) {
        hullRecords[base + GPU_WEDGE_RECORD_PLANES + i] = floatBitsToUint(b.record.planes[i]);
        hullRecords[base + GPU_WEDGE_RECORD_PLANES_SIDE0 + i] = floatBitsToUint(b.record.planesSide0[i]);
    }
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        hullRecords[base + GPU_WEDGE_RECORD_LIGHT_PLANES + i] = floatBitsToUint(b.record.lightPlanes[i]);
}

#include "common/hull_queue.glsl"
