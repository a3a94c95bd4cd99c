// Descriptor declarations shared by the frame's passes (bindings from render/gpu_frame_dh.h).
#ifndef STSV_SHADERS_FRAME_BINDINGS_GLSL
#define STSV_SHADERS_FRAME_BINDINGS_GLSL

#include "render/gpu_frame_dh.h"
#include "sampling/light_sampling_dh.h"

layout(std430, set = 0, binding = GPU_BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };
layout(std430, set = 0, binding = GPU_BINDING_ALPHA) readonly buffer Alpha { uint alphaWords[]; };
layout(std430, set = 0, binding = GPU_BINDING_TEXTURES) readonly buffer Textures { GpuTexture textures[]; };
layout(std430, set = 0, binding = GPU_BINDING_PATTERN) readonly buffer Pattern { vec2 patternPoints[]; };
layout(std430, set = 0, binding = GPU_BINDING_FRAME) readonly buffer FrameData {
    GpuFrame frame;
    GpuLight lights[];
};
layout(push_constant) uniform Push { GpuPush pc; };

/// The shared texel rule's alpha byte (volumes/stsv_dh.h texelAt + alphaBlocks decide).
uint alphaAt(uint texture, ivec2 texel) {
    GpuTexture t = textures[texture];
    uint byteIndex = t.offset + uint(texel.y) * uint(t.width) + uint(texel.x);
    return gpuByteOf(alphaWords[byteIndex >> 2u], byteIndex);
}

/// samplePoint (sampling/light_sampling_dh.h) with the pixel's decorrelationOffset computed once
/// per pixel instead of per sample: the same fixed-point rotation, bit for bit.
vec2 samplePointWithOffset(vec2 patternPoint, uvec2 offset, bool decorrelated, uint domain) {
    vec2 u = patternPoint;
    if (decorrelated) {
        uvec2 q = (uvec2(u * SAMPLING_FIXED_ONE) + offset) & uvec2(SAMPLING_FIXED_MASK);
        u = vec2(q) * (1.0 / SAMPLING_FIXED_ONE);
    }
    return domainPoint(u, domain);
}

ivec2 textureSizeOf(uint texture) { return ivec2(textures[texture].width, textures[texture].height); }

#endif
