#include "cli/commands.h"

#include "cli/cli_util.h"
#include "cli/subcommands.h"
#include "core/error.h"
#include "core/memory_budget.h"
#include "core/version.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <new>
#include <regex>
#include <string_view>

namespace stsv {

void parseSize(const std::string& text, int& width, int& height) {
    static const std::regex pattern(R"((\d{1,6})[xX](\d{1,6}))");
    std::smatch match;
    if (!std::regex_match(text, match, pattern))
        throw UsageError("--size '" + text + "' is not of the form WIDTHxHEIGHT (e.g. 512x512)");
    width = std::stoi(match[1]);
    height = std::stoi(match[2]);
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        throw UsageError("--size " + text + " is out of range (1 to 16384 pixels per side)");
}

std::string perLightPath(const std::string& path, std::size_t light) {
    if (light == 0) return path;
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "_light" + std::to_string(light) + p.extension().string()))
        .string();
}

namespace {

/// "a .json scene, an .obj/.off mesh, or a built-in name (fence, foliage, ...)".
std::string sceneHelp() {
    std::string names;
    for (const std::string& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
    return "a .json scene, an .obj/.off mesh, or a built-in name (" + names + "; see stsv info)";
}

/// --method's help: every row of the method table.
std::string methodHelp() {
    std::string text =
        "one of:\n  auto: dcs+stsv where the scene has opaque triangles, else stsv (the default)";
    for (const MethodInfo& m : methodTable()) text += "\n  " + m.name + ": " + m.description;
    return text;
}

/// What an option given an empty value ("", '') says: the value is never the option left out.
constexpr const char* EMPTY_VALUE = "the value is empty; give one, or leave the option out";

/// The check every option that takes a value runs: an empty value is refused, naming the option.
CLI::Validator nonEmpty(const std::string& message = EMPTY_VALUE) {
    return CLI::Validator([message](std::string& value) { return value.empty() ? message : std::string(); },
                          "", "non-empty");
}

/// The check of an integer option: a decimal whole number in [lo, hi], else a message with the
/// value and the accepted values (`accepted`; "lo to hi" when empty). The value is passed on in
/// plain decimal, so that "010" is ten (CLI11 alone would read it as octal).
CLI::Validator integerIn(long long lo, long long hi, const std::string& accepted = "") {
    const std::string range = accepted.empty() ? std::to_string(lo) + " to " + std::to_string(hi) : accepted;
    return CLI::Validator(
        [lo, hi, range](std::string& value) -> std::string {
            if (value.empty()) return EMPTY_VALUE;
            const std::size_t digits = value.find_first_not_of("+-") == 1 ? 1 : 0;
            const bool whole = !value.empty() && value.size() > digits &&
                               value.find_first_of("+-", digits) == std::string::npos &&
                               value.find_first_not_of("0123456789", digits) == std::string::npos;
            if (!whole) return "'" + value + "' is not a whole number (" + range + ")";
            errno = 0;
            const long long number = std::strtoll(value.c_str(), nullptr, 10);
            if (errno == ERANGE || number < lo || number > hi)
                return value + " is out of range (" + range + ")";
            value = std::to_string(number);
            return {};
        },
        "", "integer in range");
}

/// The check of a floating-point option: a finite decimal number; its range is the command's to check.
CLI::Validator finiteNumber() {
    return CLI::Validator(
        [](std::string& value) -> std::string {
            if (value.empty()) return EMPTY_VALUE;
            char* end = nullptr;
            errno = 0;
            const double number = std::strtod(value.c_str(), &end);
            if (end != value.c_str() + value.size() || errno == ERANGE || !std::isfinite(number))
                return "'" + value + "' is not a number";
            return {};
        },
        "", "number");
}

/// The sample counts --samples takes (render/options.cpp validate checks each value).
const char* const SAMPLE_COUNTS = "16, 32, 64, 128, 256";

/// Options shared by render, bench and compare.
void addFrameOptions(CLI::App* command, FrameArgs& a) {
    command->add_option("--pattern", a.pattern, "uniform | stratified | poisson | lowdisc")
        ->capture_default_str();
    command->add_option("--seed", a.options.seed, "seed of the sample patterns and decorrelation")
        ->transform(integerIn(0, std::numeric_limits<std::uint32_t>::max()))
        ->capture_default_str();
    command->add_option("--interleave", a.options.interleave, "K for K×K interleaved sample sets (1 to 8)")
        ->transform(integerIn(1, 8))
        ->capture_default_str();
    command->add_flag("!--no-decorrelate", a.options.decorrelate, "same sample set for every pixel");
    command->add_option("--buffer", a.buffer, "light-sample buffer: bitmask | counters | transmittance")
        ->capture_default_str();
    command->add_option("--ambient", a.options.ambient, "ambient light, fraction of albedo")
        ->check(finiteNumber())
        ->capture_default_str();
    command->add_option("--size", a.size, "image size WIDTHxHEIGHT")->capture_default_str();
    command
        ->add_option(
            "--supersample", a.options.supersample,
            "K: K×K visible points per pixel, each with the pixel's light samples, averaged (1 to 4; "
            "--dump-ls keeps every sub-pixel)")
        ->transform(integerIn(1, 4))
        ->capture_default_str();
    command->add_option("--set", a.sets, "scene knob key=value (repeatable), e.g. --set count=256");
    command->add_option("--camera", a.camera,
                        "the camera, as the scene format's object: "
                        "'{\"eye\": [0, 2, 6], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fovY\": 45}'");
    command->add_option(
        "--light", a.lights,
        "a light replacing the scene's, as the scene format's object (repeatable), e.g. "
        "'{\"type\": \"disk\", \"position\": [0, 4, 0], \"normal\": [0, -1, 0], \"radius\": 0.5, "
        "\"radiance\": [40, 40, 40]}'");
    command->add_option("--add-light", a.addLights,
                        "a light added to the scene's, as the scene format's object (repeatable)");
    command->add_option("--param", a.params,
                        "method parameter name=value (repeatable; see stsv info for each method's)");
    command->add_option("--device", a.options.device,
                        "Vulkan device: index or name substring (see stsv info)");
    command->add_flag("--validation", a.options.validation, "Vulkan validation layers (messages on stderr)");
    command
        ->add_option(
            "--extrusion", a.extrusion,
            "Vulkan stage that builds the STSV volumes and wedge bounds: auto | hull | geometry | mesh "
            "(auto: no volume drawn for STSV and dcs's opaque triangles: compute passes walk a tree "
            "of the S-triangles' balls, or of the light's silhouette clusters, per screen tile and "
            "block; pw's wedge bounds as hull; hull: the scene box clipped by each volume's and the "
            "light's planes in a compute pass and drawn indirect; mesh: the same hulls culled by a "
            "task shader and clipped and emitted by a mesh shader, where the device has "
            "VK_EXT_mesh_shader; geometry: the paper's ten-vertex prism)")
        ->capture_default_str();
    command->add_option("--max-memory", a.maxMemory,
                        "memory the scene and the frame may hold, e.g. 8G or 512M (default: half of this "
                        "machine's physical memory); larger inputs are refused before they are allocated");
    command->add_flag("-q,--quiet", a.quiet, "no progress display or summary line");
}

/// Names of the options given on the command line ("scene", "--size", ...).
std::vector<std::string> givenOptions(const CLI::App* command) {
    std::vector<std::string> names;
    for (const CLI::Option* o : command->get_options()) {
        if (o->count() == 0) continue;
        if (o->get_lnames().empty())
            names.push_back(o->get_name());
        else
            for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
    }
    return names;
}

/// Every option of `app`'s commands that takes a value refuses an empty one (nonEmpty), the
/// scene's with a message of its own.
void refuseEmptyValues(CLI::App& app) {
    for (CLI::App* command : app.get_subcommands({})) {
        if (CLI::Option* scene = command->get_option_no_throw("scene"))
            scene->check(nonEmpty(
                "the scene name is empty; give a built-in name, a .json scene or an .obj/.off mesh"));
        if (CLI::Option* inputs = command->get_option_no_throw("inputs"))
            inputs->check(
                nonEmpty("the scene or file name is empty; give a SCENE, or two .npy or .exr files"));
        for (CLI::Option* option : command->get_options())
            if (option->get_type_size() != 0) option->check(nonEmpty());
    }
}

/// The deepest nesting of brackets an argument may hold. CLI11 reads a bracketed value of a
/// repeatable option (--set, --param, --light, --add-light) as a list, splitting it one level at a
/// time and copying the rest at each (60,000 levels took 3 GiB in 3 s); the JSON options nest two
/// or three levels, and their reader refuses past 64 (scene/json_scene.cpp), as this does.
constexpr int MAX_ARGUMENT_NESTING = 64;

/// The option an argument of `command` is the value of: "--light" for "--light=..." or the value
/// after "--light" (an option that takes one), else "the scene" (a positional argument).
std::string optionOfArgument(const CLI::App* command, char** argv, int k) {
    const std::string_view arg = argv[k];
    if (arg.starts_with("--")) return std::string(arg.substr(0, arg.find('=')));
    if (command != nullptr && k > 1) {
        const std::string_view previous = argv[k - 1];
        std::string name(previous.substr(0, previous.find('=')));
        const CLI::Option* option =
            name.size() > 1 && name[0] == '-' ? command->get_option_no_throw(name) : nullptr;
        if (option != nullptr && option->get_type_size() != 0) return name;
    }
    return command != nullptr && command->get_name() == "compare" ? "the inputs" : "the scene";
}

/// UsageError, naming the option, for an argument whose brackets ([ ] and { }) nest deeper than
/// MAX_ARGUMENT_NESTING; run before CLI11 parses.
void refuseDeeplyNestedArguments(CLI::App& app, int argc, char** argv) {
    const CLI::App* command = nullptr;
    for (const CLI::App* c : app.get_subcommands({}))
        if (argc > 1 && c->get_name() == argv[1]) command = c;
    for (int k = 1; k < argc; ++k) {
        int depth = 0, deepest = 0;
        for (const char* c = argv[k]; *c != '\0'; ++c) {
            if (*c == '[' || *c == '{') deepest = std::max(deepest, ++depth);
            if ((*c == ']' || *c == '}') && depth > 0) --depth;
        }
        if (deepest > MAX_ARGUMENT_NESTING)
            throw UsageError(optionOfArgument(command, argv, k) + ": the value nests brackets " +
                             std::to_string(deepest) + " levels deep, more than the " +
                             std::to_string(MAX_ARGUMENT_NESTING) + " accepted (a light or camera nests 2)");
    }
}

/// The memory limit of --max-memory, set before anything can quote it (an allocation that fails
/// while CLI11 reads the arguments): the last --max-memory given. A value that is no size is left
/// to the check after parsing, which names it. The arguments are not copied.
void setMemoryLimitFromArguments(int argc, char** argv) {
    setMemoryLimit(0);
    constexpr std::string_view option = "--max-memory";
    for (int k = 1; k < argc; ++k) {
        const std::string_view arg = argv[k];
        std::string_view value;
        if (arg.starts_with(option) && arg.size() > option.size() && arg[option.size()] == '=')
            value = arg.substr(option.size() + 1);
        else if (arg == option && k + 1 < argc)
            value = argv[k + 1];
        else
            continue;
        if (value.size() > 64) continue;
        try {
            setMemoryLimit(parseMemorySize(std::string(value)));
        } catch (const Error&) {
        }
    }
}

} // namespace

int runReportingErrors(const std::function<int()>& command) {
    try {
        return command();
    } catch (const Error& e) {
        std::fprintf(stderr, "stsv: error: %s\n", printable(e.message()).c_str());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(
            stderr,
            "stsv: error: out of memory: an allocation failed below the memory limit of %s; the "
            "scene, the frame's --size and --samples or the lights need more than this machine gives\n",
            describeMemoryLimit().c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "stsv: internal error: %s\n", printable(e.what()).c_str());
        return 2;
    } catch (...) {
        std::fprintf(stderr, "stsv: internal error: an exception of unknown type\n");
        return 2;
    }
}

namespace {

/// `stsv render`: its options into `r`.
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& r) {
    r.options.samples = 64;
    CLI::App* command =
        app.add_subcommand("render", "render a scene: image, visibility, light-sample buffers, stats");
    command->add_option("scene", r.scene, sceneHelp())->required();
    command->add_option("--method", r.method, methodHelp())->capture_default_str();
    command->add_option("--backend", r.backend,
                        "vulkan | cpu (default " + toString(defaultBackend()) +
                            ", or the method's own backend where it lacks that one)");
    command->add_option("--samples", r.options.samples, "light samples per pixel: 16, 32, 64, 128, 256")
        ->transform(integerIn(16, 256, SAMPLE_COUNTS))
        ->capture_default_str();
    addFrameOptions(command, r);
    command->add_option(
        "-o,--output", r.output,
        "lit image: .png (sRGB, 8 bits) or .exr (linear RGB, half floats); default SCENE.png when no output "
        "is given");
    command->add_option(
        "--visibility", r.visibility,
        "visibility v_coef: .png (linear gray, 8 bits), .exr (float32 Y) or .npy (float32 [H, W])");
    command->add_option("--dump-ls", r.dumpLs, "light-sample buffer as NumPy .npy (one file per light)");
    command->add_option(
        "--shadow-map", r.shadowMap,
        "image-based methods: each light's shadow map as NumPy .npy, float32 [faces, size, size] "
        "of linear depth (inf: no surface)");
    command->add_option("--stats", r.stats, "parameters, counts, timings and buffer memory as JSON");
    return command;
}

/// `stsv info`: its options into `i`.
CLI::App* addInfoCommand(CLI::App& app, InfoArgs& i) {
    i.options.samples = 64;
    CLI::App* command = app.add_subcommand(
        "info", "list methods, built-in scenes and the machine's capabilities; with a SCENE, what it holds "
                "and the memory a frame of the given options would take, without rendering");
    command->add_option("scene", i.scene, sceneHelp());
    command
        ->add_option("--method", i.method, "method whose frame memory is estimated (auto: the scene's own)")
        ->capture_default_str();
    command->add_option("--backend", i.backend, "vulkan | cpu");
    command->add_option("--samples", i.options.samples, "light samples per pixel")
        ->transform(integerIn(16, 256, SAMPLE_COUNTS))
        ->capture_default_str();
    addFrameOptions(command, i);
    command->add_flag("--methods", i.methodPairs,
                      "only the method/backend pairs, one 'method backend' per line");
    command->add_flag("--markdown", i.markdown,
                      "only the method table, in Markdown (the README's method list)");
    command->add_flag("--json", i.json, "the method table and the built-in scenes as JSON");
    return command;
}

/// `stsv bench`: its options into `b`.
CLI::App* addBenchCommand(CLI::App& app, BenchArgs& b) {
    CLI::App* command = app.add_subcommand("bench", "time frames per method, backend and sample count");
    command->add_option("scene", b.scene, sceneHelp());
    command
        ->add_option(
            "--methods", b.methods,
            "comma-separated, of: auto (the scene's own: dcs+stsv, or stsv without opaque triangles), " +
                methodNameList("and"))
        ->capture_default_str();
    command->add_option("--backends", b.backends,
                        "comma-separated: vulkan,cpu (default: " +
                            std::string(defaultBackend() == Backend::Vulkan ? "vulkan,cpu" : "cpu") +
                            "; methods vulkan lacks run on cpu)");
    command->add_option("--samples", b.samples, "comma-separated sample counts, e.g. 16,64,256")
        ->capture_default_str();
    command->add_option(
        "--vary", b.vary,
        "one scene per value of a knob, e.g. count=250,1000,4000, or per scene, e.g. scene=fence,fence-mesh");
    command->add_option("--repeat", b.repeat, "timed frames per configuration")
        ->transform(integerIn(MIN_REPEAT, MAX_REPEAT))
        ->capture_default_str();
    command->add_option("--warmup", b.warmup, "untimed frames before them")
        ->transform(integerIn(MIN_WARMUP, MAX_WARMUP))
        ->capture_default_str();
    command->add_flag("--check", b.check,
                      "compare each configuration's light-sample bits with the reference's");
    command->add_option("--json", b.json, "write the results as JSON");
    command->add_option("--preset", b.preset,
                        "named configuration from bench/presets.json (see --list-presets)");
    command->add_option("--presets", b.presetsFile,
                        "read presets from this JSON file instead of the built-in ones");
    command->add_flag("--list-presets", b.listPresets, "print the presets and exit");
    addFrameOptions(command, b);
    command->get_option("--extrusion")
        ->description("Vulkan stages that build the volumes, comma-separated: each Vulkan configuration runs "
                      "through each (auto | hull | geometry | mesh; see stsv render --help)");
    return command;
}

/// `stsv compare`: its options into `c`.
CLI::App* addCompareCommand(CLI::App& app, CompareArgs& c) {
    c.options.samples = 64;
    CLI::App* command =
        app.add_subcommand("compare", "error tables and images of methods against the reference, "
                                      "or of two --dump-ls .npy files");
    command->add_option("inputs", c.inputs, "SCENE, or A.npy B.npy")->required()->expected(1, 2);
    command
        ->add_option("--methods", c.methods,
                     "comma-separated, each method[/backend], e.g. stsv,stsv/cpu; auto: the scene's own "
                     "(dcs+stsv, or stsv without opaque triangles)")
        ->capture_default_str();
    command->add_option("--backend", c.backend,
                        "backend of methods without one (default " + toString(defaultBackend()) + ")");
    command->add_option("--against", c.against, "method[/backend] the others are compared with")
        ->capture_default_str();
    command
        ->add_option(
            "--samples", c.options.samples,
            "light samples per pixel: 16, 32, 64, 128, 256 (two .npy files: the count they must hold)")
        ->transform(integerIn(16, 256, SAMPLE_COUNTS))
        ->capture_default_str();
    command->add_option("--out", c.out,
                        "directory for the images (visibility, |difference| heat map, lit image)");
    command->add_option("--json", c.json, "write the error table as JSON");
    command->add_option("--heat-scale", c.heatScale, "difference shown yellow in the heat maps")
        ->check(finiteNumber())
        ->capture_default_str();
    command
        ->add_option("--converged", c.converged,
                     "K: also compare with the converged reference, the mean of K renders of --against "
                     "with seeds SEED … SEED+K-1 (cached, see --no-cache)")
        ->transform(integerIn(1, MAX_CONVERGED_FRAMES));
    command->add_option("--kind", c.kind,
                        "two .npy light-sample files without their .npy.json metadata (from an older stsv "
                        "or NumPy): what they hold, bitmask | counters | transmittance");
    command->add_flag("--no-cache", c.noCache, "render the converged reference even when the cache holds it");
    command->add_option("--report", c.report,
                        "directory for index.html: options, error tables, lit/visibility/heat-map images");
    command->add_option("--sheet", c.sheet, "contact sheet PNG: per method lit, visibility, heat map");
    command->add_option(
        "--knobs", c.knobs,
        "a knobs file (tune --json): its methods render with its knobs (--param wins over it)");
    addFrameOptions(command, c);
    return command;
}

/// `stsv tune`: its options into `t`.
CLI::App* addTuneCommand(CLI::App& app, TuneArgs& t) {
    t.options.samples = 64;
    t.size = "128x128"; // tuning renders many frames
    CLI::App* command = app.add_subcommand(
        "tune", "search an image-based method's knobs for the least error against the converged references "
                "of training scenes; the best knobs beside the defaults on held-out scenes");
    command
        ->add_option("method", t.methods,
                     "the image-based method (or several, comma-separated) whose knobs are searched")
        ->required();
    command->add_option("--scenes", t.scenes, "the training scenes (several values, or comma-separated)")
        ->required()
        ->expected(1, -1);
    command
        ->add_option("--validate", t.validate,
                     "held-out scenes: the defaults' and the best knobs' error on them")
        ->expected(1, -1);
    command->add_option(
        "--knob", t.knobs,
        "NAME or NAME=LO:HI: a knob to search (repeatable; default: the method's tunable knobs, "
        "those that do not trade time for quality)");
    command
        ->add_option("--budget", t.budget,
                     "the most renders of each method's search (one per training scene per point tried)")
        ->transform(integerIn(1, MAX_TUNE_BUDGET))
        ->capture_default_str();
    command
        ->add_option("--objective", t.objective,
                     "mean: the mean over the training scenes of error/defaults' error; worst: each scene "
                     "searched alone first, then the worst over the scenes of error/that scene's own best "
                     "(the knobs nearest every scene's best at once)")
        ->check(CLI::IsMember({"mean", "worst"}))
        ->capture_default_str();
    command
        ->add_option("--converged", t.converged,
                     "K: each scene's reference is the mean of K renders of --against (cached as compare's)")
        ->transform(integerIn(1, MAX_CONVERGED_FRAMES))
        ->capture_default_str();
    command->add_option("--against", t.against, "method[/backend] of the converged references")
        ->capture_default_str();
    command->add_option("--backend", t.backend, "backend of the methods tuned: cpu | vulkan")
        ->capture_default_str();
    command->add_option("--samples", t.options.samples, "light samples per pixel: 16, 32, 64, 128, 256")
        ->transform(integerIn(16, 256, SAMPLE_COUNTS))
        ->capture_default_str();
    command->add_flag("--no-cache", t.noCache,
                      "render the converged references even when the cache holds them");
    command->add_option("--json", t.json,
                        "write the best knobs and the errors as JSON (compare --knobs reads it)");
    addFrameOptions(command, t);
    command->get_option("--param")->description(
        "method parameter name=value (repeatable): fixed at that value, not searched");
    return command;
}

} // namespace

int runCli(int argc, char** argv) {
    // A file size limit (ulimit -f) stops a write with SIGXFSZ, whose default kills the process
    // and leaves a partial file; ignored, the write fails with EFBIG, which writeFileBytes reports
    // and cleans up after, as it does a full disk.
    std::signal(SIGXFSZ, SIG_IGN);
    CLI::App app{"stsv: soft shadows from area lights for opaque and perforated triangles"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("stsv ") + version());

    RenderArgs r;
    CLI::App* render = addRenderCommand(app, r);
    InfoArgs i;
    CLI::App* info = addInfoCommand(app, i);
    BenchArgs b;
    CLI::App* bench = addBenchCommand(app, b);
    CompareArgs c;
    CLI::App* compare = addCompareCommand(app, c);
    TuneArgs t;
    CLI::App* tune = addTuneCommand(app, t);
    refuseEmptyValues(app);

    return runReportingErrors([&]() -> int {
        try {
            const std::string first = argc > 1 ? argv[1] : "-";
            if (first[0] != '-' && first != "render" && first != "info" && first != "bench" &&
                first != "compare" && first != "tune")
                throw UsageError("unknown command '" + std::string(argv[1]) +
                                 "' (expected render, info, bench, compare or tune)");
            setMemoryLimitFromArguments(argc, argv);
            refuseDeeplyNestedArguments(app, argc, argv);
            app.parse(argc, argv);
            // The memory limit before anything is loaded: the default, unless the command says
            // otherwise (info too: what it loads, it loads under the same limit as a render).
            setMemoryLimit(0);
            for (const FrameArgs* a : {static_cast<const FrameArgs*>(&r), static_cast<const FrameArgs*>(&i),
                                       static_cast<const FrameArgs*>(&b), static_cast<const FrameArgs*>(&c),
                                       static_cast<const FrameArgs*>(&t)})
                if (!a->maxMemory.empty()) setMemoryLimit(parseMemorySize(a->maxMemory));
            if (*render) {
                r.argv.assign(argv, argv + argc);
                return runRender(r);
            }
            if (*info) return runInfo(i);
            if (*bench) {
                b.given = givenOptions(bench);
                b.argv.assign(argv, argv + argc);
                return runBench(b);
            }
            if (*compare) {
                c.argv.assign(argv, argv + argc);
                c.samplesGiven = compare->get_option("--samples")->count() > 0;
                return runCompare(c);
            }
            if (*tune) {
                t.argv.assign(argv, argv + argc);
                return runTune(t);
            }
        } catch (const CLI::ParseError& e) {
            if (e.get_exit_code() == 0) return app.exit(e); // --help, --version
            std::fprintf(stderr, "stsv: error: %s (see stsv --help)\n", printable(e.what()).c_str());
            return 1;
        }
        return 0;
    });
}

} // namespace stsv
