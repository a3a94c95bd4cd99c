#include "shadowmaps/summed_area.h"

#include "core/error.h"
#include "core/parallel.h"
#include "shadowmaps/filtered_lookup.h"

#include <algorithm>

namespace stsv {

SummedAreaTable buildSummedAreaTable(const float* values, int width, int height) {
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw UsageError("summed-area table: size must be 1 … 16384 texels per side");
    SummedAreaTable t;
    t.width = width;
    t.height = height;
    const std::size_t stride = std::size_t(width) + 1;
    t.sums.assign(stride * (std::size_t(height) + 1), 0);
    // Rows in parallel (prefix sums along x), then columns (prefix sums along y): exact, so the
    // order does not matter.
    parallelFor(std::size_t(height), [&](std::size_t y) {
        std::int64_t run = 0;
        std::int64_t* row = t.sums.data() + (y + 1) * stride;
        const float* in = values + y * std::size_t(width);
        for (int x = 0; x < width; ++x) row[x + 1] = run += filteredFixed(in[x]);
    });
    parallelFor(std::size_t(width), [&](std::size_t x) {
        std::int64_t run = 0;
        for (int y = 1; y <= height; ++y) {
            std::int64_t& s = t.sums[std::size_t(y) * stride + x + 1];
            s = run += s;
        }
    });
    return t;
}

float SummedAreaTable::mean(int x0, int y0, int x1, int y1) const {
    const ivec2 lo = clamp(ivec2(x0, y0), ivec2(0), ivec2(width, height));
    const ivec2 hi = clamp(ivec2(x1, y1), ivec2(0), ivec2(width, height));
    if (hi.x <= lo.x || hi.y <= lo.y) return 0.0f;
    const FilteredSource source{this, nullptr};
    const std::int64_t sum = filteredSatSum(source, 0u, uint(width) + 1u, lo, hi);
    return float(sum) * (1.0f / 4294967296.0f) / (float(hi.x - lo.x) * float(hi.y - lo.y));
}

int MipPyramid::levels() const {
    return int(filteredMipLevels(uint(size)));
}

int MipPyramid::levelSize(int level) const {
    return int(filteredMipSize(uint(size), uint(level)));
}

float MipPyramid::at(int level, int x, int y) const {
    return texels[filteredMipOffset(uint(size), uint(level)) +
                  std::size_t(y) * std::size_t(levelSize(level)) + std::size_t(x)];
}

float MipPyramid::trilinear(float u, float v, float width) const {
    return filteredMipTrilinear(FilteredSource{nullptr, this}, 0u, uint(size), vec2(u, v), width, logSpace);
}

MipPyramid buildMipPyramid(const float* values, int size, bool logSpace) {
    if (size < 1 || size > 16384) throw UsageError("mip pyramid: size must be 1 … 16384 texels");
    MipPyramid m;
    m.size = size;
    m.logSpace = logSpace;
    m.texels.assign(filteredMipPlaneTexels(uint(size)), 0.0f);
    std::copy(values, values + std::size_t(size) * std::size_t(size), m.texels.begin());
    const FilteredSource source{nullptr, &m};
    for (uint level = 1; level < filteredMipLevels(uint(size)); ++level) {
        const uint n = filteredMipSize(uint(size), level), base = filteredMipOffset(uint(size), level);
        parallelFor(std::size_t(n), [&](std::size_t y) {
            for (uint x = 0; x < n; ++x)
                m.texels[base + uint(y) * n + x] =
                    filteredMipDownsample(source, 0u, uint(size), level, uvec2(x, uint(y)), logSpace);
        });
    }
    return m;
}

} // namespace stsv
