// `stsv info`: what this build offers and what the machine has.
#include "cli/cli_util.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/memory_budget.h"
#include "core/version.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "render/frame.h"
#include "render/vulkan/gpu_renderer.h"
#include "scene/load.h"

#include <glm/trigonometric.hpp>

#include <embree3/rtcore.h>

#include <algorithm>
#include <iostream>
#include <sstream>
#include <thread>

namespace stsv {

namespace {

/// The --extrusion values device `d` runs.
std::vector<std::string> extrusionNames(const DeviceInfo& d) {
    std::vector<std::string> names;
    for (const ExtrusionStage stage : offeredExtrusions(d)) names.push_back(toString(stage));
    return names;
}

/// The light-sample buffers row `m` writes, from the table: for each kind --buffer may ask of it
/// (transmittance only where MethodInfo::writesTransmittance), the kind the row's frame holds
/// (MethodInfo::bufferKind), each once, in --buffer's order. None for a row that writes a
/// visibility image only.
std::vector<BufferKind> bufferKindsOf(const MethodInfo& m) {
    std::vector<BufferKind> kinds;
    if (m.output == MethodOutput::Visibility) return kinds;
    for (BufferKind requested : {BufferKind::Bitmask, BufferKind::Counters, BufferKind::Transmittance}) {
        if (requested == BufferKind::Transmittance && !m.writesTransmittance()) continue;
        const BufferKind held = m.bufferKind(requested);
        if (std::find(kinds.begin(), kinds.end(), held) == kinds.end()) kinds.push_back(held);
    }
    return kinds;
}

/// "a, b or c".
std::string listText(const std::vector<BufferKind>& kinds, const char* conjunction) {
    std::string text;
    for (std::size_t i = 0; i < kinds.size(); ++i)
        text += (i == 0                  ? ""
                 : i + 1 == kinds.size() ? std::string(" ") + conjunction + " "
                                         : ", ") +
                toString(kinds[i]);
    return text;
}

/// What row `m` writes per light: "per-sample bitmask, counters or transmittance (--buffer)",
/// "per-sample counters", "visibility image", or for a visibility row that takes translucent
/// triangles' transmittance (MethodInfo::writesTransmittance) "visibility image (fractional
/// through translucent triangles with --buffer transmittance)".
std::string writesText(const MethodInfo& m) {
    const std::vector<BufferKind> kinds = bufferKindsOf(m);
    if (kinds.empty())
        return toString(m.output) + (m.writesTransmittance()
                                         ? " (fractional through translucent triangles with "
                                           "--buffer transmittance)"
                                         : "");
    return "per-sample " + listText(kinds, "or") + (kinds.size() > 1 ? " (--buffer)" : "");
}

std::string backendList(const MethodInfo& m) {
    std::string text;
    for (Backend b : m.backends) text += (text.empty() ? "" : ", ") + toString(b);
    return text;
}

const char* lightTypeName(uint type) {
    switch (type) {
    case LIGHT_RECTANGLE:
        return "rectangle";
    case LIGHT_DISK:
        return "disk";
    case LIGHT_SPHERE:
        return "sphere";
    default:
        return "directional";
    }
}

nlohmann::json vec(vec3 v) {
    return {v.x, v.y, v.z};
}

/// The texels the scene holds, RGBA8, and what each texture's record costs besides.
double textureBytes(const Scene& scene) {
    double bytes = 0.0;
    for (const Texture& t : scene.textures) bytes += double(t.rgba.capacity()) + double(sizeof(Texture));
    return bytes;
}

/// What the scene holds from loading to a frame: each triangle's share of every stage
/// (SCENE_BYTES_PER_TRIANGLE: positions, meshes, adjacency, the ray tracer's BVH, GPU tables),
/// its textures' texels, and its materials, meshes and lights.
double sceneBytes(const Scene& scene) {
    return double(scene.triangleCount()) * SCENE_BYTES_PER_TRIANGLE + textureBytes(scene) +
           double(scene.materials.size() * sizeof(Material) + scene.meshes.size() * sizeof(Mesh) +
                  scene.lights.size() * sizeof(Light));
}

/// What a scene holds and what a frame of `args`' options would hold, as JSON (printed as text
/// or as it is with --json).
nlohmann::json sceneInfo(const InfoArgs& args) {
    RenderOptions o = resolveFrameOptions(args);
    const bool automatic = args.method == AUTO_METHOD;
    if (!automatic) o.method = parseMethod(args.method);
    const Scene scene = loadScene(args.scene, sceneOptionsOf(args));
    if (automatic) o.method = autoMethod(scene);
    o.params = parseMethodParams(methodInfo(o.method), args.params);
    o.backend =
        args.backend.empty() ? defaultBackendFor(o.method, defaultBackend()) : parseBackend(args.backend);
    checkBackendSupports(o.method, o.backend);
    printSceneWarnings(scene, args.quiet);

    nlohmann::json j = sceneStats(scene);
    j["opaque_triangles"] = scene.triangleCount() - j["perforated_triangles"].get<std::size_t>() -
                            j["translucent_triangles"].get<std::size_t>();
    nlohmann::json materials = nlohmann::json::array();
    for (const Material& m : scene.materials) {
        nlohmann::json e = {{"name", m.name}, {"albedo", vec(m.albedo)}, {"double_sided", m.doubleSided}};
        e["alpha_mode"] = m.alphaMode == AlphaMode::Blend  ? "blend"
                          : m.alphaMode == AlphaMode::Mask ? (m.perforated() ? "mask" : "opaque")
                                                           : "opaque";
        if (m.translucent()) e["alpha_factor"] = m.alphaFactor;
        // The texture whose alpha the material reads: a translucent one's blend texture (its
        // binary stand-in is derived), else the mask.
        const int texture = m.translucent() ? m.blendTexture : m.alphaTexture;
        if (texture >= 0) {
            const Texture& t = scene.textures[std::size_t(texture)];
            e["alpha_texture"] = {{"name", t.name},
                                  {"width", t.width},
                                  {"height", t.height},
                                  {"wrap", m.wrap == WrapMode::Repeat ? "repeat" : "clamp"}};
        }
        materials.push_back(e);
    }
    j["materials"] = materials;
    nlohmann::json lights = nlohmann::json::array();
    for (const Light& l : scene.lights) {
        nlohmann::json e = {{"type", lightTypeName(l.type)}, {"radiance", vec(l.radiance)}};
        if (l.type == LIGHT_DIRECTIONAL) {
            e["direction"] = vec(l.normal);
            e["angular_radius_degrees"] = glm::degrees(l.angularRadius);
        } else {
            e["position"] = vec(l.position);
            if (l.type != LIGHT_SPHERE) e["normal"] = vec(l.normal);
            if (l.type == LIGHT_RECTANGLE)
                e["size"] = {2.0f * length(l.axisU), 2.0f * length(l.axisV)};
            else
                e["radius"] = l.radius;
        }
        lights.push_back(e);
    }
    j["light_list"] = lights;
    const Bounds b = scene.bounds();
    j["bounds"] = {{"lo", vec(b.lo)}, {"hi", vec(b.hi)}, {"extent", vec(b.extent())}};
    j["camera"] = {{"eye", vec(scene.camera.eye)},
                   {"target", vec(scene.camera.target)},
                   {"up", vec(scene.camera.up)},
                   {"fov_y_degrees", scene.camera.fovY}};
    const double frameBytes = estimateFrameBytes(o, scene);
    j["memory"] = {{"scene_bytes", sceneBytes(scene)},
                   {"texture_bytes", textureBytes(scene)},
                   {"frame_bytes", frameBytes},
                   {"limit_bytes", memoryLimitBytes()},
                   {"frame",
                    {{"method", toString(o.method)},
                     {"backend", toString(o.backend)},
                     {"width", o.width},
                     {"height", o.height},
                     {"samples", o.samples},
                     {"buffer", toString(o.buffer)}}}};
    return j;
}

void printSceneInfo(const nlohmann::json& j, std::ostream& out) {
    auto v3 = [](const nlohmann::json& v) {
        std::ostringstream s;
        s << '(' << v[0].get<double>() << ", " << v[1].get<double>() << ", " << v[2].get<double>() << ')';
        return s.str();
    };
    out << printable(j["source"].get<std::string>()) << '\n';
    out << "  triangles: " << j["triangles"] << " (" << j["opaque_triangles"] << " opaque, "
        << j["perforated_triangles"] << " perforated, " << j["translucent_triangles"]
        << " translucent); faces skipped as degenerate: " << j["skipped_faces"]
        << "; triangles of zero area (kept, drawn by no method): " << j["zero_area_triangles"] << '\n';
    out << "  materials:\n";
    for (const nlohmann::json& m : j["materials"]) {
        out << "    " << printable(m["name"].get<std::string>()) << ": albedo " << v3(m["albedo"])
            << (m["double_sided"].get<bool>() ? ", double-sided" : "") << ", "
            << m["alpha_mode"].get<std::string>();
        if (m.contains("alpha_factor")) out << " (alpha factor " << m["alpha_factor"].get<double>() << ")";
        if (m.contains("alpha_texture")) {
            const nlohmann::json& t = m["alpha_texture"];
            out << ", alpha texture " << printable(t["name"].get<std::string>()) << " (" << t["width"] << "x"
                << t["height"] << ", " << t["wrap"].get<std::string>() << ")";
        }
        out << '\n';
    }
    out << "  lights:\n";
    for (const nlohmann::json& l : j["light_list"]) {
        out << "    " << l["type"].get<std::string>();
        if (l.contains("position")) out << " at " << v3(l["position"]);
        if (l.contains("direction")) out << " towards " << v3(l["direction"]);
        if (l.contains("normal")) out << ", normal " << v3(l["normal"]);
        if (l.contains("size"))
            out << ", " << l["size"][0].get<double>() << " x " << l["size"][1].get<double>();
        if (l.contains("radius")) out << ", radius " << l["radius"].get<double>();
        if (l.contains("angular_radius_degrees"))
            out << ", angular radius " << l["angular_radius_degrees"].get<double>() << " degrees";
        out << ", radiance " << v3(l["radiance"]) << '\n';
    }
    out << "  bounds: " << v3(j["bounds"]["lo"]) << " to " << v3(j["bounds"]["hi"]) << '\n';
    const nlohmann::json& c = j["camera"];
    out << "  camera: eye " << v3(c["eye"]) << ", target " << v3(c["target"]) << ", up " << v3(c["up"])
        << ", fovY " << c["fov_y_degrees"].get<double>() << " degrees\n";
    const nlohmann::json& m = j["memory"];
    const nlohmann::json& f = m["frame"];
    out << "  memory: scene about " << formatBytes(m["scene_bytes"].get<double>()) << " (textures "
        << formatBytes(m["texture_bytes"].get<double>()) << "); a " << f["width"] << "x" << f["height"]
        << " frame of " << f["method"].get<std::string>() << " on " << f["backend"].get<std::string>()
        << " with " << f["samples"] << " samples (" << f["buffer"].get<std::string>() << ") about "
        << formatBytes(m["frame_bytes"].get<double>()) << "; limit " << describeMemoryLimit() << '\n';
}

} // namespace

int runInfo(const InfoArgs& args) {
    std::ostream& out = std::cout;
    if (!args.scene.empty()) {
        const nlohmann::json j = sceneInfo(args);
        if (args.json)
            out << j.dump(2) << '\n';
        else
            printSceneInfo(j, out);
        return 0;
    }
    if (args.methodPairs) {
        for (const MethodInfo& m : methodTable())
            for (Backend b : m.backends) out << m.name << ' ' << toString(b) << '\n';
        return 0;
    }
    if (args.markdown) {
        out << methodTableMarkdown();
        return 0;
    }
    if (args.json) {
        nlohmann::json scenes = nlohmann::json::array();
        for (const std::string& name : builtinSceneNames()) {
            nlohmann::json knobs = nlohmann::json::array();
            for (const SceneKnob& k : builtinSceneKnobs(name))
                knobs.push_back({{"name", k.name}, {"default", k.defaultValue}, {"help", k.description}});
            scenes.push_back({{"name", name}, {"description", describeBuiltinScene(name)}, {"knobs", knobs}});
        }
        nlohmann::json shaderSource;
        try {
            const ShaderCompiler shaders;
            shaderSource = {{"embedded", shaders.shaderDirectory().empty()},
                            {"source", shaders.describeSource()}};
        } catch (const Error& e) {
            shaderSource = {{"embedded", false}, {"error", e.message()}};
        }
        nlohmann::json vulkan;
        try {
            nlohmann::json devices = nlohmann::json::array();
            for (const DeviceInfo& d : listDevices())
                devices.push_back({{"index", d.index},
                                   {"name", d.name},
                                   {"driver", d.driverName + " (" + d.driverInfo + ")"},
                                   {"api", apiVersionString(d.apiVersion)},
                                   {"geometry_shader", d.geometryShader},
                                   {"mesh_shader", d.meshShader},
                                   {"extrusions", extrusionNames(d)},
                                   {"device_local_bytes", d.deviceLocalBytes}});
            vulkan = {{"devices", devices}};
        } catch (const Error& e) {
            vulkan = {{"devices", nlohmann::json::array()}, {"error", e.message()}};
        }
        out << nlohmann::json{{"version", version()},
                              {"methods", methodTableJson()},
                              {"scenes", scenes},
                              {"shaders", shaderSource},
                              {"cpu_threads", std::thread::hardware_concurrency()},
                              {"embree", RTC_VERSION_STRING},
                              {"vulkan", vulkan}}
                   .dump(2)
            << '\n';
        return 0;
    }
    out << "stsv " << version() << ": soft shadows from area lights with soft textured shadow volumes\n\n";
    out << "methods:\n";
    for (const MethodInfo& m : methodTable()) {
        out << "  " << m.name << ": " << m.description << '\n';
        out << "      " << toString(m.family) << "; writes " << writesText(m) << "; runs on "
            << backendList(m) << '\n';
        for (const MethodKnob& k : m.knobs)
            out << "      --param " << k.name << '=' << k.defaultValue << "  " << k.help << " (" << k.min
                << " to " << k.max << ")\n";
    }
    out << "backends:  vulkan, cpu (default: " << toString(defaultBackend()) << ")\n";
    out << "patterns:  uniform, stratified, poisson, lowdisc; samples 16, 32, 64, 128, 256\n";
    std::vector<BufferKind> buffers; // every kind some row writes
    for (const MethodInfo& m : methodTable())
        for (BufferKind kind : bufferKindsOf(m))
            if (std::find(buffers.begin(), buffers.end(), kind) == buffers.end()) buffers.push_back(kind);
    std::sort(buffers.begin(), buffers.end());
    out << "buffers:   " << listText(buffers, "and") << " (--buffer; default "
        << toString(BufferKind::Bitmask) << ")\n";
    out << "built-in scenes:\n";
    for (const std::string& name : builtinSceneNames()) {
        out << "  " << name << ": " << describeBuiltinScene(name) << '\n';
        for (const SceneKnob& k : builtinSceneKnobs(name))
            out << "      --set " << k << "  " << k.description << '\n';
    }
    try {
        const ShaderCompiler shaders;
        out << "shaders: " << shaders.describeSource()
            << (shaders.shaderDirectory().empty() ? " (STSV_SHADER_DIR=FOLDER reads a folder instead)\n"
                                                  : " (STSV_SHADER_DIR)\n");
    } catch (const Error& e) {
        out << "shaders: " << printable(e.message()) << '\n';
    }
    out << "cpu threads: " << std::thread::hardware_concurrency() << '\n';
    out << "embree: " << RTC_VERSION_STRING << '\n';
    try {
        const std::vector<DeviceInfo> devices = listDevices();
        if (devices.empty()) out << "vulkan: no devices\n";
        for (const DeviceInfo& d : devices) {
            out << "vulkan " << describe(d) << "  extrusions (--extrusion):";
            for (const std::string& name : extrusionNames(d)) out << ' ' << name;
            out << '\n';
        }
    } catch (const Error& e) {
        std::string reason = printable(e.message());
        if (const auto nl = reason.find('\n'); nl != std::string::npos) reason.resize(nl);
        out << "vulkan: unavailable (" << reason << ")\n";
    }
    return 0;
}

} // namespace stsv
