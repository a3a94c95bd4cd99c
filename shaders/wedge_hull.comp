#version 450
// Wedge bounds as their hulls (as stsv_hull.comp): one invocation per side of each potential
// silhouette edge builds the bound of wedge.geom (wedgeSetupBound), then the closed polyhedron of
// the carrier's volume and light planes inside the scene box (extrusion_dh.h
// stsvVolumeHullSetup), and appends its triangles and the edge's record (GpuWedgeRecord) for
// the indirect draw of hull.vert + wedge.frag.
#extension GL_GOOGLE_include_directive : require
// Threads per workgroup, set by render/gpu_hulls.cpp to what shared memory holds: the clipping
// keeps its polyhedron there (clip_box_dh.h).
#ifndef CLIP_SHARED_INVOCATIONS
#define CLIP_SHARED_INVOCATIONS 8
#endif
#include "wedge_bindings.glsl"
#include "hull_append.glsl"

layout(local_size_x = CLIP_SHARED_INVOCATIONS) in;

layout(std430, set = 0, binding = GPU_BINDING_STATS) buffer Stats { GpuStats stats[]; };

void main() {
    // Workgroups in rows of at most 65535 (the minimum maxComputeWorkGroupCount[0]).
    uint thread = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * uint(CLIP_SHARED_INVOCATIONS) +
                  gl_LocalInvocationID.x;
    if (thread == 0u) draw.instanceCount = 1u;
    // Every edge's side 0, then every side 1 (as stsv_hull.comp).
    uint edgeCount = uint(edges.length());
    uint side = thread >= edgeCount ? 1u : 0u;
    uint e = thread - side * edgeCount;
    if (side > 1u || e >= edgeCount) return;
    WedgeBound b;
    if (!wedgeSetupBound(e, side, pc.light, b)) return;
    uint drawn;
    uint record = appendHull(
        stsvVolumeHullSetup(b.vol, b.lp, b.v0, b.v1, b.v2, vec3(frame.boxLo), vec3(frame.boxHi)), drawn);
    if (drawn == 0u) return;
    atomicAdd(stats[pc.light].wedgeHulls, 1u);
    atomicAdd(stats[pc.light].wedgeHullTriangles, drawn);
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
