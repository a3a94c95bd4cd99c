// The shadow-map family's knobs in world units (DESIGN §4.6): the kernels given in metres at the
// receiver (pcf_world_radius, fm_world_radius) and PCSS's penumbra, which follows from the light
// and the depths, keep their world width when the map's texels change, so a setting means the
// same at any sm_size and fit; and at their defaults every image-based method makes the penumbra
// of the parallel planes of DESIGN §6 within a bound stated with its reason (scenes that no
// default was tuned on).
#include "shadowmaps/shadow_map.h"
#include "tests/render/parallel_planes.h"
#include "tests/render/shadow_map_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <utility>
#include <vector>

namespace stsv {
namespace {

using namespace test;

/// msm-hausdorff: an image-family variant with no name of its own in the Method enum.
const Method MSM_HAUSDORFF = imageMethod(ShadowMapMethod(SHADOW_FILTER_MSM_HAUSDORFF));

/// The frame's map texel on the visible receivers (the ground; its stats' median).
double frameTexel(const Frame& f) {
    return f.stats["shadow_maps"][0]["texel_world_median"].get<double>();
}

TEST(ShadowMapUnits, PcfAndPcssPenumbraeKeepTheirWorldWidthAcrossMapSizes) {
    // The occluder at h_o = 1.5 (W = 0.6 m) and the maps fitted to the view (the default): the
    // camera under the occluder sees ±0.45 m of ground, so the map holds only the occluder above
    // it and its texels are under a millimetre on the ground at 2048², 0.8 pixel columns of 3.5 mm.
    const Scene scene = parallelPlanes(1.5f);
    const double W = penumbraWidth(1.5f);
    for (const Method m : {Method::Pcf, Method::Pcss}) {
        const char* name = methodInfo(m).name.c_str();
        // PCF: a kernel of 2 cm either side, 13 texels at 1024², 26 at 2048² (its taps spread
        // beyond pcf_max_radius there, keeping the width); its 5 %…95 % width on a hard edge is
        // 0.9 of the kernel's 4 cm.
        const MethodParams base =
            m == Method::Pcf ? MethodParams{{"pcf_world_radius", 0.02}} : MethodParams{};
        MethodParams coarse = base, fine = base;
        coarse["sm_size"] = 1024.0;
        fine["sm_size"] = 2048.0;
        const Frame fc = renderCpu(scene, m, WIDTH, HEIGHT, coarse, 64, 3u);
        const Frame ff = renderCpu(scene, m, WIDTH, HEIGHT, fine, 64, 3u);
        const double texel = frameTexel(fc);
        const double wc = measuredWidth(columnProfile(fc)), wf = measuredWidth(columnProfile(ff));
        const double expected = m == Method::Pcf ? (HIGH - LOW) * 2.0 * 0.02 : diskLevelWidth(W);
        std::printf("%s: 5-95 %% width %.4f m at 1024^2 (texel %.5f m), %.4f m at 2048^2 (texel %.5f m); "
                    "expected %.4f\n",
                    name, wc, texel, wf, frameTexel(ff), expected);
        ASSERT_FALSE(std::isnan(wc) || std::isnan(wf)) << name;
        // The two texel sizes differ by 2: a kernel counted in texels would halve its width.
        EXPECT_NEAR(frameTexel(ff), 0.5 * texel, 0.01 * texel) << name;
        // Within a texel of the coarser map, plus a pixel column (3.5 mm: where the profile's
        // crossing falls between columns).
        EXPECT_NEAR(wf, wc, texel + 0.0035) << name;
        // And the width is the world one asked for (PCF) or estimated (PCSS: the disk kernel of
        // W): within two texels of the coarser map and a column.
        EXPECT_NEAR(wc, expected, 2.0 * texel + 0.0035) << name;
        EXPECT_NEAR(wf, expected, 2.0 * texel + 0.0035) << name;
        // Nothing bounded the kernels at 1024² (PCF's 12 texels either side are within
        // pcf_max_radius; PCSS's search and filter within pcss_max_search and pcss_max_kernel).
        const nlohmann::json& stats = fc.stats["shadow_maps"][0];
        if (m == Method::Pcf) {
            EXPECT_EQ(stats["kernel_strided_pixels"].get<std::uint64_t>(), 0u) << name;
        } else {
            EXPECT_EQ(stats["kernel_clamped_pixels"].get<std::uint64_t>(), 0u) << name;
            EXPECT_EQ(stats["search_clamped_pixels"].get<std::uint64_t>(), 0u) << name;
        }
    }
}

/// Two occluders at different heights over the ground of parallelPlanes, their edges apart: a
/// low one at 0.5 m over x < −0.2 (penumbra 1/7 m centred on x = −0.229) and a high one at 1 m
/// over x > 0.15 (penumbra 1/3 m centred on x = 0.2). Each receiver's blocker search (the light
/// seen through the map's near plane, the high occluder's depth) spans at most ±0.17 m of the
/// ground's projection, so no penumbra's search finds the other occluder: each is the single edge
/// at its own depth, in one map whose depth range holds both.
Scene twoOccluders() {
    Scene s;
    s.source = "parallel-planes-two-occluders";
    s.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    s.materials.push_back({"occluder", vec3(0.5f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(s, 0.0f, -2.0f, 2.0f, -2.0f, 2.0f, 0);
    addHorizontalQuad(s, 0.5f, -1.2f, -0.2f, -1.0f, 1.0f, 1);
    addHorizontalQuad(s, 1.0f, 0.15f, 1.15f, -1.0f, 1.0f, 1);
    const Scene one = parallelPlanes(0.5f);
    s.lights = one.lights;
    s.camera = one.camera;
    return s;
}

/// The occluders of parallelPlanes(h) or twoOccluders() as closed slabs: each quad's underside
/// 1 cm below it, facing down (the sides stand edge-on to the light's centre). peel assumes closed
/// objects: behind a lone face towards the light it counts everything as shadowed, so a lone
/// quad shadows as a slab reaching to the ground. A ray through the slab's side below its top
/// edge goes on to meet its underside: the shadow is the top edge's, the analytic ramp's.
void addUnderside(Scene& s, float y, float x0, float x1, float z0, float z1) {
    const vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
    s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), 1);
    s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), 1);
}
Scene closedParallelPlanes(float occluderHeight) {
    Scene s = parallelPlanes(occluderHeight);
    addUnderside(s, occluderHeight - 0.01f, -1.0f, 0.0f, -1.0f, 1.0f);
    return s;
}
Scene closedTwoOccluders() {
    Scene s = twoOccluders();
    addUnderside(s, 0.49f, -1.2f, -0.2f, -1.0f, 1.0f);
    addUnderside(s, 0.99f, 0.15f, 1.15f, -1.0f, 1.0f);
    return s;
}

/// The analytic visibility of twoOccluders(): the square light's linear ramp under each edge
/// (the shadows hide disjoint parts of the light, and the penumbrae do not meet).
double twoOccludersRamp(double x) {
    const double low = linearRamp(x - (-0.2 * LIGHT_HEIGHT / (LIGHT_HEIGHT - 0.5)), penumbraWidth(0.5f));
    const double high = linearRamp(0.15 * LIGHT_HEIGHT / (LIGHT_HEIGHT - 1.0) - x, penumbraWidth(1.0f));
    return std::clamp(low + high - 1.0, 0.0, 1.0);
}

/// RMSE of the profile against `expected` over the columns within 0.75·W of a penumbra's centre
/// (the penumbrae and a quarter of their width beyond each side: a penumbra too wide or too
/// narrow counts).
template <typename F>
double penumbraRmse(const Profile& p, F expected, const std::vector<std::pair<double, double>>& penumbrae) {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < p.x.size(); ++i)
        for (const auto& [centre, width] : penumbrae)
            if (std::abs(p.x[i] - centre) < 0.75 * width) {
                const double e = p.v[i] - expected(p.x[i]);
                sum += e * e;
                ++n;
                break;
            }
    return n ? std::sqrt(sum / n) : std::nan("");
}

TEST(ShadowMapDefaults, EveryImageBasedMethodMakesTheParallelPlanesPenumbraAtItsDefaults) {
    // Every knob at its default but sm_size = 1024 (csm's 32 summed-area tables at 2048² need
    // over a gigabyte; the kernels are in world units, and the test above holds the widths
    // across map sizes).
    const MethodParams params = {{"sm_size", 1024.0}};
    const double widthOne = penumbraWidth(1.5f);
    struct Case {
        const char* name;
        Scene scene;
        Scene closed; ///< the occluders as closed slabs (for peel)
        std::function<double(double)> truth;
        std::vector<std::pair<double, double>> penumbrae; ///< (centre, width) on the ground
    };
    const std::vector<Case> cases = {
        {"one occluder at 1.5 m",
         parallelPlanes(1.5f),
         closedParallelPlanes(1.5f),
         [&](double x) { return linearRamp(x, widthOne); },
         {{0.0, widthOne}}},
        {"two occluders at 0.5 m and 1 m",
         twoOccluders(),
         closedTwoOccluders(),
         twoOccludersRamp,
         {{-0.2 * LIGHT_HEIGHT / (LIGHT_HEIGHT - 0.5), penumbraWidth(0.5f)},
          {0.15 * LIGHT_HEIGHT / (LIGHT_HEIGHT - 1.0), penumbraWidth(1.0f)}}},
    };
    const ShadowMapSettings defaults = defaultShadowMapSettings(ShadowMapMethod::Pcf);
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        // PCF's fixed kernel (pcf_world_radius either side) makes a ramp of its own width under
        // each edge: its error is that ramp's against the analytic one, computed here.
        const double rho = defaults.pcfWorldRadius;
        const auto pcfRamp = [&](double x) {
            double v = 1.0;
            for (const auto& [centre, width] : c.penumbrae) {
                // Which side is lit: the truth's slope at the centre.
                const bool rising = c.truth(centre + 0.25 * width) > c.truth(centre - 0.25 * width);
                v = std::min(v, linearRamp(rising ? x - centre : centre - x, 2.0 * rho));
            }
            return v;
        };
        std::map<Method, double> error;
        for (const Method m : {Method::Pcf, Method::Pcss, Method::Vsm, Method::Esm, Method::Evsm, Method::Msm,
                               MSM_HAUSDORFF, Method::Csm}) {
            const Frame f = renderCpu(c.scene, m, WIDTH, HEIGHT, params, 64, 3u);
            const Profile p = columnProfile(f);
            error[m] = penumbraRmse(p, c.truth, c.penumbrae);
            std::printf("%s, %s: penumbra RMSE %.4f against the analytic ramp\n", c.name,
                        methodInfo(m).name.c_str(), error[m]);
            if (m == Method::Pcf) {
                const double expected = penumbraRmse(Profile{p.x,
                                                             [&] {
                                                                 std::vector<double> v;
                                                                 for (const double x : p.x)
                                                                     v.push_back(pcfRamp(x));
                                                                 return v;
                                                             }()},
                                                     c.truth, c.penumbrae);
                std::printf("  pcf's own ramp of %.3f m against the analytic one: %.4f\n", 2.0 * rho,
                            expected);
                // The texel staircase and the strided taps: 0.02.
                EXPECT_NEAR(error[m], expected, 0.02);
            }
        }
        // PCSS filters the centre's hard shadow with a disk of the penumbra's width: its profile
        // is the disk segment, up to 0.058 from the linear ramp (PcssParallelPlanes), 0.035 RMS
        // over these columns; 0.05 with the 128 rotated taps' noise.
        EXPECT_LT(error[Method::Pcss], 0.05);
        // The filtered representations average a box of the width PCSS estimates: on one occluder
        // plane over one receiver plane a box over the hard edge is the linear ramp itself. MSM
        // (a summed-area table, two depths: exact) is left with the half-texel rounding of the box
        // and the search's tap noise (measured 0.003): 0.02. VSM reads mips at its defaults, as
        // ESM and EVSM always do: 4 × 4 bilinear taps of a level whose texels are up to a cell wide
        // round the ramp's ends (measured 0.007 to 0.011 for the three): 0.02 for VSM, 0.04 for
        // the exponential warps. CSM's 16 damped terms smooth the step: 0.03.
        EXPECT_LT(error[Method::Vsm], 0.02);
        EXPECT_LT(error[Method::Msm], 0.02);
        // The Hausdorff reconstruction of the same moments: two depths inside [0, 1], the same bound.
        EXPECT_LT(error[MSM_HAUSDORFF], 0.02);
        EXPECT_LT(error[Method::Csm], 0.03);
        EXPECT_LT(error[Method::Esm], 0.04);
        EXPECT_LT(error[Method::Evsm], 0.04);
        // ESM reduces to a box filter here, as VSM does: within a factor of 3 of it (and no worse
        // than 0.01 beyond: VSM's own error can be near zero).
        EXPECT_LT(error[Method::Esm], 3.0 * error[Method::Vsm] + 0.01);

        // The grid and the transmittance functions, every knob at its default (their own sizes).
        for (const Method m : {Method::Peel, Method::Avsm, Method::Vpcss}) {
            const Scene& scene = m == Method::Peel ? c.closed : c.scene;
            error[m] = penumbraRmse(columnProfile(renderCpu(scene, m, WIDTH, HEIGHT, {}, 64, 3u)), c.truth,
                                    c.penumbrae);
            std::printf("%s, %s: penumbra RMSE %.4f against the analytic ramp\n", c.name,
                        methodInfo(m).name.c_str(), error[m]);
        }
        // peel marches each light sample's ray through the depth grid of the closed slabs: the
        // reference's answer but where a ray's crossing of the occluder's edge falls within a grid
        // texel of it, and the 64 samples' noise averaged over the 32 rows.
        EXPECT_LT(error[Method::Peel], 0.02);
        // The lone quads: every ray under an occluder in the light centre's view counts as blocked
        // (the documented limitation), a penumbra cut on its lit side: far beyond the slabs'.
        const double open = penumbraRmse(
            columnProfile(renderCpu(c.scene, Method::Peel, WIDTH, HEIGHT, {}, 64, 3u)), c.truth, c.penumbrae);
        std::printf("%s, peel on the lone quads: penumbra RMSE %.4f\n", c.name, open);
        EXPECT_GT(open, 3.0 * error[Method::Peel]);
        // AVSM looks its functions up from the light's centre: a hard shadow. Against a linear
        // ramp of width W, a step at its centre errs by ½ − |x|/W over the penumbra, an RMSE of
        // 1/√18 = 0.236 over the columns counted (1.5·W wide): its limitation, held both ways.
        EXPECT_NEAR(error[Method::Avsm], 1.0 / std::sqrt(18.0), 0.02);
        // vpcss is PCSS on the functions (opaque blockers have transmittance 0): PCSS's bound.
        EXPECT_LT(error[Method::Vpcss], 0.05);
    }
}

} // namespace
} // namespace stsv
