#version 450
// The samples of the STSV fragments the hull draw deferred (stsv.frag appends the pixel and the
// volume's record of every fragment that passes the plane tests): one thread a fragment, with
// the per-pixel set-up and per-sample test of the fragment (stsv_samples.glsl,
// volumes/stsv_fragment_dh.h). Every thread of a batch has a fragment to test, where the hull
// draw's batches hold the few pixels a small hull triangle covers and run as long as their
// slowest lane. Bits go to the mask words that stsv_merge.comp ORs into the light's bitmask,
// counters straight to the counters, a translucent triangle's optical depths straight to the
// light's depth sums (transmittance frames).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_samples.glsl"

layout(local_size_x = 64) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };
#if !LS_COUNTERS
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_STSV_MASK_WORDS) buffer MaskWords { uint maskWords[]; };
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
    for (uint e = gl_GlobalInvocationID.x; e < count; e += stride) {
        uvec2 entry = deferred[e];
        uvec2 pixel = uvec2(entry.x % frame.width, entry.x / frame.width);
        vec3 p = vec3(imageLoad(gPosition, ivec2(pixel)));
        uvec4 ids = stsvRecordTexel(entry.y, GPU_STSV_RECORD_IDS);
        StsvTriangle t = stsvRecordTriangle(entry.y, ids);
        StsvPixel px;
        StsvSampleSource src;
        ivec2 size;
        // The side-ownership rule of stsvFragmentPixel.
        if (!stsvPixelSetup(pixel, p, t, ids.w & 255u, px, src, size)) continue;
        ++inside;
#if LS_COUNTERS
        uint counterWord = lsPixelCounterWord(entry.x, uint(SAMPLE_COUNT));
#endif
        for (uint w = 0u; w < uint(WORD_COUNT); ++w) {
            uint bits = stsvSampleWord(t, px, src, size, w, entry.x);
#if LS_COUNTERS
            stsvAddOccludedLayers(counterWord, w, bits);
#else
            if (bits != 0u) atomicOr(maskWords[entry.x * uint(WORD_COUNT) + w], bits);
#endif
        }
    }
    // One atomic per subgroup: lavapipe runs atomics one lane at a time.
    inside = subgroupAdd(inside);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].inside, inside);
        atomicAdd(stats[pc.light].deferred, inside);
    }
}
