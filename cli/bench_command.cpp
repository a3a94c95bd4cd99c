// `stsv bench`: frame times per configuration (scene variant × method × backend × samples),
// start-up excluded, warm-up frames discarded, K timed frames summarised as median/min/max.
#include "cli/cli_util.h"
#include "cli/commands.h"
#include "cli/compare_report.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/files.h"
#include "core/progress.h"
#include "core/timer.h"
#include "core/version.h"
#include "gpu/device.h"
#include "render/renderer.h"
#include "scene/load.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <new>
#include <thread>
#include <unistd.h>

namespace stsv {

// bench/presets.json, compiled in by cli/CMakeLists.txt.
extern const char* const BENCH_PRESETS_JSON;

namespace {

struct Variant {
    std::string label; ///< "" or "count=250" (a knob); "" when the scene itself varies
    SceneOptions sceneOptions;
    std::string scene; ///< the scene spec of this variant
};

struct Config {
    Method method;
    Backend backend;
    int samples;
    std::size_t variant;
    MethodParams params;                             ///< the method's --param values, defaults included
    ExtrusionStage extrusion = ExtrusionStage::Auto; ///< Vulkan: one of --extrusion's list
    /// "vulkan", or "vulkan/mesh" with an extrusion asked for.
    std::string backendLabel() const {
        return toString(backend) + (extrusion == ExtrusionStage::Auto ? "" : "/" + toString(extrusion));
    }
    std::string label() const {
        return toString(method) + "/" + backendLabel() + " " + std::to_string(samples);
    }
};

// The implicit special members of json/map/vector members are what bugprone-exception-escape sees.
struct Result { // NOLINT(bugprone-exception-escape)
    Config config;
    nlohmann::json scene;
    double startupMs = 0.0;
    std::vector<double> frameMs;
    std::map<std::string, std::vector<double>> passes;
    std::vector<LightSampleBuffer> lightSamples; ///< of the last timed frame (for --check)
    ImageF visibility;                           ///< of the last timed frame (for --check)
    nlohmann::json lastStats;
    std::string error;
    std::optional<double> speedup;
    std::optional<double> agreementPercent;
    std::size_t differingSamples = 0;
    std::optional<ImageError> visibilityError; ///< --check: v_coef against the reference's
};

/// Adds every number under `passes` to `out`, nested objects as "outer/inner".
void collectPasses(const nlohmann::json& passes, const std::string& prefix,
                   std::map<std::string, std::vector<double>>& out) {
    if (!passes.is_object()) return;
    for (const auto& [name, value] : passes.items()) {
        if (value.is_number())
            out[prefix + name].push_back(value.get<double>());
        else if (value.is_object())
            collectPasses(value, prefix + name + "/", out);
    }
}

std::vector<Variant> makeVariants(const BenchArgs& args, const std::string& vary) {
    const SceneOptions base = sceneOptionsOf(args);
    if (vary.empty()) return {{"", base, args.scene}};
    const auto eq = vary.find('=');
    if (eq == std::string::npos || eq == 0)
        throw UsageError("--vary '" + vary + "' is not of the form key=value1,value2,...");
    const std::string key = vary.substr(0, eq);
    const std::vector<std::string> values = splitList(vary.substr(eq + 1), "--vary");
    if (values.empty()) throw UsageError("--vary '" + vary + "' lists no values");
    std::vector<Variant> variants;
    for (const std::string& v : values) {
        // scene=A,B: one variant per scene, each with the --set knobs (e.g. the same fence as
        // perforated quads and as a mesh).
        if (key == "scene") {
            variants.push_back({"", base, v});
            continue;
        }
        Variant variant{key, base, args.scene};
        variant.label.append("=").append(v);
        variant.sceneOptions.set[key] = v;
        variants.push_back(variant);
    }
    return variants;
}

/// Runs one configuration: the renderer is built once (start-up), then warm-up and timed frames.
void runConfiguration(const Scene& scene, RenderOptions o, int warmup, int repeat, bool progressOn,
                      const std::function<void(const std::string&, bool)>& onFrame, Result& result) {
    o.method = result.config.method;
    o.params = result.config.params;
    o.backend = result.config.backend;
    o.samples = result.config.samples;
    o.extrusion = result.config.extrusion;
    // A method without fractional transmittance runs on bits, as in compare.
    if (o.buffer == BufferKind::Transmittance && !methodInfo(o.method).writesTransmittance())
        o.buffer = BufferKind::Bitmask;
    const std::string label = result.config.label();
    // The bar of this configuration is decided now; renderers' own bars stay off meanwhile.
    Progress::setEnabled(progressOn);
    Progress progress(label, std::size_t(warmup + repeat) + 1);
    Progress::setEnabled(false);

    Timer startup;
    const std::unique_ptr<FrameRenderer> renderer = makeRenderer(scene, o);
    result.startupMs = startup.milliseconds();
    progress.advance();
    for (int i = 0; i < warmup + repeat; ++i) {
        const bool timed = i >= warmup;
        Timer wall;
        Frame frame = renderer->render();
        const double wallMs = wall.milliseconds();
        progress.advance();
        if (onFrame) onFrame(label, timed);
        if (i == 0)
            for (const std::string& warning : frameWarnings(frame.stats))
                std::fprintf(stderr, "stsv: warning: %s: %s\n", label.c_str(), printable(warning).c_str());
        if (i == 0 && frame.stats.contains("startup_ms") && frame.stats["startup_ms"].is_number())
            result.startupMs = frame.stats["startup_ms"].get<double>();
        if (!timed) continue;
        const nlohmann::json& ms = frame.stats["frame_ms"];
        result.frameMs.push_back(ms.is_number() ? ms.get<double>() : wallMs);
        collectPasses(frame.stats.value("passes", nlohmann::json::object()), "", result.passes);
        if (i + 1 == warmup + repeat) {
            result.lightSamples = std::move(frame.lightSamples);
            result.visibility = std::move(frame.visibility);
            result.lastStats = std::move(frame.stats);
        }
    }
    progress.finish();
}

void printTable(const std::vector<Result>& results, const std::vector<Variant>& variants, bool check) {
    std::printf("%-24s %-10s %-15s %7s %11s %11s %11s %11s %9s%s\n", "scene", "method", "backend", "samples",
                "startup ms", "median ms", "min ms", "max ms", "speed-up",
                check ? "  identical bits   vis RMSE   vis bias" : "");
    for (const Result& r : results) {
        const Config& c = r.config;
        const Variant& variant = variants[c.variant];
        const std::string name = variant.label.empty() ? variant.scene : variant.scene + " " + variant.label;
        if (!r.error.empty()) {
            std::printf("%-24s %-10s %-15s %7d  failed: %s\n", name.c_str(), toString(c.method).c_str(),
                        c.backendLabel().c_str(), c.samples, r.error.c_str());
            continue;
        }
        const Summary f = summarize(r.frameMs);
        char speedup[32] = "-";
        if (r.speedup) std::snprintf(speedup, sizeof speedup, "%.1fx", *r.speedup);
        char agreement[96] = "";
        if (check) {
            char bits[32], vis[48] = "";
            if (r.agreementPercent)
                std::snprintf(bits, sizeof bits, "  %12.4f %%", *r.agreementPercent);
            else
                std::snprintf(bits, sizeof bits, "  %14s", "-");
            if (r.visibilityError)
                std::snprintf(vis, sizeof vis, " %10.5f %+10.5f", r.visibilityError->rmse,
                              r.visibilityError->bias);
            std::snprintf(agreement, sizeof agreement, "%s%s", bits, vis);
        }
        std::printf("%-24s %-10s %-15s %7d %11.1f %11.2f %11.2f %11.2f %9s%s\n", name.c_str(),
                    toString(c.method).c_str(), c.backendLabel().c_str(), c.samples, r.startupMs, f.median,
                    f.min, f.max, speedup, agreement);
        for (const auto& [pass, values] : r.passes) {
            const Summary p = summarize(values);
            std::printf("  %-62s %11.2f %11.2f %11.2f\n", pass.c_str(), p.median, p.min, p.max);
        }
    }
}

} // namespace

namespace {

/// Where presets come from, as messages name it.
std::string presetsSource(const std::string& file) {
    return file.empty() ? "bench/presets.json (built in)" : file;
}

/// "a string", "an array", ...: the JSON type of `value`, as a message names it.
std::string jsonTypeName(const nlohmann::json& value) {
    const std::string type = value.type_name();
    return (type == "array" || type == "object" ? "an " : "a ") + type;
}

/// A preset's whole number `value` of `key`, in [lo, hi]; UsageError naming the preset, the key
/// and the range otherwise. Checked as a double before it is converted (1e30 is no int).
long long presetInteger(const std::string& where, const std::string& key, const nlohmann::json& value,
                        long long lo, long long hi) {
    const std::string range = " (" + std::to_string(lo) + " to " + std::to_string(hi) + ")";
    if (!value.is_number())
        throw UsageError(where + ": \"" + key + "\" must be a whole number" + range + ", not " +
                         jsonTypeName(value));
    if (value.is_number_unsigned()) {
        const std::uint64_t v = value.get<std::uint64_t>();
        if (v > std::uint64_t(hi))
            throw UsageError(where + ": \"" + key + "\" " + value.dump() + " is out of range" + range);
        return (long long)(v);
    }
    if (value.is_number_integer()) {
        const std::int64_t v = value.get<std::int64_t>();
        if (v < lo || v > hi)
            throw UsageError(where + ": \"" + key + "\" " + value.dump() + " is out of range" + range);
        return v;
    }
    const double v = value.get<double>();
    if (!(v >= double(lo) && v <= double(hi)))
        throw UsageError(where + ": \"" + key + "\" " + value.dump() + " is out of range" + range);
    if (v != std::floor(v))
        throw UsageError(where + ": \"" + key + "\" " + value.dump() + " is not a whole number" + range);
    return (long long)(v);
}

} // namespace

nlohmann::json loadBenchPresets(const std::string& file) {
    std::string text = BENCH_PRESETS_JSON;
    const std::string source = presetsSource(file);
    if (!file.empty()) text = readFileBytes(file, "presets file", std::size_t(1) << 24);
    nlohmann::json presets;
    try {
        presets = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        // nlohmann's text without its "[json.exception.parse_error.101] " tag.
        const std::string what = e.what();
        const std::size_t tag = what.rfind("[json.exception", 0) == 0 ? what.find("] ") : std::string::npos;
        throw InputError(source,
                         "not valid JSON: " + (tag == std::string::npos ? what : what.substr(tag + 2)));
    }
    if (!presets.is_object()) throw InputError(source, "presets must be a JSON object of name → preset");
    // Each preset an object whose description, where it has one, is text (--list-presets prints it).
    for (const auto& [name, preset] : presets.items()) {
        if (!preset.is_object())
            throw InputError(source, "preset '" + name + "' must be an object of option → value, not " +
                                         jsonTypeName(preset));
        if (preset.contains("description") && !preset["description"].is_string())
            throw InputError(source, "preset '" + name + "': \"description\" must be a string, not " +
                                         jsonTypeName(preset["description"]));
    }
    return presets;
}

void applyBenchPreset(BenchArgs& args, const nlohmann::json& presets, const std::string& name) {
    const std::string source = presetsSource(args.presetsFile);
    if (presets.empty()) throw UsageError("unknown preset '" + name + "': " + source + " holds no presets");
    if (!presets.contains(name)) {
        std::string names;
        for (const auto& [n, p] : presets.items()) names += (names.empty() ? "" : ", ") + n;
        throw UsageError("unknown preset '" + name + "' (presets of " + source + ": " + names + ")");
    }
    const nlohmann::json& p = presets.at(name);
    const std::string where = "preset '" + name + "' of " + source;
    auto given = [&](const std::string& option) {
        return std::find(args.given.begin(), args.given.end(), option) != args.given.end();
    };
    // The keys that hold text, each an option's value ("samples": "16,64", as --samples takes it).
    const std::vector<std::pair<const char*, std::string*>> texts = {
        {"scene", &args.scene},     {"size", &args.size},         {"samples", &args.samples},
        {"methods", &args.methods}, {"backends", &args.backends}, {"vary", &args.vary},
        {"pattern", &args.pattern}, {"buffer", &args.buffer},     {"extrusion", &args.extrusion}};
    for (const auto& [key, value] : p.items()) {
        if (key == "description") continue;
        const std::string option = key == "scene" ? "scene" : "--" + key;
        if (given(option)) continue;
        const auto text = std::find_if(texts.begin(), texts.end(),
                                       [&name = key](const auto& t) { return name == t.first; });
        if (text != texts.end()) {
            if (!value.is_string())
                throw UsageError(where + ": \"" + key + "\" must be a string, as " + option +
                                 " takes it, not " + jsonTypeName(value));
            *text->second = value.get<std::string>();
        } else if (key == "repeat") {
            args.repeat = int(presetInteger(where, key, value, MIN_REPEAT, MAX_REPEAT));
        } else if (key == "warmup") {
            args.warmup = int(presetInteger(where, key, value, MIN_WARMUP, MAX_WARMUP));
        } else if (key == "seed") {
            args.options.seed =
                std::uint32_t(presetInteger(where, key, value, 0, std::numeric_limits<std::uint32_t>::max()));
        } else if (key == "check") {
            if (!value.is_boolean())
                throw UsageError(where + ": \"check\" must be true or false, not " + jsonTypeName(value));
            args.check = value.get<bool>();
        } else if (key == "set" || key == "param") {
            const bool strings = value.is_array() && std::all_of(value.begin(), value.end(),
                                                                 [](const auto& v) { return v.is_string(); });
            if (!strings)
                throw UsageError(where + ": \"" + key +
                                 "\" must be an array of strings (\"name=value\"), not " +
                                 jsonTypeName(value));
            (key == "set" ? args.sets : args.params) = value.get<std::vector<std::string>>();
        } else {
            throw UsageError(where + ": unknown key '" + key + "'");
        }
    }
}

namespace {
/// --list-presets.
void printPresets(const nlohmann::json& presets) {
    for (const auto& [name, p] : presets.items()) {
        std::printf("%s: %s\n  ", name.c_str(), p.value("description", "").c_str());
        for (const auto& [key, value] : p.items())
            if (key != "description") std::printf(" %s=%s", key.c_str(), value.dump().c_str());
        std::printf("\n");
    }
}

void checkBenchArgs(const BenchArgs& args) {
    if (args.scene.empty() && args.vary.rfind("scene=", 0) != 0)
        throw UsageError("bench needs a SCENE, --vary scene=A,B or --preset NAME (see --list-presets)");
    if (args.repeat < MIN_REPEAT || args.repeat > MAX_REPEAT)
        throw UsageError("--repeat " + std::to_string(args.repeat) + " is out of range (" +
                         std::to_string(MIN_REPEAT) + " to " + std::to_string(MAX_REPEAT) + ")");
    if (args.warmup < MIN_WARMUP || args.warmup > MAX_WARMUP)
        throw UsageError("--warmup " + std::to_string(args.warmup) + " is out of range (" +
                         std::to_string(MIN_WARMUP) + " to " + std::to_string(MAX_WARMUP) + ")");
}

bool isGroundTruth(Method m) {
    return methodInfo(m).family == MethodFamily::GroundTruth;
}

/// Method × backend pairs, the reference first (so that --check and the speed-ups have it when
/// the others run). A pair the backend does not implement (the reference on vulkan) is skipped
/// with a note, into `skipped`; a method left without any backend runs on its own first backend.
std::vector<std::pair<Method, Backend>> benchPairs(const std::vector<Method>& methods,
                                                   const std::vector<Backend>& backends,
                                                   nlohmann::json& skipped) {
    std::vector<std::pair<Method, Backend>> pairs;
    for (Method m : methods) {
        bool ran = false;
        for (Backend b : backends) {
            const auto pair = std::make_pair(m, b);
            if (std::find(pairs.begin(), pairs.end(), pair) != pairs.end()) continue;
            if (!backendImplements(m, b)) {
                const std::string reason = unsupportedReason(m, b);
                skipped.push_back({{"method", toString(m)}, {"backend", toString(b)}, {"reason", reason}});
                std::fprintf(stderr, "note: skipping %s/%s: %s\n", toString(m).c_str(), toString(b).c_str(),
                             reason.c_str());
                continue;
            }
            pairs.push_back(pair);
            ran = true;
        }
        const auto own = std::make_pair(m, methodInfo(m).backends.front());
        if (!ran && std::find(pairs.begin(), pairs.end(), own) == pairs.end()) {
            std::fprintf(stderr, "note: %s runs on the %s backend\n", toString(m).c_str(),
                         toString(own.second).c_str());
            pairs.push_back(own);
        }
    }
    std::stable_partition(pairs.begin(), pairs.end(), [&](const auto& p) { return isGroundTruth(p.first); });
    return pairs;
}

/// What a bench runs: the configurations of the command line.
struct BenchPlan {
    RenderOptions base;
    std::vector<ExtrusionStage> extrusions; ///< each Vulkan configuration runs through each
    std::vector<Method> methods;
    std::vector<MethodParams> params; ///< [methods]
    std::vector<int> samples;
    std::vector<Variant> variants;
    std::vector<std::pair<Method, Backend>> pairs;
    nlohmann::json skipped = nlohmann::json::array();
    std::vector<OutputFile> outputs;

    const MethodParams& paramsOf(Method m) const {
        return params[std::size_t(std::find(methods.begin(), methods.end(), m) - methods.begin())];
    }
};

BenchPlan planBench(const BenchArgs& args) {
    BenchPlan plan;
    // --extrusion takes a list here: each Vulkan configuration runs through each stage, in one run.
    BenchArgs single = args;
    single.extrusion = "auto";
    plan.base = resolveFrameOptions(single);
    for (const std::string& e : splitList(args.extrusion, "--extrusion"))
        plan.extrusions.push_back(parseExtrusionStage(e));
    if (plan.extrusions.empty()) throw UsageError("--extrusion is empty");
    for (const std::string& m : splitList(args.methods, "--methods")) plan.methods.push_back(parseMethod(m));
    std::vector<Backend> backends;
    const std::string backendList =
        args.backends.empty() ? (defaultBackend() == Backend::Vulkan ? "vulkan,cpu" : "cpu") : args.backends;
    for (const std::string& b : splitList(backendList, "--backends")) backends.push_back(parseBackend(b));
    if (plan.methods.empty()) throw UsageError("--methods is empty");
    if (backends.empty()) throw UsageError("--backends is empty");
    plan.params = paramsForMethods(plan.methods, args.params);
    plan.samples = parseIntList(args.samples, "--samples");
    for (int n : plan.samples) {
        RenderOptions probe = plan.base;
        probe.samples = n;
        validate(probe);
    }
    plan.variants = makeVariants(args, args.vary);
    // The results file: a .json, none of the files the bench reads (checked again against each
    // variant's textures once it is loaded).
    std::vector<InputFile> inputs;
    if (!args.presetsFile.empty()) inputs.push_back({"the presets file", args.presetsFile});
    for (const Variant& v : plan.variants)
        if (std::error_code ec; std::filesystem::is_regular_file(v.scene, ec))
            inputs.push_back({"a scene", v.scene});
    plan.outputs = {{"--json", args.json, {".json"}}};
    checkOutputFiles(plan.outputs, inputs);
    plan.pairs = benchPairs(plan.methods, backends, plan.skipped);
    const bool haveReference = !plan.pairs.empty() && isGroundTruth(plan.pairs.front().first);
    if (args.check && !haveReference) throw UsageError("--check needs the reference among --methods");
    return plan;
}

/// The --json document of the results so far ("complete": false until the end).
nlohmann::json benchJson(const BenchArgs& args, const BenchPlan& plan, const std::vector<Result>& results,
                         bool complete) {
    const RenderOptions& base = plan.base;
    const bool vulkanAsked = std::any_of(plan.pairs.begin(), plan.pairs.end(),
                                         [](const auto& p) { return p.second == Backend::Vulkan; });
    nlohmann::json machine = machineJson(vulkanAsked, base.device);
    for (const Result& r : results)
        if (r.config.backend == Backend::Vulkan && r.lastStats.contains("gpu")) {
            machine["device"] = r.lastStats["gpu"].value("device", std::string());
            machine["driver"] = r.lastStats["gpu"].value("driver", std::string());
        }
    nlohmann::json configurations = nlohmann::json::array();
    for (const Result& r : results) {
        const Config& c = r.config;
        RenderOptions o = base;
        o.method = c.method;
        o.params = c.params;
        o.backend = c.backend;
        o.samples = c.samples;
        o.extrusion = c.extrusion;
        const Variant& variant = plan.variants[c.variant];
        nlohmann::json j = {{"method", toString(c.method)},
                            {"backend", toString(c.backend)},
                            {"samples", c.samples},
                            {"size", std::to_string(base.width) + "x" + std::to_string(base.height)},
                            {"set", variant.sceneOptions.set},
                            {"variant", variant.label},
                            {"scene_name", variant.scene},
                            {"scene", r.scene},
                            {"options", toJson(o)},
                            {"warmup", args.warmup},
                            {"repeat", r.frameMs.size()}};
        if (!r.error.empty()) {
            j["error"] = r.error;
            configurations.push_back(j);
            continue;
        }
        j["startup_ms"] = r.startupMs;
        j["frame_ms"] = toJson(summarize(r.frameMs));
        j["frame_ms_samples"] = r.frameMs;
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [name, values] : r.passes) passes[name] = toJson(summarize(values));
        j["passes"] = passes;
        j["speedup_vs_reference"] = r.speedup ? nlohmann::json(*r.speedup) : nlohmann::json(nullptr);
        if (args.check && r.agreementPercent) {
            j["identical_bits_percent"] = *r.agreementPercent;
            j["differing_samples"] = r.differingSamples;
        }
        if (r.visibilityError)
            j["visibility_vs_reference"] = {{"rmse", r.visibilityError->rmse},
                                            {"bias", r.visibilityError->bias},
                                            {"max_abs", r.visibilityError->maxAbs}};
        // The last frame's stats, whole, but for what the bench summarised itself above
        // (options, scene, frame and pass times).
        for (const auto& [key, value] : r.lastStats.items())
            if (!j.contains(key)) j[key] = value;
        configurations.push_back(j);
    }
    return {{"scene", args.scene},
            {"preset", args.preset.empty() ? nlohmann::json(nullptr) : nlohmann::json(args.preset)},
            {"version", version()},
            {"command", shellCommandLine(args.argv)},
            {"machine", machine},
            {"configurations", configurations},
            {"skipped", plan.skipped},
            {"complete", complete}};
}

/// Each result of a group (one sample count of one variant) against the group's reference: the
/// speed-up, and with --check the visibility error and the differing bits.
void compareWithReference(std::vector<Result>& results, std::size_t groupStart, std::size_t referenceIndex,
                          bool check) {
    const Result& reference = results[referenceIndex];
    for (std::size_t i = groupStart; i < results.size(); ++i) {
        Result& r = results[i];
        if (!r.error.empty()) continue;
        r.speedup = summarize(reference.frameMs).median / summarize(r.frameMs).median;
        if (check) {
            r.visibilityError = compareImages(r.visibility, reference.visibility);
            r.visibilityError->absDifference = ImageF();
        }
        // Bits only for methods that write per-sample results (not a visibility image).
        if (check && methodInfo(r.config.method).output != MethodOutput::Visibility) {
            std::size_t differing = 0, compared = 0;
            for (std::size_t l = 0; l < r.lightSamples.size() && l < reference.lightSamples.size(); ++l) {
                const LightSampleDiff d =
                    compareLightSamples(r.lightSamples[l], reference.lightSamples[l], 0,
                                        transmittanceBoth(r.lightSamples[l], reference.lightSamples[l]));
                differing += d.differingSamples;
                compared += d.comparedSamples;
            }
            r.differingSamples = differing;
            r.agreementPercent = compared ? 100.0 * double(compared - differing) / double(compared) : 0.0;
        }
    }
}

/// Runs every configuration on variant v, appending to `results`; false when one failed.
bool benchVariant(const BenchArgs& args, const BenchPlan& plan, std::size_t v, bool progressOn,
                  std::vector<Result>& results) {
    const RenderOptions& base = plan.base;
    const Variant& variant = plan.variants[v];
    Timer loadTimer;
    const Scene scene = loadScene(variant.scene, variant.sceneOptions);
    const double loadMs = loadTimer.milliseconds();
    printSceneWarnings(scene, args.quiet);
    checkOutputFiles(plan.outputs, sceneInputFiles(variant.scene, scene));
    // Every method and backend at the largest sample count: an image-based method's maps
    // may outweigh the light-sample buffers.
    for (const auto& [method, backend] : plan.pairs) {
        RenderOptions largest = base;
        largest.method = method;
        largest.backend = backend;
        largest.params = plan.paramsOf(method);
        largest.samples = *std::max_element(plan.samples.begin(), plan.samples.end());
        if (largest.buffer == BufferKind::Transmittance && !methodInfo(method).writesTransmittance())
            largest.buffer = BufferKind::Bitmask;
        checkFrameMemory(largest, scene);
    }
    nlohmann::json counts = sceneStats(scene);
    counts["load_ms"] = loadMs;
    if (!args.quiet)
        std::fprintf(stderr, "%s%s%s: %zu triangles (%zu perforated), %zu light(s), %dx%d\n",
                     printable(variant.scene).c_str(), variant.label.empty() ? "" : " ",
                     printable(variant.label).c_str(), counts["triangles"].get<std::size_t>(),
                     counts["perforated_triangles"].get<std::size_t>(), counts["lights"].get<std::size_t>(),
                     base.width, base.height);
    bool failed = false;
    for (int n : plan.samples) {
        std::optional<std::size_t> referenceIndex;
        const std::size_t groupStart = results.size();
        for (const auto& [method, backend] : plan.pairs)
            for (std::size_t x = 0; x < (backend == Backend::Vulkan ? plan.extrusions.size() : 1); ++x) {
                Result r;
                r.config = {method,
                            backend,
                            n,
                            v,
                            plan.paramsOf(method),
                            backend == Backend::Vulkan ? plan.extrusions[x] : ExtrusionStage::Auto};
                r.scene = counts;
                try {
                    runConfiguration(scene, base, args.warmup, args.repeat, progressOn, args.onFrame, r);
                } catch (const std::bad_alloc&) {
                    r.error = "out of memory";
                } catch (const Error& e) {
                    r.error = printable(e.message());
                }
                Progress::setEnabled(progressOn);
                if (!args.quiet && !progressOn && r.error.empty()) // a log line where there is no bar
                    std::fprintf(stderr, "  %s: %zu timed frames, median %.2f ms\n", r.config.label().c_str(),
                                 r.frameMs.size(), summarize(r.frameMs).median);
                if (!r.error.empty()) {
                    failed = true;
                    std::fprintf(stderr, "stsv: error: %s: %s\n", r.config.label().c_str(), r.error.c_str());
                }
                results.push_back(std::move(r));
                if (isGroundTruth(method) && results.back().error.empty())
                    referenceIndex = results.size() - 1;
            }
        if (referenceIndex) compareWithReference(results, groupStart, *referenceIndex, args.check);
        // Buffers are only kept for the check within one group.
        for (std::size_t i = groupStart; i < results.size(); ++i) {
            results[i].lightSamples.clear();
            results[i].visibility = ImageF();
        }
    }
    return !failed;
}

} // namespace

int runBench(BenchArgs& args) {
    const bool progressOn = !args.quiet && isatty(fileno(stderr));
    if (args.listPresets || !args.preset.empty()) {
        const nlohmann::json presets = loadBenchPresets(args.presetsFile);
        if (args.listPresets) {
            printPresets(presets);
            return 0;
        }
        applyBenchPreset(args, presets, args.preset);
    }
    checkBenchArgs(args);
    if (namesAutoMethod(args.methods, "--methods")) {
        // auto: the method each variant's scene calls for, each scene loaded for it (and again to run).
        std::vector<Method> chosen;
        for (const Variant& v : makeVariants(args, args.vary))
            chosen.push_back(autoMethod(loadScene(v.scene, v.sceneOptions)));
        args.methods = resolveAutoMethods(args.methods, "--methods", chosen);
        if (!args.quiet) std::fprintf(stderr, "--methods auto: %s\n", printable(args.methods).c_str());
    }
    const BenchPlan plan = planBench(args);

    std::vector<Result> results;
    bool failed = false;
    // --json is rewritten after each scene variant ("complete": false until the end), so a run
    // stopped early keeps what it measured.
    const auto writeResults = [&](bool complete) {
        if (!args.json.empty()) writeJson(args.json, benchJson(args, plan, results, complete));
    };
    for (std::size_t v = 0; v < plan.variants.size(); ++v) {
        if (!benchVariant(args, plan, v, progressOn, results)) failed = true;
        if (v + 1 < plan.variants.size()) writeResults(false);
    }

    printTable(results, plan.variants, args.check);
    for (const auto& s : plan.skipped)
        std::printf("skipped %s/%s: %s\n", s["method"].get<std::string>().c_str(),
                    s["backend"].get<std::string>().c_str(), s["reason"].get<std::string>().c_str());

    writeResults(true);
    if (!args.json.empty()) std::printf("wrote %s\n", printable(args.json).c_str());
    return failed ? 1 : 0;
}

} // namespace stsv
