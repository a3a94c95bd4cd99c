// --supersample K on every method and backend: the images at the requested size, the
// light-sample buffer of the K·W × K·H sub-pixels, the stats naming K.
#include "cli_test_util.h"

#include "core/image.h"
#include "render/methods.h"
#include "sampling/ls_buffer.h"

#include <gtest/gtest.h>

#include <string>

namespace stsv::test {
namespace {

TEST(SupersampleCli, EveryMethodOnEveryBackendWritesPixelsAndKeepsSubPixels) {
    ScratchDir dir;
    for (const MethodInfo& m : methodTable())
        for (Backend b : m.backends) {
            const std::string name = m.name + "_" + toString(b);
            std::vector<std::string> args = {"render",
                                             "fence",
                                             "--method",
                                             m.name,
                                             "--backend",
                                             toString(b),
                                             "--size",
                                             "12x8",
                                             "--samples",
                                             "16",
                                             "--supersample",
                                             "3",
                                             "-o",
                                             dir.file(name + ".png"),
                                             "--stats",
                                             dir.file(name + ".json"),
                                             "-q"};
            const bool perSample = m.output != MethodOutput::Visibility;
            if (perSample) {
                args.push_back("--dump-ls");
                args.push_back(dir.file(name + ".npy"));
            }
            const CliResult r = runStsv(args);
            ASSERT_EQ(r.code, 0) << describe(args, r);
            const Image8 lit = readPngRgba(dir.file(name + ".png"));
            EXPECT_EQ(lit.width, 12) << name;
            EXPECT_EQ(lit.height, 8) << name;
            const nlohmann::json s = readJson(dir.file(name + ".json"));
            EXPECT_EQ(s["options"]["supersample"], 3) << name;
            EXPECT_EQ(s["options"]["width"], 12) << name;
            if (perSample) {
                const LightSampleBuffer ls = LightSampleBuffer::readNpy(dir.file(name + ".npy"));
                EXPECT_EQ(ls.width(), 36) << name;
                EXPECT_EQ(ls.height(), 24) << name;
            }
        }
    const CliResult bad = runStsv({"render", "fence", "--supersample", "5", "-q"});
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("--supersample: 5 is out of range (1 to 4)"), std::string::npos) << bad.err;
}

} // namespace
} // namespace stsv::test
