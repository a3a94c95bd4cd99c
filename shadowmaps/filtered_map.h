// A light's map as a filtered representation (DESIGN §4.6): per face, the channels of VSM, ESM,
// EVSM, MSM or CSM (filtered_shadow_dh.h) made from the map's depths, each with its summed-area
// table or mip pyramid (summed_area.h), and the per-pixel lookup: the channels' averages over a
// square kernel around the receiver, turned into a lit fraction. The CPU backend runs it.
#pragma once

#include "shadowmaps/filtered_shadow_dh.h"
#include "shadowmaps/shadow_filter.h"
#include "shadowmaps/shadow_map.h"
#include "shadowmaps/summed_area.h"

#include <cstddef>
#include <vector>

namespace stsv {

/// Values per texel of a filter's representation: VSM 2, ESM 1, EVSM 4, MSM 4, CSM 2·csm_terms.
int filteredChannels(const ShadowMapSettings& settings);

/// Bytes the representation holds per light: the channels' summed-area tables (8-byte integers,
/// (size + 1)² per face and channel) or mip pyramids (4-byte floats, 4/3 of size² per face and
/// channel), ESM always the latter.
std::size_t filteredMapBytes(const ShadowMapView& view, const ShadowMapSettings& settings);

class FilteredShadowMap {
  public:
    /// The representation of `map` for settings.filter (a filtered one).
    FilteredShadowMap(const ShadowMap& map, const ShadowMapSettings& settings);

    /// Lit fraction of a receiver whose kernel spans `radius` texels either side of its texel
    /// (a square of 2·radius + 1 texels; a summed-area table rounds the radius to whole texels).
    float visibility(const ShadowReceiver& r, float radius) const;

    const ShadowMapView& view() const { return m_view; }
    bool usesMip() const { return !m_mip.empty(); }

  private:
    /// The channels' means over the kernel, into `out` (filteredChannels values).
    void average(const ShadowReceiver& r, float radius, float* out) const;

    ShadowMapView m_view;
    ShadowMapSettings m_settings;
    int m_channels;
    std::vector<SummedAreaTable> m_sat; ///< [face · channels + channel]
    std::vector<MipPyramid> m_mip;      ///< [face · channels + channel]
};

} // namespace stsv
