#version 450
// Resolve of one light (STSV paper Algorithm 2; DESIGN §4.4): v_coef = visible samples / N and
// Monte-Carlo direct lighting albedo/π · (1/N) Σ_k sampleContribution_k · V_k
// (sampling/resolve_dh.h, which the CPU resolve calls too), accumulated into the colour and
// visibility images. The first light's dispatch writes ambient (or background) first, as render/cpu/cpu_renderer.cpp.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef LS_COUNTERS
#define LS_COUNTERS 0
#endif
#ifndef RESOLVE_VCOEF
#define RESOLVE_VCOEF 0
#endif
#include "render/shaders/frame_bindings.glsl"
#include "sampling/light_sampling_dh.h"

#define WORD_COUNT ((SAMPLE_COUNT + 31) / 32)
#define WORD_BITS (SAMPLE_COUNT < 32 ? SAMPLE_COUNT : 32)

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_RESOLVE_COLOR, rgba32f) uniform image2D colorImage;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_RESOLVE_VISIBILITY, r32f) uniform image2D visibilityImage;
#if LS_COUNTERS || LS_OPAQUE_COUNTERS
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) readonly buffer Counters { uint counters[]; };
#endif
#if !LS_COUNTERS
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_MASKS, rg32ui) readonly uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
#endif
#if LS_TRANSMITTANCE && !RESOLVE_VCOEF
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_DEPTHS) readonly buffer Depths { uint depths[]; };
#endif
#if RESOLVE_VCOEF
// Penumbra wedges: v_coef per pixel (wedge_fold.comp), which scales the unshadowed lighting.
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_VCOEF, r32f) readonly uniform image2D vcoefImage;
#endif

// The data access of sampling/resolve_dh.h: sample points through pixelSamplePoint
// (frame_bindings.glsl), occlusion bits from the mask images (loaded once per pixel) or the
// counters, or in a transmittance frame from both (DCS's layers beside STSV's bits) with the
// samples' optical depths. With STSV_PATTERN_Q the loops are unrolled, so k, the mask word and bit and the
// pattern point are constants in each copy of the body.
struct ResolveSource {
    PixelSamples samples;
    uint domain;      ///< LightFrame::domain
    uint counterWord; ///< lsPixelCounterWord: the pixel's first counter word
    uint depthSlot;   ///< lsCounterSlot of the pixel's sample 0: its first optical depth
    uvec2 m0;         ///< mask words 0…7 (attachment i holds words 2i, 2i + 1)
    uvec2 m1;
    uvec2 m2;
    uvec2 m3;
};
vec2 resolveSourcePoint(ResolveSource s, uint k) {
    return pixelSamplePoint(s.samples, k, s.domain);
}
uint resolveSourceWord(ResolveSource s, uint w) {
    return w == 0u ? s.m0.x : w == 1u ? s.m0.y : w == 2u ? s.m1.x : w == 3u ? s.m1.y :
           w == 4u ? s.m2.x : w == 5u ? s.m2.y : w == 6u ? s.m3.x : s.m3.y;
}
bool resolveSourceOccluded(ResolveSource s, uint word, uint k) {
#if RESOLVE_VCOEF
    return false; // PW: every sample lit, scaled by v_coef
#elif LS_COUNTERS
    return ((counters[s.counterWord + lsCounterWord(k)] >> lsCounterShift(k)) & 65535u) != 0u;
#elif LS_OPAQUE_COUNTERS
    return (word & lsMaskBit(k)) != 0u ||
           ((counters[s.counterWord + lsCounterWord(k)] >> lsCounterShift(k)) & 65535u) != 0u;
#else
    return (word & lsMaskBit(k)) != 0u;
#endif
}
#if LS_TRANSMITTANCE && !RESOLVE_VCOEF
// PW's v_coef holds STSV's mean transmittance already (wedge_fold.comp): every sample lit.
float resolveSourceTransmittance(ResolveSource s, uint k) {
    return transmittanceOfDepth(depths[s.depthSlot + k]);
}
#define RESOLVE_TRANSMITTANCE
#endif
#define RESOLVE_SOURCE
#define RESOLVE_UNROLL STSV_UNROLL
#include "sampling/resolve_dh.h"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) return;
    uint tri = imageLoad(gTriangle, pixel).x;
    bool covered = tri != 0xffffffffu;
    vec3 albedo = covered ? vec3(triangles[tri].albedo) : vec3(0.0);
    vec3 color;
    float visibility;
    if (pc.initialize != 0u) {
        color = covered ? frame.ambient * albedo : vec3(frame.background);
        visibility = 0.0;
    } else {
        color = vec3(imageLoad(colorImage, pixel));
        visibility = imageLoad(visibilityImage, pixel).x;
    }
    if (pc.light < frame.lightCount) {
        if (!covered) {
            visibility += frame.lightWeight;
        } else {
            Light light = lights[pc.light].light;
            vec3 p = vec3(imageLoad(gPosition, pixel));
            vec3 n = gpuShadingNormal(triangles[tri], vec3(frame.eye), p);
            LightFrame lf = lightFrame(light, p, frame.farDistance);
            ResolveSource src;
            src.samples = pixelSamples(uvec2(pixel), uint(SAMPLE_COUNT));
            src.domain = lf.domain;
            src.counterWord =
                lsPixelCounterWord(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT));
            src.depthSlot = lsCounterSlot(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT), 0u);
#if LS_COUNTERS || RESOLVE_VCOEF
            src.m0 = uvec2(0u);
            src.m1 = uvec2(0u);
            src.m2 = uvec2(0u);
            src.m3 = uvec2(0u);
#else
            src.m0 = imageLoad(masks[0], pixel).xy;
            src.m1 = SAMPLE_COUNT > 64 ? imageLoad(masks[1], pixel).xy : uvec2(0u);
            src.m2 = SAMPLE_COUNT > 128 ? imageLoad(masks[2], pixel).xy : uvec2(0u);
            src.m3 = SAMPLE_COUNT > 192 ? imageLoad(masks[3], pixel).xy : uvec2(0u);
#endif
            ResolveSums sums = resolveSamples(light, lf, p, n, src, uint(WORD_COUNT), uint(WORD_BITS));
            vec3 sum = resolveContributionSum(light, lf, sums);
#if RESOLVE_VCOEF
            float v = imageLoad(vcoefImage, pixel).x;
#elif LS_TRANSMITTANCE
            float v = sums.transmitted / float(SAMPLE_COUNT);
#else
            float v = float(sums.visible) / float(SAMPLE_COUNT);
#endif
            color += resolveDirectLighting(albedo, sum, RESOLVE_VCOEF != 0 ? v : 1.0, uint(SAMPLE_COUNT));
            visibility += frame.lightWeight * v;
        }
    }
    imageStore(colorImage, pixel, vec4(color, 1.0));
    imageStore(visibilityImage, pixel, vec4(visibility));
}
