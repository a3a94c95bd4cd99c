// The filtered shadow maps' math (shadowmaps/filtered_shadow_dh.h) and box filters
// (shadowmaps/summed_area.h) against what can be worked out by hand or by brute force: the
// Chebyshev bounds of VSM and EVSM never fall below the exact lit fraction of a depth set, MSM
// stays within its bias of it, every method is exactly lit where the receiver is nearer than all
// depths, extreme depths and exponents give no inf or NaN, a cleared map filters to lit, VSM
// equals PCF for one occluder plane over one receiver plane, light bleeding goes the way the
// lecture says, MSM's moment bias trades light leaking for self-shadowing, and the summed-area table and the
// mip pyramid equal a double-precision box filter within the precision their formats give.
#include "shadowmaps/filtered_shadow_dh.h"
#include "shadowmaps/summed_area.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace stsv {
namespace {

struct Averages {
    vec2 vsm{0.0f};
    vec4 evsm{0.0f};
    vec4 msm{0.0f};
    float esmLog = 0.0f; ///< log E[exp(c z)]
    std::vector<float> csmCos, csmSin;
};

constexpr float ESM_C = 80.0f, POS = 40.0f, NEG = 5.0f;
constexpr int TERMS = 16;

/// The methods' filtered values of a depth set, averaged in double precision.
Averages average(const std::vector<float>& z) {
    Averages a;
    const double n = double(z.size());
    double top = -1e300;
    for (float d : z) top = std::max(top, double(ESM_C) * d);
    double esm = 0.0;
    std::vector<double> c(TERMS, 0.0), s(TERMS, 0.0);
    dvec2 vsm(0.0);
    dvec4 evsm(0.0), msm(0.0);
    for (float d : z) {
        vsm += dvec2(vsmMoments(d)) / n;
        evsm += dvec4(evsmMoments(d, POS, NEG)) / n;
        msm += dvec4(msmMoments(d)) / n;
        esm += std::exp(double(ESM_C) * d - top) / n;
        for (int k = 1; k <= TERMS; ++k) {
            c[std::size_t(k - 1)] += std::cos(double(csmFrequency(k)) * d) / n;
            s[std::size_t(k - 1)] += std::sin(double(csmFrequency(k)) * d) / n;
        }
    }
    a.vsm = vec2(vsm);
    a.evsm = vec4(evsm);
    a.msm = vec4(msm);
    a.esmLog = float(top + std::log(esm));
    for (int k = 0; k < TERMS; ++k) {
        a.csmCos.push_back(float(c[std::size_t(k)]));
        a.csmSin.push_back(float(s[std::size_t(k)]));
    }
    return a;
}

float csm(const Averages& a, float t, bool damp = true) {
    float series = 0.5f;
    for (int k = 1; k <= TERMS; ++k)
        series += csmTerm(a.csmCos[std::size_t(k - 1)], a.csmSin[std::size_t(k - 1)], t, k, TERMS, damp);
    return csmVisibility(series);
}

/// The exact lit fraction: depths at or behind the receiver.
float litFraction(const std::vector<float>& z, float t) {
    int lit = 0;
    for (float d : z) lit += d >= t ? 1 : 0;
    return float(lit) / float(z.size());
}

TEST(FilteredShadows, ChebyshevBoundsNeverFallBelowTheExactLitFraction) {
    // Random kernels of 9 to 49 depths: uniform, two clusters (an occluder edge), one cluster.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    float worstMsm = 0.0f, worstHausdorff = 0.0f;
    int hausdorffTighter = 0;
    const float msmBias = 3e-5f;
    for (int trial = 0; trial < 4000; ++trial) {
        const int n = 9 + int(u(rng) * 40.0f);
        const int kind = trial % 3;
        const float a = u(rng), b = u(rng);
        std::vector<float> z;
        for (int i = 0; i < n; ++i) {
            const float spread = 0.02f * u(rng);
            z.push_back(kind == 0 ? u(rng) : kind == 1 ? (u(rng) < 0.4f ? a : b) + spread : a + spread);
        }
        const Averages avg = average(z);
        const float t = u(rng);
        const float exact = litFraction(z, t);
        // Float evaluation of a bound of a double average: a few ulps of the values.
        EXPECT_GE(vsmVisibility(avg.vsm, t, 0.0f, 0.0f), exact - 1e-5f) << "trial " << trial;
        EXPECT_GE(evsmVisibility(avg.evsm, t, POS, NEG, 0.0f, 0.0f), exact - 1e-5f) << "trial " << trial;
        const float msm = msmVisibility(avg.msm, t, msmBias);
        const float hausdorff = msmHausdorffVisibility(avg.msm, t, msmBias);
        worstMsm = std::max(worstMsm, exact - msm);
        worstHausdorff = std::max(worstHausdorff, exact - hausdorff);
        // The Hausdorff bound ranges over fewer distributions (those on [0, 1]): never more
        // light than Hamburger's, to the float round-off of its own arithmetic.
        EXPECT_LE(hausdorff, msm + 1e-5f) << "trial " << trial;
        if (hausdorff < msm - 1e-3f) ++hausdorffTighter;
    }
    std::printf("MSM Hausdorff (bias %g): lit fraction at most %.5f below the exact one; %d of 4000 kernels "
                "with less light than Hamburger's\n",
                double(msmBias), double(worstHausdorff), hausdorffTighter);
    EXPECT_LT(worstHausdorff, 0.02f);
    // Its four-point solution is no corner case: random kernels reach it often.
    EXPECT_GT(hausdorffTighter, 100);
    // MSM's bound is sharp (it is met by some distribution with these moments), so float
    // round-off and the bias decide how far below the exact fraction it may dip.
    std::printf("MSM (bias %g): lit fraction at most %.5f below the exact one\n", double(msmBias),
                double(worstMsm));
    EXPECT_LT(worstMsm, 0.02f);
}

TEST(FilteredShadows, EveryMethodIsLitWhereTheReceiverIsNearerThanEveryDepth) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<float> z;
        const float lo = 0.1f + 0.85f * u(rng);
        for (int i = 0; i < 25; ++i) z.push_back(lo + (1.0f - lo) * u(rng));
        float nearest = 1.0f;
        for (float d : z) nearest = std::min(nearest, d);
        const Averages avg = average(z);
        const float t = nearest * u(rng);
        EXPECT_EQ(vsmVisibility(avg.vsm, t, 1e-6f, 0.3f), 1.0f);
        EXPECT_EQ(evsmVisibility(avg.evsm, t, POS, NEG, 1e-6f, 0.3f), 1.0f);
        EXPECT_EQ(esmVisibility(avg.esmLog, ESM_C, t), 1.0f);
        // MSM's bias moves α of the mass to depths 0 and 1: a lower bound on the shadow of α/2.
        EXPECT_GE(msmVisibility(avg.msm, t, 3e-5f), 1.0f - 3e-5f);
        EXPECT_GE(msmHausdorffVisibility(avg.msm, t, 3e-5f), 1.0f - 3e-5f);
        // CSM: the truncated square wave is above ½ on (0, 1), so 2·rec ≥ 1, but round-off near
        // x = 0: receivers at least 1/(2M) in front.
        if (nearest - t > 0.5f / float(TERMS)) {
            EXPECT_EQ(csm(avg, t), 1.0f) << nearest << " " << t;
        }
    }
}

TEST(FilteredShadows, ExtremeDepthsAndExponentsGiveNoInfOrNan) {
    for (const float z : {0.0f, 1.0f})
        for (const float t : {0.0f, 0.5f, 1.0f, 1.5f}) {
            const std::vector<float> one(9, z);
            const Averages avg = average(one);
            for (const float bias : {0.0f, 6e-7f, 3e-5f}) {
                const float m = msmVisibility(avg.msm, t, bias);
                EXPECT_TRUE(std::isfinite(m) && m >= 0.0f && m <= 1.0f) << z << " " << t << " " << bias;
                const float h = msmHausdorffVisibility(avg.msm, t, bias);
                EXPECT_TRUE(std::isfinite(h) && h >= 0.0f && h <= 1.0f) << z << " " << t << " " << bias;
            }
            // The largest exponents: ESM c = 88 (ln FLT_MAX ≈ 88.7), EVSM warps of 42.
            const float esmLog = 88.0f * z;
            EXPECT_TRUE(std::isfinite(esmVisibility(esmLog, 88.0f, t)));
            const vec4 e = evsmMoments(z, 42.0f, 42.0f);
            EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z) && std::isfinite(e.w));
            const float ev = evsmVisibility(e, t, 42.0f, 42.0f, 1e-4f, 0.0f);
            EXPECT_TRUE(std::isfinite(ev) && ev >= 0.0f && ev <= 1.0f) << z << " " << t;
            const float c = csm(avg, t);
            EXPECT_TRUE(std::isfinite(c) && c >= 0.0f && c <= 1.0f);
        }
    // The log-space sum of exponents far apart: no overflow, the largest dominates.
    EXPECT_NEAR(esmLogSum4(vec4(88.0f, 0.0f, 1.0f, 2.0f), vec4(0.25f)), 88.0f + std::log(0.25f), 1e-4f);
}

TEST(FilteredShadows, AClearedMapFiltersToLit) {
    // Nothing seen: every texel at the far value 1; every receiver in range is lit.
    const Averages avg = average(std::vector<float>(16, 1.0f));
    for (float t = 0.0f; t <= 1.0f; t += 0.0625f) {
        EXPECT_EQ(vsmVisibility(avg.vsm, t, 1e-6f, 0.0f), 1.0f) << t;
        EXPECT_EQ(evsmVisibility(avg.evsm, t, POS, NEG, 1e-6f, 0.0f), 1.0f) << t;
        EXPECT_EQ(esmVisibility(avg.esmLog, ESM_C, t), 1.0f) << t;
        // CSM's square wave has period 2: at z − t = 1 (a receiver on the near plane) it jumps,
        // and the series gives ½ there; from 1/(2M) on it is above ½.
        if (t >= 0.5f / float(TERMS)) {
            EXPECT_EQ(csm(avg, t), 1.0f) << t;
        }
        EXPECT_GE(msmVisibility(avg.msm, t, 3e-5f), 1.0f - 3e-5f) << t;
        EXPECT_GE(msmHausdorffVisibility(avg.msm, t, 3e-5f), 1.0f - 3e-5f) << t;
    }
}

TEST(FilteredShadows, VsmEqualsPcfForOneOccluderPlaneOverOneReceiverPlane) {
    // A kernel with a fraction f of texels on an occluder at z_o and the rest on the receiver
    // at z_r, the receiver at t = z_r: μ = f·z_o + (1 − f)·z_r, σ² = f(1 − f)(z_r − z_o)²,
    // t − μ = f(z_r − z_o), so Chebyshev's bound is σ²/(σ² + (t − μ)²) = 1 − f, PCF's fraction.
    for (int k = 0; k <= 49; ++k) {
        std::vector<float> z(49, 0.7f);
        for (int i = 0; i < k; ++i) z[std::size_t(i)] = 0.3f;
        const Averages avg = average(z);
        // Float moments of values in [0, 1]: the variance's cancellation leaves about 1e-6.
        EXPECT_NEAR(vsmVisibility(avg.vsm, 0.7f, 0.0f, 0.0f), litFraction(z, 0.7f), 2e-5f) << k << " of 49";
    }
}

TEST(FilteredShadows, LightBleedingOfTwoOccludersGoesTheWayTheLectureSays) {
    // Two occluders over a receiver: half the kernel sees the upper one (z = 0.2), half the lower
    // (z = 0.7); the receiver at 0.8 is in full shadow. VSM's variance spans both occluders and
    // lets light through; its bleeding reduction cuts that, MSM's four moments much more. ESM:
    // exact far behind a single occluder, over-bright in contact with it.
    std::vector<float> z(50, 0.2f);
    for (std::size_t i = 25; i < z.size(); ++i) z[i] = 0.7f;
    const Averages avg = average(z);
    const float t = 0.8f;
    const float vsm = vsmVisibility(avg.vsm, t, 1e-6f, 0.0f);
    const float reduced = vsmVisibility(avg.vsm, t, 1e-6f, 0.4f);
    const float msm = msmVisibility(avg.msm, t, 3e-5f);
    const float evsm = evsmVisibility(avg.evsm, t, POS, NEG, 1e-6f, 0.0f);
    const Averages single = average(std::vector<float>(25, 0.5f));
    const float esmContact = esmVisibility(single.esmLog, ESM_C, 0.51f);
    const float esmFar = esmVisibility(single.esmLog, ESM_C, 0.8f);
    std::printf("light bleeding (truth 0): vsm %.4f, vsm with reduction 0.4 %.4f, evsm %.4f, msm %.4f; "
                "esm 0.01 behind an occluder %.4f, 0.3 behind %.6f\n",
                double(vsm), double(reduced), double(evsm), double(msm), double(esmContact), double(esmFar));
    EXPECT_GT(vsm, 0.2f);     // (0.0625)/(0.0625 + 0.35²) = 0.34
    EXPECT_EQ(reduced, 0.0f); // 0.34 is below the reduction's 0.4
    EXPECT_LT(msm, 0.5f * vsm);
    // Both occluders and the receiver lie inside [0, 1]: the Hausdorff bound leaks no more.
    EXPECT_LE(msmHausdorffVisibility(avg.msm, t, 3e-5f), msm + 1e-6f);
    EXPECT_LT(evsm, vsm);
    EXPECT_GT(esmContact, 0.4f); // exp(−80·0.01) = 0.45
    EXPECT_LT(esmFar, 1e-6f);    // exp(−80·0.3)
}

using MomentReconstruction = float (*)(vec4, float, float);

constexpr float MSM_ALPHAS[] = {6e-7f, 3e-6f, 1e-5f, 3e-5f, 1e-4f, 3e-4f};

/// Self-shadowing and light leaking of one reconstruction of the four moments per moment bias α
/// (MSM_ALPHAS) and offset (1e-4, 1e-3). The moment bias α smooths the reconstruction over a depth
/// scale of about √α, which works both ways. Acne: a receiver's own surface (a 5 × 5 kernel on a
/// slope) stored a little in front of where the receiver looks it up (t = z₀ + e, as rasterisation
/// and interpolation leave it): the truth is lit, a sharp bound darkens it. Leaking: a receiver at
/// distance d behind a flat occluder filling the kernel: the truth is 0, the smoothed bound lets
/// light through. Averages over random depths; printed as the tables in docs/methods.md.
struct BiasTrade {
    float acne[6][2] = {};
    float leak[6][2] = {};
};

BiasTrade msmBiasTrade(MomentReconstruction visibility, const char* name) {
    const float offsets[] = {1e-4f, 1e-3f}; // e and d, in normalised depth
    BiasTrade r;
    for (int ai = 0; ai < 6; ++ai) {
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        const int trials = 2000;
        for (int trial = 0; trial < trials; ++trial) {
            const float z0 = 0.05f + 0.9f * u(rng);
            const float slope = 1e-3f * u(rng);
            std::vector<float> surface;
            for (int i = 0; i < 25; ++i) surface.push_back(z0 + slope * float(i % 5 - 2));
            const Averages own = average(surface);
            const Averages occluder = average(std::vector<float>(25, 0.9f * z0));
            for (int k = 0; k < 2; ++k) {
                r.acne[ai][k] +=
                    (1.0f - visibility(own.msm, z0 + offsets[k], MSM_ALPHAS[ai])) / float(trials);
                r.leak[ai][k] +=
                    visibility(occluder.msm, 0.9f * z0 + offsets[k], MSM_ALPHAS[ai]) / float(trials);
            }
        }
        std::printf("%s msm_bias %-6g: self-shadowing at e = 1e-4 %.4f, 1e-3 %.4f; leaking at d = 1e-4 %.4f, "
                    "1e-3 %.4f\n",
                    name, double(MSM_ALPHAS[ai]), double(r.acne[ai][0]), double(r.acne[ai][1]),
                    double(r.leak[ai][0]), double(r.leak[ai][1]));
    }
    return r;
}

TEST(FilteredShadows, MsmBiasTradesLightLeakingForSelfShadowing) {
    const BiasTrade r = msmBiasTrade(msmVisibility, "msm");
    for (int ai = 1; ai < 6; ++ai) {
        for (int k = 0; k < 2; ++k) {
            EXPECT_LT(r.acne[ai][k], r.acne[ai - 1][k]) << "alpha " << MSM_ALPHAS[ai];
            EXPECT_GT(r.leak[ai][k], r.leak[ai - 1][k]) << "alpha " << MSM_ALPHAS[ai];
        }
    }
    // At the ends of the published range the trade is large: 50× the bias, several times the
    // leak one normalised millidepth behind an occluder, and a fraction of the self-shadowing.
    EXPECT_GT(r.leak[5][1], 5.0f * r.leak[0][1]);
    EXPECT_LT(r.acne[5][1], 0.5f * r.acne[0][1]);
}

TEST(FilteredShadows, MsmHausdorffLeaksLessThanHamburgerAndSelfShadowsMore) {
    // The Hausdorff bound is the larger shadow intensity of the same moments, so at every bias it
    // trades the other way from a larger bias: less leaking, more self-shadowing. The bias hardly
    // moves its self-shadowing (the four-point solution puts the bias's mass at 0 and 1 back where
    // it came from), and behind an occluder it leaks about half of what Hamburger does.
    const BiasTrade hamburger = msmBiasTrade(msmVisibility, "msm");
    const BiasTrade hausdorff = msmBiasTrade(msmHausdorffVisibility, "msm-hausdorff");
    for (int ai = 0; ai < 6; ++ai) {
        for (int k = 0; k < 2; ++k) {
            EXPECT_LE(hausdorff.leak[ai][k], hamburger.leak[ai][k]) << "alpha " << MSM_ALPHAS[ai];
            EXPECT_GE(hausdorff.acne[ai][k], hamburger.acne[ai][k]) << "alpha " << MSM_ALPHAS[ai];
        }
        // One normalised millidepth behind an occluder, from the 16-bit end of the published
        // range on (measured 0.49 to 0.59 of Hamburger's leak).
        if (MSM_ALPHAS[ai] >= 1e-5f) {
            EXPECT_LT(hausdorff.leak[ai][1], 0.7f * hamburger.leak[ai][1]) << "alpha " << MSM_ALPHAS[ai];
        }
    }
}

TEST(FilteredShadows, CsmDampingReducesTheRingingOfTheTruncatedSeries) {
    // One depth, receivers swept behind it from 0.05 on: the undamped series ripples around 0
    // (its Gibbs overshoot of 9 % of the jump sits closer to the jump); Lanczos' σ factors
    // bring the ripple down.
    const Averages avg = average({0.5f});
    float rawRipple = 0.0f, dampedRipple = 0.0f;
    for (float t = 0.55f; t <= 1.0f; t += 0.001f) {
        // Receivers behind the occluder by more than 1/(2M): the truth is 0 (shadow) there; before
        // the offset clamp, the series should be 0.
        float raw = 0.5f, damped = 0.5f;
        for (int k = 1; k <= TERMS; ++k) {
            raw +=
                csmTerm(avg.csmCos[std::size_t(k - 1)], avg.csmSin[std::size_t(k - 1)], t, k, TERMS, false);
            damped +=
                csmTerm(avg.csmCos[std::size_t(k - 1)], avg.csmSin[std::size_t(k - 1)], t, k, TERMS, true);
        }
        rawRipple = std::max(rawRipple, std::abs(raw));
        dampedRipple = std::max(dampedRipple, std::abs(damped));
    }
    std::printf("CSM, M = %d: largest |series| in the shadow: %.4f undamped, %.4f damped\n", TERMS,
                double(rawRipple), double(dampedRipple));
    EXPECT_GT(rawRipple, 0.03f); // measured 0.049
    EXPECT_LT(dampedRipple, 0.5f * rawRipple);
}

/// Box mean in double precision, the oracle.
double boxMean(const std::vector<float>& v, int w, int x0, int y0, int x1, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += double(v[std::size_t(y) * std::size_t(w) + std::size_t(x)]);
    return sum / (double(x1 - x0) * double(y1 - y0));
}

TEST(SummedArea, RectangleMeansMatchADoublePrecisionBoxFilterWithinTheFixedPointStep) {
    // A 1024 × 768 channel of moments near 1 with small variations (the hard case for float
    // sums: a far plane with a few blockers), and random rectangles from 1 × 1 to the whole.
    const int w = 1024, h = 768;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> values(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            values[std::size_t(y) * w + std::size_t(x)] =
                (x / 64 + y / 64) % 5 == 0 ? 0.3f + 0.01f * u(rng) : 0.999f + 0.001f * u(rng);
    const SummedAreaTable sat = buildSummedAreaTable(values.data(), w, h);
    // The same table in plain float sums, for comparison.
    std::vector<float> naive(std::size_t(w + 1) * std::size_t(h + 1), 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            naive[std::size_t(y + 1) * (w + 1) + std::size_t(x + 1)] =
                values[std::size_t(y) * w + std::size_t(x)] +
                naive[std::size_t(y) * (w + 1) + std::size_t(x + 1)] +
                naive[std::size_t(y + 1) * (w + 1) + std::size_t(x)] -
                naive[std::size_t(y) * (w + 1) + std::size_t(x)];
    double worst = 0.0, worstNaive = 0.0;
    for (int trial = 0; trial < 3000; ++trial) {
        const int side = trial % 4 == 0 ? 1 + int(u(rng) * 4.0f) : 1 + int(u(rng) * 200.0f);
        const int x0 = int(u(rng) * float(w - side)), y0 = int(u(rng) * float(h - side));
        const int x1 = x0 + side, y1 = y0 + side;
        const double truth = boxMean(values, w, x0, y0, x1, y1);
        const double got = sat.mean(x0, y0, x1, y1);
        // Each value rounded to 2⁻³² (mean off by at most 2⁻³³); the exact integer sum converted
        // to float, scaled by 2⁻³² (exact) and divided by the area in float, as a shader does it:
        // two roundings of 2⁻²⁴ of the mean.
        const double bound = std::ldexp(1.0, -33) + std::ldexp(std::abs(truth), -23);
        ASSERT_LE(std::abs(got - truth), bound) << side << "² at " << x0 << ", " << y0;
        worst = std::max(worst, std::abs(got - truth));
        const auto at = [&](int x, int y) { return naive[std::size_t(y) * (w + 1) + std::size_t(x)]; };
        const double naiveMean =
            double(at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0)) / (double(side) * double(side));
        worstNaive = std::max(worstNaive, std::abs(naiveMean - truth));
    }
    std::printf("summed-area means against double box filters: fixed point off by at most %.3g, "
                "plain float sums by %.3g\n",
                worst, worstNaive);
    // Clipping at the edges: the rectangle's part inside.
    EXPECT_NEAR(sat.mean(-5, -5, 3, 2), boxMean(values, w, 0, 0, 3, 2), 1e-6);
    EXPECT_EQ(sat.mean(10, 10, 10, 20), 0.0f);
}

TEST(MipPyramid, LevelsAreBlockMeansAndTrilinearMatchesTheBoxAtAlignedFootprints) {
    const int n = 256;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> values(std::size_t(n) * n);
    for (float& v : values) v = u(rng);
    const MipPyramid mip = buildMipPyramid(values.data(), n);
    ASSERT_EQ(mip.levels(), 9);
    for (int level = 1; level < 9; ++level) {
        const int block = 1 << level, size = n >> level;
        for (int j = 0; j < size; j += 7)
            for (int i = 0; i < size; i += 5) {
                const double truth =
                    boxMean(values, n, i * block, j * block, (i + 1) * block, (j + 1) * block);
                // Float means of 4 values per level, each exact to half an ulp of 1: level·2⁻²⁴.
                const float tol = float(level) * std::ldexp(1.0f, -23);
                EXPECT_NEAR(mip.at(level, i, j), truth, tol);
                // At the block's centre, a footprint of exactly the block reads that texel.
                const float uc = (float(i) + 0.5f) / float(size), vc = (float(j) + 0.5f) / float(size);
                EXPECT_NEAR(mip.trilinear(uc, vc, float(block)), truth, tol + 1e-6f);
            }
    }
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

TEST(FilteredShadows, MsmMovesWithTheRoundingOfItsDepths) {
    // Two maps of one scene whose depths differ only by rounding (the Vulkan rasteriser
    // interpolates a texel's depth, the CPU intersects its ray: floats an ulp or two apart) give
    // moments a few ulps apart. The Hankel matrix's last pivot d33 = b4 − b2² − l32²·d22 of a
    // kernel whose depths lie within about √α of each other (a receiver's own surface, one flat
    // occluder) is of the order of 10⁻⁸ to 10⁻⁷ there, while a float ulp of b4 and b2² (near z²,
    // up to 1) is 6·10⁻⁸: float rounding decides d33, and with it the roots and the result. One
    // ulp of change in the depths moves single results by tenths; on average by less, and less
    // the larger α (it lifts the pivots above the rounding). Kernels: 5 × 5 depths on a gentle
    // slope, a receiver on that surface up to 10⁻⁴ behind it, every depth moved by −1, 0 or +1
    // ulp at random.
    const float alphas[] = {6e-7f, 3e-6f, 3e-5f};
    float worst[3] = {}, mean[3] = {};
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int trials = 4000;
    for (int trial = 0; trial < trials; ++trial) {
        const float z0 = 0.05f + 0.9f * u(rng);
        const float slope = 2e-4f * u(rng);
        std::vector<float> a, b;
        for (int i = 0; i < 25; ++i) {
            const int column = i % 5, row = i / 5;
            const float z = z0 + slope * float(column - 2) + slope * 0.7f * float(row - 2);
            a.push_back(z);
            const float r = u(rng);
            b.push_back(r < 1.0f / 3.0f   ? std::nextafter(z, 0.0f)
                        : r < 2.0f / 3.0f ? z
                                          : std::nextafter(z, 2.0f));
        }
        const vec4 ma = average(a).msm, mb = average(b).msm;
        const float t = z0 + 1e-4f * u(rng);
        for (int ai = 0; ai < 3; ++ai) {
            const float d = std::abs(msmVisibility(ma, t, alphas[ai]) - msmVisibility(mb, t, alphas[ai]));
            worst[ai] = std::max(worst[ai], d);
            mean[ai] += d / float(trials);
        }
    }
    for (int ai = 0; ai < 3; ++ai)
        std::printf("msm_bias %-6g: |dv| from one-ulp depth changes: max %.4f, mean %.5f\n",
                    double(alphas[ai]), double(worst[ai]), double(mean[ai]));
    // At the default a single kernel moves by tenths (measured 0.51), the mean by under 1 %.
    EXPECT_GT(worst[0], 0.1f);
    EXPECT_LT(mean[0], 0.01f);
    // A larger bias halves the mean change and more (measured 0.0074, 0.0028, 0.0012).
    EXPECT_LT(mean[1], 0.5f * mean[0]);
    EXPECT_LT(mean[2], 0.5f * mean[1]);
}

} // namespace
} // namespace stsv
