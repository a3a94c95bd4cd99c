#version 450
// STSV extrusion (STSV paper §2.2–2.3, Fig. 6; DESIGN §4.2): one invocation per side of each
// S-triangle builds the volume with the same dh functions as the CPU mirror and emits its
// ten-vertex strip. The fragment shader gets the triangle constants, the volume's planes and
// the light planes as flat
// varyings (the paper's approach): no setup pass, no SSBO written and read in one draw.
#extension GL_GOOGLE_include_directive : require
#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_volume.glsl"

layout(triangles, invocations = 2) in; // gl_InvocationID = side (paper §6 double-sided fix)
layout(triangle_strip, max_vertices = 10) out;

layout(location = 0) flat out vec4 outM0;
layout(location = 1) flat out vec4 outM1;
layout(location = 2) flat out vec4 outM2;
layout(location = 3) flat out vec4 outUv0E1;
layout(location = 4) flat out vec4 outUvE2;
layout(location = 5) flat out uvec4 outIds;
layout(location = 6) flat out vec4 outPlanes[STSV_VOLUME_MAX_PLANES];
layout(location = 11) flat out vec4 outLightPlanes[STSV_LIGHT_PLANES_MAX];

void main() {
    StsvTriangle t;
    StsvVolume vol;
    StsvLightPlanes lp;
    uint side = uint(gl_InvocationID);
    if (!stsvSetupVolume(uint(gl_PrimitiveIDIn), side, pc.light, true, t, vol, lp)) return;
    GpuStsvRecord v = stsvPackRecord(t, vol, lp, side);
    for (uint i = 0u; i < STSV_STRIP_VERTEX_COUNT; ++i) {
        gl_Position = frame.clipFromWorld * vol.vertices[i];
        outM0 = v.m0;
        outM1 = v.m1;
        outM2 = v.m2;
        outUv0E1 = v.uv0E1;
        outUvE2 = v.uvE2;
        outIds = v.ids;
        for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) outPlanes[k] = v.planes[k];
        for (uint k = 0u; k < STSV_LIGHT_PLANES_MAX; ++k) outLightPlanes[k] = v.lightPlanes[k];
        EmitVertex();
    }
    EndPrimitive();
}
