// Light-sample buffer addressing (DESIGN §4.4): where sample k of a pixel lives in the bitmask
// and in the depth-complexity counters. The one definition used by every shader that reads or
// writes a buffer and by LightSampleBuffer, so that a GPU readback is the CPU layout byte for
// byte. Compiles as C++ and GLSL (core/dh.h).
//
// Bitmask: ceil(N/32) 32-bit words per pixel, sample k in bit k % 32 of word k / 32 (1 =
// occluded). On the GPU the words of a pixel sit in RG32UI attachments (storage images in the
// resolve): attachment i holds word 2i in .x and word 2i + 1 in .y.
// Counters: one 16-bit counter per sample, pixel-major (slot = pixel·N + k, pixel = y·W + x). The
// GPU packs two slots per uint (slot s in bits 16·(s % 2) of word s / 2), which is the
// little-endian order of LightSampleBuffer's uint16 array.
#ifndef STSV_SAMPLING_LS_BUFFER_DH_H
#define STSV_SAMPLING_LS_BUFFER_DH_H

#include "core/dh.h"

DH_BEGIN

/// 32-bit mask words per pixel for N samples.
DH_FUNC uint lsMaskWordCount(uint sampleCount) {
    return (sampleCount + 31u) / 32u;
}

/// The word of the pixel's mask that holds sample k.
DH_FUNC uint lsMaskWord(uint k) {
    return k >> 5u;
}

/// Sample k's bit within its word (lsMaskWord).
DH_FUNC uint lsMaskBit(uint k) {
    return 1u << (k & 31u);
}

/// The RG32UI attachment (or storage image) that holds mask word `word`; lsMaskComponent says
/// which of its two channels (0 = .x).
DH_FUNC uint lsMaskAttachment(uint word) {
    return word >> 1u;
}
DH_FUNC uint lsMaskComponent(uint word) {
    return word & 1u;
}

/// Row-major pixel index, row 0 first.
DH_FUNC uint lsPixelIndex(uvec2 pixel, uint width) {
    return pixel.y * width + pixel.x;
}

/// The 16-bit counter slot of sample k of pixel `pixelIndex` (lsPixelIndex), N samples a pixel.
DH_FUNC uint lsCounterSlot(uint pixelIndex, uint sampleCount, uint k) {
    return pixelIndex * sampleCount + k;
}

/// The GPU uint that holds counter slot `slot`, and the shift of its 16 bits there; applied to a
/// sample index k, the word relative to lsPixelCounterWord (below).
DH_FUNC uint lsCounterWord(uint slot) {
    return slot >> 1u;
}
DH_FUNC uint lsCounterShift(uint slot) {
    return 16u * (slot & 1u);
}

/// The GPU's first counter word of pixel `pixelIndex`. With N even (every GPU sample count) a
/// pixel's counters fill the N/2 words from there, and sample k's counter lies in word
/// lsPixelCounterWord + lsCounterWord(k) at lsCounterShift(k): the shaders address it so, with
/// a constant offset per sample once their loops are unrolled.
DH_FUNC uint lsPixelCounterWord(uint pixelIndex, uint sampleCount) {
    return lsCounterWord(lsCounterSlot(pixelIndex, sampleCount, 0u));
}

/// The occlusion bits of the two counters a GPU counter word holds: bit 0 for the slot in its low
/// half (even slot), bit 1 for the high half (count ≠ 0: occluded).
DH_FUNC uint lsCounterPairBits(uint word) {
    return ((word & 65535u) != 0u ? 1u : 0u) | ((word >> 16u) != 0u ? 2u : 0u);
}

/// Occluded samples among the bits of mask word w of a pixel with N samples: the bits of samples
/// k < N only (the last word's high bits stand for no sample).
DH_FUNC uint lsMaskWordOccludedCount(uint bits, uint w, uint sampleCount) {
    uint valid = min(32u, sampleCount - 32u * w);
    return uint(bitCount(valid == 32u ? bits : bits & ((1u << valid) - 1u)));
}

/// The visible fraction of a pixel's N samples, `occluded` of them occluded: what a bitmask or
/// counter pixel passes to the lit image, and one minus the occluded fraction PW subtracts for its
/// perforated triangles (pwVisibilityWithStsv). With transmittance the fraction is the samples'
/// mean transmittance, Σ_k T_k / N (T_k = 0 where occluded), summed in sample order.
DH_FUNC float lsVisibleFraction(uint occluded, uint sampleCount) {
    return float(sampleCount - occluded) / float(sampleCount);
}
DH_FUNC float lsMeanTransmittance(float transmittanceSum, uint sampleCount) {
    return transmittanceSum / float(sampleCount);
}

DH_END

#endif // STSV_SAMPLING_LS_BUFFER_DH_H
