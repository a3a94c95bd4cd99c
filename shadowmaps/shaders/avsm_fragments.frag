#version 450
// The fragment lists of the transmittance functions (`avsm`, `vpcss`; DESIGN §4.6): every
// surface at a texel centre that takes light, with its depth (as the map's, shadowmap.frag) and
// the optical-depth units its texel takes, as the Embree reference's crossings count them
// (reference/embree_scene.cpp hitUnits): a translucent triangle its material's table at its blend
// texture's alpha, an opaque one or a perforated one's blocking texel OPTICAL_DEPTH_OPAQUE, a
// hole nothing. Pushed onto the texel's list; avsm_build.comp orders and compresses the lists.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#define SHADOW_MAP_WRITE
#define AVSM_LISTS
#define FRAME_DEPTH_TABLES
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

layout(location = 0) in vec2 inBary;
layout(location = 1) flat in uint inFace;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuShadowMapStats stats[]; };

/// The units the texel of triangle `t` at barycentrics `bary` takes.
uint surfaceUnits(GpuTriangle t, vec2 bary) {
    bool translucent = (t.flags & GPU_TRIANGLE_TRANSLUCENT) != 0u;
    bool textured = (t.flags & STSV_FLAG_OPAQUE) == 0u;
    uint alpha = 255u;
    if (textured) {
        vec2 uv = t.t0 + bary.x * (t.t1 - t.t0) + bary.y * (t.t2 - t.t0);
        uint wrap = (t.flags & STSV_FLAG_CLAMP) != 0u ? WRAP_CLAMP : WRAP_REPEAT;
        alpha = alphaAt(t.texture, texelAt(uv, textureSizeOf(t.texture), wrap));
    }
    if (translucent) return depthTables[t.material * 256u + alpha];
    return alphaBlocks(alpha) ? OPTICAL_DEPTH_OPAQUE : 0u;
}

void main() {
    uint tri = uint(gl_PrimitiveID);
    GpuTriangle t = triangles[tri];
    uint units = surfaceUnits(t, inBary);
    if (units == 0u) return;
    ShadowMapView v = shadowViews[pc.light];
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, inFace, X, Y, Z);
    vec3 q = gpuPointOnTriangle(t, inBary) - v.origin;
    float depth = v.projection == SHADOW_MAP_CUBE ? length(q) : dot(q, Z);
    uvec2 texel = uvec2(gl_FragCoord.xy);
    uint index = (inFace * v.size + texel.y) * v.size + texel.x;
    // The count goes on past the end, so the host knows how much room the frame needed.
    uint slot = atomicAdd(stats[pc.light].avsmFragments, 1u);
    if (slot >= avsmLists.capacity) {
        atomicOr(stats[pc.light].avsmLost, 1u);
        return;
    }
    uint next = atomicExchange(avsmHeads[index], slot + 1u);
    avsmFragmentAt(slot).value = uvec4(floatBitsToUint(depth), units, tri, next);
}
