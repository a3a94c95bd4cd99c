#version 450
// The deferred fragments' mask words (stsv_samples.comp) ORed into the light's bitmask images,
// which the hull draw wrote for the fragments it did not defer (lsMaskAttachment: image i holds
// words 2i and 2i + 1).
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#include "render/shaders/frame_bindings.glsl"
#include "volumes/vulkan/gpu_stsv_dh.h"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_MASKS, rg32ui) uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_STSV_MASK_WORDS) readonly buffer MaskWords { uint maskWords[]; };

#define WORD_COUNT ((SAMPLE_COUNT + 31) / 32)

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.width || pixel.y >= frame.height) return;
    uint base = lsPixelIndex(pixel, frame.width) * uint(WORD_COUNT);
    for (uint i = 0u; 2u * i < uint(WORD_COUNT); ++i) {
        uvec2 words = uvec2(maskWords[base + 2u * i], 2u * i + 1u < uint(WORD_COUNT) ? maskWords[base + 2u * i + 1u] : 0u);
        if (words == uvec2(0u)) continue;
        imageStore(masks[i], ivec2(pixel), imageLoad(masks[i], ivec2(pixel)) | uvec4(words, 0u, 0u));
    }
}
