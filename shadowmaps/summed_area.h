// Box filters of a map channel in O(1) per lookup (DESIGN §4.6): a summed-area table (Crow 1984)
// and a mip pyramid, the host storage of the planes filtered_lookup_dh.h reads. The filtered
// shadow maps (filtered_shadow_dh.h) average their channels over a rectangle with either.
//
// Precision: a summed-area table of 32-bit floats loses the small values it adds to large running
// sums (a 2048² face of values near 1 sums to 4·10⁶, where a float's step is 0.25), and a
// rectangle's mean is the difference of four such sums, so a small kernel's mean can be off by
// 0.1 — enough to wreck a variance of 10⁻⁶. This table holds 64-bit fixed-point integers instead:
// each value in [−1, 1] is rounded to a multiple of 2⁻³² (filteredFixed) and the sums are exact
// (integer addition is associative, so any order, CPU or GPU, gives the same table). A rectangle's
// mean is then off by at most 2⁻³³ (the rounding of its values) plus the float conversion of the
// result (2⁻²⁴ of it). A face of up to 16384² values of magnitude ≤ 1 sums to at most 2⁶⁰.
#pragma once

#include <cstdint>
#include <vector>

namespace stsv {

/// The summed-area table of one width × height channel (row-major): sums[(y + 1)·(width + 1) +
/// x + 1] = Σ of the fixed-point values over [0, x] × [0, y]; row 0 and column 0 are zero.
struct SummedAreaTable {
    int width = 0;
    int height = 0;
    std::vector<std::int64_t> sums;

    /// Mean of the values over texels [x0, x1) × [y0, y1), clipped to the channel; 0 for an empty
    /// rectangle.
    float mean(int x0, int y0, int x1, int y1) const;
};

SummedAreaTable buildSummedAreaTable(const float* values, int width, int height);

/// A mip pyramid of one square channel, its levels one after another (filteredMipOffset): level 0
/// the values, level l + 1 the mean of each 2 × 2 block of level l (at an odd size, the last row
/// and column average the texels that exist). Float sums of four values: a level-l texel is the
/// mean of its 2ˡ × 2ˡ block to within l·2⁻²⁴ of the largest magnitude.
struct MipPyramid {
    int size = 0;
    /// The values are logarithms (ESM's c·z) and every mean is taken of their exponentials,
    /// log Σ wᵢ·exp(lᵢ) (esmLogSum4), so no exponential is ever formed.
    bool logSpace = false;
    std::vector<float> texels;

    int levels() const;
    int levelSize(int level) const;
    float at(int level, int x, int y) const;
    /// Trilinear average over a square footprint `width` texels (level-0 units) wide centred at
    /// (u, v) ∈ [0, 1]²: bilinear in the two levels whose texels bracket the width, blended by
    /// log₂ of the width. Clamped at the edges.
    float trilinear(float u, float v, float width) const;
};

MipPyramid buildMipPyramid(const float* values, int size, bool logSpace = false);

} // namespace stsv
