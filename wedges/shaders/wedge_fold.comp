#version 450
// After the centre and wedge passes of one light (DESIGN §4.5; STSV paper Algorithm 2):
//   D(r) = the layer count of dcs_center.comp;
//   DCS (WEDGE_PW 0): every sample counter becomes D(r) + its signed edge crossings, read as two
//          signed 16-bit halves and clamped at 0 like the CPU mirror; it runs right after the
//          wedge passes, so that STSV's layers (dcs+stsv) add to the clamped count, as on the CPU;
//   PW (WEDGE_PW 1): the v_coef image becomes v_coef = 1 − clamp([D(r) > 0] + Σ wedge terms,
//          0, 1), minus the occluded fraction of the STSV samples for pw+stsv (WEDGE_STSV 1).
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef LS_COUNTERS
#define LS_COUNTERS 0
#endif
#ifndef WEDGE_PW
#define WEDGE_PW 0
#endif
#ifndef WEDGE_STSV
#define WEDGE_STSV 0
#endif
#include "wedges/shaders/wedge_bindings.glsl"
#include "wedges/pw_dh.h"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CENTER, r32i) readonly uniform iimage2D centerCount;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_VCOEF, r32f) uniform image2D vcoefImage;
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_MASKS, rg32ui) readonly uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
#if WEDGE_STSV && LS_TRANSMITTANCE
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_DEPTHS) readonly buffer Depths { uint depths[]; };
#endif

#if WEDGE_STSV
/// Occluded fraction of the pixel's STSV samples (the perforated triangles, Algorithm 2 line 13):
/// one minus their visible fraction, counted as LightSampleBuffer::visibleFraction counts it
/// (sampling/ls_buffer_dh.h). Each mask image holds two words (.x, .y) and is loaded once.
float stsvOccludedFraction(ivec2 pixel) {
    const uint sampleCount = uint(SAMPLE_COUNT);
    const uint wordCount = lsMaskWordCount(sampleCount);
#if LS_TRANSMITTANCE
    uint slot = lsCounterSlot(lsPixelIndex(uvec2(pixel), frame.width), sampleCount, 0u);
    float transmitted = 0.0;
    for (uint image = 0u; image < lsMaskAttachment(wordCount - 1u) + 1u; ++image) {
        uvec2 m = imageLoad(masks[image], pixel).xy;
        for (uint w = 2u * image; w < min(2u * image + 2u, wordCount); ++w) {
            uint bits = lsMaskComponent(w) == 0u ? m.x : m.y;
            for (uint k = 32u * w; k < min(32u * w + 32u, sampleCount); ++k) {
                if ((bits & lsMaskBit(k)) == 0u) transmitted += transmittanceOfDepth(depths[slot + k]);
            }
        }
    }
    return 1.0 - lsMeanTransmittance(transmitted, sampleCount);
#else
    uint occluded = 0u;
#if LS_COUNTERS
    uint pixelBase = lsPixelCounterWord(lsPixelIndex(uvec2(pixel), frame.width), sampleCount);
    for (uint j = 0u; j < sampleCount / 2u; ++j) occluded += uint(bitCount(lsCounterPairBits(counters[pixelBase + j])));
#else
    for (uint image = 0u; image < lsMaskAttachment(wordCount - 1u) + 1u; ++image) {
        uvec2 m = imageLoad(masks[image], pixel).xy;
        for (uint w = 2u * image; w < min(2u * image + 2u, wordCount); ++w)
            occluded += lsMaskWordOccludedCount(lsMaskComponent(w) == 0u ? m.x : m.y, w, sampleCount);
    }
#endif
    return 1.0 - lsVisibleFraction(occluded, sampleCount);
#endif
}
#endif

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) return;
    uint tri = imageLoad(gTriangle, pixel).x;
    if (tri == GPU_NO_TRIANGLE) return;
    int d = imageLoad(centerCount, pixel).x;
#if WEDGE_PW
    float v = pwVisibility(pwCenterOcclusion(d) + imageLoad(vcoefImage, pixel).x);
#if WEDGE_STSV
    v = pwVisibilityWithStsv(v, stsvOccludedFraction(pixel));
#endif
    imageStore(vcoefImage, pixel, vec4(v));
#else
    // Each word holds L + 65536·H modulo 2^32 with L, H the signed sums of its two samples;
    // adding D(r) to both halves and sign-extending recovers them exactly while |L|, |H| < 2^15.
    uint pixelBase = lsPixelCounterWord(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT));
    for (uint j = 0u; j < uint(SAMPLE_COUNT / 2); ++j) {
        uint word = counters[pixelBase + j] + uint(d) * 65537u;
        int lo = int(word << 16u) >> 16;
        int hi = int(word - uint(lo)) >> 16;
        counters[pixelBase + j] = uint(max(lo, 0)) | (uint(max(hi, 0)) << 16u);
    }
#endif
}
