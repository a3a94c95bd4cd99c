// The STSV fragment (STSV paper Algorithm 2, §2.3–2.4; DESIGN §4.3): what volumes/shaders/stsv.frag's
// main() runs for a fragment whose volume covers the visible point p, and what the CPU mirror
// (volumes/cpu/cpu_stsv.cpp) runs for each (pixel, covering volume) pair. Compiles as C++ and GLSL
// (core/dh.h).
//
// Data access. The two sides read the pixel's sample pattern and the triangle's alpha texels
// from different places (baked constants, uniform or storage buffers on the GPU; SamplePlan and
// Texture on the CPU), and on lavapipe that access must stay inside the sample loop (a table of
// the pixel's sample points would live in scratch memory, gathered per lane). So the includer
// defines, before including this header, a type and two functions:
//   struct StsvSampleSource                       what the pixel's samples and texels are read from
//   vec2 stsvSourcePoint(StsvSampleSource s, uint k)      frame coordinates (a, b) of sample k
//                                                         (samplePoint of light_sampling_dh.h)
//   bool stsvSourceBlocks(StsvSampleSource s, ivec2 texel) alphaBlocks of the texel of the
//                                                         triangle's texture
// and the macro STSV_SAMPLE_SOURCE. A pass that writes transmittance defines STSV_SAMPLE_DEPTH too,
// and a third function:
//   uint stsvSourceDepth(StsvSampleSource s, StsvTriangle t, ivec2 texel)
//                                                         the optical-depth units (scene/
//                                                         occlusion_rules_dh.h) a crossing at the
//                                                         texel adds: for STSV_FLAG_TRANSLUCENT
//                                                         the material's table at the texel's
//                                                         alpha (entry 255 with STSV_FLAG_OPAQUE),
//                                                         else OPTICAL_DEPTH_OPAQUE where it
//                                                         blocks and 0 where it does not.
// Declared functions would do for GLSL, but C++ would then need globals; a source value passed in keeps the
// C++ side reentrant and the GLSL side free of cost (every call is inlined, the struct scalarised).
#ifndef STSV_VOLUMES_STSV_FRAGMENT_DH_H
#define STSV_VOLUMES_STSV_FRAGMENT_DH_H

#ifndef STSV_SAMPLE_SOURCE
#error "define StsvSampleSource, stsvSourcePoint and stsvSourceBlocks, then STSV_SAMPLE_SOURCE"
#endif

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/ls_buffer_dh.h"
#include "volumes/stsv_dh.h"

DH_BEGIN

/// Per-pixel setup of S-triangle t for a point p that its volume `side` covers: J = W·M
/// applied to the pixel's light frame (Eq. 3), segments from tMin (shadowTMin). False when the
/// crossing belongs to the other side's volume: side 0 owns e > 0 (p behind the triangle as
/// seen from the light centre), side 1 owns e < 0, so a triangle counts at most once per sample
/// even when both of its volumes hold p (the paper's §6 double-sided fix).
DH_FUNC bool stsvFragmentPixel(StsvTriangle t, uint side, vec3 p, LightFrame lf, float tMin,
                               DH_OUT(StsvPixel) px) {
    px = stsvSetupPixel(t, p, lf.center, lf.T, lf.B, tMin);
    return side == 0u ? px.e > 0.0f : px.e < 0.0f;
}

/// True iff light sample k is occluded by triangle t: the projective test (Eq. 1–3) and, for a
/// textured triangle of `textureSize` texels, the texel rule at the crossing (Eq. 4–5).
DH_FUNC bool stsvSampleOccluded(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 textureSize,
                                uint k) {
    ivec2 texel;
    if (!stsvSampleCrosses(t, px, stsvSourcePoint(src, k), textureSize, texel)) return false;
    return (t.flags & STSV_FLAG_OPAQUE) != 0u || stsvSourceBlocks(src, texel);
}

/// Occlusion bits of mask word w (ls_buffer_dh.h): samples k = 32w + b, b < bitCount, against
/// triangle t. One word per call: the word index stays uniform across the fragments of a SIMD
/// batch, so the mask lives in registers.
DH_FUNC uint stsvOcclusionWord(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 textureSize, uint w,
                               uint bitCount) {
    uint bits = 0u;
    for (uint b = 0u; b < bitCount; ++b) {
        uint k = 32u * w + b;
        if (stsvSampleOccluded(t, px, src, textureSize, k)) bits |= lsMaskBit(k);
    }
    return bits;
}

/// stsvOcclusionWord over the samples of word w whose bits are set in `untested` only: callers
/// leave out samples that cannot change the result — those outside the triangle's projection
/// (stsvSampleRegion), and with a bitmask those an earlier triangle already occluded.
DH_FUNC uint stsvOcclusionWordOf(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 textureSize,
                                 uint w, uint untested) {
    uint bits = 0u;
    while (untested != 0u) {
        uint k = 32u * w + uint(findLSB(untested));
        untested &= untested - 1u;
        if (stsvSampleOccluded(t, px, src, textureSize, k)) bits |= lsMaskBit(k);
    }
    return bits;
}

#ifdef STSV_SAMPLE_DEPTH
/// The optical-depth units triangle t adds to light sample k: 0 when the segment misses it, else
/// stsvSourceDepth at the crossing's texel (OPTICAL_DEPTH_OPAQUE for a blocking one).
DH_FUNC uint stsvSampleDepth(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 textureSize, uint k) {
    ivec2 texel;
    if (!stsvSampleCrosses(t, px, stsvSourcePoint(src, k), textureSize, texel)) return 0u;
    return stsvSourceDepth(src, t, texel);
}
#endif

DH_END

#endif // STSV_VOLUMES_STSV_FRAGMENT_DH_H
