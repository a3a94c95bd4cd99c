#version 450
// The depth grid of `peel` (shadowmaps/depth_grid_dh.h): every fragment of every triangle per
// texel centre (no depth test, no culling), alpha-tested with the shared texel rule as the map,
// at the depth the map measures (axial, or radial for cube maps). Two draws:
//   DEPTH_GRID_STEP 0: the texel's depth range, nearest and farthest (atomicMax of their words);
//   DEPTH_GRID_STEP 1: the farthest front-face and back-face depth of each subinterval of that
//                      range (atomicMax into the slot of the fragment's subinterval).
// The grid is reached by device address (ShadowMapView::representationLow/High): a cube map's grid
// outgrows a storage buffer's range.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#ifndef DEPTH_GRID_STEP
#define DEPTH_GRID_STEP 0
#endif
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"
#include "shadowmaps/depth_grid_dh.h"

layout(buffer_reference, std430, buffer_reference_align = 4) buffer GridWordRef { uint value; };

layout(location = 0) in vec2 inBary;
layout(location = 1) flat in uint inFace;

void main() {
    GpuTriangle t = triangles[uint(gl_PrimitiveID)];
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
    uint bins = shadowParams.peelBins;
    uint base = peelTexelBase(v, inFace, ivec2(gl_FragCoord.xy), bins);
    uint64_t address = packUint2x32(uvec2(v.representationLow, v.representationHigh)) + 4ul * uint64_t(base);
#if DEPTH_GRID_STEP == 0
    atomicMax(GridWordRef(address).value, peelNearWord(depth));
    atomicMax(GridWordRef(address + 4ul).value, peelDepthWord(depth));
#else
    // Front: the triangle faces the light, its winding normal against the ray from the light.
    vec3 n = cross(vec3(t.v1 - t.v0), vec3(t.v2 - t.v0));
    vec3 ray = v.projection == SHADOW_MAP_ORTHOGRAPHIC ? Z : q;
    bool front = dot(n, ray) < 0.0;
    float lo = peelWordDepth(~GridWordRef(address).value);
    float hi = peelWordDepth(GridWordRef(address + 4ul).value);
    uint slot = 2u + 2u * uint(peelBin(depth, lo, hi, bins)) + (front ? 0u : 1u);
    atomicMax(GridWordRef(address + 4ul * uint64_t(slot)).value, peelDepthWord(depth));
#endif
}
