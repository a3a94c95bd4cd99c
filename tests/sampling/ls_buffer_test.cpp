// Light-sample buffers (DESIGN §4.4): word layout, counters, v_coef, memory, the --dump-ls
// --dump-ls .npy layout byte by byte, read-back and comparison.
#include "core/error.h"
#include "core/image.h"
#include "sampling/ls_buffer.h"
#include "scene/occlusion_rules_dh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace stsv {
namespace {

using Kind = BufferKind;

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("stsv_sampling_" + name)).string();
}

std::vector<std::uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Removes a .npy and the metadata beside it.
void removeNpy(const std::string& path) {
    std::remove(path.c_str());
    std::remove(npyInfoPath(path).c_str());
}

/// The header dict and the data bytes of a version-1 .npy file.
std::pair<std::string, std::vector<std::uint8_t>> splitNpy(const std::vector<std::uint8_t>& file) {
    EXPECT_GE(file.size(), 10u);
    EXPECT_EQ(std::string(file.begin() + 1, file.begin() + 6), "NUMPY");
    EXPECT_EQ(file[0], 0x93);
    const std::size_t headerLen = file[8] | (std::size_t(file[9]) << 8);
    EXPECT_EQ((10 + headerLen) % 16, 0u) << "npy data must be aligned";
    return {std::string(file.begin() + 10, file.begin() + 10 + std::ptrdiff_t(headerLen)),
            std::vector<std::uint8_t>(file.begin() + 10 + std::ptrdiff_t(headerLen), file.end())};
}

TEST(LightSampleBuffer, BitmaskWordLayoutMatchesTheGpu) {
    LightSampleBuffer ls(3, 2, 64, Kind::Bitmask);
    ASSERT_EQ(ls.wordsPerPixel(), 2);
    ASSERT_EQ(ls.words().size(), 3u * 2u * 2u);
    ls.setOccluded(1, 1, 0);
    ls.setOccluded(1, 1, 31);
    ls.setOccluded(1, 1, 33);
    ls.setOccluded(2, 0, 63);
    // Pixel (1, 1) is pixel 4 in row order: words 8 and 9.
    EXPECT_EQ(ls.words()[8], 0x80000001u);
    EXPECT_EQ(ls.words()[9], 0x00000002u);
    EXPECT_EQ(ls.words()[5], 0x80000000u); // pixel (2, 0), word 1
    for (std::size_t i : {0u, 1u, 2u, 3u, 4u, 6u, 7u, 10u, 11u}) EXPECT_EQ(ls.words()[i], 0u) << "word " << i;
    EXPECT_TRUE(ls.occluded(1, 1, 33));
    EXPECT_FALSE(ls.occluded(1, 1, 32));
    EXPECT_TRUE(ls.visible(0, 0, 0));
    EXPECT_EQ(ls.count(1, 1, 31), 1);
    EXPECT_FLOAT_EQ(ls.visibleFraction(1, 1), 61.0f / 64.0f);
    EXPECT_THROW(ls.addCount(0, 0, 0, 1), UsageError);
    // 16 samples use the low half of one word; the resolve ignores the unused high bits.
    LightSampleBuffer small(1, 1, 16, Kind::Bitmask);
    small.words()[0] = 0xFFFF0003u;
    EXPECT_FLOAT_EQ(small.visibleFraction(0, 0), 14.0f / 16.0f);
}

TEST(LightSampleBuffer, CountersAreModularLikeGpuAtomics) {
    LightSampleBuffer ls(2, 2, 16, Kind::Counters);
    ls.addCount(1, 0, 3, -1); // DCS: −1 crossing before D(r) arrives
    EXPECT_TRUE(ls.occluded(1, 0, 3));
    ls.addCount(1, 0, 3, 1);
    EXPECT_EQ(ls.count(1, 0, 3), 0);
    EXPECT_TRUE(ls.visible(1, 0, 3));
    ls.addCount(1, 0, 3, 2);
    ls.addCount(1, 0, 4, 1);
    ls.setOccluded(1, 0, 5);
    ls.setOccluded(1, 0, 3); // already occluded: count unchanged
    EXPECT_EQ(ls.count(1, 0, 3), 2);
    EXPECT_EQ(ls.count(1, 0, 5), 1);
    EXPECT_EQ(ls.counters()[std::size_t(1 * 16 + 3)], 2u);
    EXPECT_FLOAT_EQ(ls.visibleFraction(1, 0), 13.0f / 16.0f);
    EXPECT_FLOAT_EQ(ls.visibleFraction(0, 1), 1.0f);
    const ImageF v = resolveVisibility(ls);
    ASSERT_EQ(v.channels, 1);
    EXPECT_FLOAT_EQ(v.at(1, 0, 0), 13.0f / 16.0f);
    EXPECT_FLOAT_EQ(v.at(0, 0, 0), 1.0f);
}

TEST(LightSampleBuffer, MemoryIsTheBitCount) {
    // STSV paper §5.1: 1024² pixels × 64 samples = 8 MiB.
    EXPECT_EQ(LightSampleBuffer(1024, 1024, 64, Kind::Bitmask).memoryBytes(), 8u * 1024u * 1024u);
    EXPECT_EQ(LightSampleBuffer(640, 480, 16, Kind::Bitmask).memoryBytes(), 640u * 480u * 16u / 8u);
    EXPECT_EQ(LightSampleBuffer(640, 480, 16, Kind::Bitmask).storageBytes(), 640u * 480u * 4u);
    EXPECT_EQ(LightSampleBuffer(10, 10, 32, Kind::Counters).memoryBytes(), 10u * 10u * 32u * 2u);
}

TEST(LightSampleBuffer, RejectsAbsurdSizes) {
    EXPECT_THROW(LightSampleBuffer(0, 4, 16, Kind::Bitmask), UsageError);
    EXPECT_THROW(LightSampleBuffer(4, -1, 16, Kind::Bitmask), UsageError);
    EXPECT_THROW(LightSampleBuffer(4, 4, 0, Kind::Counters), UsageError);
    EXPECT_THROW(LightSampleBuffer(4, 4, 5000, Kind::Bitmask), UsageError);
    EXPECT_THROW(LightSampleBuffer(1 << 15, 1 << 15, 16, Kind::Bitmask), UsageError);
}

TEST(LightSampleBuffer, BitmaskNpyLayoutIsExact) {
    // 3 × 2 pixels, 16 samples → uint8 [2, 3, 2]; sample k in bit k%8 of byte k/8.
    LightSampleBuffer ls(3, 2, 16, Kind::Bitmask);
    ls.setOccluded(0, 0, 0);  // top-left: byte 0 = 0x01
    ls.setOccluded(0, 0, 9);  // byte 1 = 0x02
    ls.setOccluded(2, 0, 7);  // top-right: byte 0 = 0x80
    ls.setOccluded(1, 1, 8);  // bottom-middle: byte 1 = 0x01
    ls.setOccluded(1, 1, 15); // byte 1 |= 0x80
    ls.setOccluded(0, 1, 3);  // bottom-left: byte 0 = 0x08
    const std::string path = tempPath("bitmask.npy");
    ls.writeNpy(path);
    const auto [header, data] = splitNpy(fileBytes(path));
    EXPECT_NE(header.find("'descr': '|u1'"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (2, 3, 2)"), std::string::npos) << header;
    EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
    const std::vector<std::uint8_t> expected = {
        0x01, 0x02, 0x00, 0x00, 0x80, 0x00, // row 0 (top): pixels x = 0, 1, 2
        0x08, 0x00, 0x00, 0x81, 0x00, 0x00, // row 1
    };
    EXPECT_EQ(data, expected);
    const LightSampleBuffer back = LightSampleBuffer::readNpy(path);
    EXPECT_EQ(back.kind(), Kind::Bitmask);
    EXPECT_EQ(back.samples(), 16);
    EXPECT_EQ(back.words(), ls.words());
    EXPECT_EQ(compareLightSamples(ls, back).differingSamples, 0u);
    removeNpy(path);
}

TEST(LightSampleBuffer, BitmaskNpyAcrossWordsRoundTrips) {
    LightSampleBuffer ls(5, 3, 128, Kind::Bitmask);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int k = (x + 3 * y) % 7; k < 128; k += 5 + x) ls.setOccluded(x, y, k);
    const std::string path = tempPath("bitmask128.npy");
    ls.writeNpy(path);
    const auto [header, data] = splitNpy(fileBytes(path));
    EXPECT_NE(header.find("'shape': (3, 5, 16)"), std::string::npos) << header;
    ASSERT_EQ(data.size(), 3u * 5u * 16u);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int k = 0; k < 128; ++k) {
                const int byte = (y * 5 + x) * 16 + k / 8;
                const bool bit = (data[std::size_t(byte)] >> (k % 8)) & 1u;
                ASSERT_EQ(bit, ls.occluded(x, y, k)) << "x=" << x << " y=" << y << " k=" << k;
            }
    const LightSampleBuffer back = LightSampleBuffer::readNpy(path);
    EXPECT_EQ(back.words(), ls.words());
    removeNpy(path);
    LightSampleBuffer odd(1, 1, 12, Kind::Bitmask);
    EXPECT_THROW(odd.writeNpy(path), UsageError);
}

TEST(LightSampleBuffer, CounterNpyUsesUint8ThenUint16) {
    LightSampleBuffer ls(2, 1, 16, Kind::Counters);
    ls.addCount(0, 0, 0, 3);
    ls.addCount(1, 0, 15, 255);
    const std::string path = tempPath("counters.npy");
    ls.writeNpy(path);
    {
        const auto [header, data] = splitNpy(fileBytes(path));
        EXPECT_NE(header.find("'descr': '|u1'"), std::string::npos) << header;
        EXPECT_NE(header.find("'shape': (1, 2, 16)"), std::string::npos) << header;
        ASSERT_EQ(data.size(), 32u);
        EXPECT_EQ(data[0], 3);
        EXPECT_EQ(data[31], 255);
        for (std::size_t i = 1; i < 31; ++i) EXPECT_EQ(data[i], 0) << i;
        const LightSampleBuffer back = LightSampleBuffer::readNpy(path, Kind::Counters);
        EXPECT_EQ(back.counters(), ls.counters());
    }
    ls.addCount(1, 0, 15, 1); // 256: no longer fits uint8
    ls.addCount(0, 0, 1, 0x1234);
    ls.writeNpy(path);
    {
        const auto [header, data] = splitNpy(fileBytes(path));
        EXPECT_NE(header.find("'descr': '<u2'"), std::string::npos) << header;
        ASSERT_EQ(data.size(), 64u);
        EXPECT_EQ(data[0], 3);
        EXPECT_EQ(data[1], 0);
        EXPECT_EQ(data[2], 0x34); // little endian
        EXPECT_EQ(data[3], 0x12);
        EXPECT_EQ(data[62], 0x00);
        EXPECT_EQ(data[63], 0x01);
        const LightSampleBuffer back = LightSampleBuffer::readNpy(path); // uint16 → counters
        EXPECT_EQ(back.kind(), Kind::Counters);
        EXPECT_EQ(back.counters(), ls.counters());
        EXPECT_EQ(compareLightSamples(ls, back, 16, true).differingSamples, 0u);
        EXPECT_THROW(LightSampleBuffer::readNpy(path, Kind::Bitmask), InputError);
    }
    removeNpy(path);
}

TEST(LightSampleBuffer, TransmittanceIsAnOpticalDepthSumWrittenAsFloat16) {
    LightSampleBuffer ls(2, 1, 16, Kind::Transmittance);
    // α = 0.5 twice: optical depth 2 ln 2 → T = 1/4 (to the fixed point's 2^−16 and float16's step).
    const std::uint32_t half = std::uint32_t(std::llround(std::log(2.0) * 65536.0));
    ls.addOpticalDepth(0, 0, 3, half);
    ls.addOpticalDepth(0, 0, 3, half);
    ls.addOpticalDepth(1, 0, 5, OPTICAL_DEPTH_OPAQUE);
    // A sum that wraps 2^32 units is an occlusion, whatever the order of the terms.
    ls.addOpticalDepth(1, 0, 7, 0xC0000000u);
    ls.addOpticalDepth(1, 0, 7, 0x40000000u);
    EXPECT_EQ(ls.opticalDepth(0, 0, 3), 2 * half);
    EXPECT_TRUE(ls.occluded(1, 0, 5));
    EXPECT_TRUE(ls.occluded(1, 0, 7));
    EXPECT_EQ(ls.transmittance(1, 0, 7), 0.0f);
    EXPECT_EQ(ls.transmittance(0, 0, 0), 1.0f);
    EXPECT_NEAR(ls.transmittance(0, 0, 3), 0.25f, 1e-6f);
    // v_coef is the mean transmittance: (15 + 0.25) / 16 and (16 − 2) / 16.
    EXPECT_NEAR(ls.visibleFraction(0, 0), 15.25f / 16.0f, 1e-6f);
    EXPECT_EQ(ls.visibleFraction(1, 0), 14.0f / 16.0f);
    // Bits (for the opaque part) and one 32-bit depth per sample.
    EXPECT_EQ(LightSampleBuffer::storageBytes(2, 1, 16, Kind::Transmittance), 2u * 4u + 2u * 16u * 4u);
    EXPECT_EQ(LightSampleBuffer::payloadBytes(2, 1, 16, Kind::Transmittance), 2u * 16u * 2u);
    const std::string path = tempPath("transmittance.npy");
    ls.writeNpy(path);
    const auto [header, data] = splitNpy(fileBytes(path));
    EXPECT_NE(header.find("'descr': '<f2'"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (1, 2, 16)"), std::string::npos) << header;
    ASSERT_EQ(data.size(), 64u);
    EXPECT_EQ(data[0], 0x00); // 1.0 = 0x3C00, little endian
    EXPECT_EQ(data[1], 0x3C);
    EXPECT_EQ(data[6], 0x00); // 0.25 = 0x3400
    EXPECT_EQ(data[7], 0x34);
    EXPECT_EQ(data[2 * (16 + 5)], 0x00); // 0
    EXPECT_EQ(data[2 * (16 + 5) + 1], 0x00);
    const LightSampleBuffer back = LightSampleBuffer::readNpy(path);
    EXPECT_EQ(back.kind(), Kind::Transmittance);
    for (int x = 0; x < 2; ++x)
        for (int k = 0; k < 16; ++k)
            EXPECT_EQ(halfBits(back.transmittance(x, 0, k)), halfBits(ls.transmittance(x, 0, k)))
                << x << " " << k;
    EXPECT_THROW(ls.addCount(0, 0, 0, 1), UsageError);
    removeNpy(path);
}

TEST(LightSampleBuffer, ReadNpyRejectsOtherArrays) {
    const std::string path = tempPath("bad.npy");
    const float f[4] = {0, 1, 2, 3};
    writeNpy(path, "<f4", {1, 1, 4}, f, sizeof(f));
    EXPECT_THROW(LightSampleBuffer::readNpy(path), InputError);
    const std::uint8_t b[4] = {0, 1, 2, 3};
    writeNpy(path, "|u1", {2, 2}, b, sizeof(b));
    EXPECT_THROW(LightSampleBuffer::readNpy(path), InputError);
    removeNpy(path);
}

// A uint8 [H, W, 16] array is a bitmask of 128 samples or counters of 16: the metadata beside it
// says which, and how it was made; NumPy's reader refuses other keys in the .npy header itself.
TEST(LightSampleBuffer, NpyMetadataSaysTheKindTheArrayCannot) {
    LightSampleBuffer counters(3, 2, 16, Kind::Counters);
    counters.addCount(1, 1, 15, 7);
    const std::string path = tempPath("meta.npy");
    counters.writeNpy(path, "dcs/cpu");
    const auto [header, data] = splitNpy(fileBytes(path));
    EXPECT_NE(header.find("'shape': (2, 3, 16)"), std::string::npos) << header;
    EXPECT_EQ(header.find("kind"), std::string::npos) << "NumPy refuses extra header keys: " << header;
    const std::optional<LightSampleFileInfo> info = readLightSampleInfo(path);
    ASSERT_TRUE(info.has_value());
    EXPECT_EQ(info->kind, Kind::Counters);
    EXPECT_EQ(info->samples, 16);
    EXPECT_EQ(info->width, 3);
    EXPECT_EQ(info->height, 2);
    EXPECT_EQ(info->method, "dcs/cpu");
    const LightSampleBuffer back = LightSampleBuffer::readNpy(path); // counters, not 128 bits
    EXPECT_EQ(back.kind(), Kind::Counters);
    EXPECT_EQ(back.samples(), 16);
    EXPECT_EQ(back.count(1, 1, 15), 7);
    EXPECT_THROW(LightSampleBuffer::readNpy(path, Kind::Bitmask), InputError) << "a kind its metadata denies";

    // Without the metadata, a uint8 array's kind is not guessed: it must be given.
    std::remove(npyInfoPath(path).c_str());
    EXPECT_FALSE(readLightSampleInfo(path).has_value());
    try {
        (void)LightSampleBuffer::readNpy(path);
        ADD_FAILURE() << "read a uint8 array of no known kind";
    } catch (const InputError& e) {
        EXPECT_NE(e.message().find("meta.npy.json"), std::string::npos) << e.message();
    }
    EXPECT_EQ(LightSampleBuffer::readNpy(path, Kind::Counters).samples(), 16);
    EXPECT_EQ(LightSampleBuffer::readNpy(path, Kind::Bitmask).samples(), 128);

    // Metadata of another array, or not metadata at all, is refused.
    std::ofstream(npyInfoPath(path))
        << R"({"format": "stsv light samples", "kind": "counters", "samples": 16, )"
        << R"("width": 4, "height": 2})";
    EXPECT_THROW((void)LightSampleBuffer::readNpy(path), InputError);
    for (const char* text :
         {"{", "[]", R"({"format": "other"})",
          R"({"format": "stsv light samples", "kind": "bits", "samples": 16, "width": 3, "height": 2})",
          R"({"format": "stsv light samples", "kind": "counters", "samples": 0, "width": 3, "height": 2})"}) {
        std::ofstream(npyInfoPath(path)) << text;
        EXPECT_THROW(readLightSampleInfo(path), InputError) << text;
    }
    removeNpy(path);
}

TEST(LightSampleBuffer, CompareCountsDifferingSamplesAndListsPixels) {
    LightSampleBuffer a(4, 3, 32, Kind::Bitmask);
    LightSampleBuffer b(4, 3, 32, Kind::Counters);
    a.setOccluded(2, 0, 1);
    b.addCount(2, 0, 1, 3); // occluded in both: not a difference of occlusion
    a.setOccluded(3, 1, 4);
    a.setOccluded(3, 1, 5);
    b.setOccluded(0, 2, 31);
    b.setOccluded(1, 0, 0);
    LightSampleDiff d = compareLightSamples(a, b);
    EXPECT_EQ(d.comparedSamples, 4u * 3u * 32u);
    EXPECT_EQ(d.differingSamples, 4u);
    EXPECT_EQ(d.differingPixels, 3u);
    ASSERT_EQ(d.firstPixels.size(), 3u);
    EXPECT_EQ(d.firstPixels[0], ivec2(1, 0)); // row order
    EXPECT_EQ(d.firstPixels[1], ivec2(3, 1));
    EXPECT_EQ(d.firstPixels[2], ivec2(0, 2));
    d = compareLightSamples(a, b, 1);
    EXPECT_EQ(d.firstPixels.size(), 1u);
    EXPECT_EQ(d.differingPixels, 3u);
    // Exact counts between two counter buffers.
    LightSampleBuffer c(4, 3, 32, Kind::Counters);
    c.addCount(2, 0, 1, 1);
    EXPECT_EQ(compareLightSamples(b, c, 16, false).differingSamples, 2u);
    EXPECT_EQ(compareLightSamples(b, c, 16, true).differingSamples, 3u);
    EXPECT_THROW(compareLightSamples(a, LightSampleBuffer(4, 3, 64, Kind::Bitmask)), UsageError);
    EXPECT_THROW(compareLightSamples(a, LightSampleBuffer(3, 4, 32, Kind::Bitmask)), UsageError);
}

} // namespace
} // namespace stsv
