// Float values that break arithmetic written for ordinary ones: signed zeros, subnormals, the
// extremes of the normal range, the integers where float stops resolving units (2^24), values
// whose product with a texture size overflows, infinities and NaNs with either sign and several
// payloads (x86 makes negative quiet NaNs, GPUs positive ones). Shared by the texel-rule tests on
// the CPU and on Vulkan.
#pragma once

#include <bit>
#include <cstdint>
#include <random>
#include <vector>

namespace stsv::test {

inline std::vector<float> extremeFloats() {
    const std::uint32_t bits[] = {
        0x00000000u, 0x80000000u, // ±0
        0x00000001u, 0x80000001u, // smallest subnormals
        0x007fffffu, 0x807fffffu, // largest subnormals
        0x00800000u, 0x80800000u, // smallest normals
        0x3f7fffffu, 0xbf7fffffu, // 1 − 2^−24
        0x3f800000u, 0xbf800000u, // ±1
        0x4b7fffffu, 0xcb7fffffu, // 2^24 − 1
        0x4b800000u, 0xcb800000u, // 2^24
        0x4b800001u, 0xcb800001u, // 2^24 + 2
        0x4f000000u, 0xcf000000u, // 2^31
        0x5d5e0b6bu, 0xdd5e0b6bu, // 1e18
        0x7e967699u, 0xfe967699u, // 1e38
        0x7f7fffffu, 0xff7fffffu, // ±FLT_MAX
        0x7f800000u, 0xff800000u, // ±inf
        0x7fc00000u, 0xffc00000u, // quiet NaNs
        0x7f800001u, 0xff800001u, // signalling NaNs
        0x7fffffffu, 0xffffffffu, // NaNs with every payload bit
    };
    std::vector<float> values;
    for (std::uint32_t b : bits) values.push_back(std::bit_cast<float>(b));
    return values;
}

/// `count` floats of uniformly random bit patterns (every exponent as likely: most are huge or
/// tiny, 1 in 256 is an infinity or a NaN).
inline std::vector<float> randomBitFloats(std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<float> values(count);
    for (float& v : values) v = std::bit_cast<float>(std::uint32_t(rng()));
    return values;
}

} // namespace stsv::test
