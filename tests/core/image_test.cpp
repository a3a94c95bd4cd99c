#include "core/error.h"
#include "core/image.h"
#include "core/memory_budget.h"
#include "core/parallel.h"
#include "tests/support/zero_png.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace stsv {
namespace {

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("stsv_core_" + name)).string();
}

TEST(Image, PngRoundTripIsExact) {
    Image8 image;
    image.width = 5;
    image.height = 3;
    image.channels = 4;
    for (int i = 0; i < 5 * 3 * 4; ++i) image.pixels.push_back(static_cast<std::uint8_t>(i * 13 + 7));
    writePng(tempPath("rt.png"), image);
    const Image8 back = readPngRgba(tempPath("rt.png"));
    EXPECT_EQ(back.width, 5);
    EXPECT_EQ(back.height, 3);
    EXPECT_EQ(back.pixels, image.pixels);
}

TEST(Image, MissingPngNamesTheFile) {
    try {
        readPngRgba("/nonexistent/texture.png");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/texture.png"), std::string::npos) << e.what();
    }
}

TEST(Image, OnlyPngIsDecoded) {
    // A valid binary PPM (2x1, white and black): stb can decode it, yet a texture must be a PNG, and
    // stb's other decoders stay out of reach (fuzzing crashed its PNM reader on a broken one).
    const std::string ppm = std::string("P6\n2 1\n255\n") + std::string(3, '\xff') + std::string(3, '\0');
    const std::string path = tempPath("texture_is_ppm.png");
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_NE(f, nullptr);
        ASSERT_EQ(std::fwrite(ppm.data(), 1, ppm.size(), f), ppm.size());
        std::fclose(f);
    }
    try {
        readPngRgba(path);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find("not a PNG file"), std::string::npos) << what;
    }
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
    std::fclose(f);
}

TEST(Image, PngIsHeldToTheMemoryLimitAtTheDecodersPeak) {
    // 4096² texels in 106 KB: 64 MiB as RGBA8, 128 MiB at the peak of decoding and handing the
    // texels on (PNG8_PEAK_BYTES_PER_PIXEL, measured). A limit between the two refuses it, with
    // the file, the image's size and the limit, before stb decodes anything.
    const std::string path = tempPath("zeros_4096.png");
    writeBytes(path, test::zeroPng(4096));
    struct DefaultLimitAfter {
        ~DefaultLimitAfter() { setMemoryLimit(0); }
    } restore;
    setMemoryLimit(std::uint64_t(100) << 20);
    try {
        readPngRgba(path);
        FAIL() << "expected UsageError";
    } catch (const UsageError& e) {
        const std::string what = e.what();
        for (const char* part :
             {"zeros_4096.png", "image of 4096x4096 pixels", "128.1 MiB", "memory limit of 100.0 MiB"})
            EXPECT_NE(what.find(part), std::string::npos) << what << "\nmissing: " << part;
    }
    // The estimate from the header alone, for each kind of file: its bytes plus the measured peak.
    const std::string png = test::zeroPng(16);
    const ImageHeader header =
        readImageHeader("zeros", reinterpret_cast<const std::uint8_t*>(png.data()), png.size());
    EXPECT_EQ(header.width, 16);
    EXPECT_FALSE(header.jpeg || header.sixteenBit || header.interlaced);
    EXPECT_EQ(header.peakBytes(1000), 1000.0 + 8.0 * 256.0);
    // Under the default limit it decodes: grey 0 with alpha 255.
    setMemoryLimit(0);
    const Image8 image = readPngRgba(path);
    ASSERT_EQ(image.width, 4096);
    EXPECT_EQ(image.at(4095, 4095, 0), 0);
    EXPECT_EQ(image.at(4095, 4095, 3), 255);
}

TEST(Image, APngChunkRunningPastTheFilesEndIsRefusedBeforeDecoding) {
    // A valid 4x4 PNG whose IDAT chunk's length field then says 1 GiB: stb would grow its buffer
    // to that before finding the file too short. The chunk walk refuses it first.
    std::string bytes = test::zeroPng(4);
    const std::size_t idat = bytes.find("IDAT") - 4;
    ASSERT_LT(idat, bytes.size());
    for (int i = 0; i < 4; ++i) bytes[idat + std::size_t(i)] = char(i == 0 ? 0x40 : 0);
    const std::string path = tempPath("chunk_past_the_end.png");
    writeBytes(path, bytes);
    try {
        readPngRgba(path);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("chunk_past_the_end.png: not a readable PNG (its IDAT chunk at byte " +
                            std::to_string(idat) +
                            " declares 1073741824 bytes of data, past the file's end)"),
                  std::string::npos)
            << what;
    }
    // The file as written, chunk lengths intact, decodes.
    writeBytes(path, test::zeroPng(4));
    EXPECT_EQ(readPngRgba(path).width, 4);
}

TEST(Image, PngDataInflatingPastItsHeaderIsRefusedNearTheLimit) {
    // 16x16 pixels declared (16 rows of a filter byte and 16 samples: 272 bytes), 64 MiB of zeros
    // in its data (426 KB of file): stb would grow its buffer to hold them all and decode the
    // first 272 bytes. Where the limit leaves no room for that, the data is inflated first into
    // the declared size and refused.
    const std::string path = tempPath("inflates.png");
    writeBytes(path, test::zeroPng(16, std::uint64_t(64) << 20));
    struct DefaultLimitAfter {
        ~DefaultLimitAfter() { setMemoryLimit(0); }
    } restore;
    setMemoryLimit(std::uint64_t(32) << 20);
    try {
        readPngRgba(path);
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(
            what.find(
                "inflates.png: not a readable PNG (its image data inflates past the 272 bytes its header "
                "declares"),
            std::string::npos)
            << what;
    }
    // A file that holds what it declares passes the same check: 4096² under a limit of 130 MiB,
    // above its estimate of 128.1 MiB but below what its 106 KB could inflate to.
    const std::string fair = tempPath("zeros_4096_fair.png");
    writeBytes(fair, test::zeroPng(4096));
    setMemoryLimit(std::uint64_t(130) << 20);
    EXPECT_EQ(readPngRgba(fair).width, 4096);
}

TEST(Image, NpyHeaderIsAlignedAndRoundTrips) {
    std::vector<std::uint16_t> data = {1, 2, 3, 65535, 7, 9};
    writeNpy(tempPath("a.npy"), "<u2", {2, 3}, data.data(), data.size() * 2);
    const NpyArray back = readNpy(tempPath("a.npy"));
    EXPECT_EQ(back.dtype, "<u2");
    EXPECT_EQ(back.shape, (std::vector<std::size_t>{2, 3}));
    ASSERT_EQ(back.bytes.size(), 12u);
    EXPECT_EQ(std::filesystem::file_size(tempPath("a.npy")) % 64, 12u); // data starts 64-byte aligned
    EXPECT_EQ(std::memcmp(back.bytes.data(), data.data(), 12), 0);
}

TEST(Image, SrgbEncodingOfKnownValues) {
    ImageF f(3, 1, 1);
    f.pixels = {0.0f, 1.0f, 0.5f};
    const Image8 e = toImage8(f, true);
    EXPECT_EQ(e.pixels[0], 0);
    EXPECT_EQ(e.pixels[1], 255);
    EXPECT_EQ(e.pixels[2], 188); // sRGB(0.5) = 0.7354 → 187.5, rounds to 188
}

TEST(Parallel, VisitsEveryIndexOnceAndRethrows) {
    std::vector<std::atomic<int>> hits(10007);
    parallelFor(hits.size(), [&](std::size_t i) { hits[i]++; });
    for (std::size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << "index " << i;
    std::vector<std::atomic<int>> pixels(37 * 21);
    parallelForPixels(37, 21, [&](int x, int y) { pixels[std::size_t(y * 37 + x)]++; });
    for (std::size_t i = 0; i < pixels.size(); ++i) ASSERT_EQ(pixels[i].load(), 1) << "pixel " << i;
    std::vector<std::atomic<int>> chunked(100003);
    parallelForChunks(chunked.size(), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) chunked[i]++;
    });
    for (std::size_t i = 0; i < chunked.size(); ++i) ASSERT_EQ(chunked[i].load(), 1) << "item " << i;
    EXPECT_THROW(parallelFor(100,
                             [](std::size_t i) {
                                 if (i == 42) throw Error("boom");
                             }),
                 Error);
}

} // namespace
} // namespace stsv
