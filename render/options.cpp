#include "render/options.h"

#include "core/error.h"

namespace stsv {

Method parseMethod(const std::string& name) {
    if (name == "reference") return Method::Reference;
    if (name == "stsv") return Method::Stsv;
    if (name == "pw") return Method::Pw;
    if (name == "dcs") return Method::Dcs;
    if (name == "pw+stsv") return Method::PwStsv;
    if (name == "dcs+stsv") return Method::DcsStsv;
    throw UsageError("unknown method '" + name +
                     "' (expected reference, stsv, pw, dcs, pw+stsv or dcs+stsv)");
}

Backend parseBackend(const std::string& name) {
    if (name == "cpu") return Backend::Cpu;
    if (name == "vulkan") return Backend::Vulkan;
    throw UsageError("unknown backend '" + name + "' (expected vulkan or cpu)");
}

BufferKind parseBufferKind(const std::string& name) {
    if (name == "bitmask") return BufferKind::Bitmask;
    if (name == "counters") return BufferKind::Counters;
    throw UsageError("unknown light-sample buffer '" + name + "' (expected bitmask or counters)");
}

std::string toString(Method method) {
    switch (method) {
    case Method::Reference:
        return "reference";
    case Method::Stsv:
        return "stsv";
    case Method::Pw:
        return "pw";
    case Method::Dcs:
        return "dcs";
    case Method::PwStsv:
        return "pw+stsv";
    case Method::DcsStsv:
        return "dcs+stsv";
    }
    return "?";
}
std::string toString(Backend backend) {
    return backend == Backend::Cpu ? "cpu" : "vulkan";
}
std::string toString(BufferKind kind) {
    return kind == BufferKind::Bitmask ? "bitmask" : "counters";
}

void validate(const RenderOptions& o) {
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        throw UsageError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                         " is out of range (1 to 16384 per side)");
    if (o.samples != 16 && o.samples != 32 && o.samples != 64 && o.samples != 128 && o.samples != 256)
        throw UsageError("--samples " + std::to_string(o.samples) + " is not one of 16, 32, 64, 128, 256");
    if (o.interleave < 1 || o.interleave > 8)
        throw UsageError("--interleave " + std::to_string(o.interleave) + " is out of range (1 to 8)");
    if (!(o.ambient >= 0.0f && o.ambient <= 1.0f)) throw UsageError("--ambient must lie in [0, 1]");
}

nlohmann::json toJson(const RenderOptions& o) {
    return {{"method", toString(o.method)},
            {"backend", toString(o.backend)},
            {"width", o.width},
            {"height", o.height},
            {"samples", o.samples},
            {"pattern", toString(o.pattern)},
            {"seed", o.seed},
            {"interleave", o.interleave},
            {"decorrelate", o.decorrelate},
            {"buffer", toString(o.buffer)},
            {"ambient", o.ambient},
            {"device", o.device},
            {"validation", o.validation}};
}

} // namespace stsv
