#version 450
// Wedge bound of one potential silhouette edge (DESIGN §4.5; as render/cpu_wedges.cpp): the
// STSV volume of the edge's carrier face (a segment towards the light that touches the edge
// touches the closed face, which its STSV volume bounds conservatively), both sides when the
// light straddles the face's plane (one invocation per side). Edges that cannot be a silhouette
// for any point of the light emit nothing. The fragment (wedge.frag) gets the planes as flat
// varyings and reads the edge by index.
#extension GL_GOOGLE_include_directive : require
#include "wedge_bindings.glsl"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"

layout(points, invocations = 2) in; // gl_InvocationID = side of the carrier face
layout(triangle_strip, max_vertices = 10) out;

layout(location = 0) flat out uvec4 outIds; ///< edge, side | light planes' count << 8, planeCount, WEDGE_SIDE0_PRESENT | side 0's planeCount
layout(location = 1) flat out vec4 outPlanes[STSV_VOLUME_MAX_PLANES];
/// Side 1 only: its points inside side 0 are side 0's.
layout(location = 6) flat out vec4 outPlanesSide0[STSV_VOLUME_MAX_PLANES];
/// The carrier's light planes (extrusion_dh.h stsvLightPlanes): a segment from p to the light
/// that touches the edge touches the carrier, whose shadow they bound.
layout(location = 11) flat out vec4 outLightPlanes[STSV_LIGHT_PLANES_MAX];

/// dcsPotentialSilhouette (wedges/dcs_dh.h) of the edge, as wedges/adjacency.cpp
/// potentialSilhouetteEdges: open and non-manifold edges always.
bool potentialSilhouette(GpuEdge edge, vec4 sphere) {
    if (edge.faceCount != 2u) return true;
    return dcsPotentialSilhouette(edge.v0, edge.v1, edgeFaces[edge.firstFace].opposite,
                                  edgeFaces[edge.firstFace + 1u].opposite, sphere);
}

void main() {
    uint e = uint(gl_PrimitiveIDIn);
    uint side = uint(gl_InvocationID);
    GpuEdge edge = edges[e];
    if (edge.carrier == GPU_NO_TRIANGLE) return;
    vec4 sphere = lights[pc.light].sphere;
    if (!potentialSilhouette(edge, sphere)) return;
    GpuTriangle g = triangles[edge.carrier];
    vec3 v0 = vec3(g.v0);
    vec3 v1 = vec3(g.v1);
    vec3 v2 = vec3(g.v2);
    if (side >= stsvSideCount(v0, v1, v2, sphere)) return;
    vec3 lo = vec3(frame.boxLo);
    vec3 hi = vec3(frame.boxHi);
    StsvVolume vol = stsvBuildVolume(v0, v1, v2, sphere, lo, hi, side);
    if ((vol.flags & STSV_VOLUME_EMPTY) != 0u) return;
    // Side 1 hands the points of the side-0 volume to side 0, so that every point is visited
    // once (the CPU mirror tests "inside any of the face's volumes").
    StsvVolume vol0;
    vol0.planeCount = 0u;
    vol0.flags = STSV_VOLUME_EMPTY;
    for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) vol0.planes[k] = vec4(0.0);
    if (side == 1u) vol0 = stsvBuildVolume(v0, v1, v2, sphere, lo, hi, 0u);
    uint side0 = (vol0.flags & STSV_VOLUME_EMPTY) == 0u ? WEDGE_SIDE0_PRESENT | vol0.planeCount : 0u;
    StsvLightPlanes lp = stsvNoLightPlanes();
    LightFrame square;
    if (lightSampleSquare(lights[pc.light].light, frame.farDistance, square))
        lp = stsvLightPlanes(v0, v1, v2, square.center, square.T, square.B, lo, hi);
    for (uint i = 0u; i < STSV_STRIP_VERTEX_COUNT; ++i) {
        gl_Position = frame.clipFromWorld * vol.vertices[i];
        outIds = uvec4(e, side | (lp.count << 8u), vol.planeCount, side0);
        for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) {
            outPlanes[k] = vol.planes[k];
            outPlanesSide0[k] = vol0.planes[k];
        }
        for (uint k = 0u; k < STSV_LIGHT_PLANES_MAX; ++k) outLightPlanes[k] = lp.planes[k];
        EmitVertex();
    }
    EndPrimitive();
}
