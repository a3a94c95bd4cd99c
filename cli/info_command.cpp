// `stsv info`: what this build offers and what the machine has.
#include "cli/cli_util.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/version.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "scene/load.h"

#include <embree3/rtcore.h>

#include <iostream>
#include <sstream>
#include <thread>

namespace stsv {

namespace {

std::string backendList(const MethodInfo& m) {
    std::string text;
    for (Backend b : m.backends) text += (text.empty() ? "" : ", ") + toString(b);
    return text;
}

} // namespace

int runInfo(const InfoArgs& args) {
    std::ostream& out = std::cout;
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
            shaderSource = {{"embedded", false}, {"error", e.what()}};
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
                                   {"device_local_bytes", d.deviceLocalBytes}});
            vulkan = {{"devices", devices}};
        } catch (const Error& e) {
            vulkan = {{"devices", nlohmann::json::array()}, {"error", e.what()}};
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
        out << "      " << toString(m.family) << "; writes " << toString(m.output) << "; runs on "
            << backendList(m) << '\n';
        for (const MethodKnob& k : m.knobs)
            out << "      --param " << k.name << '=' << k.defaultValue << "  " << k.help << " (" << k.min
                << " to " << k.max << ")\n";
    }
    out << "backends:  vulkan, cpu (default: " << toString(defaultBackend()) << ")\n";
    out << "patterns:  uniform, stratified, poisson, lowdisc; samples 16, 32, 64, 128, 256\n";
    out << "buffers:   bitmask, counters\n";
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
        out << "shaders: " << e.what() << '\n';
    }
    out << "cpu threads: " << std::thread::hardware_concurrency() << '\n';
    out << "embree: " << RTC_VERSION_STRING << '\n';
    try {
        const std::vector<DeviceInfo> devices = listDevices();
        if (devices.empty()) out << "vulkan: no devices\n";
        for (const DeviceInfo& d : devices) out << "vulkan " << describe(d);
    } catch (const Error& e) {
        std::string reason = e.what();
        if (const auto nl = reason.find('\n'); nl != std::string::npos) reason.resize(nl);
        out << "vulkan: unavailable (" << reason << ")\n";
    }
    return 0;
}

} // namespace stsv
