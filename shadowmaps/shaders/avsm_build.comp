#version 450
// The transmittance functions of one light (`avsm`, `vpcss`; DESIGN §4.6) from the fragment
// lists of avsm_fragments.frag: per texel, the fragments in (depth, triangle) order, appended
// into at most avsm_nodes nodes (shadowmaps/avsm_dh.h avsmAppend), as the CPU backend appends the
// crossings of its texel-centre rays sorted the same way. The order the rasteriser listed them
// in does not matter. Each walk of the list picks the AVSM_BATCH least fragments after the last
// one appended (a sorted insertion) and appends them: n / AVSM_BATCH walks of a list of n, with
// no bound on n; it ends at the first opaque node (nothing behind it changes the function).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#define AVSM_LISTS
#define AVSM_BINDINGS
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

layout(local_size_x = 64) in;

/// Fragments a walk of a list sorts (10 000 particles at 1024² list 67 a texel on average; on
/// lavapipe 16, 32 and 64 build their functions in 24, 21 and 21 s).
const uint AVSM_BATCH = 32u;
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
        // The list in batches: each walk keeps the AVSM_BATCH least fragments after the last one
        // appended, sorted (insertion), then appends them.
        float batchDepth[AVSM_BATCH];
        uint batchTri[AVSM_BATCH];
        uint batchUnits[AVSM_BATCH];
        float lastDepth = 0.0;
        uint lastTri = 0u;
        bool first = true;
        bool done = false;
        while (!done) {
            uint m = 0u;
            for (uint n = avsmHeads[texel]; n != 0u;) {
                uvec4 e = avsmFragmentAt(n - 1u).value;
                n = e.w;
                float depth = uintBitsToFloat(e.x);
                if (!first && !after(depth, e.z, lastDepth, lastTri)) continue;
                // Full, and not before the batch's last: not in this batch.
                if (m == AVSM_BATCH && !after(batchDepth[m - 1u], batchTri[m - 1u], depth, e.z)) continue;
                uint j = m < AVSM_BATCH ? m : AVSM_BATCH - 1u;
                m = min(m + 1u, AVSM_BATCH);
                for (; j > 0u && after(batchDepth[j - 1u], batchTri[j - 1u], depth, e.z); --j) {
                    batchDepth[j] = batchDepth[j - 1u];
                    batchTri[j] = batchTri[j - 1u];
                    batchUnits[j] = batchUnits[j - 1u];
                }
                batchDepth[j] = depth;
                batchTri[j] = e.z;
                batchUnits[j] = e.y;
            }
            for (uint k = 0u; k < m && !done; ++k) {
                avsmAppend(f, batchDepth[k], batchUnits[k], src.maxNodes);
                done = f.count > 0u && f.units[f.count - 1u] == OPTICAL_DEPTH_OPAQUE;
            }
            done = done || m < AVSM_BATCH;
            if (m > 0u) {
                first = false;
                lastDepth = batchDepth[m - 1u];
                lastTri = batchTri[m - 1u];
            }
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
