// The image family's frame stats, shared by both backends: what a light's map covers, what its
// filter clamped, and the warnings a user should read about them.
#pragma once

#include "core/gbuffer.h"
#include "scene/camera.h"
#include "shadowmaps/avsm.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

/// The fraction of clamped kernels (or blocker searches) above which shadowMapWarnings speaks.
constexpr double KERNEL_CLAMP_WARNING = 0.01;

/// {"kernel_clamped_pixels", "kernel_clamped_fraction"}: how many of the pixels with a visible
/// surface had their PCSS kernel cut to pcss_max_kernel, counted and as a fraction (both
/// backends).
nlohmann::json kernelClampStats(std::uint64_t clampedPixels, const GBuffer& gbuffer);

/// {"kernel_strided_pixels", "kernel_strided_fraction"}: the same for PCF's kernels whose taps
/// pcf_max_radius spread more than three texels apart.
nlohmann::json kernelStrideStats(std::uint64_t stridedPixels, const GBuffer& gbuffer);

/// {"search_clamped_pixels", "search_clamped_fraction"}: the same for the blocker search cut to
/// pcss_max_search (PCSS, vpcss, the filtered maps with fm_kernel=1).
nlohmann::json searchClampStats(std::uint64_t clampedPixels, const GBuffer& gbuffer);

/// {"march": {"rays", "steps_mean", "steps_max", "max_steps", "capped_rays", "capped_fraction"}}.
nlohmann::json peelMarchStats(const PeelMarchCounts& counts);

/// A light's transmittance functions (`avsm`, `vpcss`; both backends): the nodes per texel that
/// holds any (mean, max), the texels with nodes, those that had more surfaces than nodes, and the
/// map's bytes (avsmBytes).
nlohmann::json avsmStatsJson(const AvsmStats& stats, std::size_t bytes);

/// What a light's map covers (both backends): its projection, faces, texels, the fit
/// (`"view"` or `"scene"`), depth range, and the texel footprint at the visible receivers
/// (shadowTexelFootprint).
nlohmann::json shadowMapViewStats(const ShadowMapView& view, const ShadowMapSettings& settings,
                                  const Camera& camera, const GBuffer& gbuffer);

/// The warnings of a frame of `method` from its stats' "shadow_maps" (one object per light):
/// open edges where a method assumes closed objects, peel's capped marches, and PCSS's kernels
/// (pcss_max_kernel) or blocker searches (pcss_max_search) clamped, or PCF's taps spread
/// (pcf_max_radius), for more than KERNEL_CLAMP_WARNING of the pixels.
std::vector<std::string> shadowMapWarnings(const std::string& method, const nlohmann::json& frameStats);

} // namespace stsv
