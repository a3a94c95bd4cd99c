// OpenEXR outputs: the lit image as linear half-float RGB, the visibility as float32 Y, holding
// the values the frame has (no 8-bit quantisation, no clipping) and the same as the .npy; compare
// takes visibility files.
#include "cli_test_util.h"

#include "core/image.h"
#include "render/renderer.h"
#include "scene/load.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace stsv::test {
namespace {

TEST(ExrCli, LitAndVisibilityHoldTheFramesValuesAndMatchTheNpy) {
    ScratchDir dir;
    const std::vector<std::string> common = {"render",    "fence", "--backend", "cpu", "--size", "48x32",
                                             "--samples", "16",    "--seed",    "3",   "-q"};
    auto run = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = common;
        args.insert(args.end(), extra.begin(), extra.end());
        const CliResult r = runStsv(args);
        ASSERT_EQ(r.code, 0) << describe(args, r);
    };
    run({"-o", dir.file("lit.exr"), "--visibility", dir.file("v.exr")});
    run({"--visibility", dir.file("v.npy")});

    // Another reader, OpenEXR's exrheader (Debian's openexr), sees the layout the docs give.
    auto header = [](const std::string& path) {
        const ShellResult r = runShell("exrheader '" + path + "'");
        EXPECT_EQ(r.code, 0) << r.out;
        return r.out;
    };
    const std::string vHeader = header(dir.file("v.exr")), litHeader = header(dir.file("lit.exr"));
    EXPECT_NE(vHeader.find("Y, 32-bit floating-point, sampling 1 1"), std::string::npos) << vHeader;
    EXPECT_NE(vHeader.find("dataWindow (type box2i): (0 0) - (47 31)"), std::string::npos) << vHeader;
    for (const char* channel :
         {"R, 16-bit floating-point", "G, 16-bit floating-point", "B, 16-bit floating-point"})
        EXPECT_NE(litHeader.find(channel), std::string::npos) << litHeader;

    const ImageF v = readExr(dir.file("v.exr"));
    ASSERT_EQ(v.channels, 1);
    ASSERT_EQ(v.width, 48);
    ASSERT_EQ(v.height, 32);
    const NpyArray npy = readNpy(dir.file("v.npy"));
    ASSERT_EQ(npy.bytes.size(), v.pixels.size() * sizeof(float));
    // float32 both: the same bits.
    EXPECT_EQ(std::memcmp(npy.bytes.data(), v.pixels.data(), npy.bytes.size()), 0);
    // Unquantised: values between the 8-bit steps a PNG would hold (16 samples: multiples of 1/16).
    bool between = false;
    for (float x : v.pixels) between |= std::abs(x * 255.0f - std::round(x * 255.0f)) > 0.01f;
    EXPECT_TRUE(between) << "every value sits on an 8-bit step";

    // The lit image is the frame's linear colour, rounded to half floats (relative 2^-11).
    RenderOptions o;
    o.backend = Backend::Cpu;
    o.width = 48;
    o.height = 32;
    o.samples = 16;
    o.seed = 3;
    const Frame frame = renderFrame(loadScene("fence"), o);
    const ImageF lit = readExr(dir.file("lit.exr"));
    ASSERT_EQ(lit.channels, 3);
    ASSERT_EQ(lit.pixels.size(), frame.color.pixels.size());
    for (std::size_t i = 0; i < lit.pixels.size(); ++i)
        ASSERT_NEAR(lit.pixels[i], frame.color.pixels[i], std::abs(frame.color.pixels[i]) * 0.0005f + 1e-7f)
            << i;
}

TEST(ExrCli, CompareTakesTwoVisibilityFiles) {
    ScratchDir dir;
    for (const char* method : {"stsv", "pcss"}) {
        const CliResult r =
            runStsv({"render", "fence", "--backend", "cpu", "--method", method, "--size", "48x32",
                     "--samples", "16", "--visibility", dir.file(std::string(method) + ".exr"), "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const CliResult same = runStsv({"compare", dir.file("stsv.exr"), dir.file("stsv.exr")});
    ASSERT_EQ(same.code, 0) << same.err;
    EXPECT_NE(same.out.find("RMSE 0.000000"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("SSIM 1.000000"), std::string::npos) << same.out;
    const CliResult diff =
        runStsv({"compare", dir.file("stsv.exr"), dir.file("pcss.exr"), "--out", dir.file("d")});
    ASSERT_EQ(diff.code, 0) << diff.err;
    EXPECT_EQ(diff.out.find("RMSE 0.000000"), std::string::npos) << diff.out;
    EXPECT_TRUE(std::filesystem::exists(dir.file("d/difference.png")));
    // Not an EXR: one line naming the file.
    {
        std::ofstream bad(dir.file("bad.exr"));
        bad << "not an exr";
    }
    const CliResult bad = runStsv({"compare", dir.file("bad.exr"), dir.file("stsv.exr")});
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("bad.exr"), std::string::npos) << bad.err;
}

} // namespace
} // namespace stsv::test
