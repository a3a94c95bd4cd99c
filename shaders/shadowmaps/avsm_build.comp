#version 450
// The transmittance functions of one light (`avsm`, `vpcss`; DESIGN §4.6) from the fragment
// lists of avsm_fragments.frag: per texel, the fragments in (depth, triangle) order, appended
// into at most avsm_nodes nodes (shadowmaps/avsm_dh.h avsmAppend), as the CPU backend appends the
// crossings of its texel-centre rays sorted the same way. The order the rasteriser listed them
// in does not matter. Each step picks the least fragment after the last one appended, a walk of
// the list: quadratic in the list's length, but without a bound on it; the walk ends at the
// first opaque node (nothing behind it changes the function).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#define AVSM_LISTS
#define AVSM_BINDINGS
#include "common/frame_bindings.glsl"
#include "shadowmaps/shadow_bindings.glsl"

layout(local_size_x = 64) in;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuShadowMapStats stats[]; };

// The workgroup's stats, added to the light's once.
shared uint groupTexels;
shared uint groupNodes;
shared uint groupMaxNodes;
shared uint groupOverflowed;

/// Whether fragment (depth, tri) comes after (lastDepth, lastTri) in (depth, triangle) order.
bool after(float depth, uint tri, float lastDepth, uint lastTri) {
    return depth > lastDepth || (depth == lastDepth && tri > lastTri);
}

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        groupTexels = 0u;
        groupNodes = 0u;
        groupMaxNodes = 0u;
        groupOverflowed = 0u;
    }
    barrier();
    ShadowMapView v = shadowViews[pc.light];
    AvsmSource src = avsmSourceOf(v);
    uint face = gl_GlobalInvocationID.y;
    uint inFace = gl_GlobalInvocationID.x;
    if (inFace < v.size * v.size) {
        uint texel = face * v.size * v.size + inFace;
        AvsmFunction f = avsmEmpty();
        float lastDepth = 0.0;
        uint lastTri = 0u;
        bool first = true;
        for (;;) {
            uint best = 0u;
            float bestDepth = 0.0;
            uint bestTri = 0u;
            for (uint n = avsmHeads[texel]; n != 0u; n = avsmFragments[n - 1u].w) {
                uvec4 e = avsmFragments[n - 1u];
                float depth = uintBitsToFloat(e.x);
                if (!first && !after(depth, e.z, lastDepth, lastTri)) continue;
                if (best == 0u || after(bestDepth, bestTri, depth, e.z)) {
                    best = n;
                    bestDepth = depth;
                    bestTri = e.z;
                }
            }
            if (best == 0u) break;
            avsmAppend(f, bestDepth, avsmFragments[best - 1u].y, src.maxNodes);
            first = false;
            lastDepth = bestDepth;
            lastTri = bestTri;
            if (f.count > 0u && f.units[f.count - 1u] == OPTICAL_DEPTH_OPAQUE) break;
        }
        avsmWordAt(src.address, texel).value = gpuAvsmHeader(f.count, f.overflowed);
        for (uint j = 0u; j < f.count; ++j) {
            uint word = gpuAvsmNodeWord(src.texels, texel, src.maxNodes, j);
            avsmWordAt(src.address, word).value = floatBitsToUint(f.depth[j]);
            avsmWordAt(src.address, word + 1u).value = f.units[j];
        }
        if (f.count > 0u) {
            atomicAdd(groupTexels, 1u);
            atomicAdd(groupNodes, f.count);
            atomicMax(groupMaxNodes, f.count);
            atomicAdd(groupOverflowed, f.overflowed);
        }
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && groupTexels > 0u) {
        atomicAdd(stats[pc.light].avsmTexels, groupTexels);
        atomicAdd(stats[pc.light].avsmNodes, groupNodes);
        atomicMax(stats[pc.light].avsmMaxNodes, groupMaxNodes);
        atomicAdd(stats[pc.light].avsmOverflowed, groupOverflowed);
    }
}
