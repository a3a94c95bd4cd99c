#version 450
// Light-space map (DESIGN §4.6): the nearest surface per texel centre, alpha-tested with the
// shared texel rule as the G-buffer, as linear depth (axial, or radial for cube maps) kept by
// atomicMax of gpuShadowDepthWord (render/vulkan/gpu_frame_dh.h). No attachments: the map is a buffer
// the filters read texel by texel, as the CPU reads its traced map.
#extension GL_GOOGLE_include_directive : require
#define SHADOW_MAP_WRITE
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

layout(location = 0) in vec2 inBary;
layout(location = 1) flat in uint inFace;

void main() {
    uint tri = uint(gl_PrimitiveID);
    GpuTriangle t = triangles[tri];
    if ((t.flags & STSV_FLAG_OPAQUE) == 0u) {
        vec2 uv = t.t0 + inBary.x * (t.t1 - t.t0) + inBary.y * (t.t2 - t.t0);
        uint wrap = (t.flags & STSV_FLAG_CLAMP) != 0u ? WRAP_CLAMP : WRAP_REPEAT;
        ivec2 texel = texelAt(uv, textureSizeOf(t.texture), wrap);
        if (!alphaBlocks(alphaAt(t.texture, texel))) discard;
    }
    ShadowMapView v = shadowViews[pc.light];
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, inFace, X, Y, Z);
    vec3 q = gpuPointOnTriangle(t, inBary) - v.origin;
    float depth = v.projection == SHADOW_MAP_CUBE ? length(q) : dot(q, Z);
    uvec2 texel = uvec2(gl_FragCoord.xy);
    uint index = (inFace * v.size + texel.y) * v.size + texel.x;
    atomicMax(shadowDepth[index], gpuShadowDepthWord(depth));
}
