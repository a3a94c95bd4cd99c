// Images a failed image test leaves for a person to look at: the actual image, the expected one
// and their difference, as PNGs beside ctest's log. The folder is $STSV_TEST_IMAGES, else
// BUILD/Testing/Temporary/images; each test writes into a subfolder named Suite.Test. CI keeps
// the folder when the suite fails (.ci/run).
#pragma once

#include "core/image.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace stsv::test {

/// The folder of the running test's failure images (not created).
inline std::filesystem::path failureImageDir() {
    const char* env = std::getenv("STSV_TEST_IMAGES");
    std::filesystem::path root =
        env && *env ? std::filesystem::path(env) : std::filesystem::path(STSV_TEST_IMAGES_DIR);
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    if (info) root /= std::string(info->test_suite_name()) + "." + info->name();
    return root;
}

/// When the running test has failed: writes name_actual.png, name_expected.png and name_diff.png
/// (|actual − expected|, the largest over the channels, times `diffGain`, clamped to 1) into
/// failureImageDir(), and prints where. `srgb`: encode the images (lit images) rather than
/// writing them linearly (visibility). The two images must have one size and channel count.
inline void writeFailureImages(const std::string& name, const ImageF& actual, const ImageF& expected,
                               bool srgb = false, float diffGain = 4.0f) {
    if (!::testing::Test::HasFailure()) return;
    if (actual.width != expected.width || actual.height != expected.height ||
        actual.channels != expected.channels)
        return;
    const std::filesystem::path dir = failureImageDir();
    std::filesystem::create_directories(dir);
    ImageF diff(actual.width, actual.height, 1);
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            float d = 0.0f;
            for (int c = 0; c < actual.channels; ++c)
                d = std::max(d, std::abs(actual.at(x, y, c) - expected.at(x, y, c)));
            diff.at(x, y, 0) = std::min(1.0f, diffGain * d);
        }
    writePng((dir / (name + "_actual.png")).string(), toImage8(actual, srgb));
    writePng((dir / (name + "_expected.png")).string(), toImage8(expected, srgb));
    writePng((dir / (name + "_diff.png")).string(), toImage8(diff, false));
    std::printf("failure images: %s/%s_{actual,expected,diff}.png\n", dir.string().c_str(), name.c_str());
}

} // namespace stsv::test
