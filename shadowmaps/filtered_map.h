// A light's map as a filtered representation (DESIGN §4.6): per face and channel, the values of
// VSM, ESM, EVSM, MSM or CSM (filtered_shadow_dh.h) made from the map's depths, as a summed-area
// table or a mip pyramid (summed_area.h), and the per-pixel lookup of filtered_lookup_dh.h — the
// code the Vulkan shaders run. The CPU backend uses it.
#pragma once

#include "shadowmaps/shadow_filter.h"
#include "shadowmaps/shadow_map.h"
#include "shadowmaps/summed_area.h"

#include <cstddef>
#include <vector>

namespace stsv {

/// Bytes the representation holds per light: summed-area tables of 8-byte integers ((size + 1)²
/// per face and channel) or mip pyramids of 4-byte floats (about 4/3 of size² per face and
/// channel; ESM and EVSM always).
std::size_t filteredMapBytes(const ShadowMapView& view, const ShadowMapSettings& settings);

class FilteredShadowMap {
  public:
    /// The representation of `map` for settings.filter (a filtered one).
    FilteredShadowMap(const ShadowMap& map, const ShadowMapSettings& settings);

    /// Lit fraction of a receiver whose kernel spans `radius` texels either side of its texel
    /// (filteredVisibility).
    float visibility(const ShadowReceiver& r, float radius) const;

  private:
    ShadowMapView m_view;
    ShadowFilterParams m_params;
    std::vector<SummedAreaTable> m_sat; ///< [face · channels + channel]
    std::vector<MipPyramid> m_mip;      ///< [face · channels + channel]
};

} // namespace stsv
