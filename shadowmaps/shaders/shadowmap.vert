#version 450
// Light-space map (DESIGN §4.6): every triangle, unindexed (so gl_PrimitiveID is the scene
// triangle), one instance per face of the light's map (shadowmaps/shadow_map_dh.h).
#extension GL_GOOGLE_include_directive : require
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

layout(location = 0) out vec2 outBary; ///< (b1, b2) of the triangle
layout(location = 1) flat out uint outFace;

void main() {
    uint corner = uint(gl_VertexIndex) % 3u;
    GpuTriangle t = triangles[uint(gl_VertexIndex) / 3u];
    vec4 world = corner == 0u ? t.v0 : (corner == 1u ? t.v1 : t.v2);
    outBary = vec2(corner == 1u ? 1.0 : 0.0, corner == 2u ? 1.0 : 0.0);
    outFace = uint(gl_InstanceIndex);
    ShadowMapView v = shadowViews[pc.light];
    gl_Position = shadowMapClip(v, outFace, vec3(world));
}
