#version 450
// Wedge bound of one carrier face, for the edges it carries (DESIGN §4.5; as
// wedges/cpu/cpu_wedges.cpp): the STSV volume of the face (a segment towards the light that touches
// an edge touches the closed face, which its STSV volume bounds conservatively), both sides when
// the light straddles the face's plane (one invocation per side). A face none of whose edges can
// be a silhouette for any point of the light emits nothing. The fragment (wedge.frag) gets the
// planes as flat varyings and reads the carrier's edges by index.
#extension GL_GOOGLE_include_directive : require
#include "wedges/shaders/wedge_bindings.glsl"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"

layout(points, invocations = 2) in; // gl_InvocationID = side of the carrier face
layout(triangle_strip, max_vertices = 10) out;

layout(location = 0) flat out uvec4 outIds; ///< GpuWedgeRecord::ids
layout(location = 1) flat out vec4 outPlanes[STSV_VOLUME_MAX_PLANES];
/// Side 1 only: its points inside side 0 are side 0's.
layout(location = 6) flat out vec4 outPlanesSide0[STSV_VOLUME_MAX_PLANES];
/// The carrier's light planes (extrusion_dh.h stsvLightPlanes): a segment from p to the light
/// that touches an edge touches the carrier, whose shadow they bound.
layout(location = 11) flat out vec4 outLightPlanes[STSV_LIGHT_PLANES_MAX];

void main() {
    uint c = uint(gl_PrimitiveIDIn);
    uint side = uint(gl_InvocationID);
    WedgeBound b;
    if (!wedgeSetupBound(c, side, pc.light, true, b)) return;
    for (uint i = 0u; i < STSV_STRIP_VERTEX_COUNT; ++i) {
        gl_Position = frame.clipFromWorld * b.vol.vertices[i];
        outIds = b.record.ids;
        for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) {
            outPlanes[k] = b.record.planes[k];
            outPlanesSide0[k] = b.record.planesSide0[k];
        }
        for (uint k = 0u; k < STSV_LIGHT_PLANES_MAX; ++k) outLightPlanes[k] = b.record.lightPlanes[k];
        EmitVertex();
    }
    EndPrimitive();
}
