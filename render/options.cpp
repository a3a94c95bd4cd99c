#include "render/options.h"

#include "core/error.h"
#include "render/frame.h"

namespace stsv {

void validate(const RenderOptions& o) {
    if (o.width < 1 || o.width > 16384 || o.height < 1 || o.height > 16384)
        throw UsageError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                         " is out of range (1 to 16384 per side)");
    if (o.samples != 16 && o.samples != 32 && o.samples != 64 && o.samples != 128 && o.samples != 256)
        throw UsageError("--samples " + std::to_string(o.samples) + " is not one of 16, 32, 64, 128, 256");
    if (o.interleave < 1 || o.interleave > 8)
        throw UsageError("--interleave " + std::to_string(o.interleave) + " is out of range (1 to 8)");
    if (!(o.ambient >= 0.0f && o.ambient <= 1.0f)) throw UsageError("--ambient must lie in [0, 1]");
    if (o.supersample < 1 || o.supersample > 4)
        throw UsageError("--supersample " + std::to_string(o.supersample) + " is out of range (1 to 4)");
    if (o.width * o.supersample > 16384 || o.height * o.supersample > 16384)
        throw UsageError("--supersample " + std::to_string(o.supersample) + " of " + std::to_string(o.width) +
                         "x" + std::to_string(o.height) + " needs a sub-pixel grid above 16384 per side");
    validateMethodParams(methodInfo(o.method), o.params);
    if (o.buffer == BufferKind::Transmittance && !methodInfo(o.method).writesTransmittance()) {
        std::string writers;
        for (const MethodInfo& m : methodTable())
            if (m.writesTransmittance()) writers += (writers.empty() ? "" : ", ") + m.name;
        throw UsageError("--buffer transmittance: " + methodInfo(o.method).name +
                         " does not write fractional transmittance (" + writers + " do)");
    }
}

RenderOptions frameOptions(RenderOptions options) {
    options.buffer = methodInfo(options.method).bufferKind(options.buffer);
    options.width *= options.supersample;
    options.height *= options.supersample;
    return options;
}

SamplePlan samplePlanOf(const RenderOptions& o) {
    SamplePlan plan = makeSamplePlan(o.pattern, o.samples, o.seed, o.interleave, o.decorrelate);
    plan.supersample = o.supersample;
    return plan;
}

void resolveSupersampling(Frame& frame, const RenderOptions& requested) {
    const int k = requested.supersample;
    if (k > 1) {
        auto average = [&](const ImageF& fine) {
            ImageF out(requested.width, requested.height, fine.channels);
            const float weight = 1.0f / float(k * k);
            for (int y = 0; y < requested.height; ++y)
                for (int x = 0; x < requested.width; ++x)
                    for (int c = 0; c < fine.channels; ++c) {
                        float sum = 0.0f;
                        for (int j = 0; j < k; ++j)
                            for (int i = 0; i < k; ++i) sum += fine.at(x * k + i, y * k + j, c);
                        out.at(x, y, c) = sum * weight;
                    }
            return out;
        };
        frame.color = average(frame.color);
        frame.visibility = average(frame.visibility);
    }
    if (frame.stats.contains("options")) {
        frame.stats["options"]["width"] = requested.width;
        frame.stats["options"]["height"] = requested.height;
    }
}

namespace {

/// The method's knobs, given or default.
MethodParams withDefaults(const RenderOptions& o) {
    MethodParams params = o.params;
    for (const MethodKnob& k : methodInfo(o.method).knobs) params.emplace(k.name, k.defaultValue);
    return params;
}

} // namespace

ExtrusionStage parseExtrusionStage(const std::string& name) {
    if (name == "auto") return ExtrusionStage::Auto;
    if (name == "geometry") return ExtrusionStage::Geometry;
    if (name == "mesh") return ExtrusionStage::Mesh;
    if (name == "hull") return ExtrusionStage::Hull;
    throw UsageError("unknown extrusion stage '" + name + "' (expected auto, hull, geometry or mesh)");
}

std::string toString(ExtrusionStage stage) {
    switch (stage) {
    case ExtrusionStage::Geometry:
        return "geometry";
    case ExtrusionStage::Mesh:
        return "mesh";
    case ExtrusionStage::Hull:
        return "hull";
    case ExtrusionStage::Auto:
        break;
    }
    return "auto";
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
            {"validation", o.validation},
            {"extrusion", toString(o.extrusion)},
            {"supersample", o.supersample},
            {"params", withDefaults(o)}};
}

double methodKnob(const RenderOptions& options, std::string_view name) {
    const MethodInfo& method = methodInfo(options.method);
    const MethodKnob* knob = method.knob(name);
    if (!knob) throw UsageError("method " + method.name + " has no parameter '" + std::string(name) + "'");
    const auto given = options.params.find(std::string(name));
    return given != options.params.end() ? given->second : knob->defaultValue;
}

ShadowMapSettings shadowMapSettings(const RenderOptions& options) {
    const ShadowMapMethod filter = methodInfo(options.method).shadowMap;
    return filter == ShadowMapMethod::None ? ShadowMapSettings{}
                                           : shadowMapSettingsFrom(filter, options.params);
}

} // namespace stsv
