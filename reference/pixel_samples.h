// The light samples of one pixel: identical for every method (DESIGN §4.1), so methods can
// be compared sample by sample.
#pragma once

#include "sampling/light_sampling_dh.h"
#include "sampling/pattern.h"

namespace stsv {

/// Frame-domain point (a, b) of sample k of pixel (x, y): the pattern point of the pixel's
/// interleaved set, decorrelated per pixel, mapped to the frame's domain.
inline vec2 pixelSamplePoint(const SamplePlan& plan, int x, int y, int k, uint domain) {
    const vec2 u = plan.points[std::size_t(plan.setIndex(x, y)) * plan.count + k];
    return samplePoint(u, uvec2(uint(x), uint(y)), plan.seed, plan.decorrelate, domain);
}

} // namespace stsv
