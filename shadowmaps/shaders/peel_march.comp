#version 450
// `peel`'s march (shadowmaps/depth_grid_dh.h): every light sample's ray from the visible point
// through the light's depth grid, the samples it finds occluded set in the light's bitmask images
// (lsMaskAttachment: image i holds words 2i and 2i + 1), or the surfaces it crosses added to their
// counters — the same function the CPU backend runs. PEEL_LANES invocations share a pixel, lane j
// marching samples j, j + PEEL_LANES, …: one sample's march loops up to
// peel_max_steps·(peel_bins + 1) times, and the host (peelMarchLanes) gives each invocation few
// enough samples to stay under lavapipe's loop limit. The lanes' bits meet in shared memory, and
// lane 0 stores the pixel's. Each invocation adds its rays' steps, capped rays and longest march
// to the light's stats.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef LS_COUNTERS
#define LS_COUNTERS 0
#endif
#define WORD_COUNT ((SAMPLE_COUNT + 31) / 32)
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

#ifndef PEEL_LANES
#define PEEL_LANES 1
#endif
#ifndef PEEL_GROUP
#define PEEL_GROUP 64
#endif
#define PEEL_PIXELS (PEEL_GROUP / PEEL_LANES)

// A workgroup takes PEEL_PIXELS pixels of one row.
layout(local_size_x = PEEL_GROUP) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
#if LS_COUNTERS
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
#else
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_MASKS, rg32ui) uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
#endif
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuShadowMapStats stats[]; };

// The data access of depth_grid_dh.h: the light's grid by device address.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer GridWordRef { uint value; };
struct PeelGridSource {
    uint64_t address;
};
uint peelGridWord(PeelGridSource s, uint index) {
    return GridWordRef(s.address + 4ul * uint64_t(index)).value;
}
#define PEEL_GRID_SOURCE
#include "shadowmaps/depth_grid_dh.h"

#if !LS_COUNTERS
shared uint groupWords[PEEL_PIXELS][WORD_COUNT];
#endif

void main() {
    uint lane = gl_LocalInvocationID.x % uint(PEEL_LANES);
    uint slot = gl_LocalInvocationID.x / uint(PEEL_LANES);
    uvec2 pixel = uvec2(gl_WorkGroupID.x * uint(PEEL_PIXELS) + slot, gl_WorkGroupID.y);
    // No early return: the barriers below need every invocation.
    bool covered = pixel.x < frame.width && pixel.y < frame.height &&
                   imageLoad(gTriangle, ivec2(pixel)).x != GPU_NO_TRIANGLE;
    uint words[WORD_COUNT];
    for (uint w = 0u; w < uint(WORD_COUNT); ++w) words[w] = 0u;
    uint steps = 0u, capped = 0u, longest = 0u;
    if (covered) {
        vec3 p = vec3(imageLoad(gPosition, ivec2(pixel)));
        vec3 n = gpuShadingNormal(triangles[imageLoad(gTriangle, ivec2(pixel)).x], vec3(frame.eye), p);
        LightFrame lf = lightFrame(lights[pc.light].light, p, frame.farDistance);
        PixelSamples samples = pixelSamples(pixel, uint(SAMPLE_COUNT));
        ShadowMapView v = shadowViews[pc.light];
        PeelGridSource src;
        src.address = packUint2x32(uvec2(v.representationLow, v.representationHigh));
        uint bins = shadowParams.peelBins, maxSteps = shadowParams.peelMaxSteps;
        ShadowReceiver r = shadowReceiver(v, p, n, shadowParams.bias, shadowParams.normalOffset, vec2(1.0, 0.0));
#if LS_COUNTERS
        uint counterWord = lsPixelCounterWord(lsPixelIndex(pixel, frame.width), uint(SAMPLE_COUNT));
#endif
        for (uint k = lane; k < uint(SAMPLE_COUNT); k += uint(PEEL_LANES)) {
            vec3 s = lightSamplePosition(lf, pixelSamplePoint(samples, k, lf.domain));
            PeelMarch m = peelRayMarch(src, v, bins, maxSteps, r, s, uint(LS_COUNTERS));
            steps += m.steps;
            capped += m.capped;
            longest = max(longest, m.steps);
            if (m.occluded == 0u) continue;
#if LS_COUNTERS
            atomicAdd(counters[counterWord + lsCounterWord(k)], m.crossings << lsCounterShift(k));
#else
            words[lsMaskWord(k)] |= lsMaskBit(k);
#endif
        }
    }
    if (steps != 0u) {
        // A 64-bit sum of 32-bit atomics: a carry out of the low word adds one to the high word.
        uint before = atomicAdd(stats[pc.light].peelStepsLow, steps);
        if (before + steps < before) atomicAdd(stats[pc.light].peelStepsHigh, 1u);
        atomicMax(stats[pc.light].peelLongest, longest);
    }
    if (capped != 0u) atomicAdd(stats[pc.light].peelCapped, capped);
#if !LS_COUNTERS
    if (lane == 0u)
        for (uint w = 0u; w < uint(WORD_COUNT); ++w) groupWords[slot][w] = 0u;
    barrier();
    for (uint w = 0u; w < uint(WORD_COUNT); ++w)
        if (words[w] != 0u) atomicOr(groupWords[slot][w], words[w]);
    barrier();
    if (covered && lane == 0u)
        for (uint i = 0u; 2u * i < uint(WORD_COUNT); ++i) {
            uvec2 pair = uvec2(groupWords[slot][2u * i],
                               2u * i + 1u < uint(WORD_COUNT) ? groupWords[slot][2u * i + 1u] : 0u);
            imageStore(masks[i], ivec2(pixel), uvec4(pair, 0u, 0u)); // the frame cleared them
        }
#endif
}
