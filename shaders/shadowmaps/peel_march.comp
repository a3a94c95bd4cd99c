#version 450
// `peel`'s march (shadowmaps/depth_grid_dh.h), one thread a pixel: every light sample's ray from
// the visible point through the light's depth grid, the samples it finds occluded set in the
// light's bitmask images (lsMaskAttachment: image i holds words 2i and 2i + 1), or one layer
// added to their counters — the same function the CPU backend runs.
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
#include "common/frame_bindings.glsl"
#include "shadowmaps/shadow_bindings.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
#if LS_COUNTERS
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
#else
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_MASKS, rg32ui) uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
#endif

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

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.width || pixel.y >= frame.height) return;
    if (imageLoad(gTriangle, ivec2(pixel)).x == GPU_NO_TRIANGLE) return;
    vec3 p = vec3(imageLoad(gPosition, ivec2(pixel)));
    LightFrame lf = lightFrame(lights[pc.light].light, p, frame.farDistance);
    uint base = interleaveSet(samplePixelOf(pixel), frame.interleave) * uint(SAMPLE_COUNT);
    uvec2 offset = decorrelationOffset(samplePixelOf(pixel), frame.seed);
    bool decorrelate = frame.decorrelate != 0u;
    ShadowMapView v = shadowViews[pc.light];
    PeelGridSource src;
    src.address = packUint2x32(uvec2(v.representationLow, v.representationHigh));
    uint bins = shadowParams.peelBins, steps = shadowParams.peelSteps;
#if LS_COUNTERS
    uint counterWord = lsPixelCounterWord(lsPixelIndex(pixel, frame.width), uint(SAMPLE_COUNT));
#endif
    uint words[WORD_COUNT];
    for (uint w = 0u; w < uint(WORD_COUNT); ++w) words[w] = 0u;
    for (uint k = 0u; k < uint(SAMPLE_COUNT); ++k) {
        vec3 s = lightSamplePosition(lf, pixelSamplePoint(base, k, offset, decorrelate, lf.domain));
        if (!peelRayOccluded(src, v, bins, steps, p, s)) continue;
#if LS_COUNTERS
        atomicAdd(counters[counterWord + lsCounterWord(k)], 1u << lsCounterShift(k));
#else
        words[lsMaskWord(k)] |= lsMaskBit(k);
#endif
    }
#if !LS_COUNTERS
    for (uint i = 0u; 2u * i < uint(WORD_COUNT); ++i) {
        uvec2 pair = uvec2(words[2u * i], 2u * i + 1u < uint(WORD_COUNT) ? words[2u * i + 1u] : 0u);
        imageStore(masks[i], ivec2(pixel), uvec4(pair, 0u, 0u)); // the frame cleared them
    }
#endif
}
