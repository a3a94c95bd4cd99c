#version 450
// The DCS samples of the silhouette fragments the wedge draw listed (wedge.frag: every fragment
// inside its edge's bound with the edge a silhouette seen from p): one thread a fragment, with the
// pixel's light frame and edge term (wedge_term.glsl) — or, with WEDGE_LISTED_TERMS, the term the
// walk listed with the pair (dcs_clusters.comp) — then for each light sample x
// k_e·[r → x crosses the edge]·sign(ℓ·X) added to its 16-bit counter (Forest, Barthe & Paulin
// 2008). The counters are modular: wedge_fold.comp adds D(r) and reads them as signed.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef WEDGE_LISTED_TERMS
#define WEDGE_LISTED_TERMS 0
#endif
#include "wedges/shaders/wedge_term.glsl"

layout(local_size_x = 64) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
#if !WEDGE_LISTED_TERMS
#include "wedges/edge_cluster_dh.h"
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DCS_BLOCKS) readonly buffer DcsBlocks { uint dcsBlocks[]; };
#endif

void main() {
    // Everything the draw or this part of the walk tried to list, past the end too: the host
    // grows a short list, or walks in more parts.
    if (gl_GlobalInvocationID.x == 0u) {
        atomicAdd(stats[pc.light].listed, deferredCount.x);
        atomicMax(stats[pc.light].listedPart, deferredCount.x);
    }
    uint count = deferredEntries();
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    uint inside = 0u;
    for (uint i = gl_GlobalInvocationID.x; i < count; i += stride) {
        uvec2 entry = deferred[i];
        uvec2 pixel = uvec2(entry.x % frame.width, entry.x / frame.width);
        vec3 l;
        vec3 h0;
        vec3 h1;
        int k;
        uint domain;
#if WEDGE_LISTED_TERMS
        // The walk listed the pair with its term (dcs_clusters.comp stage 4).
        wedgeTermLoad(i, l, h0, h1, k);
        domain = lightDomain(lights[pc.light].light);
#else
        // A pixel whose segments' gaps meet a triangle counts its samples' segments (dcs_rays.comp);
        // the walk lists no pair of such a pixel.
        uint blocks = clusterBlocksAlong(frame.width) * clusterBlocksAlong(frame.height);
        if ((dcsBlocks[dcsPixelGapWord(blocks, entry.x)] & (1u << (entry.x % 32u))) != 0u) continue;
        vec3 p = vec3(imageLoad(gPosition, ivec2(pixel)));
        uint receiver = imageLoad(gTriangle, ivec2(pixel)).x;
        LightFrame lf;
        if (!wedgePixelTerm(p, wedgeEdgeAt(entry.y), receiver, l, h0, h1, k, lf)) continue;
        domain = lf.domain;
#endif
        ++inside;
        PixelSamples samples = pixelSamples(pixel, uint(SAMPLE_COUNT));
        uint counterWord = lsPixelCounterWord(entry.x, uint(SAMPLE_COUNT));
        STSV_UNROLL for (uint s = 0u; s < uint(SAMPLE_COUNT); ++s) {
            vec2 ab = pixelSamplePoint(samples, s, domain);
            int crossing = dcsSampleCrossing(l, h0, h1, ab);
            // A negative addend wraps modulo 2^32 across the word's two 16-bit counters, which
            // wedge_fold.comp undoes.
            if (crossing != 0)
                atomicAdd(counters[counterWord + lsCounterWord(s)], uint(k * crossing) << lsCounterShift(s));
        }
    }
    // One atomic a subgroup: an atomic runs lane by lane on lavapipe.
    inside = subgroupAdd(inside);
    if (subgroupElect() && inside > 0u) atomicAdd(stats[pc.light].inside, inside);
}
