// `stsv info`: what this build offers and what the machine has.
#include "cli/cli_util.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "gpu/device.h"
#include "scene/load.h"

#include <embree3/rtcore.h>

#include <iostream>
#include <sstream>
#include <thread>

namespace stsv {

int runInfo() {
    std::ostream& out = std::cout;
    out << "stsv " << STSV_VERSION << ": soft shadows from area lights with soft textured shadow volumes\n\n";
    out << "methods:   reference (Embree ray tracing), stsv (soft textured shadow volumes), pw (penumbra "
           "wedges),\n"
           "           dcs (depth complexity sampling), pw+stsv, dcs+stsv (wedges for opaque, STSV for "
           "perforated)\n";
    out << "on vulkan:";
    for (Method m :
         {Method::Reference, Method::Stsv, Method::Pw, Method::Dcs, Method::PwStsv, Method::DcsStsv})
        if (backendImplements(m, Backend::Vulkan)) out << ' ' << toString(m);
    out << " (every method runs on cpu)\n";
    out << "backends:  vulkan, cpu (default: " << toString(defaultBackend()) << ")\n";
    out << "patterns:  uniform, stratified, poisson, lowdisc; samples 16, 32, 64, 128, 256\n";
    out << "buffers:   bitmask, counters\n";
    out << "built-in scenes:\n";
    for (const std::string& name : builtinSceneNames()) {
        out << "  " << name << ": " << describeBuiltinScene(name) << '\n';
        for (const SceneKnob& k : builtinSceneKnobs(name))
            out << "      --set " << k << "  " << k.description << '\n';
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
