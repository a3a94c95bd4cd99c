#include "cli/commands.h"

#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/frame.h"
#include "scene/load.h"

#include <CLI/CLI.hpp>
#include <embree3/rtcore.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <thread>

namespace stsv {

void parseSize(const std::string& text, int& width, int& height) {
    static const std::regex pattern(R"((\d{1,6})[xX](\d{1,6}))");
    std::smatch match;
    if (!std::regex_match(text, match, pattern))
        throw UsageError("--size '" + text + "' is not of the form WIDTHxHEIGHT (e.g. 512x512)");
    width = std::stoi(match[1]);
    height = std::stoi(match[2]);
}

std::string perLightPath(const std::string& path, std::size_t light) {
    if (light == 0) return path;
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "_light" + std::to_string(light) + p.extension().string())).string();
}

namespace {

struct RenderArgs {
    std::string scene;
    std::string method = "stsv";
    std::string backend = "cpu";
    std::string pattern = "poisson";
    std::string buffer = "bitmask";
    std::string size = "512x512";
    std::string output;
    std::string visibility;
    std::string dumpLs;
    std::string stats;
    std::vector<std::string> sets;
    RenderOptions options;
    bool quiet = false;
};

void writeJson(const std::string& path, const nlohmann::json& json) {
    std::ofstream out(path);
    if (!out) throw Error(path + ": cannot open for writing");
    out << json.dump(2) << '\n';
}

int runRender(RenderArgs& args) {
    if (args.quiet) Progress::setEnabled(false);
    RenderOptions& o = args.options;
    o.method = parseMethod(args.method);
    o.backend = parseBackend(args.backend);
    o.pattern = parsePatternKind(args.pattern);
    o.buffer = parseBufferKind(args.buffer);
    parseSize(args.size, o.width, o.height);
    validate(o);

    SceneOptions sceneOptions;
    for (const std::string& s : args.sets) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError("--set '" + s + "' is not of the form key=value");
        sceneOptions.set[s.substr(0, eq)] = s.substr(eq + 1);
    }
    Timer loadTimer;
    const Scene scene = loadScene(args.scene, sceneOptions);
    const double loadMs = loadTimer.milliseconds();

    Frame frame = renderFrame(scene, o);
    frame.stats["scene_load_ms"] = loadMs;

    if (args.output.empty() && args.visibility.empty() && args.dumpLs.empty() && args.stats.empty())
        args.output = std::filesystem::path(args.scene).stem().string() + ".png";
    if (!args.output.empty()) writePng(args.output, toImage8(frame.color, true));
    if (!args.visibility.empty()) writePng(args.visibility, toImage8(frame.visibility, false));
    if (!args.dumpLs.empty())
        for (std::size_t l = 0; l < frame.lightSamples.size(); ++l)
            frame.lightSamples[l].writeNpy(perLightPath(args.dumpLs, l));
    frame.stats["outputs"] = {{"image", args.output}, {"visibility", args.visibility}, {"light_samples", args.dumpLs}};
    if (!args.stats.empty()) writeJson(args.stats, frame.stats);
    if (!args.quiet)
        std::fprintf(stderr, "%s: %s, %d samples, %dx%d: frame %.1f ms\n", scene.source.c_str(),
                     toString(o.method).c_str(), o.samples, o.width, o.height, frame.stats["frame_ms"].get<double>());
    return 0;
}

int runInfo() {
    std::cout << "stsv " << STSV_VERSION << " — soft shadows from area lights with soft textured shadow volumes\n\n";
    std::cout << "methods:  reference (Embree ray tracing), stsv (soft textured shadow volumes)\n";
    std::cout << "backends: cpu\n";
    std::cout << "patterns: uniform, stratified, poisson, lowdisc; samples 16, 32, 64, 128, 256\n";
    std::cout << "built-in scenes:\n";
    for (const std::string& name : builtinSceneNames()) {
        std::cout << "  " << name;
        const auto knobs = builtinSceneKnobs(name);
        if (!knobs.empty()) {
            std::cout << "  (--set";
            for (const auto& k : knobs) std::cout << ' ' << k;
            std::cout << ')';
        }
        std::cout << '\n';
    }
    std::cout << "cpu threads: " << std::thread::hardware_concurrency() << '\n';
    std::cout << "embree: " << RTC_VERSION_STRING << '\n';
    return 0;
}

} // namespace

int runCli(int argc, char** argv) {
    CLI::App app{"stsv: soft shadows from area lights for opaque and perforated triangles"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(STSV_VERSION));

    RenderArgs r;
    CLI::App* render = app.add_subcommand("render", "render a scene: image, visibility, light-sample buffers, stats");
    render->add_option("scene", r.scene, "a .json scene, an .obj/.off mesh, or a built-in name (fence, foliage)")
        ->required();
    render->add_option("--method", r.method, "reference | stsv")->capture_default_str();
    render->add_option("--backend", r.backend, "cpu")->capture_default_str();
    render->add_option("--samples", r.options.samples, "light samples per pixel: 16, 32, 64, 128, 256")
        ->capture_default_str();
    render->add_option("--pattern", r.pattern, "uniform | stratified | poisson | lowdisc")->capture_default_str();
    render->add_option("--seed", r.options.seed, "seed of the sample patterns and decorrelation")->capture_default_str();
    render->add_option("--interleave", r.options.interleave, "K for K×K interleaved sample sets")->capture_default_str();
    render->add_flag("!--no-decorrelate", r.options.decorrelate, "same sample set for every pixel");
    render->add_option("--buffer", r.buffer, "light-sample buffer: bitmask | counters")->capture_default_str();
    render->add_option("--ambient", r.options.ambient, "ambient light, fraction of albedo")->capture_default_str();
    render->add_option("--size", r.size, "image size WIDTHxHEIGHT")->capture_default_str();
    render->add_option("-o,--output", r.output, "lit image (PNG, sRGB)");
    render->add_option("--visibility", r.visibility, "visibility v_coef image (PNG, linear gray)");
    render->add_option("--dump-ls", r.dumpLs, "light-sample buffer as NumPy .npy (one file per light)");
    render->add_option("--stats", r.stats, "parameters, timings and counts as JSON");
    render->add_option("--set", r.sets, "scene knob key=value (repeatable), e.g. --set count=256");
    render->add_flag("-q,--quiet", r.quiet, "no progress display or summary line");

    CLI::App* info = app.add_subcommand("info", "list methods, built-in scenes and the machine's capabilities");

    try {
        app.parse(argc, argv);
        if (*render) return runRender(r);
        if (*info) return runInfo();
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const Error& e) {
        std::fprintf(stderr, "stsv: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "stsv: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}

} // namespace stsv
