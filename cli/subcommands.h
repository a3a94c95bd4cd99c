// The `stsv` subcommands behind runCli: their arguments as parsed, and the functions that run
// them. Each run function throws (UsageError, InputError, Error) and returns an exit code;
// runCli prints the one-line message.
#pragma once

#include "render/options.h"
#include "scene/load.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace stsv {

/// Options every rendering command shares (render, bench, compare).
struct FrameArgs {
    std::string pattern = "poisson";
    std::string buffer = "bitmask";
    std::string size = "512x512";
    std::string extrusion = "auto";
    std::vector<std::string> sets;   ///< scene knobs key=value
    std::vector<std::string> params; ///< method knobs name=value (render/methods.h)
    RenderOptions options;           ///< samples, seed, interleave, decorrelate, ambient, device, validation
    std::string camera;              ///< --camera JSON (scene/load.h SceneOptions)
    std::vector<std::string> lights; ///< --light JSON, repeatable
    std::vector<std::string> addLights; ///< --add-light JSON, repeatable
    std::string maxMemory;              ///< --max-memory (core/memory_budget.h); empty: the default
    bool quiet = false;
};

/// The scene options of a command: --set knobs, --camera, --light, --add-light.
SceneOptions sceneOptionsOf(const FrameArgs& args);

/// args.options with pattern, buffer and size parsed, validated (UsageError naming the option).
RenderOptions resolveFrameOptions(const FrameArgs& args);

struct RenderArgs : FrameArgs {
    std::string scene;
    std::string method = "stsv";
    std::string backend; ///< empty: defaultBackend() (cpu for the reference)
    std::string output;
    std::string visibility;
    std::string dumpLs;
    std::string shadowMap; ///< .npy per light of an image-based method's map
    std::string stats;
    std::vector<std::string> argv; ///< the command line, recorded in --stats
};
int runRender(RenderArgs& args);

struct InfoArgs : FrameArgs {
    bool methodPairs = false; ///< "method backend" lines only
    bool markdown = false;    ///< the method table in Markdown only
    bool json = false;        ///< methods and scenes as JSON
    std::string scene;        ///< when given: that scene's contents and a frame's memory, nothing else
    std::string method = "stsv";
    std::string backend;
};
int runInfo(const InfoArgs& args);

/// The ranges of bench's --repeat (timed frames) and --warmup (untimed frames before them).
constexpr int kMinRepeat = 1;
constexpr int kMaxRepeat = 10000;
constexpr int kMinWarmup = 0;
constexpr int kMaxWarmup = 1000;

/// Bench arguments; `given` lists the options given on the command line, which override a
/// preset's values.
struct BenchArgs : FrameArgs {
    std::string scene;
    std::string methods = "stsv,reference";
    std::string backends; ///< empty: "vulkan,cpu" (or "cpu" while render/ lacks vulkan)
    std::string samples = "64";
    std::string vary; ///< "key=v1,v2,…": one scene per value
    int repeat = 5;
    int warmup = 1;
    bool check = false;
    std::string json;
    std::string preset;
    std::string presetsFile; ///< empty: the built-in bench/presets.json
    bool listPresets = false;
    std::vector<std::string> given;
    std::vector<std::string> argv; ///< the command line, recorded in --json
    /// Called after every frame a configuration renders (tests count timed frames with it).
    std::function<void(const std::string& configuration, bool timed)> onFrame;
};
int runBench(BenchArgs& args);

/// The presets: bench/presets.json compiled in, or `file`. UsageError/InputError on bad JSON.
nlohmann::json loadBenchPresets(const std::string& file = "");
/// Applies preset `name` to `args` for every option not in args.given; UsageError naming the
/// known presets when there is no such preset, or naming an unknown key of the preset.
void applyBenchPreset(BenchArgs& args, const nlohmann::json& presets, const std::string& name);

/// The most seeds compare --converged averages (a bound against typing mistakes, not a limit of
/// the math).
constexpr int kMaxConvergedFrames = 4096;

struct CompareArgs : FrameArgs {
    std::vector<std::string> inputs; ///< SCENE, or two .npy files
    std::string methods = "stsv";
    std::string backend; ///< empty: defaultBackend()
    std::string against = "reference";
    std::string out; ///< directory for the error images (none when empty)
    std::string json;
    float heatScale = 0.25f;       ///< |Δ visibility| shown yellow in the heat maps
    std::optional<int> converged;  ///< K: also compare with the mean of K seeds of --against
    bool noCache = false;          ///< render the converged reference even when the cache holds it
    std::string report;            ///< directory for index.html and its images (none when empty)
    std::string sheet;             ///< contact-sheet PNG (none when empty)
    std::string kind;              ///< two .npy files without metadata: what they hold (--kind)
    bool samplesGiven = false;     ///< --samples was given (two .npy files must hold that many)
    std::vector<std::string> argv; ///< the command line, shown in the report
};
int runCompare(CompareArgs& args);

} // namespace stsv
