// Appending a volume's hull (volumes/clip_box_dh.h, extrusion_dh.h stsvVolumeHullSetup) for the
// indirect draw of hull.vert: stsv_hull.comp and wedge_hull.comp. The draw arguments and counts,
// the records (GPU_HULL_RECORD_TEXELS texels each, written by the caller) and the vertices
// (world xyz bits, record index) are appended with atomics; the buffers were sized at start-up
// by a run of the same pass, and nothing is written past them (the host reports the counts).
#ifndef STSV_SHADERS_HULL_APPEND_GLSL
#define STSV_SHADERS_HULL_APPEND_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "render/vulkan/gpu_volumes_dh.h"
#include "volumes/extrusion_dh.h"
#include "render/shaders/hull_faces.glsl"

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_DRAW) buffer HullDraw { GpuHullDraw draw; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_RECORDS) writeonly buffer HullRecords { uvec4 hullRecords[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_VERTICES) writeonly buffer HullVertices { uvec4 hullVertices[]; };

const uint HULL_NO_RECORD = 0xffffffffu;

/// A hull corner in world space with its record, as hull.vert reads it.
uvec4 hullVertex(vec3 corner, vec3 origin, float scale, uint record) {
    return uvec4(floatBitsToUint(hullWorldCorner(corner, origin, scale)), record);
}

/// The hull of `h` appended: the fans of its faces that the rasteriser keeps (hullDrawnFaces).
/// Returns the record index whose texels the caller writes (hullRecords[record ·
/// GPU_HULL_RECORD_TEXELS + i]), or HULL_NO_RECORD when nothing was appended; `triangles` gets
/// the triangles counted.
uint appendHull(StsvHullSetup h, out uint triangles) {
    triangles = 0u;
    if (h.empty != 0u) return HULL_NO_RECORD;
    ClippedBox hull = clipBox(h.lo, h.hi, h.planes, h.count, h.minCut);
    uint corners;
    uint drawn = hullDrawnFaces(hull, h, triangles, corners);
    if (triangles == 0u) return HULL_NO_RECORD;
    uint record = atomicAdd(draw.records, 1u);
    uint first = atomicAdd(draw.vertexCount, 3u * triangles);
    if ((record + 1u) * GPU_HULL_RECORD_TEXELS > uint(hullRecords.length()) ||
        first + 3u * triangles > uint(hullVertices.length()))
        return HULL_NO_RECORD;
    uint k = first;
    for (uint f = 0u; f < hull.faceCount; ++f) {
        if ((drawn & (1u << f)) == 0u) continue;
        uint o = f * CLIP_MAX_FACE_VERTICES;
        uvec4 a = hullVertex(CLIP_CORNER(hull, o), h.origin, h.scale, record);
        for (uint i = 1u; i + 1u < hull.count[f]; ++i) {
            hullVertices[k] = a;
            hullVertices[k + 1u] = hullVertex(CLIP_CORNER(hull, o + i), h.origin, h.scale, record);
            hullVertices[k + 2u] = hullVertex(CLIP_CORNER(hull, o + i + 1u), h.origin, h.scale, record);
            k += 3u;
        }
    }
    return record;
}

#endif
