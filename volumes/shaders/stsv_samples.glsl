// The per-sample half of an STSV fragment (volumes/stsv_fragment_dh.h), for stsv.frag and for
// stsv_samples.comp, which runs it for the fragments the hull draw deferred: the pixel's sample
// source, the set-up of (triangle, pixel), and the hull records read as texels.
#ifndef STSV_SHADERS_STSV_SAMPLES_GLSL
#define STSV_SHADERS_STSV_SAMPLES_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_volume.glsl"
#include "render/shaders/deferred_list.glsl"
#include "sampling/light_sampling_dh.h"

#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#define WORD_COUNT ((SAMPLE_COUNT + 31) / 32)
#define WORD_BITS (SAMPLE_COUNT < 32 ? SAMPLE_COUNT : 32)

// The data access of volumes/stsv_fragment_dh.h: the pixel's samples through pixelSamplePoint
// (frame_bindings.glsl), the texels through the triangle's texture record, loaded once per
// pixel (storage-buffer loads are per-lane loops on lavapipe).
struct StsvSampleSource {
    PixelSamples samples;
    uint domain; ///< LightFrame::domain
    GpuTexture texture;
    uint depthTable; ///< a translucent triangle's material table: its first entry in depthTables
};
vec2 stsvSourcePoint(StsvSampleSource s, uint k) {
    return pixelSamplePoint(s.samples, k, s.domain);
}
bool stsvSourceBlocks(StsvSampleSource s, ivec2 texel) {
    return alphaBlocks(alphaAtTexture(s.texture, texel));
}
#if LS_TRANSMITTANCE
uint stsvSourceDepth(StsvSampleSource s, StsvTriangle t, ivec2 texel) {
    if ((t.flags & STSV_FLAG_TRANSLUCENT) != 0u)
        return depthTables[s.depthTable + ((t.flags & STSV_FLAG_OPAQUE) != 0u ? 255u : alphaAtTexture(s.texture, texel))];
    return (t.flags & STSV_FLAG_OPAQUE) != 0u || stsvSourceBlocks(s, texel) ? OPTICAL_DEPTH_OPAQUE : 0u;
}
#define STSV_SAMPLE_DEPTH
#endif
#define STSV_SAMPLE_SOURCE
#include "volumes/stsv_fragment_dh.h"

/// Triangle t against pixel `pixel` with visible point p, for volume side `side`: J applied to
/// the light frame (stsvFragmentPixel), the sample source and the texture's size. False when the
/// crossing belongs to the other side's volume.
bool stsvPixelSetup(uvec2 pixel, vec3 p, StsvTriangle t, uint side, out StsvPixel px, out StsvSampleSource src,
                    out ivec2 size) {
    Light light = lights[pc.light].light;
    LightFrame lf = lightFrame(light, p, frame.farDistance);
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    bool opaque = (t.flags & STSV_FLAG_OPAQUE) != 0u;
    src.samples = pixelSamples(pixel, uint(SAMPLE_COUNT));
    src.domain = lf.domain;
    src.texture = textures[opaque ? 0u : t.texture];
    size = opaque ? ivec2(1) : ivec2(src.texture.width, src.texture.height);
    src.depthTable = 0u;
#if LS_TRANSMITTANCE
    if ((t.flags & STSV_FLAG_TRANSLUCENT) != 0u) src.depthTable = triangles[t.triangle].material * 256u;
#endif
    return stsvFragmentPixel(t, side, p, lf, shadowTMin(p, lf.center, sceneDiameter), px);
}

#ifndef LS_COUNTERS
#define LS_COUNTERS 0
#endif
#if LS_COUNTERS
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };

/// One more layer on the 16-bit counter of each sample whose bit is set in `bits`, word w of the
/// pixel whose counters start at `counterWord` (lsPixelCounterWord).
void stsvAddOccludedLayers(uint counterWord, uint w, uint bits) {
    while (bits != 0u) {
        uint k = 32u * w + uint(findLSB(bits));
        bits &= bits - 1u;
        atomicAdd(counters[counterWord + lsCounterWord(k)], 1u << lsCounterShift(k));
    }
}
#endif

#if LS_TRANSMITTANCE
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_DEPTHS) buffer Depths { uint depths[]; };

/// Translucent triangle t's optical depth added to the samples of mask word w of pixel
/// `pixelIndex` (lsPixelIndex), as atomic integer sums that no drawing order changes; returns
/// the bits of the samples it occludes: at an α = 1 texel, or where the sum passes 2^32 units
/// (scene/occlusion_rules_dh.h), as the CPU mirror's volumes/cpu/cpu_stsv.cpp. The sums of
/// occluded samples are meaningless: the readback zeroes them.
uint stsvAddDepthWord(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 size, uint w, uint bitCount,
                      uint pixelIndex) {
    uint bits = 0u;
    uint slot = lsCounterSlot(pixelIndex, uint(SAMPLE_COUNT), 32u * w);
    for (uint b = 0u; b < bitCount; ++b) {
        uint k = 32u * w + b;
        uint units = stsvSampleDepth(t, px, src, size, k);
        if (units == 0u) continue;
        if (units == OPTICAL_DEPTH_OPAQUE) {
            bits |= lsMaskBit(k);
            continue;
        }
        uint before = atomicAdd(depths[slot + b], units);
        if (before + units < before) bits |= lsMaskBit(k);
    }
    return bits;
}
#endif

/// The occlusion bits of mask word w of pixel `pixelIndex` that triangle t sets; a translucent
/// triangle adds its optical depths too (transmittance frames).
uint stsvSampleWord(StsvTriangle t, StsvPixel px, StsvSampleSource src, ivec2 size, uint w, uint pixelIndex) {
#if LS_TRANSMITTANCE
    if ((t.flags & STSV_FLAG_TRANSLUCENT) != 0u) return stsvAddDepthWord(t, px, src, size, w, uint(WORD_BITS), pixelIndex);
#endif
    return stsvOcclusionWord(t, px, src, size, w, uint(WORD_BITS));
}

// The hull pass's records (GpuStsvRecord at GPU_STSV_RECORD_* texels): a texel fetch at a
// per-lane index is a vector gather on lavapipe, a storage-buffer load a loop over the lanes.
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_RECORD_TEXELS) uniform usamplerBuffer recordTexels;
uvec4 stsvRecordTexel(uint record, uint i) {
    return texelFetch(recordTexels, int(record * GPU_HULL_RECORD_TEXELS + i));
}
vec4 stsvRecordVec4(uint record, uint i) {
    return uintBitsToFloat(stsvRecordTexel(record, i));
}
bool stsvRecordExists(uint record) {
    return record < uint(textureSize(recordTexels)) / GPU_HULL_RECORD_TEXELS;
}
StsvTriangle stsvRecordTriangle(uint record, uvec4 ids) {
    return stsvUnpackTriangle(stsvRecordVec4(record, 0u), stsvRecordVec4(record, 1u), stsvRecordVec4(record, 2u),
                              stsvRecordVec4(record, 3u), stsvRecordVec4(record, 4u), ids);
}

#endif
