#version 450
// The filtered representation of a light's map (DESIGN §4.6): the channels of VSM, ESM, EVSM, MSM
// or CSM from the rasterised depths, as 64-bit fixed-point summed-area tables or float mips, with
// the functions of shadowmaps/filtered_lookup_dh.h that the CPU backend runs
// (shadowmaps/filtered_map.cpp).
//   FILTERED_STEP 0: summed-area rows — one invocation per plane row: the channel's fixed-point
//                    values and their running sum along the row (and the zero row and column)
//                 1: summed-area columns — one invocation per plane column: running sums down it
//                 2: mip level 0 — one invocation per texel: every channel's value
//                 3: mip level pc.initialize — one invocation per texel of that level
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#ifndef FILTERED_STEP
#define FILTERED_STEP 0
#endif
#define FILTERED_MAP_BINDINGS
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

#if FILTERED_STEP < 2
layout(local_size_x = 64) in;
#else
layout(local_size_x = 16, local_size_y = 16) in;
#endif

float depthAt(ShadowMapView v, uint face, uint x, uint y) {
    return filteredDepth(v, gpuShadowDepthOf(shadowDepth[(face * v.size + y) * v.size + x]));
}

void main() {
    ShadowMapView v = shadowViews[pc.light];
    ShadowFilterParams p = shadowParams;
    uint size = v.size;
    uint stride = size + 1u;
    FilteredSource src = filteredSourceOf(v);
#if FILTERED_STEP == 0
    // One channel per invocation: a local array of 32 running sums came out wrong on lavapipe
    // beyond 16 channels.
    uint row = gl_GlobalInvocationID.x;
    if (row >= size * v.faces * p.channels) return;
    uint plane = row / size, y = row % size;
    uint face = plane / p.channels, c = plane % p.channels;
    filteredSumAt(src, plane, (y + 1u) * stride).value = int64_t(0);
    if (y == 0u)
        for (uint x = 0u; x <= size; ++x) filteredSumAt(src, plane, x).value = int64_t(0);
    int64_t run = int64_t(0);
    for (uint x = 0u; x < size; ++x) {
        run += filteredFixed(filteredChannelValue(p, depthAt(v, face, x, y), c));
        filteredSumAt(src, plane, (y + 1u) * stride + x + 1u).value = run;
    }
#elif FILTERED_STEP == 1
    uint column = gl_GlobalInvocationID.x;
    if (column >= size * v.faces * p.channels) return;
    uint plane = column / size, x = column % size + 1u;
    int64_t run = int64_t(0);
    for (uint y = 1u; y <= size; ++y) {
        FilteredSumRef entry = filteredSumAt(src, plane, y * stride + x);
        run += entry.value;
        entry.value = run;
    }
#elif FILTERED_STEP == 2
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint face = gl_GlobalInvocationID.z;
    if (texel.x >= size || texel.y >= size) return;
    FilteredChannels ch = filteredChannelValues(p, depthAt(v, face, texel.x, texel.y));
    for (uint c = 0u; c < p.channels; ++c)
        filteredMipAt(src, face * p.channels + c, texel.y * size + texel.x).value = ch.v[c];
#else
    uint level = pc.initialize;
    uint n = filteredMipSize(size, level);
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint plane = gl_GlobalInvocationID.z;
    if (texel.x >= n || texel.y >= n) return;
    filteredMipAt(src, plane, filteredMipOffset(size, level) + texel.y * n + texel.x).value =
        filteredMipDownsample(src, plane, size, level, texel, p.method == SHADOW_FILTER_ESM);
#endif
}
