#include "shadowmaps/summed_area.h"

#include "core/error.h"
#include "core/parallel.h"
#include "shadowmaps/filtered_shadow_dh.h"

#include <algorithm>
#include <cmath>

namespace stsv {

std::int64_t summedAreaFixed(float value) {
    const double v = std::clamp(double(value), -1.0, 1.0);
    return std::int64_t(std::llround(v * SUMMED_AREA_ONE));
}

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
        for (int x = 0; x < width; ++x) row[x + 1] = run += summedAreaFixed(in[x]);
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
    x0 = std::clamp(x0, 0, width);
    x1 = std::clamp(x1, 0, width);
    y0 = std::clamp(y0, 0, height);
    y1 = std::clamp(y1, 0, height);
    if (x1 <= x0 || y1 <= y0) return 0.0f;
    const std::size_t stride = std::size_t(width) + 1;
    const auto at = [&](int x, int y) { return sums[std::size_t(y) * stride + std::size_t(x)]; };
    const std::int64_t sum = at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
    const double area = double(x1 - x0) * double(y1 - y0);
    return float(double(sum) / (SUMMED_AREA_ONE * area));
}

namespace {

/// The weighted mean of four values, or of their exponentials in log space.
float blend4(bool logSpace, vec4 values, vec4 weights) {
    return logSpace ? esmLogSum4(values, weights) : dot(values, weights);
}

} // namespace

MipPyramid buildMipPyramid(const float* values, int size, bool logSpace) {
    if (size < 1 || size > 16384) throw UsageError("mip pyramid: size must be 1 … 16384 texels");
    MipPyramid m;
    m.logSpace = logSpace;
    m.sizes.push_back(size);
    m.levels.emplace_back(values, values + std::size_t(size) * std::size_t(size));
    while (m.sizes.back() > 1) {
        const int from = m.sizes.back(), to = (from + 1) / 2;
        const std::vector<float>& src = m.levels.back();
        std::vector<float> dst(std::size_t(to) * std::size_t(to));
        parallelFor(std::size_t(to), [&](std::size_t y) {
            for (int x = 0; x < to; ++x) {
                vec4 block(0.0f), inside(0.0f);
                for (int k = 0; k < 4; ++k) {
                    const int sx = 2 * x + (k & 1), sy = 2 * int(y) + (k >> 1);
                    if (sx >= from || sy >= from) continue;
                    block[k] = src[std::size_t(sy) * std::size_t(from) + std::size_t(sx)];
                    inside[k] = 1.0f;
                }
                const float n = inside.x + inside.y + inside.z + inside.w;
                dst[y * std::size_t(to) + std::size_t(x)] = blend4(logSpace, block, inside / n);
            }
        });
        m.sizes.push_back(to);
        m.levels.push_back(std::move(dst));
    }
    return m;
}

float MipPyramid::bilinear(int level, float u, float v) const {
    level = std::clamp(level, 0, int(levels.size()) - 1);
    const int n = sizes[std::size_t(level)];
    const std::vector<float>& l = levels[std::size_t(level)];
    const float x = u * float(n) - 0.5f, y = v * float(n) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const auto at = [&](int i, int j) {
        i = std::clamp(i, 0, n - 1);
        j = std::clamp(j, 0, n - 1);
        return l[std::size_t(j) * std::size_t(n) + std::size_t(i)];
    };
    const int ix = int(fx), iy = int(fy);
    return blend4(logSpace, vec4(at(ix, iy), at(ix + 1, iy), at(ix, iy + 1), at(ix + 1, iy + 1)),
                  vec4((1.0f - ax) * (1.0f - ay), ax * (1.0f - ay), (1.0f - ax) * ay, ax * ay));
}

float MipPyramid::trilinear(float u, float v, float width) const {
    const float lod = std::clamp(std::log2(std::max(width, 1.0f)), 0.0f, float(levels.size() - 1));
    const int lo = int(std::floor(lod));
    const float f = lod - float(lo);
    const float a = bilinear(lo, u, v);
    if (!(f > 0.0f)) return a;
    return blend4(logSpace, vec4(a, bilinear(lo + 1, u, v), 0.0f, 0.0f), vec4(1.0f - f, f, 0.0f, 0.0f));
}

} // namespace stsv
