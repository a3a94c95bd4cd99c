#version 450
// z-fail count of dcs_center.geom's volumes (DESIGN §4.5): only faces behind the visible point
// pass the depth test (GREATER against the G-buffer depth, before the shader: early tests); a
// back face is where the view ray leaves a volume (+w), a front face where it enters (−w), so a
// point collects +1 per volume that contains it. The near cap of the visible triangle itself is
// skipped (self-shadowing rule); wedge_fold.comp accounts for the rest of that triangle's volume.
#extension GL_GOOGLE_include_directive : require
#include "frame_bindings.glsl"

layout(early_fragment_tests) in;

layout(location = 0) flat in int inWeight;
layout(location = 1) flat in uint inSkipTriangle;

layout(set = 0, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = 0, binding = GPU_BINDING_CENTER, r32i) uniform iimage2D centerCount;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (inSkipTriangle != GPU_NO_TRIANGLE && imageLoad(gTriangle, pixel).x == inSkipTriangle) return;
    imageAtomicAdd(centerCount, pixel, gl_FrontFacing ? -inWeight : inWeight);
}
