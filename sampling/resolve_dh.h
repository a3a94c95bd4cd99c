// The resolve of one light at one pixel (STSV paper Algorithm 2, last step; DESIGN §4.4): the
// visible samples and the Monte-Carlo direct lighting
//   Lo(p) = albedo/π · (1/N) Σ_k sampleContribution_k · V_k             ("Direct MC" of the paper)
// as render/shaders/resolve.comp's main() and the CPU resolve (sampling/light_sampling.cpp resolveDirect,
// render/cpu/cpu_renderer.cpp resolveLight) both run it. Compiles as C++ and GLSL (core/dh.h).
//
// Data access. The pixel's occlusion bits come from mask images or counters on the GPU and from a
// LightSampleBuffer on the CPU, its sample points from baked constants, uniform or storage
// buffers or a SamplePlan; so the includer defines, before including this header,
//   struct ResolveSource                               what the pixel's samples are read from
//   vec2 resolveSourcePoint(ResolveSource s, uint k)   frame coordinates (a, b) of sample k
//   uint resolveSourceWord(ResolveSource s, uint w)    what the pixel holds for mask word w
//                                                      (its occlusion bits, sampling/ls_buffer_dh.h)
//   bool resolveSourceOccluded(ResolveSource s, uint word, uint k)
//                                                      sample k occluded, given the word of k / 32
// and the macro RESOLVE_SOURCE (a value passed in, as volumes/stsv_fragment_dh.h explains). A
// source of fractional transmittance defines RESOLVE_TRANSMITTANCE too, and
//   float resolveSourceTransmittance(ResolveSource s, uint k)
//                                                      the fraction of sample k's light that gets
//                                                      through where it is not occluded
// so that V_k is 0 for an occluded sample and that fraction otherwise. The
// per-sample test is the source's so that counters are read once per sample at a constant offset
// from the pixel's first word (with the loops unrolled), as cheap on lavapipe as a mask bit.
// RESOLVE_UNROLL, empty by default, is the sample loops' attribute: resolve.comp sets [[unroll]]
// with a baked pattern, so that sample k's point and bit are constants in each copy of the body.
#ifndef STSV_SAMPLING_RESOLVE_DH_H
#define STSV_SAMPLING_RESOLVE_DH_H

#ifndef RESOLVE_SOURCE
#error                                                                                                       \
    "define ResolveSource, resolveSourcePoint, resolveSourceWord and resolveSourceOccluded, then RESOLVE_SOURCE"
#endif
#ifndef RESOLVE_UNROLL
#define RESOLVE_UNROLL
#endif

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"

DH_BEGIN

/// Running sums of one pixel's resolve.
struct ResolveSums {
    vec3 sum;          ///< Σ sampleContribution over visible samples (lights without a normal)
    float emitterSum;  ///< Σ resolveEmitterWeight over visible samples (rectangles, disks)
    uint visible;      ///< visible samples
    float transmitted; ///< Σ V_k (with RESOLVE_TRANSMITTANCE; else unused)
    uint pad1;
    uint pad2;
};

/// Rectangles and disks: their sampleContribution factors into a constant radiance·area and
/// resolveEmitterWeight. A compile-time constant in shaders built with FIXED_LIGHT_TYPE.
DH_FUNC bool resolveLightIsEmitter(Light light) {
    return SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE || SAMPLING_LIGHT_TYPE(light) == LIGHT_DISK;
}

/// sampleContribution of a light that emits along its normal N without its constant factor
/// radiance·area: cosθp·cosθl/|d|², d = s − p, written as max(n·d, 0)·max(−N·d, 0)/|d|⁴ — no
/// square root and one division per sample (the resolve's bottleneck on lavapipe). Equal to
/// sampleContribution / (radiance·area) in exact arithmetic; the rounding differs by a few ulp.
DH_FUNC float resolveEmitterWeight(vec3 n, vec3 lightNormal, vec3 d) {
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return 0.0f;
    float r = 1.0f / dist2;
    return (max(dot(n, d), 0.0f) * r) * (max(-dot(lightNormal, d), 0.0f) * r);
}

/// Sums over the pixel's samples, words outside and bits inside (wordCount words of bitCount
/// samples each, sampling/ls_buffer_dh.h), for receiver p with shading normal n (world units) in
/// light frame lf. The visibility terms are selects, not branches (SIMD lanes run both sides).
DH_FUNC ResolveSums resolveSamples(Light light, LightFrame lf, vec3 p, vec3 n, ResolveSource src,
                                   uint wordCount, uint bitCount) {
    ResolveSums sums;
    sums.sum = vec3(0.0f);
    sums.emitterSum = 0.0f;
    sums.visible = 0u;
    sums.transmitted = 0.0f;
    sums.pad1 = 0u;
    sums.pad2 = 0u;
    bool emitter = resolveLightIsEmitter(light);
    RESOLVE_UNROLL for (uint w = 0u; w < wordCount; ++w) {
        uint word = resolveSourceWord(src, w);
        RESOLVE_UNROLL for (uint b = 0u; b < bitCount; ++b) {
            uint k = 32u * w + b;
            bool occluded = resolveSourceOccluded(src, word, k);
            vec3 s = lightSamplePosition(lf, resolveSourcePoint(src, k));
            sums.visible += occluded ? 0u : 1u;
#ifdef RESOLVE_TRANSMITTANCE
            // V_k · x equals the select below where V_k is 0 or 1.
            float v = occluded ? 0.0f : resolveSourceTransmittance(src, k);
            sums.transmitted += v;
            if (emitter) {
                sums.emitterSum += v * resolveEmitterWeight(n, light.normal, s - p);
            } else {
                sums.sum += v * sampleContribution(light, lf, p, n, s);
            }
#else
            if (emitter) {
                float weight = resolveEmitterWeight(n, light.normal, s - p);
                sums.emitterSum += occluded ? 0.0f : weight;
            } else {
                vec3 c = sampleContribution(light, lf, p, n, s);
                sums.sum += occluded ? vec3(0.0f) : c;
            }
#endif
        }
    }
    return sums;
}

/// Σ_k sampleContribution_k · V_k from the sums: for emitters the constant factor radiance · A,
/// A = 4|T×B| (square domain) or π|T×B| (disk), times the weights' sum.
DH_FUNC vec3 resolveContributionSum(Light light, LightFrame lf, ResolveSums sums) {
    if (!resolveLightIsEmitter(light)) return sums.sum;
    float frameArea = length(cross(lf.T, lf.B));
    float area = lf.domain == DOMAIN_SQUARE ? 4.0f * frameArea : SAMPLING_PI * frameArea;
    return light.radiance * (area * sums.emitterSum);
}

/// Lambertian direct lighting of N samples whose contributions sum to `sum`, scaled by `scale`
/// (1, or PW's v_coef, which modulates the unshadowed lighting). Linear RGB.
DH_FUNC vec3 resolveDirectLighting(vec3 albedo, vec3 sum, float scale, uint sampleCount) {
    return albedo * (1.0f / SAMPLING_PI) * (sum * scale) / float(sampleCount);
}

DH_END

#endif // STSV_SAMPLING_RESOLVE_DH_H
