// `stsv compare --converged K`, its cache, `--report` (rendered by a headless browser) and
// `--sheet`, on tiny frames with the cpu backend.
#include "cli/converged_reference.h"
#include "core/error.h"
#include "core/image.h"
#include "render/renderer.h"
#include "scene/load.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::readText;
using test::runStsv;
using test::ScopedEnv;
using test::ScratchDir;
namespace fs = std::filesystem;

std::vector<std::string> compareArgs(const ScratchDir& dir, const std::string& json,
                                     std::vector<std::string> extra) {
    std::vector<std::string> args = {"compare",   "fence", "--methods", "stsv/cpu",     "--size", "32x32",
                                     "--samples", "16",    "--json",    dir.file(json), "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

CliResult runOk(const std::vector<std::string>& args) {
    CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 0) << test::describe(args, r);
    return r;
}

std::string cacheOf(const nlohmann::json& j) {
    return j["converged_reference"]["cache"].get<std::string>();
}

fs::file_time_type mtime(const std::string& path) {
    return fs::last_write_time(path);
}

ImageF readFloatNpy(const std::string& path, int channels) {
    const NpyArray a = readNpy(path);
    EXPECT_EQ(a.dtype, "<f4") << path;
    EXPECT_GE(a.shape.size(), 2u) << path;
    ImageF image(int(a.shape[1]), int(a.shape[0]), channels);
    EXPECT_EQ(a.bytes.size(), image.pixels.size() * sizeof(float)) << path;
    std::memcpy(image.pixels.data(), a.bytes.data(), std::min(a.bytes.size(), image.pixels.size() * 4));
    return image;
}

TEST(ConvergedCli, ConvergedImagesAreTheMeanOfTheSeedRenders) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const int k = 3;
    const std::uint32_t seed = 5;
    const std::vector<std::string> args =
        compareArgs(dir, "c.json", {"--converged", std::to_string(k), "--seed", std::to_string(seed)});
    const CliResult r = runOk(args);
    const nlohmann::json j = readJson(dir.file("c.json"));
    ASSERT_EQ(cacheOf(j), "written") << r.out << r.err;
    EXPECT_EQ(j["converged_reference"]["frames"], k);
    EXPECT_EQ(j["converged_reference"]["samples_per_pixel"], k * 16);
    EXPECT_EQ(j["converged_reference"]["frames_rendered"], k - 1) << "the seed-S frame is the reference's";
    const std::string entry = j["converged_reference"]["cache_entry"];
    const ImageF visibility = readFloatNpy(entry + "/visibility.npy", 1);
    const ImageF lit = readFloatNpy(entry + "/lit.npy", 3);
    ASSERT_EQ(visibility.width, 32);
    ASSERT_EQ(visibility.height, 32);

    // The mean computed here from renders of the same options, seeds S … S+K−1.
    const Scene scene = loadScene("fence");
    RenderOptions o;
    o.method = Method::Reference;
    o.backend = Backend::Cpu;
    o.width = o.height = 32;
    o.samples = 16;
    std::vector<double> visSum(visibility.pixels.size(), 0.0), litSum(lit.pixels.size(), 0.0);
    std::set<std::vector<float>> distinct; // the seeds must give different frames
    for (int f = 0; f < k; ++f) {
        o.seed = seed + std::uint32_t(f);
        const Frame frame = renderFrame(scene, o);
        ASSERT_EQ(frame.visibility.pixels.size(), visSum.size());
        for (std::size_t i = 0; i < visSum.size(); ++i) visSum[i] += frame.visibility.pixels[i];
        for (std::size_t i = 0; i < litSum.size(); ++i) litSum[i] += frame.color.pixels[i];
        distinct.insert(frame.visibility.pixels);
    }
    EXPECT_EQ(distinct.size(), std::size_t(k)) << "renders of different seeds should differ somewhere";
    // Values in [0, 1] (visibility) and below ~10 (linear radiance): the cache stores float32,
    // whose rounding is ≤ 2⁻²⁴ relative; any order of a double sum of 3 terms adds ~1e-16. 1e-6
    // is far above both and far below one sample's weight (1/48 per frame and pixel).
    int worst = -1;
    double worstError = 0.0;
    for (std::size_t i = 0; i < visSum.size(); ++i) {
        const double e = std::abs(double(visibility.pixels[i]) - visSum[i] / k);
        if (e > worstError) worstError = e, worst = int(i);
    }
    EXPECT_LE(worstError, 1e-6) << "visibility pixel " << worst << ": cached "
                                << visibility.pixels[std::size_t(std::max(worst, 0))] << " vs mean "
                                << visSum[std::size_t(std::max(worst, 0))] / k;
    double litError = 0.0;
    for (std::size_t i = 0; i < litSum.size(); ++i)
        litError = std::max(litError,
                            std::abs(double(lit.pixels[i]) - litSum[i] / k) / std::max(1.0, litSum[i] / k));
    EXPECT_LE(litError, 1e-6) << "lit image, relative error";
    // The mean of different seeds is not any single frame: the noise floor is positive.
    EXPECT_GT(j["noise_floor"]["visibility"]["rmse"].get<double>(), 0.0) << j["noise_floor"].dump();
}

TEST(ConvergedCli, OneFrameIsTheReferenceItselfSoTheNoiseFloorIsZero) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::vector<std::string> args = compareArgs(dir, "c.json", {"--converged", "1"});
    const CliResult r = runOk(args);
    const nlohmann::json j = readJson(dir.file("c.json"));
    EXPECT_EQ(j["converged_reference"]["frames_rendered"], 0);
    for (const nlohmann::json& e : {j["noise_floor"], j["rows"][0]["converged"]}) {
        for (const char* image : {"visibility", "lit"})
            for (const char* stat : {"rmse", "bias", "max_abs"})
                EXPECT_EQ(e[image][stat].get<double>(), 0.0) << image << " " << stat << ": " << e.dump();
        EXPECT_EQ(e["visibility"]["fraction_above_0_1"].get<double>(), 0.0) << e.dump();
    }
    // With K = 1 the converged columns equal the equal-sample ones.
    const nlohmann::json& stsv = j["rows"][1];
    EXPECT_DOUBLE_EQ(stsv["converged"]["visibility"]["rmse"].get<double>(),
                     stsv["visibility"]["rmse"].get<double>());
    EXPECT_DOUBLE_EQ(stsv["converged"]["visibility"]["bias"].get<double>(),
                     stsv["visibility"]["bias"].get<double>());
    EXPECT_DOUBLE_EQ(stsv["converged"]["lit"]["bias"].get<double>(), stsv["lit"]["bias"].get<double>());
    // The printed tables: the noise-floor row, zeros.
    EXPECT_NE(r.out.find("against the converged reference (16 samples per pixel)"), std::string::npos)
        << r.out;
    EXPECT_TRUE(std::regex_search(
        r.out,
        std::regex(R"(\nnoise floor +0\.00000 +\+0\.00000 +0\.00000 +0\.0000% +0\.00000 +\+0\.00000\n)")))
        << r.out;
}

TEST(ConvergedCli, CacheIsHitThenRenderedAgainWhenTheKeyChangesOrAFileIsCorrupt) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::vector<std::string> first = compareArgs(dir, "a.json", {"--converged", "2"});
    const CliResult written = runOk(first);
    EXPECT_NE(written.out.find("cache written: " + dir.file("cache")), std::string::npos) << written.out;
    const nlohmann::json a = readJson(dir.file("a.json"));
    ASSERT_EQ(cacheOf(a), "written");
    const std::string entry = a["converged_reference"]["cache_entry"];
    ASSERT_TRUE(fs::exists(entry + "/key.json")) << entry;
    const auto stamp = mtime(entry + "/visibility.npy");

    // Same command: a hit, nothing rendered or written, the same numbers.
    const CliResult hit = runOk(compareArgs(dir, "b.json", {"--converged", "2"}));
    EXPECT_NE(hit.out.find("cache hit: " + entry), std::string::npos) << hit.out;
    const nlohmann::json b = readJson(dir.file("b.json"));
    EXPECT_EQ(cacheOf(b), "hit");
    EXPECT_EQ(b["converged_reference"]["frames_rendered"], 0);
    EXPECT_EQ(mtime(entry + "/visibility.npy"), stamp);
    EXPECT_EQ(b["noise_floor"], a["noise_floor"]);
    EXPECT_EQ(b["rows"][1]["converged"], a["rows"][1]["converged"]);

    // --no-cache renders and leaves the entry alone.
    const CliResult off = runOk(compareArgs(dir, "c.json", {"--converged", "2", "--no-cache"}));
    EXPECT_EQ(cacheOf(readJson(dir.file("c.json"))), "off");
    EXPECT_EQ(readJson(dir.file("c.json"))["converged_reference"]["frames_rendered"], 1);
    EXPECT_EQ(mtime(entry + "/visibility.npy"), stamp);

    // Another seed, size, K, scene knob or ambient is another key: a new entry each.
    struct Change {
        std::string what;
        std::string size = "32x32";
        std::string frames = "2";
        std::vector<std::string> extra;
    };
    std::set<std::string> entries{entry};
    for (const Change& change :
         {Change{"seed", "32x32", "2", {"--seed", "2"}}, Change{"size", "32x24", "2", {}},
          Change{"K", "32x32", "3", {}}, Change{"--set", "32x32", "2", {"--set", "texture_size=64"}},
          Change{"ambient", "32x32", "2", {"--ambient", "0.1"}}}) {
        std::vector<std::string> args = {
            "compare", "fence",       "--methods",   "stsv/cpu", "--size",           change.size, "--samples",
            "16",      "--converged", change.frames, "--json",   dir.file("d.json"), "-q"};
        args.insert(args.end(), change.extra.begin(), change.extra.end());
        runOk(args);
        const nlohmann::json d = readJson(dir.file("d.json"));
        EXPECT_EQ(cacheOf(d), "written") << change.what;
        EXPECT_TRUE(entries.insert(d["converged_reference"]["cache_entry"].get<std::string>()).second)
            << change.what << " reused an entry";
    }
    EXPECT_EQ(mtime(entry + "/visibility.npy"), stamp);

    // Corrupt entries are ignored with a note and rendered again, never a crash.
    auto corruptAndRerun = [&](const std::string& file, const std::string& content, const std::string& why) {
        std::ofstream(entry + "/" + file, std::ios::binary | std::ios::trunc) << content;
        const CliResult again = runOk(compareArgs(dir, "e.json", {"--converged", "2"}));
        EXPECT_NE(again.err.find("note: ignoring cache entry " + entry), std::string::npos)
            << file << ": " << again.err;
        EXPECT_NE(again.err.find(why), std::string::npos) << file << ": " << again.err;
        const nlohmann::json e = readJson(dir.file("e.json"));
        EXPECT_EQ(cacheOf(e), "written") << file;
        EXPECT_EQ(e["noise_floor"], a["noise_floor"]) << file;
        const CliResult hitAgain = runOk(compareArgs(dir, "e.json", {"--converged", "2"}));
        EXPECT_EQ(cacheOf(readJson(dir.file("e.json"))), "hit") << file << " was not repaired";
    };
    corruptAndRerun("visibility.npy", "\x93NUMPY", "visibility.npy");
    corruptAndRerun("lit.npy", std::string(300, 'x'), "lit.npy");
    corruptAndRerun("key.json", "{ not json", "not valid JSON");
    {
        nlohmann::json key = readJson(entry + "/key.json");
        key["key"]["frames"] = 99;
        std::ofstream(entry + "/key.json") << key.dump();
    }
    const CliResult mismatch = runOk(compareArgs(dir, "f.json", {"--converged", "2"}));
    EXPECT_NE(mismatch.err.find("its key differs"), std::string::npos) << mismatch.err;
    EXPECT_EQ(cacheOf(readJson(dir.file("f.json"))), "written");
}

TEST(ConvergedCli, ACacheThatCannotBeWrittenIsReportedNotFatal) {
    ScratchDir dir;
    std::ofstream(dir.file("plain-file")) << "x";
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("plain-file/cache")); // under a regular file
    const CliResult r = runOk(compareArgs(dir, "c.json", {"--converged", "2"}));
    EXPECT_NE(r.err.find("note: cannot write cache entry " + dir.file("plain-file/cache")), std::string::npos)
        << r.err;
    const nlohmann::json j = readJson(dir.file("c.json"));
    EXPECT_EQ(cacheOf(j), "failed");
    EXPECT_GT(j["noise_floor"]["visibility"]["rmse"].get<double>(), 0.0) << "the images are still compared";
}

TEST(ConvergedCli, EditingAFileTheSceneReferencesInvalidatesTheCache) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    fs::copy(std::string(STSV_TEST_DATA) + "/scene", dir.file("scene"), fs::copy_options::recursive);
    const std::vector<std::string> args = {"compare",     dir.file("scene/example.json"),
                                           "--methods",   "stsv/cpu",
                                           "--size",      "24x16",
                                           "--samples",   "16",
                                           "--converged", "2",
                                           "--json",      dir.file("c.json"),
                                           "-q"};
    runOk(args);
    EXPECT_EQ(cacheOf(readJson(dir.file("c.json"))), "written");
    runOk(args);
    EXPECT_EQ(cacheOf(readJson(dir.file("c.json"))), "hit");
    // The crate's colour lives in crate.mtl, which example.json names only through crate.obj.
    std::string mtl;
    {
        std::ifstream in(dir.file("scene/crate.mtl"));
        mtl.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const auto kd = mtl.find("Kd 0.55 0.38 0.22");
    ASSERT_NE(kd, std::string::npos) << mtl;
    mtl.replace(kd, 17, "Kd 0.10 0.38 0.22");
    std::ofstream(dir.file("scene/crate.mtl"), std::ios::trunc) << mtl;
    runOk(args);
    EXPECT_EQ(cacheOf(readJson(dir.file("c.json"))), "written")
        << "a stale image of the old crate colour was reused";
}

TEST(ConvergedCli, TablesShowBothReferencesAndTheExistingTableIsKept) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const CliResult r = runOk(compareArgs(dir, "c.json", {"--converged", "4"}));
    for (const char* text :
         {"method            identical %",
          "converged reference: reference/cpu, seeds 1 to 4 (4 x 16 = 64 samples per pixel), cache written",
          "against the equal-sample reference (reference/cpu, 16 samples, seed 1):",
          "against the converged reference (64 samples per pixel):", "\nnoise floor ", "vis bias", "|dv|>0.1",
          "lit bias"})
        EXPECT_NE(r.out.find(text), std::string::npos) << text << "\n" << r.out;
    const nlohmann::json j = readJson(dir.file("c.json"));
    ASSERT_EQ(j["rows"].size(), 2u);
    for (const nlohmann::json& row : j["rows"]) {
        ASSERT_TRUE(row.contains("converged")) << row.dump();
        for (const char* stat : {"rmse", "bias", "max_abs", "fraction_above_0_1"})
            EXPECT_TRUE(row["converged"]["visibility"][stat].is_number()) << stat;
        for (const char* stat : {"rmse", "bias"})
            EXPECT_TRUE(row["converged"]["lit"][stat].is_number()) << stat;
        EXPECT_TRUE(row["visibility"]["bias"].is_number());
        EXPECT_TRUE(row["visibility"]["fraction_above_0_1"].is_number());
    }
    // The reference row against the converged one is the noise floor.
    EXPECT_EQ(j["rows"][0]["converged"], j["noise_floor"]);
    // RMSE² = bias² + variance ≥ bias².
    const nlohmann::json& c = j["rows"][1]["converged"]["visibility"];
    EXPECT_GE(c["rmse"].get<double>() + 1e-12, std::abs(c["bias"].get<double>()));

    // Without --converged the output has no converged section and the JSON no converged keys.
    const CliResult plain = runOk(compareArgs(dir, "p.json", {}));
    EXPECT_EQ(plain.out.find("converged"), std::string::npos) << plain.out;
    const nlohmann::json p = readJson(dir.file("p.json"));
    EXPECT_FALSE(p.contains("noise_floor"));
    EXPECT_FALSE(p["rows"][1].contains("converged"));
}

/// Every src="…" of the page.
std::vector<std::string> imageSources(const std::string& html) {
    std::vector<std::string> sources;
    static const std::regex src(R"re(<img src="([^"]*)")re");
    for (auto it = std::sregex_iterator(html.begin(), html.end(), src); it != std::sregex_iterator(); ++it)
        sources.push_back((*it)[1]);
    return sources;
}

TEST(ReportCli, PageNamesTheCommandEscapesTextAndReferencesItsImages) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    // A scene under a directory whose name needs escaping in HTML and quoting in a shell.
    const std::string odd = dir.file("a&b <x>");
    fs::copy(std::string(STSV_TEST_DATA) + "/scene", odd, fs::copy_options::recursive);
    const std::string report = dir.file("report");
    const std::vector<std::string> args = {"compare",     odd + "/example.json",
                                           "--methods",   "stsv/cpu,dcs+stsv/cpu",
                                           "--size",      "24x16",
                                           "--samples",   "16",
                                           "--converged", "2",
                                           "--report",    report,
                                           "-q"};
    const CliResult r = runOk(args);
    EXPECT_NE(r.out.find("report in " + report + "/index.html"), std::string::npos) << r.out;
    const std::string html = readText(report + "/index.html");
    ASSERT_FALSE(html.empty());
    EXPECT_EQ(html.find("a&b <x>"), std::string::npos) << "unescaped text in the page";
    EXPECT_NE(html.find("a&amp;b &lt;x&gt;/example.json"), std::string::npos);
    // The command line, quoted for a shell, then escaped.
    EXPECT_NE(html.find("stsv compare &#39;" + dir.file("a&amp;b &lt;x&gt;") +
                        "/example.json&#39; --methods "
                        "stsv/cpu,dcs+stsv/cpu --size 24x16 --samples 16 --converged 2 --report " +
                        report + " -q"),
              std::string::npos)
        << html.substr(0, 2000);
    EXPECT_EQ(html.find("<script"), std::string::npos);
    for (const char* text : {"noise floor", "against the converged reference", "stsv/cpu: lit",
                             "dcs+stsv/cpu: visibility", "reference/cpu: |visibility - converged|",
                             "converged reference (32 spp): lit", "alt=\"colour scale of the heat maps\""})
        EXPECT_NE(html.find(text), std::string::npos) << text;
    // Per row lit, visibility and a heat map; the converged row lit and visibility; and the heat
    // maps' colour scale: 512 pixels wide at 2 pixels per font unit, 4 + 12 + 6 + 2 + 12 + 4 font
    // units high (padding, caption, bar, gap, numbers, padding).
    std::vector<std::string> sources = imageSources(html);
    EXPECT_EQ(sources.size(), 3u * 3u + 2u + 1u) << html;
    const auto scaleSource = std::find(sources.begin(), sources.end(), "heat_scale.png");
    ASSERT_NE(scaleSource, sources.end()) << html;
    sources.erase(scaleSource);
    const Image8 legend = readPngRgba(report + "/heat_scale.png");
    EXPECT_EQ(legend.width, 512);
    EXPECT_EQ(legend.height, 2 * 40);
    for (const std::string& source : sources) {
        EXPECT_EQ(source.find('/'), std::string::npos) << source << " is not relative to the page";
        std::string file = source;
        for (std::size_t p; (p = file.find("%2B")) != std::string::npos;) file.replace(p, 3, "+");
        const Image8 image = readPngRgba(report + "/" + file);
        EXPECT_EQ(image.width, 24) << source;
        EXPECT_EQ(image.height, 16) << source;
    }
}

/// The browser: $STSV_CHROMIUM, else chromium or chromium-browser on PATH; empty when none.
std::string findChromium() {
    if (const char* env = std::getenv("STSV_CHROMIUM"); env && *env) return env;
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "");
    for (std::string d; std::getline(dirs, d, ':');)
        for (const char* name : {"chromium", "chromium-browser"})
            if (!d.empty() && ::access((fs::path(d) / name).c_str(), X_OK) == 0)
                return (fs::path(d) / name).string();
    return "";
}

/// Positions (x, y) where `image`, each pixel a scale × scale block, appears in `shot`: every
/// block's centre within `tolerance` of the image's pixel in each channel.
std::vector<std::pair<int, int>> findScaledImage(const Image8& shot, const Image8& image, int scale,
                                                 int tolerance) {
    std::vector<std::pair<int, int>> found;
    const int w = image.width * scale, h = image.height * scale, c = scale / 2;
    auto near = [&](int sx, int sy, int ix, int iy) {
        for (int ch = 0; ch < 3; ++ch)
            if (std::abs(int(shot.at(sx, sy, ch)) - int(image.at(ix, iy, ch))) > tolerance) return false;
        return true;
    };
    for (int y = 0; y + h <= shot.height; ++y)
        for (int x = 0; x + w <= shot.width; ++x) {
            bool all = true;
            for (int iy = 0; all && iy < image.height; ++iy)
                for (int ix = 0; all && ix < image.width; ++ix)
                    all = near(x + ix * scale + c, y + iy * scale + c, ix, iy);
            if (all) found.push_back({x, y});
        }
    return found;
}

TEST(ReportCli, HeadlessBrowserShowsTheMethodsImages) {
    const std::string chromium = findChromium();
    ASSERT_FALSE(chromium.empty())
        << "no chromium on PATH (nor $STSV_CHROMIUM): this test renders the --report page "
           "in a headless browser; install it with `make test-deps` (Debian: apt-get "
           "install chromium)";
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::string report = dir.file("report");
    runOk({"compare", "fence", "--methods", "stsv/cpu", "--size", "32x24", "--samples", "16", "--converged",
           "2", "--report", report, "-q"});
    const Image8 lit = readPngRgba(report + "/stsv_cpu_lit.png");
    const Image8 heat = readPngRgba(report + "/stsv_cpu_error.png");
    ASSERT_EQ(lit.width, 32);
    std::set<std::array<std::uint8_t, 3>> colours;
    for (int y = 0; y < lit.height; ++y)
        for (int x = 0; x < lit.width; ++x)
            colours.insert({lit.at(x, y, 0), lit.at(x, y, 1), lit.at(x, y, 2)});
    ASSERT_GE(colours.size(), 8u) << "the lit image should not be flat";

    // A fresh profile and HOME, no sandbox (containers, root), sRGB output at one device pixel
    // per CSS pixel, so the page's pixelated 8x images land pixel for pixel in the screenshot.
    const std::string shot = dir.file("shot.png");
    const std::string log = dir.file("chromium.log");
    const std::string command = "HOME='" + dir.file("home") + "' timeout 120 '" + chromium +
                                "' --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run "
                                "--force-device-scale-factor=1 --force-color-profile=srgb --user-data-dir='" +
                                dir.file("profile") + "' --window-size=1200,2400 --screenshot='" + shot +
                                "' 'file://" + report + "/index.html' > '" + log + "' 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(status == 0 && fs::exists(shot)) << command << "\nexit status " << status << "\n"
                                                 << readText(log);
    const Image8 page = readPngRgba(shot);
    ASSERT_EQ(page.width, 1200) << readText(log);

    // 32x24 frames are shown 8x (tileScaleFor: 256 / 32); tolerance 2 of 255 for the
    // browser's colour conversion.
    const auto litAt = findScaledImage(page, lit, 8, 2);
    EXPECT_FALSE(litAt.empty()) << "stsv/cpu's lit image is not on the rendered page (screenshot " << shot
                                << ")";
    const auto heatAt = findScaledImage(page, heat, 8, 2);
    EXPECT_FALSE(heatAt.empty()) << "stsv/cpu's heat map is not on the rendered page";
    if (!litAt.empty() && !heatAt.empty()) {
        EXPECT_EQ(litAt.front().second, heatAt.front().second) << "lit image and heat map side by side";
        EXPECT_LT(litAt.front().first, heatAt.front().first);
    }
    if (HasFailure()) {
        fs::copy_file(shot, fs::temp_directory_path() / "stsv_report_screenshot.png",
                      fs::copy_options::overwrite_existing);
        ADD_FAILURE() << "screenshot kept in " << (fs::temp_directory_path() / "stsv_report_screenshot.png");
    }
}

TEST(SheetCli, OneRowPerMethodAndTheConvergedReferenceWithLabels) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    const std::string sheetPath = dir.file("sheet.png");
    const CliResult r =
        runOk({"compare", "fence", "--methods", "stsv/cpu", "--size", "32x24", "--samples", "16",
               "--converged", "2", "--sheet", sheetPath, "--report", dir.file("report"), "-q"});
    EXPECT_NE(r.out.find("contact sheet in " + sheetPath), std::string::npos) << r.out;
    const Image8 sheet = readPngRgba(sheetPath);
    // Rows reference/cpu, stsv/cpu, converged; columns lit, visibility, heat map. Tiles are the
    // 32x24 frames 8x (256x192); padding 8; text at 2 px per stb_easy_font unit, 12 units a
    // line, so a band (title or label) is 24 + 8 px.
    const int tileW = 256, tileH = 192, pad = 8, band = 32, rows = 3, columns = 3;
    ASSERT_EQ(sheet.width, columns * tileW + (columns + 1) * pad);
    // Below the rows, the heat maps' colour scale: 40 font units high (padding 4, caption 12, bar
    // 6, gap 2, numbers 12, padding 4); its bar starts black and ends yellow.
    const int legendH = 2 * 40;
    ASSERT_EQ(sheet.height, pad + band + rows * (band + tileH + pad) + legendH);
    const int barY = pad + band + rows * (band + tileH + pad) + 2 * (4 + 12) + 2 * 3;
    auto pixel = [&](int x, int y) {
        return std::array<int, 3>{sheet.at(x, y, 0), sheet.at(x, y, 1), sheet.at(x, y, 2)};
    };
    EXPECT_EQ(pixel(2 * 4, barY), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(pixel(sheet.width - 2 * 4 - 1, barY), (std::array<int, 3>{255, 255, 0}));
    auto isText = [&](int x, int y) {
        return sheet.at(x, y, 0) == 255 && sheet.at(x, y, 1) == 255 && sheet.at(x, y, 2) == 255;
    };
    auto textPixels = [&](int y0) {
        int count = 0;
        for (int y = y0; y < y0 + band; ++y)
            for (int x = 0; x < sheet.width; ++x) count += isText(x, y) ? 1 : 0;
        return count;
    };
    EXPECT_GT(textPixels(pad), 100) << "column titles";
    for (int row = 0; row < rows; ++row)
        EXPECT_GT(textPixels(pad + band + row * (band + tileH + pad)), 100) << "label of row " << row;
    // The stsv/cpu row's lit tile is its lit image, 8x, pixel for pixel.
    const Image8 lit = readPngRgba(dir.file("report/stsv_cpu_lit.png"));
    const int tileY = pad + band + 1 * (band + tileH + pad) + band;
    int mismatches = 0;
    for (int y = 0; y < tileH; ++y)
        for (int x = 0; x < tileW; ++x)
            for (int c = 0; c < 3; ++c)
                mismatches += sheet.at(pad + x, tileY + y, c) != lit.at(x / 8, y / 8, c);
    EXPECT_EQ(mismatches, 0);
    // The converged row has no heat map: its cell is the dark background.
    const int lastY = pad + band + 2 * (band + tileH + pad) + band;
    EXPECT_EQ(sheet.at(pad + 2 * (tileW + pad) + tileW / 2, lastY + tileH / 2, 0), 32);
}

TEST(ConvergedCli, BadInputGivesOneLineAndNonZeroExit) {
    ScratchDir dir;
    ScopedEnv cache("STSV_CACHE_DIR", dir.file("cache"));
    std::ofstream(dir.file("plain-file")) << "x";
    const std::vector<std::string> small = {"--size", "8x8", "--samples", "16", "-q"};
    auto with = [&](std::vector<std::string> args) {
        args.insert(args.end(), small.begin(), small.end());
        return args;
    };
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {with({"compare", "fence", "--converged", "0"}), "--converged: 0 is out of range (1 to 4096)"},
        {with({"compare", "fence", "--converged", "-2"}), "--converged: -2 is out of range (1 to 4096)"},
        {with({"compare", "fence", "--converged", "5000"}), "--converged: 5000 is out of range (1 to 4096)"},
        {with({"compare", "fence", "--converged", "two"}), "--converged"},
        {with({"compare", dir.file("a.npy"), dir.file("b.npy"), "--converged", "2"}),
         "--converged compares renders of a SCENE"},
        {with({"compare", dir.file("a.npy"), dir.file("b.npy"), "--report", dir.file("r")}),
         "--report compares renders of a SCENE"},
        {with({"compare", "fence", "--no-cache"}), "--no-cache applies to --converged only"},
        {with({"compare", "fence", "--report", dir.file("plain-file/report")}),
         "--report " + dir.file("plain-file/report")},
        {with({"compare", "fence", "--report", dir.file("plain-file")}), "exists and is not a directory"},
        {with({"compare", "fence", "--sheet", dir.file("sheet.jpg")}), "name a .png file"},
        {with({"compare", "fence", "--sheet", dir.file("missing/sheet.png")}), "does not exist"},
    };
    for (const auto& [args, message] : cases) {
        const CliResult e = runStsv(args);
        EXPECT_NE(e.code, 0) << test::describe(args, e);
        EXPECT_EQ(e.err.rfind("stsv: error: ", 0), 0u) << test::describe(args, e);
        EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << test::describe(args, e);
        EXPECT_NE(e.err.find(message), std::string::npos) << message << "\n" << test::describe(args, e);
        EXPECT_TRUE(e.out.empty()) << "no table before the error: " << test::describe(args, e);
    }
    EXPECT_FALSE(fs::exists(dir.file("cache"))) << "no render, no cache";
}

/// The cache directory follows STSV_CACHE_DIR, XDG_CACHE_HOME, HOME in that order.
TEST(ConvergedCache, DirectoryFromTheEnvironment) {
    ScopedEnv home("HOME", "/home/someone");
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "");
        ScopedEnv stsvDir("STSV_CACHE_DIR", "");
        EXPECT_EQ(convergedCacheDirectory(), "/home/someone/.cache/stsv");
    }
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "/x/cache");
        ScopedEnv stsvDir("STSV_CACHE_DIR", "");
        EXPECT_EQ(convergedCacheDirectory(), "/x/cache/stsv");
        ScopedEnv own("STSV_CACHE_DIR", "/elsewhere");
        EXPECT_EQ(convergedCacheDirectory(), "/elsewhere");
    }
}

TEST(ConvergedCache, KeyFollowsTheSceneContentAndTheImageOptionsOnly) {
    const Scene fence = loadScene("fence");
    RenderOptions o;
    o.method = Method::Reference;
    o.backend = Backend::Cpu;
    const nlohmann::json key = convergedCacheKey(fence, o, 4);
    RenderOptions validated = o;
    validated.validation = true;
    EXPECT_EQ(convergedCacheKey(fence, validated, 4), key) << "validation layers change no pixel";
    for (const auto& change : std::vector<std::function<void(RenderOptions&)>>{
             [](RenderOptions& x) { x.seed = 2; }, [](RenderOptions& x) { x.samples = 32; },
             [](RenderOptions& x) { x.width = 256; },
             [](RenderOptions& x) { x.pattern = PatternKind::Uniform; },
             [](RenderOptions& x) { x.interleave = 2; }, [](RenderOptions& x) { x.decorrelate = false; },
             [](RenderOptions& x) { x.ambient = 0.2f; }, [](RenderOptions& x) { x.method = Method::Stsv; }}) {
        RenderOptions changed = o;
        change(changed);
        EXPECT_NE(convergedCacheKey(fence, changed, 4), key) << toJson(changed).dump();
    }
    EXPECT_NE(convergedCacheKey(fence, o, 5), key);
    Scene moved = fence;
    moved.lights[0].radiance.x += 1.0f;
    EXPECT_NE(sceneContentHash(moved), sceneContentHash(fence));
    Scene renamed = fence;
    renamed.source = "elsewhere/fence.json";
    EXPECT_EQ(sceneContentHash(renamed), sceneContentHash(fence)) << "the name does not change the pixels";
    Scene texel = fence;
    ASSERT_FALSE(texel.textures.empty());
    texel.textures[0].rgba[3] ^= 1;
    EXPECT_NE(sceneContentHash(texel), sceneContentHash(fence));
}

TEST(ConvergedCache, AverageIsThePerValueMeanInDouble) {
    Frame a, b, c;
    for (Frame* f : {&a, &b, &c}) {
        f->visibility = ImageF(2, 1, 1);
        f->color = ImageF(2, 1, 3);
    }
    a.visibility.at(0, 0, 0) = 1.0f;
    b.visibility.at(0, 0, 0) = 0.0f;
    c.visibility.at(0, 0, 0) = 0.5f;
    a.color.at(1, 0, 2) = 3.0f;
    const ConvergedImages m = averageFrames({&a, &b, &c});
    EXPECT_FLOAT_EQ(m.visibility.at(0, 0, 0), 0.5f);
    EXPECT_FLOAT_EQ(m.color.at(1, 0, 2), 1.0f);
    EXPECT_EQ(m.color.at(0, 0, 0), 0.0f);
    Frame small;
    small.visibility = ImageF(1, 1, 1);
    small.color = ImageF(1, 1, 3);
    EXPECT_THROW(averageFrames({&a, &small}), Error);
    EXPECT_THROW(averageFrames({}), Error);
}

} // namespace
} // namespace stsv
