// The texel rule shared by every method (volumes/stsv_dh.h: texelAt, alphaBlocks): nearest texel
// of mip 0, repeat or clamp, exact integer results.
#include "tests/support/extreme_floats.h"
#include "volume_test_util.h"
#include "volumes/stsv_dh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace stsv {
namespace {

std::int64_t repeatIndex(std::int64_t k, std::int64_t size) {
    return ((k % size) + size) % size;
}
std::int64_t clampIndex(std::int64_t k, std::int64_t size) {
    return std::min(std::max<std::int64_t>(k, 0), size - 1);
}

const int SIZES[] = {1, 2, 3, 4, 5, 7, 8, 16, 100, 255, 256, 1000, 1024, 4096};

TEST(Texel, CentresMapToTheirTexel) {
    // uv at texel centres (k + ½)/size, k over three periods either side of 0: far from any rounding.
    for (int sx : SIZES) {
        const int sy = 3 * sx + 1; // a different size on the other axis
        for (int k = -3 * sx; k < 3 * sx; ++k) {
            const int ky = (k * 7) % (3 * sy);
            const vec2 uv(float((k + 0.5) / sx), float((ky + 0.5) / sy));
            const ivec2 rep = texelAt(uv, ivec2(sx, sy), WRAP_REPEAT);
            const ivec2 cla = texelAt(uv, ivec2(sx, sy), WRAP_CLAMP);
            ASSERT_EQ(rep.x, repeatIndex(k, sx)) << "size " << sx << " k=" << k;
            ASSERT_EQ(rep.y, repeatIndex(ky, sy)) << "size " << sy << " k=" << ky;
            ASSERT_EQ(cla.x, clampIndex(k, sx)) << "size " << sx << " k=" << k;
            ASSERT_EQ(cla.y, clampIndex(ky, sy)) << "size " << sy << " k=" << ky;
        }
    }
}

TEST(Texel, ExactBoundariesBelongToTheTexelStartingThere) {
    // Power-of-two sizes: uv = k/size is exact, so the boundary texel is exactly k (floor rule:
    // [k, k+1)·size⁻¹ is texel k), including negative k and uv = 1 (wraps to 0, clamps to size − 1).
    for (int s : {1, 2, 4, 8, 16, 256, 1024, 4096}) {
        for (int k = -3 * s; k <= 3 * s; ++k) {
            const float u = float(k) / float(s); // exact
            ASSERT_EQ(texelAt(vec2(u, u), ivec2(s), WRAP_REPEAT), ivec2(int(repeatIndex(k, s))))
                << "s=" << s << " k=" << k;
            ASSERT_EQ(texelAt(vec2(u, u), ivec2(s), WRAP_CLAMP), ivec2(int(clampIndex(k, s))))
                << "s=" << s << " k=" << k;
        }
    }
    EXPECT_EQ(texelAt(vec2(1.0f, 0.0f), ivec2(4, 4), WRAP_REPEAT), ivec2(0, 0));
    EXPECT_EQ(texelAt(vec2(1.0f, 0.0f), ivec2(4, 4), WRAP_CLAMP), ivec2(3, 0));
    EXPECT_EQ(texelAt(vec2(-0.0f, -0.25f), ivec2(4, 4), WRAP_REPEAT), ivec2(0, 3));
    EXPECT_EQ(texelAt(vec2(-1e-9f, -0.25f), ivec2(4, 4), WRAP_REPEAT), ivec2(3, 3));
    EXPECT_EQ(texelAt(vec2(-1e-9f, -0.25f), ivec2(4, 4), WRAP_CLAMP), ivec2(0, 0));
}

TEST(Texel, InexactBoundariesPickANeighbour) {
    // Other sizes: k/size rounds to float, so the boundary may land on either side — never further.
    for (int s : {3, 5, 7, 100, 255, 1000}) {
        for (int k = -3 * s; k <= 3 * s; ++k) {
            const float u = float(double(k) / s);
            const ivec2 t = texelAt(vec2(u, u), ivec2(s), WRAP_REPEAT);
            EXPECT_TRUE(t.x == repeatIndex(k, s) || t.x == repeatIndex(k - 1, s)) << "s=" << s << " k=" << k;
            EXPECT_EQ(t.x, t.y);
        }
    }
}

TEST(Texel, LargeCoordinatesStayInRange) {
    // Exact where float holds the texel index exactly (|uv·size| < 2²¹ with uv a quarter texel from
    // any boundary), and always a valid index — also beyond 2²⁴ where texel spacing exceeds one
    // float ulp and beyond 2³¹ where an int would overflow.
    test::Rng rng(11);
    for (int s : {3, 5, 7, 100, 1000, 1024, 4096}) {
        for (int i = 0; i < 20000; ++i) {
            const double mag = std::pow(10.0, rng.uniform(0.0, 12.0));
            const double k = std::floor(rng.uniform(-mag, mag));
            const vec2 uv(float((k + rng.uniform(0.25, 0.75)) / s), float(-(k + 0.5) / s));
            for (uint wrap : {WRAP_REPEAT, WRAP_CLAMP}) {
                const ivec2 t = texelAt(uv, ivec2(s), wrap);
                ASSERT_TRUE(t.x >= 0 && t.x < s && t.y >= 0 && t.y < s)
                    << "texel " << t.x << "," << t.y << " out of range; size " << s
                    << " uv=" << glm::to_string(uv);
                if (std::abs(k) < double(1 << 21)) {
                    const auto kk = std::int64_t(k);
                    ASSERT_EQ(t.x, wrap == WRAP_REPEAT ? repeatIndex(kk, s) : clampIndex(kk, s))
                        << "size " << s << " k=" << k << " uv=" << glm::to_string(uv);
                }
            }
        }
    }
    EXPECT_EQ(texelAt(vec2(1e12f, -1e12f), ivec2(16, 16), WRAP_CLAMP), ivec2(15, 0));
    EXPECT_EQ(texelAt(vec2(3e38f, -3e38f), ivec2(16, 16), WRAP_CLAMP), ivec2(15, 0));
}

/// The rule as its comment states it, in double and 64-bit integers: floor of the float product
/// coord·size; NaN → 0; beyond ±2^24 (infinity included) → ±2^24; then wrapped or clamped.
std::int64_t statedIndex(float coord, int size, uint wrap) {
    const double index = std::floor(double(coord * float(size)));
    std::int64_t k = 0;
    if (!std::isnan(index)) k = std::int64_t(std::clamp(index, -16777216.0, 16777216.0));
    return wrap == WRAP_CLAMP ? clampIndex(k, size) : repeatIndex(k, size);
}

TEST(Texel, EveryFloatGivesATexelInsideTheTexture) {
    // Totality: NaNs of either sign and any payload, infinities, finite coordinates whose product
    // with the size overflows (1e38·256), subnormals and ±0, and random bit patterns; each axis is
    // the stated rule, so both backends, which compute the same float product, agree.
    std::vector<float> values = test::extremeFloats();
    const std::vector<float> random = test::randomBitFloats(200000, 49);
    values.insert(values.end(), random.begin(), random.end());
    for (int s : {1, 2, 3, 7, 16, 256, 1000, 4096, 8192}) {
        for (uint wrap : {WRAP_REPEAT, WRAP_CLAMP}) {
            for (std::size_t i = 0; i < values.size(); ++i) {
                const float u = values[i];
                const float v = values[values.size() - 1 - i];
                const ivec2 t = texelAt(vec2(u, v), ivec2(s, s + 1), wrap);
                ASSERT_TRUE(t.x >= 0 && t.x < s && t.y >= 0 && t.y < s + 1)
                    << "texel " << t.x << "," << t.y << " outside " << s << "x" << s + 1 << " for uv bits "
                    << std::hex << std::bit_cast<std::uint32_t>(u) << "," << std::bit_cast<std::uint32_t>(v);
                ASSERT_EQ(t.x, statedIndex(u, s, wrap)) << "size " << s << " wrap " << wrap << " u bits "
                                                        << std::hex << std::bit_cast<std::uint32_t>(u);
                ASSERT_EQ(t.y, statedIndex(v, s + 1, wrap))
                    << "size " << s + 1 << " wrap " << wrap << " v bits " << std::hex
                    << std::bit_cast<std::uint32_t>(v);
            }
        }
    }
    // Hand-worked: the crash's input, uv = 1e38 on a 16-texel repeat texture (1.6e39 overflows to
    // inf) is texel 2^24 mod 16 = 0; −1e38 likewise; NaN is 0; clamp puts ±inf on the edges.
    EXPECT_EQ(texelAt(vec2(1e38f, -1e38f), ivec2(16, 16), WRAP_REPEAT), ivec2(0, 0));
    EXPECT_EQ(texelAt(vec2(1e38f, -1e38f), ivec2(3, 3), WRAP_REPEAT), ivec2(1, 2)); // 2^24 = 3·5592405 + 1
    EXPECT_EQ(texelAt(vec2(NAN, -NAN), ivec2(16, 16), WRAP_REPEAT), ivec2(0, 0));
    EXPECT_EQ(texelAt(vec2(INFINITY, -INFINITY), ivec2(16, 16), WRAP_CLAMP), ivec2(15, 0));
    EXPECT_EQ(texelAt(vec2(NAN, NAN), ivec2(16, 16), WRAP_CLAMP), ivec2(0, 0));
}

TEST(Texel, AlphaBelowOneHalfIsAHole) {
    EXPECT_FALSE(alphaBlocks(0u));
    EXPECT_FALSE(alphaBlocks(127u));
    EXPECT_TRUE(alphaBlocks(128u));
    EXPECT_TRUE(alphaBlocks(255u));
}

} // namespace
} // namespace stsv
