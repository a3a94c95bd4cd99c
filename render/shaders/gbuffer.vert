#version 450
// G-buffer pass (DESIGN §5, pass 0): every triangle, unindexed (3 vertices per triangle), so
// gl_PrimitiveID in the fragment shader is the scene triangle index.
#extension GL_GOOGLE_include_directive : require
#include "render/shaders/frame_bindings.glsl"

layout(location = 0) out vec2 outBary; ///< (b1, b2) of the triangle

void main() {
    uint corner = uint(gl_VertexIndex) % 3u;
    GpuTriangle t = triangles[uint(gl_VertexIndex) / 3u];
    vec4 world = corner == 0u ? t.v0 : (corner == 1u ? t.v1 : t.v2);
    outBary = vec2(corner == 1u ? 1.0 : 0.0, corner == 2u ? 1.0 : 0.0);
    gl_Position = frame.clipFromWorld * vec4(vec3(world), 1.0);
}
