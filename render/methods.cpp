#include "render/methods.h"

#include "core/error.h"
#include "wedges/dcs_dh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace stsv {

namespace {

/// The knobs a shadow-map method reads (shadowmaps/shadow_map.h: the one list, with the method's
/// defaults).
std::vector<MethodKnob> mapKnobs(ShadowMapMethod filter) {
    const ShadowMapSettings defaults = defaultShadowMapSettings(filter);
    std::vector<MethodKnob> knobs;
    for (const ShadowMapKnob& k : shadowMapKnobs())
        if (k.readBy(filter))
            knobs.push_back({.name = k.name,
                             .defaultValue = k.get(defaults),
                             .min = k.min,
                             .max = k.max,
                             .integer = k.integer,
                             .help = k.help});
    return knobs;
}

/// DCS's knob, in the dcs rows.
std::vector<MethodKnob> dcsKnobs() {
    return {{.name = "ray_edges",
             .defaultValue = DCS_RAY_EDGES_PER_SAMPLE,
             .min = 0.0,
             .max = 1e9,
             .integer = false,
             .help =
                 "silhouette edges per light sample above which a 4x4 block counts its samples by rays "
                 "through the layer tree instead of crossings (0: every block with an edge; 1e9: never)"}};
}

std::vector<MethodInfo> buildTable() {
    using B = Backend;
    std::vector<MethodInfo> table = {
        {.id = Method::Reference,
         .name = "reference",
         .description = "Embree 3 shadow rays from p to every light sample, with the same alpha test",
         .family = MethodFamily::GroundTruth,
         .output = MethodOutput::SampleOcclusion,
         .backends = {B::Cpu},
         .knobs = {},
         .traced = true},
        {.id = Method::Stsv,
         .name = "stsv",
         .description = "Soft Textured Shadow Volumes: every triangle's penumbra volume, projective "
                        "barycentric lookup per sample (Eq. 1-5)",
         .family = MethodFamily::ObjectBased,
         .output = MethodOutput::SampleOcclusion,
         .backends = {B::Vulkan, B::Cpu},
         .knobs = {},
         .stsv = StsvTriangles::All},
        {.id = Method::Pw,
         .name = "pw",
         .description = "Penumbra Wedges for opaque triangles: hard shadow at the light centre plus "
                        "analytic wedge coverage",
         .family = MethodFamily::ObjectBased,
         .output = MethodOutput::Visibility,
         .backends = {B::Vulkan, B::Cpu},
         .knobs = {},
         .wedges = WedgeVariant::Pw},
        {.id = Method::Dcs,
         .name = "dcs",
         .description = "Depth Complexity Sampling for opaque triangles: layer count at the light "
                        "centre plus signed silhouette crossings",
         .family = MethodFamily::ObjectBased,
         .output = MethodOutput::SampleCounters,
         .backends = {B::Vulkan, B::Cpu},
         .knobs = dcsKnobs(),
         .wedges = WedgeVariant::Dcs},
        {.id = Method::PwStsv,
         .name = "pw+stsv",
         .description =
             "pw for opaque, STSV for perforated and translucent triangles; the STSV occluded fraction "
             "subtracted from v_coef",
         .family = MethodFamily::ObjectBased,
         .output = MethodOutput::Visibility,
         .backends = {B::Vulkan, B::Cpu},
         .knobs = {},
         .stsv = StsvTriangles::Perforated,
         .wedges = WedgeVariant::Pw},
        {.id = Method::DcsStsv,
         .name = "dcs+stsv",
         .description =
             "dcs for opaque, STSV for perforated and translucent triangles; STSV increments added to the "
             "counters",
         .family = MethodFamily::ObjectBased,
         .output = MethodOutput::SampleCounters,
         .backends = {B::Vulkan, B::Cpu},
         .knobs = dcsKnobs(),
         .stsv = StsvTriangles::Perforated,
         .wedges = WedgeVariant::Dcs},
    };
    // The image family: one row per variant, in its table's order.
    for (const ShadowMapVariant& v : shadowMapVariants())
        table.push_back({.id = imageMethod(v.filter),
                         .name = v.name,
                         .description = v.description,
                         .family = MethodFamily::ImageBased,
                         .output = v.representation == MapRepresentation::DepthGrid
                                       ? MethodOutput::SampleOcclusion
                                       : MethodOutput::Visibility,
                         .backends = {B::Vulkan, B::Cpu},
                         .knobs = mapKnobs(v.filter),
                         .shadowMap = v.filter});
    for (std::size_t i = 0; i < table.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (table[i].id == table[j].id || table[i].name == table[j].name)
                throw Error("method table: two rows of one id or name (" + table[i].name + ")");
    return table;
}

std::string formatNumber(double value) {
    std::ostringstream out;
    out << value;
    return out.str();
}

std::string knobList(const MethodInfo& method) {
    if (method.knobs.empty()) return "none";
    std::string text;
    for (const MethodKnob& k : method.knobs) {
        if (!text.empty()) text += ", ";
        text += k.name + " (" + formatNumber(k.min) + " to " + formatNumber(k.max) + ")";
    }
    return text;
}

UsageError unknownKnob(const MethodInfo& method, const std::string& name) {
    if (const char* why = retiredShadowMapKnob(name)) return UsageError("--param " + name + ": " + why);
    return UsageError("--param " + name + ": method " + method.name +
                      " has no such parameter (its parameters: " + knobList(method) + ")");
}

} // namespace

const std::vector<MethodInfo>& methodTable() {
    static const std::vector<MethodInfo> table = buildTable();
    return table;
}

const MethodInfo& methodInfo(Method method) {
    for (const MethodInfo& m : methodTable())
        if (m.id == method) return m;
    throw std::logic_error("no method of id " + std::to_string(unsigned(method)));
}

std::vector<TechniqueFamily> MethodInfo::techniques() const {
    std::vector<TechniqueFamily> families;
    if (traced) families.push_back(TechniqueFamily::Traced);
    if (wedges != WedgeVariant::None) families.push_back(TechniqueFamily::Wedges);
    if (stsv != StsvTriangles::None) families.push_back(TechniqueFamily::Stsv);
    if (shadowMap != ShadowMapMethod::None) families.push_back(TechniqueFamily::ShadowMaps);
    return families;
}

bool MethodInfo::implementedOn(Backend backend) const {
    return std::find(backends.begin(), backends.end(), backend) != backends.end();
}

bool MethodInfo::writesTransmittance() const {
    return traced || stsv != StsvTriangles::None;
}

bool MethodInfo::readsTransmittanceFunctions() const {
    return stsv::readsTransmittanceFunctions(shadowMap);
}

BufferKind MethodInfo::bufferKind(BufferKind requested) const {
    if (requested == BufferKind::Transmittance && writesTransmittance()) return requested;
    return output == MethodOutput::SampleCounters ? BufferKind::Counters : requested;
}

const MethodKnob* MethodInfo::knob(std::string_view knobName) const {
    for (const MethodKnob& k : knobs)
        if (k.name == knobName) return &k;
    return nullptr;
}

std::string methodNameList(std::string_view conjunction) {
    std::string text;
    const auto& table = methodTable();
    for (std::size_t i = 0; i < table.size(); ++i) {
        if (i > 0) text += i + 1 == table.size() ? " " + std::string(conjunction) + " " : ", ";
        text += table[i].name;
    }
    return text;
}

const MethodInfo& findMethod(std::string_view name) {
    for (const MethodInfo& m : methodTable())
        if (m.name == name) return m;
    if (name == AUTO_METHOD)
        throw UsageError(
            "method 'auto' is chosen per scene, where the scene is known (render, bench, compare); "
            "here name one of " +
            methodNameList());
    throw UsageError("unknown method '" + std::string(name) + "' (expected " + methodNameList() + ")");
}

Method parseMethod(const std::string& name) {
    return findMethod(name).id;
}

std::string toString(Method method) {
    return methodInfo(method).name;
}

Backend parseBackend(const std::string& name) {
    if (name == "cpu") return Backend::Cpu;
    if (name == "vulkan") return Backend::Vulkan;
    throw UsageError("unknown backend '" + name + "' (expected vulkan or cpu)");
}

BufferKind parseBufferKind(const std::string& name) {
    if (const std::optional<BufferKind> kind = bufferKindNamed(name)) return *kind;
    throw UsageError("unknown light-sample buffer '" + name +
                     "' (expected bitmask, counters or transmittance)");
}

std::string toString(Backend backend) {
    return backend == Backend::Cpu ? "cpu" : "vulkan";
}

std::string toString(BufferKind kind) {
    return bufferKindName(kind); // the names the files' metadata use (sampling/ls_buffer.h)
}

std::string toString(MethodFamily family) {
    switch (family) {
    case MethodFamily::ObjectBased:
        return "object-based";
    case MethodFamily::ImageBased:
        return "image-based";
    case MethodFamily::GroundTruth:
        return "ground truth";
    }
    return "?";
}

std::string toString(MethodOutput output) {
    switch (output) {
    case MethodOutput::SampleOcclusion:
        return "per-sample bits (or counters)";
    case MethodOutput::SampleCounters:
        return "per-sample counters";
    case MethodOutput::Visibility:
        return "visibility image";
    }
    return "?";
}

void validateMethodParams(const MethodInfo& method, const MethodParams& params) {
    for (const auto& [name, value] : params) {
        const MethodKnob* k = method.knob(name);
        if (!k) throw unknownKnob(method, name);
        if (!(value >= k->min && value <= k->max))
            throw UsageError("--param " + name + "=" + formatNumber(value) + " is out of range (" +
                             formatNumber(k->min) + " to " + formatNumber(k->max) + ")");
        if (k->integer && value != std::floor(value))
            throw UsageError("--param " + name + "=" + formatNumber(value) + " is not an integer");
    }
}

MethodParams parseMethodParams(const MethodInfo& method, const std::vector<std::string>& items) {
    MethodParams params;
    for (const MethodKnob& k : method.knobs) params[k.name] = k.defaultValue;
    for (const std::string& item : items) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError("--param '" + item + "' is not of the form name=value");
        const std::string name = item.substr(0, eq), text = item.substr(eq + 1);
        if (!method.knob(name)) throw unknownKnob(method, name);
        char* end = nullptr;
        const double value = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value))
            throw UsageError("--param " + item + ": '" + text + "' is not a number");
        params[name] = value;
    }
    validateMethodParams(method, params);
    return params;
}

namespace {

/// The table's "writes" column: the output, and the transmittance buffer where the row writes it.
std::string writesText(const MethodInfo& m) {
    std::string text = toString(m.output);
    if (!m.writesTransmittance()) return text;
    if (text.back() == ')') return text.insert(text.size() - 1, ", or transmittance");
    return text + " (or transmittance)";
}

} // namespace

std::string methodTableMarkdown() {
    std::string text = "| method | family | writes | backends | parameters | what it is |\n"
                       "|---|---|---|---|---|---|\n";
    for (const MethodInfo& m : methodTable()) {
        std::string backends;
        for (Backend b : m.backends) backends += (backends.empty() ? "" : ", ") + toString(b);
        std::string knobs;
        for (const MethodKnob& k : m.knobs)
            knobs += (knobs.empty() ? "`" : ", `") + k.name + "=" + formatNumber(k.defaultValue) + "`";
        text += "| `" + m.name + "` | " + toString(m.family) + " | " + writesText(m) + " | " + backends +
                " | " + (knobs.empty() ? "none" : knobs) + " | " + m.description + " |\n";
    }
    return text;
}

nlohmann::json methodTableJson() {
    nlohmann::json rows = nlohmann::json::array();
    for (const MethodInfo& m : methodTable()) {
        nlohmann::json backends = nlohmann::json::array();
        for (Backend b : m.backends) backends.push_back(toString(b));
        nlohmann::json knobs = nlohmann::json::array();
        for (const MethodKnob& k : m.knobs)
            knobs.push_back({{"name", k.name},
                             {"default", k.defaultValue},
                             {"min", k.min},
                             {"max", k.max},
                             {"integer", k.integer},
                             {"help", k.help}});
        rows.push_back({{"name", m.name},
                        {"description", m.description},
                        {"family", toString(m.family)},
                        {"writes", writesText(m)},
                        {"writes_transmittance", m.writesTransmittance()},
                        {"backends", backends},
                        {"parameters", knobs}});
    }
    return rows;
}

} // namespace stsv
