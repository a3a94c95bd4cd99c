// Helpers of the image-based baselines' rendering tests: CPU frames of one method, visibility
// comparisons over a pixel mask and the converged reference (tests/failure_images.h writes the
// images a failed comparison leaves behind).
#pragma once

#include "core/image.h"
#include "render/cpu/cpu_renderer.h"
#include "render/options.h"
#include "tests/failure_images.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>

namespace stsv::test {

/// A CPU frame of `method` at w × h with the given knobs (the rest at their defaults).
inline Frame renderCpu(const Scene& scene, Method method, int w, int h, const MethodParams& params = {},
                       int samples = 64, std::uint32_t seed = 1) {
    RenderOptions o;
    o.method = method;
    o.backend = Backend::Cpu;
    o.width = w;
    o.height = h;
    o.samples = samples;
    o.seed = seed;
    o.params = params;
    return makeCpuRenderer(scene, o)->render();
}

/// The reference's visibility averaged over `seeds` frames of `samples` samples each (DESIGN §4.6:
/// the converged reference, K seeds × N samples). Also returns the last frame's G-buffer.
inline ImageF convergedReference(const Scene& scene, int w, int h, int seeds, int samples,
                                 GBuffer* gbuffer = nullptr) {
    ImageF sum(w, h, 1);
    for (int k = 0; k < seeds; ++k) {
        const Frame f = renderCpu(scene, Method::Reference, w, h, {}, samples, std::uint32_t(101 + k));
        for (std::size_t i = 0; i < sum.pixels.size(); ++i)
            sum.pixels[i] += f.visibility.pixels[i] / float(seeds);
        if (gbuffer && k == seeds - 1) *gbuffer = f.gbuffer;
    }
    return sum;
}

using PixelMask = std::function<bool(int x, int y)>;

struct VisibilityDiff {
    double rmse = 0.0;
    double maxAbs = 0.0;
    double meanSigned = 0.0; ///< mean of actual − expected
    std::size_t pixels = 0;
};

/// RMSE, largest and mean difference of two one-channel images over the pixels of `mask`.
inline VisibilityDiff compareVisibility(const ImageF& actual, const ImageF& expected, const PixelMask& mask) {
    VisibilityDiff d;
    double sum2 = 0.0, sum = 0.0;
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            if (!mask(x, y)) continue;
            const double e = double(actual.at(x, y, 0)) - double(expected.at(x, y, 0));
            sum2 += e * e;
            sum += e;
            d.maxAbs = std::max(d.maxAbs, std::abs(e));
            ++d.pixels;
        }
    if (d.pixels) {
        d.rmse = std::sqrt(sum2 / double(d.pixels));
        d.meanSigned = sum / double(d.pixels);
    }
    return d;
}

} // namespace stsv::test
