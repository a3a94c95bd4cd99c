#version 450
// STSV volumes as their hulls (DESIGN §4.2; volumes/extrusion_dh.h stsvVolumeHull): one
// invocation per side of each S-triangle builds the volume with the same dh functions as the
// geometry shader and the CPU mirror, then the closed polyhedron of what its fragment accepts
// (the volume's and the light's planes inside the scene box), and appends the polyhedron's
// triangles and the volume's record for the indirect draw of stsv_hull.vert + stsv.frag. Where
// the ten-vertex prism of stsv.geom reaches far beyond the accepted region (a large light, a
// leaf edge-on), the hull costs no fragment that only rejects.
#extension GL_GOOGLE_include_directive : require
#include "frame_bindings.glsl"
#include "stsv_volume.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = GPU_BINDING_STSV_DRAW) buffer Draw { GpuStsvDraw draw; };
layout(std430, set = 0, binding = GPU_BINDING_STSV_RECORDS) writeonly buffer Records { GpuStsvRecord records[]; };
layout(std430, set = 0, binding = GPU_BINDING_STSV_HULL) writeonly buffer Hull { uvec4 hullVertices[]; };
layout(std430, set = 0, binding = GPU_BINDING_STATS) buffer Stats { GpuStats stats[]; };

/// A hull corner in world space (x_world = origin + scale·x) with its record: `precise`, so that
/// the corner two faces share gets the same bits in both (no contraction at one of them).
uvec4 hullVertex(vec3 corner, vec3 origin, float scale, uint record) {
    precise vec3 p = origin + scale * corner;
    return uvec4(floatBitsToUint(p), record);
}

void main() {
    if (gl_GlobalInvocationID.x == 0u) draw.instanceCount = 1u;
    // Every triangle's side 0, then every side 1: most triangles have one side, and the threads
    // of a SIMD batch with nothing to build finish together.
    uint triangleCount = uint(triangles.length());
    uint side = gl_GlobalInvocationID.x >= triangleCount ? 1u : 0u;
    uint tri = gl_GlobalInvocationID.x - side * triangleCount;
    if (side > 1u || tri >= triangleCount) return;
    StsvTriangle t;
    StsvVolume vol;
    StsvLightPlanes lp;
    if (!stsvSetupVolume(tri, side, pc.light, t, vol, lp)) return;
    GpuTriangle g = triangles[tri];
    StsvHullSetup h = stsvVolumeHullSetup(vol, lp, vec3(g.v0), vec3(g.v1), vec3(g.v2), vec3(frame.boxLo),
                                          vec3(frame.boxHi));
    if (h.empty != 0u) return;
    ClippedBox hull = clipBox(h.lo, h.hi, h.planes, h.count, h.minCut);
    // The faces the rasteriser keeps: those not turned towards the eye (stsv.frag draws back
    // faces). A face is left out only when the eye lies clearly on its outer side, 1e-4 of the
    // eye's distance beyond its plane, far beyond the rounding of the rasteriser's own decision.
    vec3 eye = (vec3(frame.eye) - h.origin) / h.scale;
    uint drawn = 0u; // bit f: face f is drawn
    uint n = 0u;
    for (uint f = 0u; f < hull.faceCount; ++f) {
        uint o = f * CLIP_MAX_FACE_VERTICES;
        vec3 normal = vec3(0.0); // Newell: twice the area, outward
        for (uint i = 0u; i < hull.count[f]; ++i) {
            vec3 a = hull.corner[o + i];
            vec3 b = hull.corner[o + (i + 1u) % hull.count[f]];
            normal += vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        }
        vec3 toEye = eye - hull.corner[o];
        if (dot(normal, toEye) > 1e-4 * length(normal) * length(toEye)) continue;
        drawn |= 1u << f;
        n += hull.count[f] - 2u;
    }
    if (n == 0u) return;
    uint record = atomicAdd(draw.records, 1u);
    uint first = atomicAdd(draw.vertexCount, 3u * n);
    atomicAdd(stats[pc.light].hullVolumes, 1u);
    atomicAdd(stats[pc.light].hullTriangles, n);
    // Past the buffers' capacity (sized at start-up by a run of this pass): the host reports the
    // overflow from the counts; write nothing out of bounds.
    if (record >= uint(records.length()) || first + 3u * n > uint(hullVertices.length())) return;
    records[record] = stsvPackRecord(t, vol, lp, side);
    // Fans of the faces, in world space (volumes/extrusion.cpp volumeHull).
    uint k = first;
    for (uint f = 0u; f < hull.faceCount; ++f) {
        if ((drawn & (1u << f)) == 0u) continue;
        uint o = f * CLIP_MAX_FACE_VERTICES;
        uvec4 a = hullVertex(hull.corner[o], h.origin, h.scale, record);
        for (uint i = 1u; i + 1u < hull.count[f]; ++i) {
            hullVertices[k] = a;
            hullVertices[k + 1u] = hullVertex(hull.corner[o + i], h.origin, h.scale, record);
            hullVertices[k + 2u] = hullVertex(hull.corner[o + i + 1u], h.origin, h.scale, record);
            k += 3u;
        }
    }
}
