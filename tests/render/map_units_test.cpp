// The shadow-map family's knobs in world units (DESIGN §4.6): the kernels given in metres at the
// receiver (pcf_world_radius, fm_world_radius) and PCSS's penumbra, which follows from the light
// and the depths, keep their world width when the map's texels change, so a setting means the
// same at any sm_size and fit; and at their defaults every depth-map method makes a penumbra on
// the parallel planes of DESIGN §6.
#include "shadowmaps/shadow_map.h"
#include "tests/render/parallel_planes.h"
#include "tests/render/shadow_map_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace stsv {
namespace {

using namespace test;

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
        // PCF: a kernel of 2 cm either side, 12 texels at 1024², 25 at 2048² (its taps spread
        // beyond pcf_max_radius 16 there, keeping the width); its 5 %…95 % width on a hard edge
        // is 0.9 of the kernel's 4 cm.
        const MethodParams base =
            m == Method::Pcf ? MethodParams{{"pcf_world_radius", 0.02}} : MethodParams{};
        MethodParams coarse = base, fine = base;
        coarse["sm_size"] = 1024.0;
        fine["sm_size"] = 2048.0;
        const Frame fc = renderCpu(scene, m, kW, kH, coarse, 64, 3u);
        const Frame ff = renderCpu(scene, m, kW, kH, fine, 64, 3u);
        const double texel = frameTexel(fc);
        const double wc = measuredWidth(columnProfile(fc)), wf = measuredWidth(columnProfile(ff));
        const double expected = m == Method::Pcf ? (kHigh - kLow) * 2.0 * 0.02 : diskLevelWidth(W);
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
        EXPECT_EQ(fc.stats["shadow_maps"][0]["kernel_clamped_pixels"].get<std::uint64_t>(), 0u) << name;
    }
}

} // namespace
} // namespace stsv
