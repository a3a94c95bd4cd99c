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

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    ASSERT_TRUE(out.good()) << path;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// `stsv render fence` on the CPU with `extra` options; fails the test when it does not exit 0.
void renderFence(const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"render", "fence", "--backend", "cpu", "--size", "24x16", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
}

/// A python3 with NumPy ("python3", else Debian's /usr/bin/python3); empty when there is none.
std::string pythonWithNumpy() {
    for (const std::string python : {"python3", "/usr/bin/python3"})
        if (runShell(python + " -c 'import numpy'").code == 0) return python;
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

/// runStsv in a child process that may take at most `seconds`: a command that blocks (on a FIFO
/// without a reader) is killed and reported as code -1 instead of hanging the tests.
CliResult runStsvWithin(int seconds, const std::vector<std::string>& args) {
    int errPipe[2];
    if (::pipe(errPipe) != 0) return {-2, "", "pipe failed"};
    const pid_t child = ::fork();
    if (child == 0) {
        ::dup2(errPipe[1], 2);
        ::close(errPipe[0]);
        std::vector<std::string> all = args;
        all.insert(all.begin(), "stsv");
        std::vector<char*> argv;
        for (std::string& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);
        std::fflush(stdout);
        const int code = runCli(int(all.size()), argv.data());
        std::fflush(stderr);
        ::_exit(code);
    }
    ::close(errPipe[1]);
    CliResult r;
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    while (::waitpid(child, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() > deadline) {
            ::kill(child, SIGKILL);
            ::waitpid(child, &status, 0);
            ::close(errPipe[0]);
            return {-1, "", "killed after " + std::to_string(seconds) + " s: the command blocked"};
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    char buffer[4096];
    for (ssize_t n; (n = ::read(errPipe[0], buffer, sizeof buffer)) > 0;)
        r.err.append(buffer, std::size_t(n));
    ::close(errPipe[0]);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
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
