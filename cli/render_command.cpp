// `stsv render`: one frame of one scene to an image, a visibility image, light-sample buffers
// and a stats JSON.
#include "cli/cli_util.h"
#include "cli/commands.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/files.h"
#include "core/progress.h"
#include "core/timer.h"
#include "core/version.h"
#include "render/renderer.h"
#include "scene/load.h"
#include "shadowmaps/kept_maps.h"
#include "shadowmaps/shadow_map_dh.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>

namespace stsv {

namespace {

/// How to read a --shadow-map file: its projection and frame (shadowmaps/shadow_map_dh.h). Texel
/// (i, j) of a face covers u in [i, i + 1)/size, v in [j, j + 1)/size of the face's window.
nlohmann::json shadowMapViewJson(const ShadowMapView& v) {
    auto vec = [](vec3 x) { return nlohmann::json::array({x.x, x.y, x.z}); };
    const char* projection = v.projection == SHADOW_MAP_CUBE           ? "cube"
                             : v.projection == SHADOW_MAP_ORTHOGRAPHIC ? "orthographic"
                                                                       : "perspective";
    return {{"projection", projection}, {"origin", vec(v.origin)},
            {"axis_x", vec(v.axisX)},   {"axis_y", vec(v.axisY)},
            {"axis_z", vec(v.axisZ)},   {"window", {v.window.x, v.window.y, v.window.z, v.window.w}},
            {"near", v.near},           {"far", v.far},
            {"size", v.size},           {"faces", v.faces}};
}

/// float32 [faces, size, size], +inf where the texel sees no surface (NumPy's np.isinf).
void writeShadowMapNpy(const std::string& path, const ShadowMap& map) {
    std::vector<float> depth = map.depth;
    for (float& d : depth)
        if (d >= SHADOW_MAP_EMPTY) d = std::numeric_limits<float>::infinity();
    const std::size_t size = map.view.size;
    writeNpy(path, "<f4", {std::size_t(map.view.faces), size, size}, depth.data(),
             depth.size() * sizeof(float));
}

} // namespace

SceneOptions sceneOptionsOf(const FrameArgs& args) {
    SceneOptions o = parseSets(args.sets);
    o.camera = args.camera;
    o.lights = args.lights;
    o.addLights = args.addLights;
    return o;
}

RenderOptions resolveFrameOptions(const FrameArgs& args) {
    RenderOptions o = args.options;
    o.pattern = parsePatternKind(args.pattern);
    o.buffer = parseBufferKind(args.buffer);
    o.extrusion = parseExtrusionStage(args.extrusion);
    parseSize(args.size, o.width, o.height);
    validate(o);
    return o;
}

namespace {

/// Every file a render writes, in the order it writes them: the options' files, each light's
/// beyond the first (perLightPath) and the metadata beside each .npy of light samples or visibility.
std::vector<OutputFile> outputFilesOf(const RenderArgs& args, std::size_t lights) {
    std::vector<OutputFile> files = {{"-o", args.output, {".png", ".exr"}},
                                     {"--visibility", args.visibility, {".png", ".npy", ".exr"}}};
    if (lowerExtension(args.visibility) == ".npy")
        files.push_back({"--visibility's metadata", npyInfoPath(args.visibility), {".json"}});
    for (std::size_t l = 0; !args.dumpLs.empty() && l < std::max<std::size_t>(lights, 1); ++l) {
        const std::string option = l == 0 ? "--dump-ls" : "--dump-ls (light " + std::to_string(l) + ")";
        files.push_back({option, perLightPath(args.dumpLs, l), {".npy"}});
        files.push_back({option + "'s metadata", npyInfoPath(perLightPath(args.dumpLs, l)), {".json"}});
    }
    for (std::size_t l = 0; !args.shadowMap.empty() && l < std::max<std::size_t>(lights, 1); ++l)
        files.push_back({l == 0 ? "--shadow-map" : "--shadow-map (light " + std::to_string(l) + ")",
                         perLightPath(args.shadowMap, l),
                         {".npy"}});
    files.push_back({"--stats", args.stats, {".json"}});
    return files;
}

std::size_t bufferBytes(const Frame& frame) {
    std::size_t bytes = 0;
    for (const LightSampleBuffer& b : frame.lightSamples) bytes += b.memoryBytes();
    return bytes;
}

} // namespace

namespace {

/// A method writes only the outputs it has: no light samples from a v_coef, no depth map from a
/// method that keeps none.
void checkMethodOutputs(const RenderArgs& args, const MethodInfo& method) {
    if (!args.dumpLs.empty() && method.output == MethodOutput::Visibility)
        throw UsageError("--dump-ls: method " + method.name +
                         " has no per-sample answer (it writes a v_coef per pixel); write that with "
                         "--visibility, or dump the light samples of a per-sample method");
    if (!args.shadowMap.empty() && method.shadowMap == ShadowMapMethod::None)
        throw UsageError("--shadow-map: method " + method.name +
                         " renders no shadow map (image-based methods do)");
    if (!args.shadowMap.empty() && method.shadowMap == ShadowMapMethod::Peel)
        throw UsageError("--shadow-map: method " + method.name +
                         " keeps a depth grid of front and back faces, not a depth map (its size and "
                         "memory are in --stats)");
    if (!args.shadowMap.empty() && readsTransmittanceFunctions(method.shadowMap))
        throw UsageError("--shadow-map: method " + method.name +
                         " keeps transmittance functions, not a depth map (their nodes and memory are in "
                         "--stats)");
}

/// --visibility: v_coef as an 8-bit PNG, a float EXR, or a float32 .npy with its metadata.
void writeVisibility(const std::string& path, const ImageF& visibility, const RenderOptions& o,
                     std::size_t lights, const std::string& madeBy, std::vector<std::string>& written) {
    const std::string ext = lowerExtension(path);
    if (ext == ".png") {
        writePng(path, toImage8(visibility, false));
    } else if (ext == ".exr") {
        writeExr(path, visibility, false); // float32 Y: v_coef unquantised
    } else {
        writeNpy(path, visibility); // float32 v_coef, unquantised
        try {
            writeJson(npyInfoPath(path), {{"format", "stsv visibility"},
                                          {"samples", o.samples},
                                          {"width", o.width},
                                          {"height", o.height},
                                          {"lights", lights},
                                          {"method", madeBy}});
        } catch (const Error&) {
            // The array and its metadata are one output: neither is left.
            std::error_code ec;
            std::filesystem::remove(path, ec);
            throw;
        }
        written.push_back(path);
        written.push_back(npyInfoPath(path));
    }
    if (ext != ".npy") written.push_back(path);
}

/// The frame's stats as --stats writes them: what the CLI adds to the renderer's (scene, load
/// and call times, buffer bytes, the command, the outputs).
void completeRenderStats(Frame& frame, const RenderArgs& args, const RenderOptions& o, const Scene& scene,
                         const SceneOptions& sceneOptions, double loadMs, double renderMs,
                         const nlohmann::json& mapViews, const std::vector<std::string>& npyFiles,
                         const std::vector<std::string>& mapFiles) {
    nlohmann::json& stats = frame.stats;
    if (!mapViews.empty()) stats["shadow_map_views"] = mapViews;
    if (!stats.contains("options")) stats["options"] = toJson(o);
    if (!stats.contains("scene")) stats["scene"] = sceneStats(scene);
    stats["scene"]["spec"] = args.scene;
    stats["scene"]["set"] = sceneOptions.set;
    stats["scene_load_ms"] = loadMs;
    stats["render_call_ms"] = renderMs; // start-up + one frame
    if (!stats.contains("light_sample_buffer_bytes")) stats["light_sample_buffer_bytes"] = bufferBytes(frame);
    stats["light_sample_buffer_bytes_total"] = bufferBytes(frame);
    stats["command"] = args.argv;
    stats["version"] = version();
    stats["outputs"] = {{"image", args.output},
                        {"visibility", args.visibility},
                        {"light_samples", npyFiles},
                        {"shadow_maps", mapFiles}};
}

} // namespace

int runRender(RenderArgs& args) {
    if (args.quiet) Progress::setEnabled(false);
    RenderOptions o = resolveFrameOptions(args);
    const SceneOptions sceneOptions = sceneOptionsOf(args);
    // `auto` is chosen by the scene's triangles, so the scene is loaded before the method's checks;
    // a named method's are made first, before a possibly long load.
    std::optional<Scene> loaded;
    double loadMs = 0.0;
    const auto load = [&] {
        Timer loadTimer;
        loaded.emplace(loadScene(args.scene, sceneOptions));
        loadMs = loadTimer.milliseconds();
    };
    const bool automatic = args.method == AUTO_METHOD;
    if (automatic) {
        load();
        o.method = autoMethod(*loaded);
    } else {
        o.method = parseMethod(args.method);
    }
    o.params = parseMethodParams(methodInfo(o.method), args.params);
    if (args.backend.empty())
        o.backend = defaultBackendFor(o.method, defaultBackend());
    else
        o.backend = parseBackend(args.backend);
    checkBackendSupports(o.method, o.backend);

    // Every output is checked before the (possibly long) render: its format is the one its
    // extension names, no two outputs share a path, and a method writes only what it has.
    if (args.output.empty() && args.visibility.empty() && args.dumpLs.empty() && args.stats.empty())
        args.output = std::filesystem::path(args.scene).stem().string() + ".png";
    checkMethodOutputs(args, methodInfo(o.method));
    // The scene file itself is checked now, its textures once it is loaded.
    std::vector<InputFile> inputs;
    if (std::error_code ec; std::filesystem::is_regular_file(args.scene, ec))
        inputs.push_back({"the scene", args.scene});
    checkOutputFiles(outputFilesOf(args, 1), inputs);
    if (!args.dumpLs.empty() && o.buffer == BufferKind::Bitmask && o.samples % 8 != 0)
        throw UsageError("--dump-ls of a bitmask needs a sample count that is a multiple of 8");
    if (!args.shadowMap.empty()) o.keepShadowMaps = true;

    if (!loaded) load();
    const Scene& scene = *loaded;
    printSceneWarnings(scene, args.quiet);
    checkFrameMemory(o, scene);
    // Now that the lights are known: every file the frame will write, the other lights' and the
    // .npy files' metadata included, against each other and against the files the scene was read from.
    const std::vector<OutputFile> outputs = outputFilesOf(args, scene.lights.size());
    checkOutputFiles(outputs, sceneInputFiles(args.scene, scene));

    Timer total;
    Frame frame = renderFrame(scene, o);
    const double renderMs = total.milliseconds();
    for (const std::string& warning : frameWarnings(frame.stats))
        std::fprintf(stderr, "stsv: warning: %s\n", printable(warning).c_str());

    const std::string madeBy = toString(o.method) + "/" + toString(o.backend);
    std::vector<std::string> written; // every file, in the order written
    if (!args.output.empty()) {
        if (lowerExtension(args.output) == ".exr")
            writeExr(args.output, frame.color, true); // linear RGB, half floats: no clipped highlights
        else
            writePng(args.output, toImage8(frame.color, true));
        written.push_back(args.output);
    }
    if (!args.visibility.empty())
        writeVisibility(args.visibility, frame.visibility, o, scene.lights.size(), madeBy, written);
    std::vector<std::string> npyFiles;
    if (!args.dumpLs.empty())
        for (std::size_t l = 0; l < frame.lightSamples.size(); ++l) {
            npyFiles.push_back(perLightPath(args.dumpLs, l));
            frame.lightSamples[l].writeNpy(npyFiles.back(), madeBy);
            written.push_back(npyFiles.back());
            written.push_back(npyInfoPath(npyFiles.back()));
        }

    std::vector<std::string> mapFiles;
    nlohmann::json mapViews = nlohmann::json::array();
    const std::vector<ShadowMap>& maps = keptMaps(frame.keptMaps).shadowMaps;
    for (std::size_t l = 0; l < maps.size(); ++l) {
        mapFiles.push_back(perLightPath(args.shadowMap, l));
        writeShadowMapNpy(mapFiles.back(), maps[l]);
        written.push_back(mapFiles.back());
        mapViews.push_back(shadowMapViewJson(maps[l].view));
    }

    completeRenderStats(frame, args, o, scene, sceneOptions, loadMs, renderMs, mapViews, npyFiles, mapFiles);
    nlohmann::json& stats = frame.stats;
    stats["method_requested"] = args.method;
    if (!args.stats.empty()) {
        writeJson(args.stats, stats);
        written.push_back(args.stats);
    }

    if (!args.quiet) {
        const double frameMs = stats.contains("frame_ms") && stats["frame_ms"].is_number()
                                   ? stats["frame_ms"].get<double>()
                                   : renderMs;
        std::fprintf(stderr, "%s: %s%s on %s, %d samples, %dx%d: frame %.1f ms (start-up %.1f ms)\n",
                     printable(scene.source).c_str(), toString(o.method).c_str(), automatic ? " (auto)" : "",
                     toString(o.backend).c_str(), o.samples, o.width, o.height, frameMs,
                     stats.value("startup_ms", 0.0));
    }
    for (const std::string& path : written) reportWritten(path, args.quiet);
    return 0;
}

} // namespace stsv
