// What the command line takes and says, as a user can rely on it: an empty value is refused, not
// read as the option left out; a number out of range names the option, the value and the range;
// `info` reads a scene under --max-memory and counts all it holds; its method list says what each
// row writes, from the table; a Vulkan driver manifest that cannot be used is named; and text
// quoted from input keeps its NUL bytes, escaped.
#include "cli_test_util.h"

#include "core/image.h"
#include "render/methods.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace stsv::test {
namespace {

namespace fs = std::filesystem;

/// The options of `command` that take a value, with their type as --help shows it ("--seed",
/// "UINT"): every line of the help's option list that names a type after the option.
std::vector<std::pair<std::string, std::string>> valueOptions(const std::string& command) {
    const CliResult help = runStsv({command, "--help"});
    EXPECT_EQ(help.code, 0) << help.err;
    static const std::regex line(R"(^  (?:-\w,)?(--[\w-]+) (TEXT|INT|UINT|FLOAT)\b)");
    std::vector<std::pair<std::string, std::string>> options;
    std::istringstream text(help.out);
    for (std::string l; std::getline(text, l);)
        if (std::smatch m; std::regex_search(l, m, line)) options.emplace_back(m[1].str(), m[2].str());
    return options;
}

const std::vector<std::string> COMMANDS = {"render", "info", "bench", "compare"};

// `-o ""` wrote fence.png in the current directory, `--camera ''` and `--backend ""` were
// ignored, and `stsv render ""` blamed -o: every option that takes a value refuses an empty one,
// naming it, and an empty scene is named as such.
TEST(TrustValues, EveryOptionRefusesAnEmptyValue) {
    ScratchDir dir;
    const fs::path before = fs::current_path();
    fs::current_path(dir.path());
    for (const std::string& command : COMMANDS) {
        const std::vector<std::pair<std::string, std::string>> options = valueOptions(command);
        EXPECT_GT(options.size(), 10u) << command << " --help lists no options";
        for (const auto& [option, type] : options) {
            const std::vector<std::string> args = {command, "fence", option, "", "-q"};
            const CliResult r = runStsv(args);
            EXPECT_EQ(r.code, 1) << describe(args, r);
            EXPECT_NE(r.err.find(option + ": the value is empty"), std::string::npos) << describe(args, r);
        }
        if (command == "info") continue; // its scene is optional
        const CliResult scene = runStsv({command, "", "-q"});
        EXPECT_EQ(scene.code, 1) << scene.out;
        EXPECT_NE(scene.err.find(command == "compare" ? "the scene or file name is empty"
                                                      : "the scene name is empty"),
                  std::string::npos)
            << scene.err;
    }
    fs::current_path(before);
    EXPECT_TRUE(fs::is_empty(dir.path())) << "a refused command wrote a file";
}

// `--seed 4294967296` said "Could not convert": every integer option names itself, the value and
// the values it takes.
TEST(TrustValues, AnIntegerOutOfRangeNamesTheOptionTheValueAndTheRange) {
    const CliResult seed = runStsv({"render", "fence", "--seed", "4294967296", "-q"});
    EXPECT_EQ(seed.code, 1);
    EXPECT_NE(seed.err.find("--seed: 4294967296 is out of range (0 to 4294967295)"), std::string::npos)
        << seed.err;
    for (const std::string& command : COMMANDS)
        for (const auto& [option, type] : valueOptions(command)) {
            if (type != "INT" && type != "UINT") continue;
            for (const std::string value : {"99999999999999999999", "-99999999999999999999", "1.5", "ten"}) {
                const std::vector<std::string> args = {command, "fence", option, value, "-q"};
                const CliResult r = runStsv(args);
                EXPECT_EQ(r.code, 1) << describe(args, r);
                EXPECT_NE(r.err.find(option + ": "), std::string::npos) << describe(args, r);
                EXPECT_NE(r.err.find(value), std::string::npos) << describe(args, r);
                EXPECT_TRUE(std::regex_search(r.err, std::regex(R"(\((-?\d+ to \d+|(\d+, )+\d+)\))")))
                    << "no accepted range in\n"
                    << describe(args, r);
            }
        }
    // bench's --samples takes a list: each item is checked alike.
    const CliResult list = runStsv({"bench", "fence", "--samples", "16,99999999999", "-q"});
    EXPECT_EQ(list.code, 1);
    EXPECT_NE(list.err.find("99999999999 is out of range (1 to 999999999)"), std::string::npos) << list.err;
    // A leading zero is decimal, not octal: --interleave 08 is 8.
    const CliResult eight = runStsv({"info", "fence", "--interleave", "08", "--json"});
    EXPECT_EQ(eight.code, 0) << eight.err;
}

/// A one-quad JSON scene whose material's alpha texture is `texture` (a path in the scene's
/// folder, as JSON text).
std::string texturedScene(const std::string& texture) {
    return R"({"materials": [{"name": "m", "alphaTexture": )" + texture +
           R"(}], "meshes": [{"quad": {"size": [1, 1]}, "material": "m"}], "lights": [{"type": "rectangle", )"
           R"("position": [0, 3, 0], "normal": [0, -1, 0], "size": [1, 1], "radiance": [1, 1, 1]}]})";
}

// `stsv info SCENE` ignored --max-memory, decoded everything, said "scene about 10.2 KiB" for a
// scene holding a large texture and printed the default limit whatever --max-memory said.
TEST(TrustValues, InfoReadsTheSceneUnderMaxMemoryAndCountsItsTextures) {
    ScratchDir dir;
    Image8 texture;
    texture.width = 1024;
    texture.height = 1024;
    texture.channels = 4;
    texture.pixels.assign(std::size_t(1024) * 1024 * 4, 255);
    writePng(dir.file("big.png"), texture);
    writeText(dir.file("scene.json"), texturedScene("\"big.png\""));
    const CliResult refused = runStsv({"info", dir.file("scene.json"), "--max-memory", "2M"});
    EXPECT_EQ(refused.code, 1) << refused.out;
    EXPECT_NE(refused.err.find("memory limit of 2.0 MiB"), std::string::npos) << refused.err;
    const CliResult j = runStsv({"info", dir.file("scene.json"), "--max-memory", "512M", "--json"});
    ASSERT_EQ(j.code, 0) << j.err;
    const nlohmann::json memory = nlohmann::json::parse(j.out)["memory"];
    EXPECT_EQ(memory["limit_bytes"], 512u << 20) << memory.dump();
    // The texels alone: 1024 × 1024 RGBA8.
    EXPECT_GE(memory["texture_bytes"].get<double>(), 4.0 * 1024 * 1024) << memory.dump();
    EXPECT_GE(memory["scene_bytes"].get<double>(), 4.0 * 1024 * 1024) << memory.dump();
    const CliResult text = runStsv({"info", dir.file("scene.json"), "--max-memory", "512M"});
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("(textures 4.0 MiB)"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("limit 512.0 MiB (--max-memory)"), std::string::npos) << text.out;
}

// `stsv info` said "buffers: bitmask, counters" and "(or counters)" for every method, never
// transmittance: both come from the method table, so a new row is described as it is.
TEST(TrustValues, InfoSaysWhatEachRowWritesFromTheTable) {
    const CliResult r = runStsv({"info"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::vector<BufferKind> every = {BufferKind::Bitmask, BufferKind::Counters,
                                           BufferKind::Transmittance};
    std::vector<bool> written(every.size(), false);
    for (const MethodInfo& m : methodTable()) {
        // What the row holds for each --buffer it takes (transmittance where it writes that), as
        // its fields say.
        std::vector<std::string> kinds;
        for (std::size_t i = 0; i < every.size() && m.output != MethodOutput::Visibility; ++i) {
            if (every[i] == BufferKind::Transmittance && !m.writesTransmittance()) continue;
            const BufferKind held = m.bufferKind(every[i]);
            written[std::size_t(held)] = true;
            if (std::find(kinds.begin(), kinds.end(), toString(held)) == kinds.end())
                kinds.push_back(toString(held));
        }
        std::string expected = "writes ";
        if (kinds.empty()) expected += "visibility image";
        for (std::size_t i = 0; i < kinds.size(); ++i)
            expected += (i == 0 ? "per-sample " : i + 1 == kinds.size() ? " or " : ", ") + kinds[i];
        const std::size_t row = r.out.find("  " + m.name + ": " + m.description + "\n");
        ASSERT_NE(row, std::string::npos) << m.name;
        const std::size_t next = r.out.find('\n', row + 3 + m.name.size() + m.description.size());
        const std::string line = r.out.substr(next + 1, r.out.find('\n', next + 1) - next - 1);
        EXPECT_NE(line.find(expected), std::string::npos)
            << m.name << ": '" << line << "' lacks '" << expected << "'";
        EXPECT_EQ(line.find("transmittance") != std::string::npos, m.writesTransmittance())
            << m.name << ": " << line;
    }
    std::string buffers = "buffers:   ";
    for (std::size_t i = 0, listed = 0, total = std::size_t(std::count(written.begin(), written.end(), true));
         i < every.size(); ++i)
        if (written[i]) {
            buffers += std::string(listed == 0           ? ""
                                   : listed + 1 == total ? " and "
                                                         : ", ") +
                       toString(every[i]);
            ++listed;
        }
    EXPECT_NE(r.out.find(buffers + " (--buffer"), std::string::npos) << "lacks '" << buffers << "':\n"
                                                                     << r.out;
}

// compare's footnote listed the n/a rows' methods by a substring test: after vpcss, pcss was
// "already there". It names each n/a row's method.
TEST(TrustValues, CompareFootnoteNamesEveryNotApplicableRow) {
    const CliResult r = runStsv({"compare", "fence", "--methods", "vpcss/cpu,pcss/cpu,stsv/cpu", "--size",
                                 "16x12", "--samples", "16", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("n/a: vpcss, pcss give(s) a v_coef per pixel"), std::string::npos) << r.out;
}

// A malformed VK_DRIVER_FILES manifest gave "VK_ERROR_OUT_OF_HOST_MEMORY at gpu/device.cpp:112"
// (garbage) or "no Vulkan driver was found" (a manifest without its keys): the message names the
// variable, the manifest and what is wrong with it.
TEST(TrustValues, AMalformedDriverManifestIsNamed) {
    ScratchDir dir;
    writeText(dir.file("garbage.json"), "garbage");
    writeText(dir.file("empty.json"), "{}");
    writeText(dir.file("no_icd.json"), R"({"file_format_version": "1.0.0"})");
    writeText(dir.file("no_library.json"),
              R"({"file_format_version": "1.0.0", "ICD": {"library_path": "./libvulkan_none.so"}})");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"garbage.json", "is not valid JSON"},
        {"empty.json", "lacks \"file_format_version\""},
        {"no_icd.json", "lacks the \"ICD\" object"},
        {"no_library.json",
         "names the driver library " + dir.file("libvulkan_none.so") + ", which does not exist"},
    };
    for (const auto& [file, problem] : cases) {
        ScopedEnv drivers("VK_DRIVER_FILES", dir.file(file));
        ScopedEnv icd("VK_ICD_FILENAMES", dir.file(file));
        const std::vector<std::string> args = {"render", "fence", "--backend",       "vulkan", "--size",
                                               "8x8",    "-o",    dir.file("v.png"), "-q"};
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        const std::string expected =
            "VK_DRIVER_FILES names the Vulkan driver manifest " + dir.file(file) + ", which " + problem;
        EXPECT_NE(r.err.find(expected), std::string::npos) << "lacks '" << expected << "'\n"
                                                           << describe(args, r);
        EXPECT_NE(r.err.find("--backend cpu"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
}

/// The frame memory `stsv info fence` estimates (memory.frame_bytes of --json) for `extra`, MiB.
double infoFrameMiB(const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"info", "fence", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json info = nlohmann::json::parse(r.out, nullptr, false);
    if (!info.contains("memory")) {
        ADD_FAILURE() << "no memory estimate\n" << describe(args, r);
        return 0.0;
    }
    return info["memory"]["frame_bytes"].get<double>() / double(1 << 20);
}

// The frame estimate counted one float a texel on six faces for every image-based method: csm at
// sm_size=2048 was estimated at 96 MiB and peaked at 1.5 GiB, and sm_size=4096 passed
// --max-memory. Each map method's estimate now grows from its smallest map to the large one as
// the peak resident size measured on fence did (MiB, /usr/bin/time -v, the numbers and the
// commands at estimateFrameBytes in cli/cli_util.cpp): not below 0.9 of it (a few MiB of
// measurement noise on the small Vulkan maps) and not above 1.6 times it (Vulkan's AVSM fragment
// lists are allocated whole and touched in part). A --max-memory between the old estimate and
// the new one refuses csm in render, compare and bench before anything is rendered.
TEST(TrustValues, TheFrameEstimateCoversEachMapMethodsMeasuredPeak) {
    struct Measured {
        const char* backend;
        const char* method;
        const char* small; ///< the baseline map
        const char* large;
        double peakMiB;              ///< peak resident size at `large` less that at `small`
        const char* extra = nullptr; ///< another --param of both renders
    };
    const std::vector<Measured> measured = {
        {"cpu", "pcf", "sm_size=256", "sm_size=4096", 61.1},
        {"cpu", "pcss", "sm_size=256", "sm_size=4096", 61.1},
        {"cpu", "vsm", "sm_size=256", "sm_size=4096", 360.4},
        {"cpu", "vsm", "sm_size=256", "sm_size=4096", 445.9, "fm_mip=0"},
        {"cpu", "esm", "sm_size=256", "sm_size=4096", 210.4},
        {"cpu", "evsm", "sm_size=256", "sm_size=4096", 658.6},
        {"cpu", "msm", "sm_size=256", "sm_size=4096", 828.9},
        {"cpu", "csm", "sm_size=256", "sm_size=4096", 6185.7},
        {"cpu", "peel", "peel_size=16", "peel_size=2048", 542.2},
        {"cpu", "avsm", "avsm_size=256", "avsm_size=4096", 1099.7},
        {"cpu", "vpcss", "avsm_size=256", "avsm_size=4096", 1099.6},
        {"vulkan", "pcf", "sm_size=256", "sm_size=4096", 58.2},
        {"vulkan", "pcss", "sm_size=256", "sm_size=4096", 68.1},
        {"vulkan", "vsm", "sm_size=256", "sm_size=4096", 202.5},
        {"vulkan", "vsm", "sm_size=256", "sm_size=4096", 292.1, "fm_mip=0"},
        {"vulkan", "esm", "sm_size=256", "sm_size=4096", 151.6},
        {"vulkan", "evsm", "sm_size=256", "sm_size=4096", 407.0},
        {"vulkan", "msm", "sm_size=256", "sm_size=4096", 578.0},
        {"vulkan", "csm", "sm_size=256", "sm_size=2048", 1025.2}, // 4096: over one Vulkan allocation
        {"vulkan", "peel", "peel_size=16", "peel_size=2048", 534.8},
        {"vulkan", "avsm", "avsm_size=256", "avsm_size=4096", 1414.4},
        {"vulkan", "vpcss", "avsm_size=256", "avsm_size=4096", 1412.2},
    };
    for (const Measured& m : measured) {
        const std::vector<std::string> row = {"--method", m.method, "--backend", m.backend, "--param"};
        std::vector<std::string> small = row, large = row;
        small.push_back(m.small);
        large.push_back(m.large);
        if (m.extra) {
            for (std::vector<std::string>* args : {&small, &large}) {
                args->push_back("--param");
                args->push_back(m.extra);
            }
        }
        const double grows = infoFrameMiB(large) - infoFrameMiB(small);
        const std::string what = std::string(m.method) + " on " + m.backend +
                                 (m.extra ? std::string(" with ") + m.extra : std::string()) + " from " +
                                 m.small + " to " + m.large + ": estimated " + std::to_string(grows) +
                                 " MiB, measured " + std::to_string(m.peakMiB);
        EXPECT_GE(grows, 0.9 * m.peakMiB) << what;
        EXPECT_LE(grows, 1.6 * m.peakMiB) << what;
    }
    for (const char* backend : {"cpu", "vulkan"})
        EXPECT_GT(infoFrameMiB({"--method", "csm", "--backend", backend}), 1024.0) << backend;

    // 512 MiB: above the old estimate of csm's frame (109 MiB), below the new (1.5 GiB).
    ScratchDir dir;
    const std::vector<std::vector<std::string>> commands = {
        {"render", "fence", "--method", "csm", "--backend", "cpu", "-o", dir.file("csm.png")},
        {"compare", "fence", "--methods", "csm/cpu", "--against", "pcf/cpu"},
        {"bench", "fence", "--methods", "pcf,csm", "--backends", "cpu", "--repeat", "1", "--warmup", "0"},
    };
    for (std::vector<std::string> args : commands) {
        for (const std::string extra : {"--size", "64x48", "--samples", "16", "--max-memory", "512M", "-q"})
            args.push_back(extra);
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find("frame of csm on cpu"), std::string::npos) << describe(args, r);
        EXPECT_NE(r.err.find("above the memory limit of 512.0 MiB"), std::string::npos) << describe(args, r);
    }
}

/// Sets the child's address space to what it uses now plus `extra` bytes (for runStsvWithin).
void limitAddressSpace(std::size_t extra) {
    std::ifstream statm("/proc/self/statm");
    std::size_t pages = 0;
    statm >> pages;
    struct rlimit limit {};
    ::getrlimit(RLIMIT_AS, &limit);
    limit.rlim_cur = rlim_t(pages * std::size_t(::sysconf(_SC_PAGESIZE)) + extra);
    ::setrlimit(RLIMIT_AS, &limit);
}

// A value of 60,000 nested brackets given to --light, --add-light, --set or --param reached 3 GiB
// in 3 s inside CLI11, which splits a bracketed value one level at a time and copies the rest at
// each. An argument nested deeper than 64 levels is refused before CLI11 reads it, naming the
// option (in a child held to 1 GiB more address space, which CLI11 ran into before).
TEST(TrustValues, AnArgumentNestedTooDeepIsRefusedBeforeParsing) {
    const std::string deep = std::string(60000, '[') + std::string(60000, ']');
    const std::vector<std::vector<std::string>> cases = {
        {"render", "fence", "--light", deep},    {"render", "fence", "--add-light", deep},
        {"render", "fence", "--set", deep},      {"render", "fence", "--method", "pcss", "--param", deep},
        {"render", "fence", "--camera=" + deep}, {"bench", "fence", "--set", deep},
        {"compare", "fence", "--light", deep},   {"info", "fence", "--param", deep},
    };
    for (std::vector<std::string> args : cases) {
        const std::string option = args[2].starts_with("--camera") ? "--camera" : args[args.size() - 2];
        for (const std::string extra : {"--backend", "cpu", "--size", "8x8", "-q"}) args.push_back(extra);
        const CliResult r = runStsvWithin(60, args, [] { limitAddressSpace(std::size_t(1) << 30); });
        const std::string shown = args[0] + " " + option + " (60000 brackets deep)";
        EXPECT_EQ(r.code, 1) << shown << "\n" << r.err;
        const std::string expected =
            option + ": the value nests brackets 60000 levels deep, more than the 64";
        EXPECT_NE(r.err.find(expected), std::string::npos) << "lacks '" << expected << "'\n" << r.err;
    }
    // 64 levels are the JSON reader's to judge, as before.
    const std::string nested64 = std::string(64, '[') + std::string(64, ']');
    const CliResult r = runStsv({"render", "fence", "--light", nested64, "--backend", "cpu", "-q"});
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_EQ(r.err.find("nests brackets"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--light"), std::string::npos) << r.err;
}

// When memory ran out while CLI11 read the arguments, the message quoted the default limit
// (half of this machine's memory) although --max-memory 1G was given: the limit is set from the
// arguments before anything can quote it. Here a 64 MiB argument that a child with 16 MiB of
// address space to spare cannot copy.
TEST(TrustValues, OutOfMemoryWhileReadingTheArgumentsQuotesTheLimitGiven) {
    const std::vector<std::string> args = {"render",    "fence", "--max-memory",
                                           "1G",        "--set", "count=" + std::string(64 << 20, '1'),
                                           "--backend", "cpu"};
    const CliResult r = runStsvWithin(60, args, [] { limitAddressSpace(std::size_t(16) << 20); });
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("stsv: error: out of memory"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("memory limit of 1.0 GiB (--max-memory)"), std::string::npos) << r.err;
}

// A scene whose only triangle had collinear corners rendered an all-background image with exit 0,
// and info said "faces skipped as degenerate: 0". It is refused naming the file; beside a
// triangle with area, info and --stats count the triangles of zero area.
TEST(TrustValues, ZeroAreaTrianglesAreCountedAndASceneOfNothingElseIsRefused) {
    ScratchDir dir;
    const std::string scene = R"({"materials": [{"name": "floor"}],
        "lights": [{"type": "sphere", "position": [0, 4, 0], "radius": 0.5, "radiance": 40}],
        "camera": {"eye": [0, 3, 6], "target": [0, 0, 0]},
        "meshes": [{"name": "d", "material": "floor", "vertices": [[0, 0, 0], [1, 0, 0], [2, 0, 0]],
                    "triangles": [[0, 1, 2]]})";
    writeText(dir.file("flat.json"), scene + "]}");
    const CliResult flat = runStsv({"render", dir.file("flat.json"), "--backend", "cpu", "--size", "8x8",
                                    "-o", dir.file("flat.png"), "-q"});
    EXPECT_EQ(flat.code, 1) << flat.err;
    EXPECT_NE(flat.err.find(dir.file("flat.json") + ": every triangle is degenerate"), std::string::npos)
        << flat.err;
    EXPECT_FALSE(fs::exists(dir.file("flat.png")));

    writeText(dir.file("mixed.json"), scene + R"(, {"quad": {"size": [8, 8]}, "material": "floor",
        "transform": {"euler": [-90, 0, 0]}}]})");
    const CliResult info = runStsv({"info", dir.file("mixed.json")});
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("faces skipped as degenerate: 0; triangles of zero area"), std::string::npos)
        << info.out;
    const CliResult render = runStsv({"render", dir.file("mixed.json"), "--backend", "cpu", "--size", "8x8",
                                      "--stats", dir.file("s.json"), "-q"});
    ASSERT_EQ(render.code, 0) << render.err;
    EXPECT_EQ(readJson(dir.file("s.json"))["scene"]["zero_area_triangles"], 1) << render.err;
    EXPECT_EQ(readJson(dir.file("s.json"))["scene"]["skipped_faces"], 0) << render.err;
}

// `--methods stsv,`, `--samples 16,,32` and `--vary repeat=1,,2` ran as if the empty item were
// not there: every list option refuses an empty item, naming the option.
TEST(TrustValues, EveryListOptionRefusesAnEmptyItem) {
    const std::vector<std::string> bench = {"bench", "fence",    "--size", "8x8", "--repeat",
                                            "1",     "--warmup", "0",      "-q"};
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--methods", "stsv,"}, "--methods 'stsv,': item 2 is empty"},
        {{"--methods", ",stsv"}, "--methods ',stsv': item 1 is empty"},
        {{"--backends", "cpu,,cpu"}, "--backends 'cpu,,cpu': item 2 is empty"},
        {{"--samples", "16,,32"}, "--samples '16,,32': item 2 is empty"},
        {{"--samples", "16,"}, "--samples '16,': item 2 is empty"},
        {{"--vary", "repeat=1,,2"}, "--vary '1,,2': item 2 is empty"},
        {{"--extrusion", "hull,"}, "--extrusion 'hull,': item 2 is empty"},
    };
    for (const auto& [options, expected] : cases) {
        std::vector<std::string> args = bench;
        args.insert(args.end(), options.begin(), options.end());
        if (options[0] != "--backends") args.insert(args.end(), {"--backends", "cpu"});
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find(expected), std::string::npos) << "lacks '" << expected << "'\n"
                                                           << describe(args, r);
    }
    for (const std::string methods : {"stsv/cpu,", "stsv/cpu,,reference/cpu"}) {
        const std::vector<std::string> args = {"compare",   "fence", "--size", "8x8",
                                               "--methods", methods, "-q"};
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find("--methods '" + methods + "': item 2 is empty"), std::string::npos)
            << describe(args, r);
    }
}

// Text quoted from input that holds a NUL byte (a JSON string "\u0000") was cut at the NUL, as
// the user guide's \xNN escapes promise it is not: the whole message arrives, the NUL as \x00.
TEST(TrustValues, ANulByteInQuotedInputIsEscapedNotTheEndOfTheMessage) {
    ScratchDir dir;
    writeText(dir.file("nul.json"), texturedScene(R"("a\u0000b.png")"));
    const CliResult r = runStsv({"render", dir.file("nul.json"), "--backend", "cpu", "--size", "8x8", "-q"});
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.err.find("a\\x00b.png"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\0'), std::string::npos) << r.err;
}

} // namespace
} // namespace stsv::test
