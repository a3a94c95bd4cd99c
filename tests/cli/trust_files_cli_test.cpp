// What the command line reads and writes, as a user can rely on it: a light-sample file says what
// it holds and compare refuses two that do not pair; no command writes over its own inputs or one
// output over another; an output that is no regular file (a FIFO, a device) is refused before any
// work instead of blocking or vanishing; and every file written is named.
#include "cli_test_util.h"

#include "core/image.h"
#include "sampling/ls_buffer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace stsv::test {
namespace {

namespace fs = std::filesystem;

/// `stsv render fence` on the CPU with `extra` options; fails the test when it does not exit 0.
void renderFence(const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"render", "fence", "--backend", "cpu", "--size", "24x16", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    // STSV unless another method is named: its bitmask follows --buffer.
    if (std::find(extra.begin(), extra.end(), "--method") == extra.end())
        args.insert(args.end(), {"--method", "stsv"});
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
}

/// A python3 with NumPy ("python3", else Debian's /usr/bin/python3); empty when there is none.
std::string pythonWithNumpy() {
    for (const char* python : {"python3", "/usr/bin/python3"})
        if (runShell(std::string(python) + " -c 'import numpy'").code == 0) return python;
    return {};
}

// A 16-sample counters dump and a 128-sample bitmask dump are both uint8 [H, W, 16]: read by
// shape, they compared as two bitmasks ("97 % identical"). Each file now says what it holds, and
// compare refuses the pair, naming both.
TEST(TrustFiles, CompareRefusesLightSampleFilesOfAnotherKindOrSampleCount) {
    ScratchDir dir;
    renderFence({"--buffer", "counters", "--samples", "16", "--dump-ls", dir.file("counters16.npy")});
    renderFence({"--buffer", "bitmask", "--samples", "128", "--dump-ls", dir.file("bits128.npy")});
    ASSERT_EQ(readNpy(dir.file("counters16.npy")).shape, readNpy(dir.file("bits128.npy")).shape);
    const std::vector<std::string> args = {"compare", dir.file("counters16.npy"), dir.file("bits128.npy")};
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 1) << describe(args, r);
    for (const std::string& text : {dir.file("counters16.npy") + " holds counters of 16 samples (stsv/cpu)",
                                    dir.file("bits128.npy") + " a bitmask of 128 samples (stsv/cpu)"})
        EXPECT_NE(r.err.find(text), std::string::npos) << "lacks '" << text << "'\n" << describe(args, r);
    EXPECT_EQ(r.out.find("identical"), std::string::npos) << r.out;

    // One kind, another sample count: refused too; the same kind and count compare.
    renderFence({"--buffer", "bitmask", "--samples", "16", "--dump-ls", dir.file("bits16.npy")});
    const CliResult counts = runStsv({"compare", dir.file("bits16.npy"), dir.file("bits128.npy")});
    EXPECT_EQ(counts.code, 1) << counts.out;
    EXPECT_NE(counts.err.find("a bitmask of 16 samples"), std::string::npos) << counts.err;
    renderFence(
        {"--buffer", "counters", "--samples", "16", "--seed", "2", "--dump-ls", dir.file("counters16b.npy")});
    const CliResult same = runStsv({"compare", dir.file("counters16.npy"), dir.file("counters16b.npy")});
    ASSERT_EQ(same.code, 0) << same.err;
    EXPECT_NE(same.out.find("24x16 pixels, 16 samples, counters"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("written by stsv/cpu and stsv/cpu"), std::string::npos) << same.out;
    // --samples, where given, is a count both files must hold.
    const CliResult wrongCount =
        runStsv({"compare", dir.file("counters16.npy"), dir.file("counters16b.npy"), "--samples", "64"});
    EXPECT_EQ(wrongCount.code, 1);
    EXPECT_NE(wrongCount.err.find("--samples 64"), std::string::npos) << wrongCount.err;
}

// The metadata is a JSON file beside the array (NumPy's reader refuses any .npy header key but
// descr, fortran_order and shape): the array still loads in NumPy, and the JSON says the kind, N
// and the method.
TEST(TrustFiles, LightSampleMetadataSitsBesideAnArrayNumpyStillLoads) {
    ScratchDir dir;
    renderFence({"--method", "dcs", "--samples", "16", "--dump-ls", dir.file("dcs.npy"), "--visibility",
                 dir.file("v.npy")});
    const nlohmann::json info = readJson(dir.file("dcs.npy.json"));
    EXPECT_EQ(info["kind"], "counters") << info.dump();
    EXPECT_EQ(info["samples"], 16) << info.dump();
    EXPECT_EQ(info["width"], 24) << info.dump();
    EXPECT_EQ(info["height"], 16) << info.dump();
    EXPECT_EQ(info["method"], "dcs/cpu") << info.dump();
    const nlohmann::json visibility = readJson(dir.file("v.npy.json"));
    EXPECT_EQ(visibility["samples"], 16) << visibility.dump();
    EXPECT_EQ(visibility["method"], "dcs/cpu") << visibility.dump();
    const std::string python = pythonWithNumpy();
    if (python.empty()) GTEST_SKIP() << "no python3 with NumPy to load the arrays with";
    const ShellResult loaded = runShell(python +
                                        " -c \"import numpy, sys; a = numpy.load(sys.argv[1]); "
                                        "v = numpy.load(sys.argv[2]); print(a.dtype, a.shape, v.shape)\" '" +
                                        dir.file("dcs.npy") + "' '" + dir.file("v.npy") + "'");
    EXPECT_EQ(loaded.code, 0) << loaded.out;
    EXPECT_NE(loaded.out.find("uint8 (16, 24, 16) (16, 24)"), std::string::npos) << loaded.out;
}

// A dump from before the metadata (or an array from NumPy) does not say what its uint8 holds:
// compare asks for --kind instead of guessing, and --kind must agree with metadata where it exists.
TEST(TrustFiles, AFileWithoutMetadataNeedsKind) {
    ScratchDir dir;
    renderFence({"--buffer", "counters", "--samples", "16", "--dump-ls", dir.file("a.npy")});
    renderFence({"--buffer", "counters", "--samples", "16", "--seed", "3", "--dump-ls", dir.file("b.npy")});
    fs::remove(dir.file("b.npy.json"));
    const CliResult guessed = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy")});
    EXPECT_EQ(guessed.code, 1) << guessed.out;
    EXPECT_NE(guessed.err.find(dir.file("b.npy") + " has no b.npy.json beside it"), std::string::npos)
        << guessed.err;
    EXPECT_NE(guessed.err.find("--kind bitmask or --kind counters"), std::string::npos) << guessed.err;
    const CliResult told = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy"), "--kind", "counters"});
    ASSERT_EQ(told.code, 0) << told.err;
    EXPECT_NE(told.out.find("24x16 pixels, 16 samples, counters"), std::string::npos) << told.out;
    // Read as bits, the 16 counters of b would be 128 samples: refused as another count.
    const CliResult wrong = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy"), "--kind", "bitmask"});
    EXPECT_EQ(wrong.code, 1) << wrong.out;
    EXPECT_NE(wrong.err.find("--kind bitmask: " + dir.file("a.npy") + " holds counters (a.npy.json says so)"),
              std::string::npos)
        << wrong.err;
    // Metadata of another array (a file NumPy overwrote) is refused, not believed.
    writeText(
        dir.file("b.npy.json"),
        R"({"format": "stsv light samples", "kind": "counters", "samples": 64, "width": 24, "height": 16})");
    const CliResult stale = runStsv({"compare", dir.file("a.npy"), dir.file("b.npy")});
    EXPECT_EQ(stale.code, 1) << stale.out;
    EXPECT_NE(stale.err.find("another array's"), std::string::npos) << stale.err;
}

// `compare --sheet s.png --json s.png` wrote the JSON into s.png and said it wrote a sheet; and
// no command wrote over a file it reads.
TEST(TrustFiles, EveryCommandRefusesTwoOutputsOnOnePathAndAnOutputThatIsAnInput) {
    ScratchDir dir;
    writeText(
        dir.file("scene.json"),
        R"({"materials": [{"name": "m"}], "meshes": [{"quad": {"size": [1, 1]}, "material": "m"}], )"
        R"("lights": [{"type": "rectangle", "position": [0, 3, 0], "normal": [0, -1, 0], "size": [1, 1], )"
        R"("radiance": [1, 1, 1]}]})");
    const std::string scene = readText(dir.file("scene.json"));
    writeText(dir.file("presets.json"), R"({"tiny": {"scene": "fence", "size": "8x8"}})");
    struct Case {
        std::vector<std::string> args;
        std::string expected;
    };
    const std::vector<Case> cases = {
        // The probe itself: refused, whichever of the two checks a path meets first.
        {{"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8", "--sheet", dir.file("s.png"),
          "--json", dir.file("./s.png")},
         "--json " + dir.file("./s.png")},
        {{"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8", "--out", dir.file("d"), "--report",
          dir.file("d")},
         "names the same file"},
        {{"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8", "--out", dir.file("d"), "--sheet",
          dir.file("d/stsv_cpu_lit.png")},
         "names the same file"},
        {{"compare", dir.file("scene.json"), "--methods", "stsv/cpu", "--size", "8x8", "--json",
          dir.file("scene.json")},
         "is the scene"},
        {{"render", dir.file("scene.json"), "--backend", "cpu", "--size", "8x8", "--stats",
          dir.file("scene.json")},
         "is the scene"},
        {{"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16", "--dump-ls",
          dir.file("x.npy"), "--stats", dir.file("x.npy.json")},
         "names the same file"},
        {{"bench", "--preset", "tiny", "--presets", dir.file("presets.json"), "--json",
          dir.file("presets.json")},
         "is the presets file"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = c.args;
        args.push_back("-q");
        const CliResult r = runStsv(args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << "lacks '" << c.expected << "'\n"
                                                             << describe(args, r);
    }
    EXPECT_FALSE(fs::exists(dir.file("s.png")));
    EXPECT_EQ(readText(dir.file("scene.json")), scene) << "an input was written over";
    EXPECT_TRUE(readJson(dir.file("presets.json")).contains("tiny"));
}

// An output that is a FIFO without a reader blocked the write forever, and one that is a device
// (/dev/null behind a .png name) took the picture nowhere: both are refused before any work,
// as inputs that are not regular files are, for every output option.
TEST(TrustFiles, OutputsThatAreNotRegularFilesAreRefusedBeforeAnyWork) {
    ScratchDir dir;
    ASSERT_EQ(::mkfifo(dir.file("fifo.png").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo(dir.file("fifo.json").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo(dir.file("fifo.npy").c_str(), 0600), 0);
    const std::vector<std::vector<std::string>> commands = {
        {"render", "fence", "--backend", "cpu", "--size", "8x8", "-o", dir.file("fifo.png")},
        {"render", "fence", "--backend", "cpu", "--size", "8x8", "--stats", dir.file("fifo.json")},
        {"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16", "--dump-ls",
         dir.file("fifo.npy")},
        {"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8", "--json", dir.file("fifo.json")},
        {"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8", "--sheet", dir.file("fifo.png")},
        {"bench", "fence", "--methods", "stsv", "--backends", "cpu", "--size", "8x8", "--json",
         dir.file("fifo.json")},
    };
    for (std::vector<std::string> args : commands) {
        args.push_back("-q");
        const CliResult r = runStsvWithin(30, args);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find("is a device, pipe or socket, not a regular file"), std::string::npos)
            << describe(args, r);
    }
    // A device behind an output's name.
    fs::create_symlink("/dev/null", dir.file("null.png"));
    const CliResult device =
        runStsv({"render", "fence", "--backend", "cpu", "--size", "8x8", "-o", dir.file("null.png"), "-q"});
    EXPECT_EQ(device.code, 1) << device.out;
    EXPECT_NE(device.err.find("-o " + dir.file("null.png") + ": is a device, pipe or socket"),
              std::string::npos)
        << device.err;
}

// A write that fails part way (a file size limit here, as a full disk would) is an error, not the
// usual summary with exit 0. RLIMIT_FSIZE stops every write to a regular file past 512 bytes with
// EFBIG once SIGXFSZ is ignored; the one-line message to stderr stays below it.
TEST(TrustFiles, AFailedWriteIsAnError) {
    ScratchDir dir;
    struct rlimit old {};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*oldHandler)(int) = std::signal(SIGXFSZ, SIG_IGN);
    for (const std::string option : {"-o", "--visibility", "--stats", "--dump-ls"}) {
        const std::string name = option == "--stats"     ? "big.json"
                                 : option == "--dump-ls" ? "big.npy"
                                                         : "big.png";
        const std::vector<std::string> args = {"render", "fence",        "--backend", "cpu",
                                               "--size", "128x128",      "--samples", "16",
                                               option,   dir.file(name), "-q"};
        struct rlimit limit = old;
        limit.rlim_cur = 512;
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
        const CliResult r = runStsv(args);
        ::setrlimit(RLIMIT_FSIZE, &old);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_NE(r.err.find("File too large"), std::string::npos) << describe(args, r);
        EXPECT_EQ(r.err.rfind("stsv: error: ", 0), 0u) << describe(args, r);
    }
    std::signal(SIGXFSZ, oldHandler);
}

/// The files under `dir`, with their sizes.
std::vector<std::pair<std::string, std::uintmax_t>> filesUnder(const fs::path& dir) {
    std::vector<std::pair<std::string, std::uintmax_t>> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file()) files.emplace_back(e.path().string(), e.file_size());
    return files;
}

// Under a file size limit (ulimit -f) as a shell starts it, with SIGXFSZ at its default, the
// first write past the limit killed stsv with that signal and left the partial file behind. Every
// writer (PNG, EXR, NPY and its metadata, the stats and bench JSON, the HTML report and its
// images, the contact sheet) now fails with the one-line error and leaves no partial file: no
// file in the folder reaches the limit, and the output named is not there (nor, for a .npy, its
// metadata).
TEST(TrustFiles, AFileSizeLimitIsAnErrorThatLeavesNoPartialFile) {
    ScratchDir dir;
    constexpr rlim_t kLimit = 1024;
    auto limited = [&dir] {
        fs::current_path(dir.path()); // a file written where no option named lands here too
        std::signal(SIGXFSZ, SIG_DFL);
        struct rlimit limit {};
        ::getrlimit(RLIMIT_FSIZE, &limit);
        limit.rlim_cur = kLimit;
        ::setrlimit(RLIMIT_FSIZE, &limit);
    };
    const std::vector<std::string> render = {"render", "fence",     "--backend", "cpu", "--size",
                                             "96x64",  "--samples", "16",        "-q"};
    const std::vector<std::string> compare = {"compare", "fence",     "--methods", "stsv/cpu", "--size",
                                              "96x64",   "--samples", "16",        "-q"};
    struct Case {
        std::vector<std::string> command;
        std::vector<std::string> options;
        std::string output; ///< a file or folder the command names, which must not be left
    };
    const std::vector<Case> cases = {
        {render, {"-o", dir.file("lit.png")}, "lit.png"},
        {render, {"-o", dir.file("lit.exr")}, "lit.exr"},
        {render, {"--visibility", dir.file("v.npy")}, "v.npy"},
        {render, {"--dump-ls", dir.file("ls.npy")}, "ls.npy"},
        // --shadow-map alone writes SCENE.png as well: an 8x8 one, below the limit, comes first.
        {{"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16", "-q"},
         {"--method", "pcf", "--shadow-map", dir.file("map.npy")},
         "map.npy"},
        {render, {"--stats", dir.file("stats.json")}, "stats.json"},
        {{"bench", "fence", "--methods", "stsv", "--backends", "cpu", "--size", "8x8", "--samples", "16",
          "--repeat", "1", "--warmup", "0", "-q"},
         {"--json", dir.file("bench.json")},
         "bench.json"},
        {compare, {"--json", dir.file("compare.json")}, "compare.json"},
        {compare, {"--sheet", dir.file("sheet.png")}, "sheet.png"},
        {compare, {"--report", dir.file("report")}, "report/index.html"},
        {compare, {"--out", dir.file("images")}, "images/stsv_cpu_lit.png"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = c.command;
        args.insert(args.end(), c.options.begin(), c.options.end());
        const CliResult r = runStsvWithin(120, args, limited);
        EXPECT_EQ(r.code, 1) << describe(args, r);
        EXPECT_EQ(r.err.rfind("stsv: error: ", 0), 0u) << describe(args, r);
        EXPECT_NE(r.err.find("File too large"), std::string::npos) << describe(args, r);
        EXPECT_FALSE(fs::exists(dir.file(c.output))) << c.output << " was left\n" << describe(args, r);
        EXPECT_FALSE(fs::exists(dir.file(c.output + ".json"))) << c.output << ".json was left";
        for (const auto& [file, size] : filesUnder(dir.path()))
            EXPECT_LT(size, kLimit) << file << " is a partial file of " << size << " bytes\n"
                                    << describe(args, r);
    }
}

// VK_DRIVER_FILES (or VK_ICD_FILENAMES) naming a FIFO, alone or in a folder of manifests, made
// the Vulkan loader's fopen wait for a writer for ever inside vkCreateInstance: `info` and a
// Vulkan render hung. Each entry of the loader's manifest variables is checked first: a FIFO is
// refused naming the variable and the entry (info says Vulkan is unavailable, and why).
TEST(TrustFiles, AVulkanManifestVariableNamingAFifoIsRefusedNotWaitedOn) {
    ScratchDir dir;
    ASSERT_EQ(::mkfifo(dir.file("icd.json").c_str(), 0600), 0);
    fs::create_directories(dir.file("icd.d"));
    ASSERT_EQ(::mkfifo(dir.file("icd.d/lvp.json").c_str(), 0600), 0);
    const std::vector<std::pair<std::string, std::string>> settings = {
        {"VK_DRIVER_FILES", dir.file("icd.json")},
        {"VK_ICD_FILENAMES", "/no/such/manifest.json:" + dir.file("icd.json")},
        {"VK_DRIVER_FILES", dir.file("icd.d")},
        {"VK_LAYER_PATH", dir.file("icd.json")},
    };
    for (const auto& [variable, value] : settings) {
        const std::string entry =
            value.ends_with("icd.d") ? dir.file("icd.d/lvp.json") : dir.file("icd.json");
        auto setting = [variable = variable, value = value] { ::setenv(variable.c_str(), value.c_str(), 1); };
        const std::vector<std::string> render = {"render", "fence", "--backend",       "vulkan", "--size",
                                                 "8x8",    "-o",    dir.file("v.png"), "-q"};
        const CliResult r = runStsvWithin(60, render, setting);
        EXPECT_EQ(r.code, 1) << variable << "=" << value << "\n" << describe(render, r);
        EXPECT_NE(r.err.find(variable + " names "), std::string::npos) << describe(render, r);
        EXPECT_NE(r.err.find(entry + ", which is a device, pipe or socket"), std::string::npos)
            << describe(render, r);
        const CliResult info = runStsvWithin(60, {"info"}, setting);
        EXPECT_EQ(info.code, 0) << variable << "=" << value << "\n" << describe({"info"}, info);
        EXPECT_NE(info.out.find("vulkan: unavailable"), std::string::npos) << info.out;
        EXPECT_NE(info.out.find(entry), std::string::npos) << info.out;
    }
}

// `render` without -o wrote SCENE.png into the current directory and said nothing: each file a
// command writes is named, once, unless -q.
TEST(TrustFiles, EveryFileWrittenIsNamed) {
    ScratchDir dir;
    const fs::path before = fs::current_path();
    fs::current_path(dir.path());
    const CliResult r = runStsv({"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16"});
    const CliResult quiet = runStsv(
        {"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16", "-o", "q.png", "-q"});
    fs::current_path(before);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir.file("fence.png")));
    EXPECT_NE(r.err.find("wrote fence.png\n"), std::string::npos) << r.err;
    ASSERT_EQ(quiet.code, 0) << quiet.err;
    EXPECT_EQ(quiet.err.find("wrote"), std::string::npos) << quiet.err;

    const CliResult all = runStsv({"render", "fence", "--backend", "cpu", "--size", "8x8", "--samples", "16",
                                   "-o", dir.file("l.png"), "--visibility", dir.file("v.npy"), "--dump-ls",
                                   dir.file("ls.npy"), "--stats", dir.file("s.json")});
    ASSERT_EQ(all.code, 0) << all.err;
    for (const std::string file : {"l.png", "v.npy", "v.npy.json", "ls.npy", "ls.npy.json", "s.json"}) {
        const std::string line = "wrote " + dir.file(file) + "\n";
        EXPECT_NE(all.err.find(line), std::string::npos) << "lacks '" << line << "'\n" << all.err;
        EXPECT_TRUE(fs::exists(dir.file(file))) << file;
    }
    const CliResult compare = runStsv({"compare", "fence", "--methods", "stsv/cpu", "--size", "8x8",
                                       "--samples", "16", "--json", dir.file("c.json"), "-q"});
    ASSERT_EQ(compare.code, 0) << compare.err;
    EXPECT_NE(compare.out.find("wrote " + dir.file("c.json") + "\n"), std::string::npos) << compare.out;
    const CliResult bench =
        runStsv({"bench", "fence", "--methods", "stsv", "--backends", "cpu", "--size", "8x8", "--samples",
                 "16", "--repeat", "1", "--warmup", "0", "--json", dir.file("b.json"), "-q"});
    ASSERT_EQ(bench.code, 0) << bench.err;
    EXPECT_NE(bench.out.find("wrote " + dir.file("b.json") + "\n"), std::string::npos) << bench.out;
}

} // namespace
} // namespace stsv::test
