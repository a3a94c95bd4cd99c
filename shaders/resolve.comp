#version 450
// Resolve of one light (STSV paper Algorithm 2; DESIGN §4.4): v_coef = visible samples / N and
// Monte-Carlo direct lighting albedo/π · (1/N) Σ_k sampleContribution_k · V_k (the same math as
// sampling/light_sampling.cpp's resolveDirect), accumulated into the colour and visibility
// images. The first light's dispatch writes ambient (or background) first, as render/frame.cpp.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef STSV_COUNTERS
#define STSV_COUNTERS 0
#endif
#ifndef RESOLVE_COVERAGE
#define RESOLVE_COVERAGE 0
#endif
#include "frame_bindings.glsl"
#include "sampling/light_sampling_dh.h"

#define WORD_COUNT ((SAMPLE_COUNT + 31) / 32)
#define WORD_BITS (SAMPLE_COUNT < 32 ? SAMPLE_COUNT : 32)
#ifdef STSV_PATTERN_Q
#define STSV_UNROLL [[unroll]]
#else
#define STSV_UNROLL
#endif

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = 0, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = 0, binding = GPU_BINDING_COLOR, rgba32f) uniform image2D colorImage;
layout(set = 0, binding = GPU_BINDING_VISIBILITY, r32f) uniform image2D visibilityImage;
#if STSV_COUNTERS
layout(std430, set = 0, binding = GPU_BINDING_COUNTERS) readonly buffer Counters { uint counters[]; };
#else
layout(set = 0, binding = GPU_BINDING_MASKS, rg32ui) readonly uniform uimage2D masks[GPU_MAX_MASK_IMAGES];
#endif
#if RESOLVE_COVERAGE
// Penumbra wedges: v_coef per pixel (wedge_fold.comp), which scales the unshadowed lighting.
layout(set = 0, binding = GPU_BINDING_COVERAGE, r32f) readonly uniform image2D coverage;
#endif

/// sampleContribution (sampling/light_sampling_dh.h) of a light that emits along its normal N
/// (rectangle, disk) without its constant factor radiance·area: cosθp·cosθl/|d|², d = s − p,
/// written as max(n·d, 0)·max(−N·d, 0)/|d|⁴ — no square root and one division per sample
/// (the resolve's bottleneck on lavapipe). Equal in exact arithmetic; the rounding differs from
/// the CPU resolve by a few ulp (tests/gpu_render compare colours to a relative 1e-4).
float emitterWeight(vec3 n, vec3 lightNormal, vec3 d) {
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0)) return 0.0;
    float r = 1.0 / dist2;
    return (max(dot(n, d), 0.0) * r) * (max(-dot(lightNormal, d), 0.0) * r);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) return;
    uint tri = imageLoad(gTriangle, pixel).x;
    bool covered = tri != 0xffffffffu;
    vec3 albedo = covered ? vec3(triangles[tri].albedo) : vec3(0.0);
    vec3 color;
    float visibility;
    if (pc.initialize != 0u) {
        color = covered ? frame.boxHi.w * albedo : vec3(frame.background);
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
            LightFrame lf = lightFrame(light, p, frame.boxLo.w);
            uint base = interleaveSet(uvec2(pixel), frame.interleave) * uint(SAMPLE_COUNT);
            uvec2 offset = decorrelationOffset(uvec2(pixel), frame.seed);
            bool decorrelate = frame.decorrelate != 0u; // once, not per sample (storage-buffer load)
#if STSV_COUNTERS
            uint pixelBase = (uint(pixel.y) * frame.width + uint(pixel.x)) * uint(SAMPLE_COUNT / 2);
#else
            uvec2 m0 = imageLoad(masks[0], pixel).xy;
            uvec2 m1 = SAMPLE_COUNT > 64 ? imageLoad(masks[1], pixel).xy : uvec2(0u);
            uvec2 m2 = SAMPLE_COUNT > 128 ? imageLoad(masks[2], pixel).xy : uvec2(0u);
            uvec2 m3 = SAMPLE_COUNT > 192 ? imageLoad(masks[3], pixel).xy : uvec2(0u);
#endif
            vec3 sum = vec3(0.0);
            float sumWeight = 0.0;
            // Rectangles and disks (the type is a compile-time constant, FIXED_LIGHT_TYPE).
            bool emitter = SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE || SAMPLING_LIGHT_TYPE(light) == LIGHT_DISK;
            uint visible = 0u;
            // Words outside, bits inside. With STSV_PATTERN_Q both are unrolled, so k, the mask bit
            // and the pattern point are constants in each copy of the body.
            STSV_UNROLL for (uint w = 0u; w < uint(WORD_COUNT); ++w) {
#if !STSV_COUNTERS
                uint word = w == 0u ? m0.x : w == 1u ? m0.y : w == 2u ? m1.x : w == 3u ? m1.y :
                            w == 4u ? m2.x : w == 5u ? m2.y : w == 6u ? m3.x : m3.y;
#endif
                STSV_UNROLL for (uint b = 0u; b < uint(WORD_BITS); ++b) {
                    uint k = 32u * w + b;
#if STSV_COUNTERS
                    bool occluded = ((counters[pixelBase + (k >> 1u)] >> (16u * (k & 1u))) & 65535u) != 0u;
#else
                    bool occluded = ((word >> b) & 1u) != 0u;
#endif
#if RESOLVE_COVERAGE
                    occluded = false; // PW: every sample lit, scaled by v_coef below
#endif
                    vec2 ab = pixelSamplePoint(base, k, offset, decorrelate, lf.domain);
                    vec3 s = lightSamplePosition(lf, ab);
                    // Selects, not a branch (SIMD lanes run both sides anyway); sum + 0 = sum.
                    visible += occluded ? 0u : 1u;
                    if (emitter) {
                        float weight = emitterWeight(n, light.normal, s - p);
                        sumWeight += occluded ? 0.0 : weight;
                    } else {
                        vec3 c = sampleContribution(light, lf, p, n, s);
                        sum += occluded ? vec3(0.0) : c;
                    }
                }
            }
            if (emitter) {
                // The constant factor of sampleContribution: radiance · A, A = 4|T×B| or π|T×B|.
                float frameArea = length(cross(lf.T, lf.B));
                float area = lf.domain == DOMAIN_SQUARE ? 4.0 * frameArea : SAMPLING_PI * frameArea;
                sum = light.radiance * (area * sumWeight);
            }
#if RESOLVE_COVERAGE
            float v = imageLoad(coverage, pixel).x;
            sum *= v;
#else
            float v = float(visible) / float(SAMPLE_COUNT);
#endif
            color += albedo * (1.0 / SAMPLING_PI) * sum / float(SAMPLE_COUNT);
            visibility += frame.lightWeight * v;
        }
    }
    imageStore(colorImage, pixel, vec4(color, 1.0));
    imageStore(visibilityImage, pixel, vec4(visibility));
}
