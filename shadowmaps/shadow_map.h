// Host side of the light-space maps (DESIGN §4.6): fitting a light's map to the scene box, the
// Poisson-disk taps of the filters, and the knobs PCF and PCSS share. The per-texel and
// per-pixel math is in shadow_map_dh.h and shadow_filter_dh.h.
#pragma once

#include "scene/scene.h"
#include "shadowmaps/shadow_map_dh.h"
#include "shadowmaps/variants.h"

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace stsv {

/// Widest perspective map before a cube map is used instead: 120° across (60° half-angle).
inline constexpr float SHADOW_MAP_MAX_HALF_ANGLE_DEGREES = 60.0f;

/// The map of `light` over the scene box `box`, `size` texels per face edge:
///  * rectangle and disk: a perspective face from the centre along the light normal whose
///    square window holds the part of the box in front of the light plane; a cube map when that
///    needs more than SHADOW_MAP_MAX_HALF_ANGLE_DEGREES off the axis (a light inside or beside
///    the box);
///  * sphere: a cube map around the centre;
///  * directional: an orthographic face along the light's direction holding the whole box.
/// near and far bound the box's depths. UsageError for an empty box or size outside 1 … 16384.
/// The fit of `sm_fit=0`: fitShadowMapToRegion(light, box, box, size).
ShadowMapView fitShadowMap(const Light& light, const Bounds& box, int size);

/// The map of `light` for what a frame can see (shadowmaps/shadow_fit.h finds the two boxes):
/// the window holds the part of `casters` in front of the light (the receivers' when there are
/// no casters: nothing is shadowed), the depths run from the nearest caster to the farthest point
/// of either box, and the projection follows the rules of fitShadowMap. Receivers outside the
/// window have no caster on their centre ray, and a filter's taps outside it see no blocker.
ShadowMapView fitShadowMapToRegion(const Light& light, const Bounds& receivers, const Bounds& casters,
                                   int size);

/// PCSS's w_light: a rectangle's larger edge, a disk's or sphere's diameter (world units); for a
/// directional light 2·tan(angular radius) (width per unit distance).
float shadowLightWidth(const Light& light);

/// Bytes of one map of `view` (faces × size² floats).
std::size_t shadowMapBytes(const ShadowMapView& view);

/// `count` points of a Poisson-disk-like set in the unit disk, deterministic for a seed: radii
/// stratified by area (the set samples the disk uniformly), angles by best-candidate sampling.
/// Every pair at least the returned minimum distance apart.
std::vector<vec2> poissonDiskTaps(int count, std::uint32_t seed, float* minDistance = nullptr);

/// One light's map: faces × size × size depths, row-major per face (SHADOW_MAP_EMPTY where the
/// texel-centre ray meets nothing).
struct ShadowMap {
    ShadowMapView view{};
    std::vector<float> depth;
    float at(uint face, ivec2 texel) const {
        return depth[(std::size_t(face) * view.size + std::size_t(texel.y)) * view.size +
                     std::size_t(texel.x)];
    }
};

/// Whether a variant reads transmittance functions (AVSM) instead of a depth map.
inline bool readsTransmittanceFunctions(ShadowMapMethod f) {
    return f != ShadowMapMethod::None &&
           shadowMapVariant(f).representation == MapRepresentation::Transmittance;
}

/// Whether a variant averages a representation of the depths (VSM, ESM, EVSM, MSM, CSM).
inline bool isFilteredRepresentation(ShadowMapMethod f) {
    return f != ShadowMapMethod::None && shadowMapVariant(f).representation == MapRepresentation::Filtered;
}

/// Whether a variant filters the depth map over a kernel of fixed world width (pcf:
/// depthKernelVisibility), not one that a blocker search sizes (pcss).
inline bool filtersFixedDepthKernel(ShadowMapMethod f) {
    if (f == ShadowMapMethod::None) return false;
    const ShadowMapVariant& row = shadowMapVariant(f);
    return row.representation == MapRepresentation::Depths && row.blockers == BlockerSearch::Never;
}

/// The knobs the shadow-map methods read (method knobs of render/methods.cpp): the filter's, which
/// both backends read as they are (ShadowFilterParams, shadow_map_dh.h), and the map's.
struct ShadowMapSettings : ShadowFilterParams {
    int size = 2048; ///< sm_size: texels per face edge
    int fit = 1;     ///< sm_fit: 0 the scene box, 1 the receivers in view and their casters
    ShadowMapMethod filter = ShadowMapMethod::None;
    // Depth-peeling soft shadows (the depth grid). The grid's texels per face edge replace
    // sm_size: at 512² and 16 subintervals a face holds 36 MB (the paper's grid is coarse).
    int peelSize = 512; ///< peel_size: grid texels per face edge
    // Transmittance functions (AVSM, volumetric PCSS). Klein et al. used 1024² and 8 nodes: at
    // 8 nodes a texel holds 68 bytes, 68 MB a face at 1024².
    int avsmSize = 1024; ///< avsm_size: texels per face edge
};

/// How `stsv tune` spaces the values it tries of a knob: evenly, or evenly in log(value) (knobs
/// whose effect is multiplicative: an exponent, a variance floor, a radius).
enum class KnobScale { Linear, Log };

/// How `stsv tune` searches a knob: whether it does unless told otherwise, and the range and
/// scale of the values it tries.
struct KnobSearch {
    /// Searched by default: the knob shapes the error and not the cost. Resolutions, tap and
    /// step counts and representation sizes are not (more is always better at more cost, so a
    /// search would pick the largest); `tune --knob NAME` searches one anyway.
    bool tunable = false;
    KnobScale scale = KnobScale::Linear;
    double lo = 0.0; ///< the range searched, within the knob's [min, max]
    double hi = 0.0;
};

/// Which variants read a knob: every one, those of a kind (by what they read of the map and
/// whether they search blockers), or (Own) those whose row in the variant table names it.
enum class KnobReaders { Every, DepthMaps, Filtered, SearchedDepths, Searched, Transmittance, Own };

/// One knob of ShadowMapSettings as a method's `--param`: its name, range and help, which variants
/// read it, and the member it sets. The one list of the knobs: the method table's parameters are
/// made from it (render/methods.cpp) and frames read the settings through it, so a name, a
/// default or a range is written once.
struct ShadowMapKnob {
    const char* name;
    double min;
    double max;
    bool integer;
    const char* help;    ///< one line, with the unit
    KnobReaders readers; ///< the variants that read it
    /// The member it sets: a float, an int or a count.
    std::variant<float ShadowMapSettings::*, int ShadowMapSettings::*, uint ShadowMapSettings::*> member;
    /// How `stsv tune` searches it (set for the tunable knobs in shadowMapKnobs(), after the list).
    KnobSearch search{};

    double get(const ShadowMapSettings& s) const {
        return std::visit([&](auto m) { return double(s.*m); }, member);
    }
    void set(ShadowMapSettings& s, double value) const {
        std::visit(
            [&](auto m) {
                using T = std::remove_reference_t<decltype(s.*m)>;
                s.*m = T(value);
            },
            member);
    }
    bool readBy(ShadowMapMethod filter) const;
    /// What `tune` searches when told to: `search` for a tunable knob; else the knob's whole
    /// [min, max], in log steps where min > 0 and max/min ≥ 64 (sm_size, tap counts), linear
    /// otherwise.
    KnobSearch searchRange() const {
        if (search.tunable) return search;
        const bool log = min > 0.0 && max >= 64.0 * min;
        return {false, log ? KnobScale::Log : KnobScale::Linear, min, max};
    }
};

/// Every knob, the ones all filters share first.
const std::vector<ShadowMapKnob>& shadowMapKnobs();

/// Why `name` is no longer a knob, naming the knob that replaced it (a unit changed: an old
/// script's value would mean something else), or null when it never was one.
const char* retiredShadowMapKnob(const std::string& name);

/// The defaults of a `filter` frame: those of ShadowMapSettings, but for the knobs where the
/// fairness sweep put the method's best elsewhere (the knobs nearest every tuning scene's own
/// best at once, docs/measurements.md "Fair defaults"): the filtered representations VSM, ESM,
/// EVSM a smaller bias with a normal offset, VSM and EVSM a smaller variance floor, VSM mips;
/// volumetric PCSS a larger bias and normal offset.
ShadowMapSettings defaultShadowMapSettings(ShadowMapMethod filter);

/// The settings of a `filter` frame: defaultShadowMapSettings(filter), with each (name, value)
/// of `params` set on its knob. UsageError for a name that is no knob of `filter` (naming the
/// knob that replaced a retired one).
ShadowMapSettings shadowMapSettingsFrom(ShadowMapMethod filter, const std::map<std::string, double>& params);

/// Texels per face edge of the frame's map: sm_size, peel_size for the depth grid (`peel`),
/// avsm_size for the transmittance functions (`avsm`, `vpcss`).
inline int shadowMapSize(const ShadowMapSettings& s) {
    if (s.filter == ShadowMapMethod::Peel) return s.peelSize;
    return readsTransmittanceFunctions(s.filter) ? s.avsmSize : s.size;
}

/// Bytes of one light's transmittance functions: faces × size² texels of a node count and
/// avsm_nodes nodes (a float depth and 32-bit units each).
std::size_t avsmBytes(const ShadowMapView& view, const ShadowMapSettings& settings);

/// Bytes of one light's depth grid (`peel`): faces × size² texels of peelTexelWords(peel_bins) words.
std::size_t depthGridBytes(const ShadowMapView& view, const ShadowMapSettings& settings);

/// Values per texel of a filtered representation (filtered_shadow_dh.h filteredChannelCount); 0
/// for the other variants.
int filteredChannelCount(const ShadowMapSettings& settings);
/// Whether a filtered representation averages through mips (fm_mip, or always where its row says
/// so) rather than summed-area tables.
bool filteredUsesMip(const ShadowMapSettings& settings);
/// Whether a frame of `settings` runs PCSS's blocker search before it filters the depths (pcss;
/// the filtered representations with fm_kernel=1). Volumetric PCSS searches its own way
/// (avsm_filter_dh.h).
bool searchesBlockers(const ShadowMapSettings& settings);

/// The settings the filter shaders read, in their buffer layout.
ShadowFilterParams shadowFilterParams(const ShadowMapSettings& settings);

/// The taps a frame uploads: the blocker-search set, then the filter set (seeded apart).
std::vector<vec2> shadowFilterTaps(const ShadowMapSettings& settings);

} // namespace stsv
