// The method table (DESIGN §2): every shadow method is one row, declared once. The command line,
// `stsv info`, bench, compare, --stats and the README's method list come from it, and the frame
// code asks a row what the method writes and which passes it composes — never which method it is.
#pragma once

#include "sampling/ls_buffer.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace stsv {

/// The first image-family method: a variant's method is this past its selector.
inline constexpr unsigned IMAGE_METHODS = 64u;

/// A method: a row of the table. The object-based rows and the reference are named here; the
/// image family's rows are its variants (shadowmaps/variants.h), IMAGE_METHODS past their dh
/// selector, so a new variant is a row of that table and needs no name here (imageMethod).
enum class Method : unsigned {
    Reference,                                 ///< Embree shadow rays
    Stsv,                                      ///< every triangle through STSV
    Pw,                                        ///< opaque triangles through penumbra wedges
    Dcs,                                       ///< opaque triangles through depth complexity sampling
    PwStsv,                                    ///< pw for opaque, STSV for perforated triangles
    DcsStsv,                                   ///< dcs for opaque, STSV for perforated triangles
    Pcf = IMAGE_METHODS + SHADOW_FILTER_PCF,   ///< percentage-closer filtering of a light-centre shadow map
    Pcss = IMAGE_METHODS + SHADOW_FILTER_PCSS, ///< percentage-closer soft shadows
    Vsm = IMAGE_METHODS + SHADOW_FILTER_VSM,   ///< variance shadow maps
    Esm = IMAGE_METHODS + SHADOW_FILTER_ESM,   ///< exponential shadow maps
    Evsm = IMAGE_METHODS + SHADOW_FILTER_EVSM, ///< exponential variance shadow maps
    Msm = IMAGE_METHODS + SHADOW_FILTER_MSM,   ///< moment shadow maps
    Csm = IMAGE_METHODS + SHADOW_FILTER_CSM,   ///< convolution shadow maps
    Peel =
        IMAGE_METHODS + SHADOW_FILTER_PEEL, ///< depth-peeling soft shadows: a depth grid marched per sample
    Avsm = IMAGE_METHODS + SHADOW_FILTER_AVSM, ///< adaptive volumetric shadow maps: hard translucent shadows
    Vpcss = IMAGE_METHODS + SHADOW_FILTER_VPCSS, ///< volumetric PCSS on the AVSM's transmittance functions
};

/// The method of an image-family variant.
constexpr Method imageMethod(ShadowMapMethod filter) {
    return Method(IMAGE_METHODS + unsigned(filter));
}

enum class Backend { Cpu, Vulkan };

enum class MethodFamily { ObjectBased, ImageBased, GroundTruth };

/// What a method writes per light.
enum class MethodOutput {
    SampleOcclusion, ///< per-sample occlusion: bits, or exact layer counts with --buffer counters
    SampleCounters,  ///< per-sample signed depth-complexity counters (always counters)
    Visibility,      ///< a per-pixel v_coef only; it scales the unshadowed direct lighting
};

/// Which triangles a method sends through the STSV pass.
enum class StsvTriangles { None, All, Perforated };

/// How a method treats the opaque triangles besides STSV (DESIGN §4.5).
enum class WedgeVariant {
    None,
    Dcs, ///< layer count at the light centre plus signed silhouette crossings per sample
    Pw,  ///< hard shadow at the light centre plus analytic wedge coverage per pixel
};

/// A family's work per light, with a CPU side (render/cpu/cpu_techniques.h) and a Vulkan side
/// (render/vulkan/vulkan_techniques.h). A row composes one or two, in the order a frame runs them.
enum class TechniqueFamily {
    Traced,     ///< Embree shadow rays to every sample (MethodInfo::traced)
    Wedges,     ///< DCS or PW over the opaque triangles (MethodInfo::wedges), then the fold
    Stsv,       ///< STSV over all or the perforated triangles (MethodInfo::stsv)
    ShadowMaps, ///< a light-centre map and its filter (MethodInfo::shadowMap)
};

/// One knob of a method, set with `--param name=value`.
struct MethodKnob {
    std::string name;
    double defaultValue = 0.0;
    double min = 0.0;
    double max = 0.0;
    bool integer = false;
    std::string help; ///< one line, with the unit
};

struct MethodInfo {
    Method id;
    std::string name;        ///< as --method takes it
    std::string description; ///< one line
    MethodFamily family;
    MethodOutput output;
    std::vector<Backend> backends; ///< the backends that implement it, preferred first
    std::vector<MethodKnob> knobs;
    // Composition per light (STSV paper Algorithm 2): each field is one family's part of the
    // row, read by that family's technique; techniques() lists those the row uses.
    bool traced = false; ///< Embree shadow rays to every sample (the ground truth)
    StsvTriangles stsv = StsvTriangles::None;
    WedgeVariant wedges = WedgeVariant::None;
    /// Image-based: a light-space map from the light centre, filtered per pixel (DESIGN §4.6).
    ShadowMapMethod shadowMap = ShadowMapMethod::None;

    bool implementedOn(Backend backend) const;
    /// The families the row composes, in the order a frame runs them per light: rays, or the
    /// opaque wedges and then STSV (Algorithm 2), or the shadow map.
    std::vector<TechniqueFamily> techniques() const;
    /// The buffer a frame of this method holds per light for the requested kind: counters for
    /// SampleCounters (signed sums), else the requested kind (for Visibility methods it holds
    /// the STSV part of the perforated triangles, or every sample lit).
    BufferKind bufferKind(BufferKind requested) const;
    /// Whether the method writes a transmittance buffer (--buffer transmittance): the fraction of
    /// light through translucent triangles per sample.
    bool writesTransmittance() const;
    /// Whether the method reads transmittance functions (`avsm`, `vpcss`): its light through
    /// translucent triangles is fractional whatever the buffer.
    bool readsTransmittanceFunctions() const;
    const MethodKnob* knob(std::string_view knobName) const;
};

/// The name `render`, `bench` and `compare` take for the method a scene calls for (autoMethod,
/// render/frame.h): a choice made once the scene is loaded, not a row of the table.
inline constexpr std::string_view AUTO_METHOD = "auto";

/// Every method, in table order.
const std::vector<MethodInfo>& methodTable();
const MethodInfo& methodInfo(Method method);
/// UsageError naming the valid methods when there is none of that name.
const MethodInfo& findMethod(std::string_view name);
/// "reference, stsv, pw, dcs, pw+stsv or dcs+stsv".
std::string methodNameList(std::string_view conjunction = "or");

std::string toString(Method method);
std::string toString(Backend backend);
std::string toString(BufferKind kind);
std::string toString(MethodFamily family);
std::string toString(MethodOutput output);
Method parseMethod(const std::string& name);
Backend parseBackend(const std::string& name);
BufferKind parseBufferKind(const std::string& name);

/// Method parameters by knob name.
using MethodParams = std::map<std::string, double>;

/// Parses `--param name=value` items for `method`: every knob at its default, then the given
/// values. UsageError naming the item and listing the method's knobs when a name is unknown, a
/// value is not a number (or not an integer for integer knobs) or lies outside the knob's range.
MethodParams parseMethodParams(const MethodInfo& method, const std::vector<std::string>& items);
/// UsageError when `params` holds a name the method lacks or a value out of range.
void validateMethodParams(const MethodInfo& method, const MethodParams& params);

/// The table as Markdown, one row per method (the README's method list is this text).
std::string methodTableMarkdown();
/// The table as JSON (stsv info --json).
nlohmann::json methodTableJson();

} // namespace stsv
