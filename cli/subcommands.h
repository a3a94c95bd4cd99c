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
#include <utility>
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
    std::string method{AUTO_METHOD}; ///< a method, or auto: the one the scene calls for (autoMethod)
    std::string backend;             ///< empty: defaultBackend() (cpu for the reference)
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
    std::string method{AUTO_METHOD};
    std::string backend;
};
int runInfo(const InfoArgs& args);

/// The ranges of bench's --repeat (timed frames) and --warmup (untimed frames before them).
constexpr int MIN_REPEAT = 1;
constexpr int MAX_REPEAT = 10000;
constexpr int MIN_WARMUP = 0;
constexpr int MAX_WARMUP = 1000;

/// Bench arguments; `given` lists the options given on the command line, which override a
/// preset's values.
struct BenchArgs : FrameArgs {
    std::string scene;
    std::string methods = "auto,reference";
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
constexpr int MAX_CONVERGED_FRAMES = 4096;

struct CompareArgs : FrameArgs {
    std::vector<std::string> inputs; ///< SCENE, or two .npy files
    std::string methods{AUTO_METHOD};
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
    std::string knobs;             ///< --knobs: a tune --json file whose methods' knobs the rows use
    bool samplesGiven = false;     ///< --samples was given (two .npy files must hold that many)
    std::vector<std::string> argv; ///< the command line, shown in the report
};
int runCompare(CompareArgs& args);

/// The most renders `tune --budget` may allow a method's search (a bound against typing mistakes).
constexpr int MAX_TUNE_BUDGET = 100000;

struct TuneArgs : FrameArgs {
    std::string methods;               ///< METHOD: one image-based method, or several comma-separated
    std::vector<std::string> scenes;   ///< --scenes: the training scenes
    std::vector<std::string> validate; ///< --validate: the held-out scenes
    std::vector<std::string> knobs; ///< --knob NAME[=LO:HI]: the knobs searched (default: the tunable ones)
    int budget = 200;               ///< renders of each method's search, the defaults' included
    /// --objective: "mean" (of each scene's error over the defaults') or "worst" (of each
    /// scene's error over its own best, found by a search on that scene alone first)
    std::string objective = "mean";
    int converged = 16;                ///< K of each scene's converged reference
    std::string against = "reference"; ///< method[/backend] of the converged references
    std::string backend = "cpu";       ///< backend of the methods tuned
    bool noCache = false;
    std::string json;
    std::vector<std::string> argv; ///< the command line, recorded in --json
};
int runTune(TuneArgs& args);

/// The knobs a `tune --json` file holds per method (what `compare --knobs` applies).
struct KnobsFile {
    std::string path;
    std::vector<std::pair<Method, MethodParams>> methods; ///< each method once, in the file's order
    const MethodParams* find(Method method) const {
        for (const auto& [m, knobs] : methods)
            if (m == method) return &knobs;
        return nullptr;
    }
};
/// Reads a knobs file: {"methods": [{"method": NAME, "knobs": {NAME: NUMBER, ...}, ...}, ...]}
/// (what tune --json writes; other keys are ignored), or one such method object. InputError
/// naming the file and the entry for bad JSON, an unknown method, a method listed twice, a knob
/// the method lacks or a value outside the knob's range.
KnobsFile readKnobsFile(const std::string& path);
/// compare --knobs: for each methods[i] the file lists, its knobs set in params[i], except those a
/// `--param` item (`paramItems`) names, which win. Per method, what its rows say of their knobs:
/// "name=value …" (a --param value marked so), empty for a method the file does not list.
std::vector<std::string> applyKnobsFile(const KnobsFile& file, const std::vector<Method>& methods,
                                        std::vector<MethodParams>& params,
                                        const std::vector<std::string>& paramItems);

} // namespace stsv
