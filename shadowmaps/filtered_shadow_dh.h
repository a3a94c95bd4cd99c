// Filtered shadow maps (DESIGN §4.6): representations of a map's depths that are averaged over a
// kernel first and compared with the receiver once, so a filter of any width costs the same per
// pixel (the filtered-shadows lecture's "how can we accelerate PCF?"). Each method maps a
// texel's depth to a few values (its moments, exponentials or Fourier basis), the filter averages
// them over a rectangle (shadowmaps/summed_area.h, or a mip level), and a reconstruction turns the
// averages and the receiver's depth into a lit fraction. Compiles as C++ and GLSL (core/dh.h).
//
// Depths are the map's linear depths normalised over its fitted range, z = (d − near)/(far − near)
// clamped to [0, 1]; a texel that sees nothing holds z = 1 (the far value: an infinite texel
// would poison every average over it), so a cleared map filters to lit for every receiver in range.
#ifndef STSV_SHADOWMAPS_FILTERED_SHADOW_DH_H
#define STSV_SHADOWMAPS_FILTERED_SHADOW_DH_H

#include "core/dh.h"
#include "shadowmaps/shadow_map_dh.h"

DH_BEGIN

/// The filtered representations among the image family's variants (ShadowFilterParams::method;
/// shadow_map_dh.h has the others). A variant is its selector here, its functions below, its
/// branches in the three dispatches at the end of this file, and its row in shadowmaps/variants.cpp.
DH_CONST uint SHADOW_FILTER_VSM = 3u;
DH_CONST uint SHADOW_FILTER_ESM = 4u;
DH_CONST uint SHADOW_FILTER_EVSM = 5u;
DH_CONST uint SHADOW_FILTER_MSM = 6u;
DH_CONST uint SHADOW_FILTER_CSM = 7u;

/// Normalised depth of a map depth d (SHADOW_MAP_EMPTY and beyond far: 1).
DH_FUNC float filteredDepth(ShadowMapView v, float d) {
    if (d >= SHADOW_MAP_EMPTY) return 1.0f;
    return clamp((d - v.near) / (v.far - v.near), 0.0f, 1.0f);
}

/// Chebyshev's one-sided inequality (Donnelly & Lauritzen 2006): for depths of mean mu and
/// variance var, P(depth ≥ t) ≥ … is bounded above by var/(var + (t − mu)²) when t > mu; the
/// lit fraction is at most that (1 when t ≤ mu). var is floored at minVariance.
DH_FUNC float chebyshevUpperBound(float mu, float m2, float t, float minVariance) {
    if (t <= mu) return 1.0f;
    float variance = max(m2 - mu * mu, minVariance);
    float d = t - mu;
    return variance / (variance + d * d);
}

/// Light-bleeding reduction: p below `amount` becomes 0, the rest is stretched to [0, 1].
DH_FUNC float bleedReduce(float p, float amount) {
    if (amount <= 0.0f) return p;
    return clamp((p - amount) / (1.0f - amount), 0.0f, 1.0f);
}

// ---- VSM (Donnelly & Lauritzen 2006): moments (z, z²) ----

DH_FUNC vec2 vsmMoments(float z) {
    return vec2(z, z * z);
}
/// Lit fraction of a receiver at normalised depth t from filtered moments m.
DH_FUNC float vsmVisibility(vec2 m, float t, float minVariance, float bleed) {
    return bleedReduce(chebyshevUpperBound(m.x, m.y, t, minVariance), bleed);
}

// ---- ESM (Annen et al. 2008, Salvi 2008): exp(c·z), filtered in log space ----
// s(z − t) ≈ exp(−c·(t − z)) = exp(−c·t)·exp(c·z): the average of exp(c·z) over the kernel
// times exp(−c·t). The map holds c·z and the filter averages in log space, L = log E[exp(c·z)]
// (log-sum-exp), so exp(c·z) is never formed and c = 80 (below ln FLT_MAX ≈ 88.7) cannot
// overflow.

/// log(Σ w_i·exp(l_i)) of four log values with weights w (Σ w > 0; zero weights allowed).
DH_FUNC float esmLogSum4(vec4 l, vec4 w) {
    float top = -3.0e38f;
    for (int i = 0; i < 4; ++i)
        if (w[i] > 0.0f) top = max(top, l[i]);
    float sum = 0.0f;
    for (int i = 0; i < 4; ++i)
        if (w[i] > 0.0f) sum += w[i] * exp(l[i] - top);
    return top + log(sum);
}
/// Lit fraction from the filtered log average L and the receiver's t.
DH_FUNC float esmVisibility(float logAverage, float c, float t) {
    return clamp(exp(logAverage - c * t), 0.0f, 1.0f);
}

// ---- EVSM (Lauritzen & McCool 2008): Chebyshev on a positive and a negative exponential warp ----
// Warps p(z) = exp(c⁺·(z − 1)) and n(z) = −exp(−c⁻·z), both increasing in z and scaled into
// [−1, 1] (Chebyshev's bound does not change under a positive scale of the warp); moments
// (p, p², −n, n²), so every stored value lies in [0, 1]. With c⁺ ≤ 42, p² keeps float range at
// every scale. The minimum variance of z is carried into each warp by its derivative at t.

DH_FUNC vec4 evsmMoments(float z, float cPos, float cNeg) {
    float p = exp(cPos * (z - 1.0f));
    float n = exp(-cNeg * z);
    return vec4(p, p * p, n, n * n);
}
DH_FUNC float evsmVisibility(vec4 m, float t, float cPos, float cNeg, float minVariance, float bleed) {
    float pt = exp(cPos * (t - 1.0f));
    float dp = cPos * pt;
    float pos = chebyshevUpperBound(m.x, m.y, pt, minVariance * dp * dp);
    float nt = exp(-cNeg * t);
    float dn = cNeg * nt;
    float neg = chebyshevUpperBound(-m.z, m.w, -nt, minVariance * dn * dn);
    return bleedReduce(min(pos, neg), bleed);
}

// ---- MSM (Peters & Klein 2015): four power moments, Hamburger reconstruction ----
// The moments b = (z, z², z³, z⁴), biased towards those of a uniform distribution's midpoint,
// b' = (1 − α)·b + α·(½, ½, ½, ½), so the Hankel matrix stays positive definite when every depth
// in the kernel is the same (α is the knob msm_bias). The shadow intensity is the bound of the
// paper's Algorithm 3: solve B(b')·c = (1, t, t²) with B the 3 × 3 Hankel matrix [1 b1 b2;
// b1 b2 b3; b2 b3 b4], take the roots z₂ ≤ z₃ of c₀ + c₁·z + c₂·z², and
//   t ≤ z₂:       G = 0
//   z₂ < t ≤ z₃:  G = (t·z₃ − b1·(t + z₃) + b2) / ((z₃ − z₂)·(t − z₂))
//   t > z₃:       G = 1 − (z₂·z₃ − b1·(z₂ + z₃) + b2) / ((t − z₂)·(t − z₃)).
// The lit fraction is 1 − G. Where the factorisation breaks down in float arithmetic (a pivot
// that is not positive, a negative discriminant, a non-finite G), the Chebyshev bound of the
// first two moments is used instead, which is a valid upper bound too: no inf or NaN leaves here.

DH_FUNC vec4 msmMoments(float z) {
    float z2 = z * z;
    return vec4(z, z2, z2 * z, z2 * z2);
}
/// The bound of Algorithm 3 for biased moments b: the shadow intensity g and the roots z₂ ≤ z₃ of
/// the three-point solution {t, z₂, z₃}; ok = 0 where the factorisation breaks down in float
/// arithmetic.
struct MsmBound {
    float g;
    float z2;
    float z3;
    uint ok;
};
DH_FUNC MsmBound msmHamburgerBound(vec4 b, float t) {
    MsmBound bound;
    bound.g = 0.0f;
    bound.z2 = 0.0f;
    bound.z3 = 0.0f;
    bound.ok = 0u;
    // Cholesky B = L·D·Lᵀ of the Hankel matrix (first row 1, b1, b2).
    float d22 = b.y - b.x * b.x;
    if (!(d22 > 0.0f)) return bound;
    float l32 = (b.z - b.x * b.y) / d22;
    float d33 = (b.w - b.y * b.y) - l32 * l32 * d22;
    if (!(d33 > 0.0f)) return bound;
    // Solve L·D·Lᵀ·c = (1, t, t²).
    float c0 = 1.0f;
    float c1 = t - b.x;
    float c2 = t * t - b.y - l32 * c1;
    c1 /= d22;
    c2 /= d33;
    c1 -= l32 * c2;
    c0 -= c1 * b.x + c2 * b.y;
    if (!(abs(c2) > 0.0f)) return bound;
    // Roots of c0 + c1·z + c2·z².
    float p = c1 / c2;
    float q = c0 / c2;
    float disc = 0.25f * p * p - q;
    if (!(disc >= 0.0f)) return bound;
    float r = sqrt(disc);
    float z2 = -0.5f * p - r;
    float z3 = -0.5f * p + r;
    float g;
    if (t <= z2)
        g = 0.0f;
    else if (t <= z3)
        g = (t * z3 - b.x * (t + z3) + b.y) / ((z3 - z2) * (t - z2));
    else
        g = 1.0f - (z2 * z3 - b.x * (z2 + z3) + b.y) / ((t - z2) * (t - z3));
    if (!(g >= -1.0e30f && g <= 1.0e30f)) return bound;
    bound.g = g;
    bound.z2 = z2;
    bound.z3 = z3;
    bound.ok = 1u;
    return bound;
}
DH_FUNC float msmVisibility(vec4 moments, float t, float bias) {
    vec4 b = (1.0f - bias) * moments + bias * vec4(0.5f);
    MsmBound bound = msmHamburgerBound(b, t);
    if (bound.ok == 0u) return chebyshevUpperBound(b.x, b.y, t, 1e-7f);
    return clamp(1.0f - bound.g, 0.0f, 1.0f);
}

// ---- MSM, Hausdorff (Peters & Klein 2015): the same moments, the depths known to lie in [0, 1] ----
// The Hamburger bound ranges over every distribution with the moments b; the normalised depths
// lie in [0, 1], and the Hausdorff moment problem bounds over those alone, which can only raise
// the shadow intensity: less light leaks. Where the three-point solution {t, z₂, z₃} lies in
// [0, 1] the two bounds agree. Where z₂ < 0 or z₃ > 1 it is no distribution on [0, 1], and the
// bound comes from the four-point one with support {0, t, z_f, 1}: the polynomial
// z·(z − 1)·(z − t)·(z − z_f) has expectation 0 under it, so with Q(z) = z·(z − 1)·(z − t),
//   z_f = E[z·Q(z)] / E[Q(z)],   E[Q] = b3 − (1 + t)·b2 + t·b1,   E[z·Q] = b4 − (1 + t)·b3 + t·b2,
// and the shadow intensity is the weight of its points before t, w₀ + [z_f < t]·w_f (Lagrange):
//   w₀ = E[(z − t)(z − z_f)(z − 1)] / (−t·z_f),   w_f = E[Q] / (z_f·(z_f − t)·(z_f − 1)).
// Where that breaks down in float arithmetic (z_f outside (0, 1) or equal to t, t at an end of
// [0, 1], a non-finite weight), the Hamburger bound stands.

DH_CONST uint SHADOW_FILTER_MSM_HAUSDORFF = 11u;
/// How far outside [0, 1] a four-point weight may lie from round-off alone.
DH_CONST float MSM_HAUSDORFF_WEIGHT_SLACK = 1e-3f;

DH_FUNC float msmHausdorffVisibility(vec4 moments, float t, float bias) {
    vec4 b = (1.0f - bias) * moments + bias * vec4(0.5f);
    MsmBound bound = msmHamburgerBound(b, t);
    if (bound.ok == 0u) return chebyshevUpperBound(b.x, b.y, t, 1e-7f);
    float hamburger = clamp(1.0f - bound.g, 0.0f, 1.0f);
    if ((bound.z2 >= 0.0f && bound.z3 <= 1.0f) || !(t > 0.0f && t < 1.0f)) return hamburger;
    float eq = b.z - (1.0f + t) * b.y + t * b.x;
    float ezq = b.w - (1.0f + t) * b.z + t * b.y;
    float zf = ezq / eq;
    if (!(zf > 0.0f && zf < 1.0f) || zf == t) return hamburger;
    float s1 = t + zf + 1.0f;
    float s2 = t * zf + t + zf;
    float w0 = (b.z - s1 * b.y + s2 * b.x - t * zf) / (-t * zf);
    float wf = eq / (zf * (zf - t) * (zf - 1.0f));
    float wt = (b.z - (zf + 1.0f) * b.y + zf * b.x) / (t * (t - zf) * (t - 1.0f));
    float w1 = (b.z - (t + zf) * b.y + t * zf * b.x) / ((1.0f - t) * (1.0f - zf));
    float g = w0 + (zf < t ? wf : 0.0f);
    // Float round-off: E[Q] and the weights cancel terms of the moments' size, and where the
    // mass crowds 0, t or 1 the four points come out of the noise. A solution with a weight
    // outside [0, 1] is no distribution, and one below the Hamburger bound contradicts it:
    // both are round-off, and the Hamburger bound stands.
    float lo = min(min(w0, wf), min(wt, w1)), hi = max(max(w0, wf), max(wt, w1));
    if (!(lo >= -MSM_HAUSDORFF_WEIGHT_SLACK && hi <= 1.0f + MSM_HAUSDORFF_WEIGHT_SLACK) || !(g >= bound.g))
        return hamburger;
    return clamp(1.0f - g, 0.0f, 1.0f);
}

// ---- CSM (Annen et al. 2007): the shadow test as a truncated Fourier series ----
// With x = z − t, the lit test H(x) (1 where the stored depth is behind the receiver) is the
// square wave of period 2 on [−1, 1]: H(x) ≈ ½ + 2·Σ_{k=1..M} sin(c_k·x)/c_k, c_k = π(2k − 1).
// sin(c_k(z − t)) = sin(c_k z)·cos(c_k t) − cos(c_k z)·sin(c_k t): the map holds cos(c_k z)
// and sin(c_k z) (2M values per texel), the filter averages them, and the series is summed at t.
// Truncation rings; the terms are damped by Lanczos' σ factors sinc(k/(M + 1)) when `damp`, and
// the reconstruction is offset as published: clamp(2·rec, 0, 1), which lights a receiver that
// equals the stored depth (the series gives ½ there) and darkens the ringing below ½ to 0.

DH_CONST int CSM_MAX_TERMS = 16;

DH_FUNC float csmFrequency(int k) {
    return 3.14159265358979f * float(2 * k - 1);
}
/// c_k·x reduced to [−π, π) (c_k·x = 2π·(2k − 1)·x/2): sin and cos of up to 31π lose accuracy on
/// some GPUs' approximations, and the two backends then disagree.
DH_FUNC float csmPhase(int k, float x) {
    float turns = 0.5f * float(2 * k - 1) * x;
    return 6.28318530718f * (fract(turns + 0.5f) - 0.5f);
}
/// Lanczos' σ factor of term k (1-based) of M.
DH_FUNC float csmDamping(int k, int terms) {
    float x = 3.14159265358979f * float(k) / float(terms + 1);
    return sin(x) / x;
}
/// Term k (1-based) of the series at receiver depth t, from the filtered cos(c_k z) and
/// sin(c_k z): 2·σ_k·(E[sin(c_k z)]·cos(c_k t) − E[cos(c_k z)]·sin(c_k t))/c_k.
DH_FUNC float csmTerm(float cosAverage, float sinAverage, float t, int k, int terms, bool damp) {
    float c = csmFrequency(k);
    float sigma = damp ? csmDamping(k, terms) : 1.0f;
    float phase = csmPhase(k, t);
    return 2.0f * sigma * (sinAverage * cos(phase) - cosAverage * sin(phase)) / c;
}
/// The lit fraction from the series' sum ½ + Σ terms, offset as published.
DH_FUNC float csmVisibility(float series) {
    return clamp(2.0f * series, 0.0f, 1.0f);
}

// ---- The dispatches: a variant's representation, its channel count and its reconstruction ----

/// Values per texel of a variant's representation (CSM: 2·csm_terms); 0 for a variant that is no
/// filtered representation.
DH_FUNC uint filteredChannelCount(uint method, uint csmTerms) {
    if (method == SHADOW_FILTER_VSM) return 2u;
    if (method == SHADOW_FILTER_ESM) return 1u;
    if (method == SHADOW_FILTER_EVSM || method == SHADOW_FILTER_MSM || method == SHADOW_FILTER_MSM_HAUSDORFF)
        return 4u;
    if (method == SHADOW_FILTER_CSM) return 2u * csmTerms;
    return 0u;
}

/// The most values a texel's representation has (CSM at CSM_MAX_TERMS).
DH_CONST uint FILTERED_MAX_CHANNELS = 32u;

struct FilteredChannels {
    float v[32];
};

/// The channels of one normalised depth z (ESM: c·z, the log of exp(c·z)).
DH_FUNC FilteredChannels filteredChannelValues(ShadowFilterParams p, float z) {
    FilteredChannels c;
    for (uint i = 0u; i < FILTERED_MAX_CHANNELS; ++i) c.v[i] = 0.0f;
    if (p.method == SHADOW_FILTER_VSM) {
        vec2 m = vsmMoments(z);
        c.v[0] = m.x;
        c.v[1] = m.y;
    } else if (p.method == SHADOW_FILTER_ESM) {
        c.v[0] = p.esmC * z;
    } else if (p.method == SHADOW_FILTER_EVSM || p.method == SHADOW_FILTER_MSM ||
               p.method == SHADOW_FILTER_MSM_HAUSDORFF) {
        vec4 m =
            p.method == SHADOW_FILTER_EVSM ? evsmMoments(z, p.evsmPositive, p.evsmNegative) : msmMoments(z);
        c.v[0] = m.x;
        c.v[1] = m.y;
        c.v[2] = m.z;
        c.v[3] = m.w;
    } else if (p.method == SHADOW_FILTER_CSM) {
        for (int k = 1; k <= int(p.csmTerms); ++k) {
            c.v[2 * (k - 1)] = cos(csmPhase(k, z));
            c.v[2 * (k - 1) + 1] = sin(csmPhase(k, z));
        }
    }
    return c;
}

/// The lit fraction the method reconstructs from a kernel's channel means `a` for a receiver at
/// normalised depth t.
DH_FUNC float filteredReconstruct(ShadowFilterParams p, FilteredChannels a, float t) {
    if (p.method == SHADOW_FILTER_VSM) return vsmVisibility(vec2(a.v[0], a.v[1]), t, p.minVariance, p.bleed);
    if (p.method == SHADOW_FILTER_ESM) return esmVisibility(a.v[0], p.esmC, t);
    if (p.method == SHADOW_FILTER_EVSM)
        return evsmVisibility(vec4(a.v[0], a.v[1], a.v[2], a.v[3]), t, p.evsmPositive, p.evsmNegative,
                              p.minVariance, p.bleed);
    if (p.method == SHADOW_FILTER_MSM)
        return msmVisibility(vec4(a.v[0], a.v[1], a.v[2], a.v[3]), t, p.msmBias);
    if (p.method == SHADOW_FILTER_MSM_HAUSDORFF)
        return msmHausdorffVisibility(vec4(a.v[0], a.v[1], a.v[2], a.v[3]), t, p.msmBias);
    float series = 0.5f;
    for (int k = 1; k <= int(p.csmTerms); ++k)
        series += csmTerm(a.v[2 * (k - 1)], a.v[2 * (k - 1) + 1], t, k, int(p.csmTerms), p.csmDamp != 0u);
    return csmVisibility(series);
}

DH_END

#endif // STSV_SHADOWMAPS_FILTERED_SHADOW_DH_H
