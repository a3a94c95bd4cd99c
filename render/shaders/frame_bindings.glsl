// Descriptor declarations of set 0, which every pass of the frame shares (render/vulkan/gpu_frame_dh.h).
#ifndef STSV_SHADERS_FRAME_BINDINGS_GLSL
#define STSV_SHADERS_FRAME_BINDINGS_GLSL

#include "render/vulkan/gpu_frame_dh.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/ls_buffer_dh.h"

layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_TEXTURES) readonly buffer Textures { GpuTexture textures[]; };
#ifdef STSV_PATTERN_VEC4S
// The pattern as a uniform buffer of STSV_PATTERN_VEC4S vec4 (two points each; std140 pads a
// vec2 array to 16 bytes): a dynamically indexed uniform load is a vector gather on lavapipe,
// a storage-buffer load a loop over the lanes. render/vulkan/gpu_frame_resources.cpp picks it when it fits.
layout(std140, set = GPU_SET_FRAME, binding = GPU_BINDING_PATTERN) uniform Pattern { vec4 patternPairs[STSV_PATTERN_VEC4S]; };
vec2 patternPointAt(uint i) {
    vec4 pair = patternPairs[i >> 1u];
    return (i & 1u) == 0u ? pair.xy : pair.zw;
}
#else
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_PATTERN) readonly buffer Pattern { vec2 patternPoints[]; };
vec2 patternPointAt(uint i) { return patternPoints[i]; }
#endif
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_FRAME) readonly buffer FrameData {
    GpuFrame frame;
    GpuLight lights[];
};
layout(push_constant) uniform Push { GpuPush pc; };

#ifndef LS_TRANSMITTANCE
#define LS_TRANSMITTANCE 0
#endif
#ifndef LS_OPAQUE_COUNTERS
#define LS_OPAQUE_COUNTERS 0
#endif
#if LS_TRANSMITTANCE || defined(FRAME_DEPTH_TABLES)
/// The materials' optical-depth tables, 256 units each (GpuTriangle::material · 256 + alpha byte):
/// a transmittance frame's, and the transmittance functions' (FRAME_DEPTH_TABLES).
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_DEPTH_TABLES) readonly buffer DepthTables { uint depthTables[]; };
#endif

#ifdef STSV_ALPHA_BIT_VEC4S
// Binary alpha, alphaBlocks of each texel as one bit, in a uniform buffer (render/vulkan/gpu_frame_resources.cpp
// picks it when it fits): a dynamically indexed uniform load is a vector gather on lavapipe, a
// storage-buffer load a loop over the lanes. GpuTexture::offset counts bits then.
layout(std140, set = GPU_SET_FRAME, binding = GPU_BINDING_ALPHA) uniform AlphaBits { uvec4 alphaBitWords[STSV_ALPHA_BIT_VEC4S]; };

/// An alpha byte with the texel's alphaBlocks decision (255 blocks, 0 is a hole) of texture
/// record `t` (loaded once by callers that fetch many texels of one texture).
uint alphaAtTexture(GpuTexture t, ivec2 texel) {
    uint bit = t.offset + uint(texel.y) * uint(t.width) + uint(texel.x);
    uint word = alphaBitWords[bit >> 7u][(bit >> 5u) & 3u];
    return ((word >> (bit & 31u)) & 1u) != 0u ? 255u : 0u;
}
#else
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_ALPHA) readonly buffer Alpha { uint alphaWords[]; };

/// The shared texel rule's alpha byte (scene/occlusion_rules_dh.h texelAt + alphaBlocks decide) of
/// texture record `t` (loaded once by callers that fetch many texels of one texture).
uint alphaAtTexture(GpuTexture t, ivec2 texel) {
    uint byteIndex = t.offset + uint(texel.y) * uint(t.width) + uint(texel.x);
    return gpuByteOf(alphaWords[byteIndex >> 2u], byteIndex);
}
#endif

uint alphaAt(uint texture, ivec2 texel) { return alphaAtTexture(textures[texture], texel); }

/// The pixel whose light samples (sample set, decorrelation, tap rotation) a sub-pixel of the
/// frame's grid takes: itself, or with supersampling K its pixel (x/K, y/K).
uvec2 samplePixelOf(uvec2 pixel) { return pixel / frame.supersample; }

/// A pixel's light samples (DESIGN §4.1), set up once per pixel by every pass that reads them:
/// its interleaved set's first pattern point and its decorrelation offset, both of its sample
/// pixel (samplePixelOf), as sampling/light_sampling.cpp sets up the CPU's.
struct PixelSamples {
    uint base;        ///< interleaveSet · N: the pixel's sample set
    uvec2 offset;     ///< decorrelationOffset of the pixel
    bool decorrelate; ///< frame.decorrelate, loaded once (a storage-buffer load)
};
PixelSamples pixelSamples(uvec2 pixel, uint sampleCount) {
    uvec2 owner = samplePixelOf(pixel);
    PixelSamples samples;
    samples.base = interleaveSet(owner, frame.interleave) * sampleCount;
    samples.offset = decorrelationOffset(owner, frame.seed);
    samples.decorrelate = frame.decorrelate != 0u;
    return samples;
}

#ifdef STSV_PATTERN_Q
/// The frame's single sample set (no interleaving) in 24-bit fixed point, q = u·2^24 exactly,
/// baked into the shader by render/vulkan/gpu_shader_defines.cpp: with the sample loops unrolled, sample k's
/// point is a constant instead of a storage-buffer load per sample and pixel (on lavapipe those
/// loads cost more than the rest of the resolve).
const uvec2 patternQ[SAMPLE_COUNT] = STSV_PATTERN_Q;
// A sample loop unrolls with it (GL_EXT_control_flow_attributes): each sample's point, counter
// word and shift are constants.
#define STSV_UNROLL [[unroll]]
#else
#define STSV_UNROLL
#endif

/// Sample k of a pixel's samples in the light frame's domain: samplePoint of
/// sampling/light_sampling_dh.h bit for bit (patternQ[k] = pattern point · 2^24 exactly, and
/// vec2(q) · 2^−24 is exact for q < 2^24), the offset computed once per pixel.
vec2 pixelSamplePoint(PixelSamples samples, uint k, uint domain) {
#ifdef STSV_PATTERN_Q
    uvec2 q = patternQ[k];
    if (samples.decorrelate) q = (q + samples.offset) & uvec2(SAMPLING_FIXED_MASK);
    return domainPoint(vec2(q) * (1.0 / SAMPLING_FIXED_ONE), domain);
#else
    vec2 u = patternPointAt(samples.base + k);
    return domainPoint(samples.decorrelate ? decorrelateBy(u, samples.offset) : u, domain);
#endif
}

ivec2 textureSizeOf(uint texture) { return ivec2(textures[texture].width, textures[texture].height); }

#endif
