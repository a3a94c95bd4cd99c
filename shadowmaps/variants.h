// The image family's variant table (DESIGN §4.6): one row per method of the family — its name and
// description, the dh selector it runs (SHADOW_FILTER_*), what it reads of the light's map, when
// it searches blockers, its own knobs and the defaults where its best lies elsewhere. The method
// table's rows (render/methods.cpp), the knob lists and the settings' defaults are made from it,
// and one test checks the rows against the dh dispatch (filtered_shadow_dh.h). A new filtered
// representation is a selector, its functions and its dispatch branches in filtered_shadow_dh.h
// and a row here.
#pragma once

#include "shadowmaps/filtered_shadow_dh.h"
#include "shadowmaps/shadow_map_dh.h"

#include <utility>
#include <vector>

namespace stsv {

/// A variant of the image family by its dh selector. The enumerators name the variants the code
/// or the tests treat apart; any selector with a row in shadowMapVariants() is a variant.
enum class ShadowMapMethod : uint {
    None = 0u,
    Pcf = SHADOW_FILTER_PCF,
    Pcss = SHADOW_FILTER_PCSS,
    Vsm = SHADOW_FILTER_VSM,
    Esm = SHADOW_FILTER_ESM,
    Evsm = SHADOW_FILTER_EVSM,
    Msm = SHADOW_FILTER_MSM,
    Csm = SHADOW_FILTER_CSM,
    Peel = SHADOW_FILTER_PEEL,
    Avsm = SHADOW_FILTER_AVSM,
    Vpcss = SHADOW_FILTER_VPCSS,
};

/// What a variant reads of its light's map.
enum class MapRepresentation {
    Depths,        ///< the depth map, compared tap by tap (pcf, pcss)
    Filtered,      ///< a representation of the depths averaged over a kernel (filtered_shadow_dh.h)
    DepthGrid,     ///< front and back depths per texel, marched per light sample (depth_grid_dh.h)
    Transmittance, ///< transmittance functions per texel (avsm_dh.h)
};

/// When a variant runs PCSS's blocker search (Fernando 2005, step 1).
enum class BlockerSearch {
    Never,
    Always,
    WithSearchedKernel, ///< when fm_kernel=1: the filtered representations' kernel sized per pixel
};

/// One row of the image family.
struct ShadowMapVariant {
    ShadowMapMethod filter;  ///< its dh selector
    const char* name;        ///< the method's name (--method)
    const char* description; ///< one line: the method table's
    MapRepresentation representation;
    BlockerSearch blockers = BlockerSearch::Never;
    /// Averages through mips whatever fm_mip says (ESM and EVSM: their exponentials span more
    /// than the 32 fractional bits of a summed-area table; exp(40·(z − 1)) is below 2⁻³² for
    /// z < 0.45, and EVSM's variance of such values vanishes: on fence 0.136 RMSE against 0.012
    /// with mips).
    bool alwaysMip = false;
    /// The knobs only this variant (or a few) reads; the knobs of a kind (every variant, the
    /// depth maps, the filtered representations, those that search, the transmittance
    /// functions) are found by kind (ShadowMapKnob::readers).
    std::vector<const char*> knobs{};
    /// (knob, value) where the variant's default differs from ShadowMapSettings' own.
    std::vector<std::pair<const char*, double>> defaults{};
};

/// Every variant, in the method table's order.
const std::vector<ShadowMapVariant>& shadowMapVariants();
/// The row of `filter`; std::logic_error (a bug) for None or a selector without a row.
const ShadowMapVariant& shadowMapVariant(ShadowMapMethod filter);

} // namespace stsv
