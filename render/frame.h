// What both backends' frames share: the Frame they fill, the FrameRenderer interface, the
// stats and warnings every frame writes. One frame: G-buffer, per light a light-sample buffer from the chosen
// method, then the resolve into visibility and Monte-Carlo direct lighting (STSV paper, Algorithm 2).
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/options.h"
#include "sampling/ls_buffer.h"
#include "scene/scene.h"
#include "shadowmaps/avsm.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace stsv {

/// Linear RGB of the pixels no triangle covers (every backend).
inline const vec3 BACKGROUND(0.02f, 0.02f, 0.03f);

struct Frame {
    GBuffer gbuffer;
    std::vector<LightSampleBuffer> lightSamples; ///< one per scene light
    ImageF color;                                ///< linear RGB: ambient + Σ lights direct lighting
    ImageF visibility; ///< one channel: v_coef averaged over the lights (1 on background)
    /// One per light for image-based methods rendered with RenderOptions::keepShadowMaps.
    std::vector<ShadowMap> shadowMaps;
    /// `peel`: one depth grid per light instead, with RenderOptions::keepShadowMaps.
    std::vector<DepthGrid> depthGrids;
    /// `avsm`, `vpcss`: one map of transmittance functions per light instead, with
    /// RenderOptions::keepShadowMaps.
    std::vector<AvsmMap> avsmMaps;
    /// options, scene counts, "startup_ms" (acceleration structures, devices, shader
    /// compilation), "frame_ms" (one frame without start-up) and "passes" (name → ms).
    nlohmann::json stats;
};

/// Renders frames of one scene with one set of options; start-up work (BVH, device,
/// pipelines, uploads) happens once in the constructor, so repeated frames measure the frame.
class FrameRenderer {
  public:
    virtual ~FrameRenderer() = default;
    virtual Frame render() = 0;
};

/// What a frame's stats say of a method on a scene, on every backend: the perforated triangles
/// a method without an STSV pass leaves out of its shadows ("ignored_perforated_triangles" and
/// "ignored_perforated_triangles_use", the method that draws them).
nlohmann::json methodSceneNotes(const Scene& scene, const MethodInfo& method);

/// The fraction of clamped kernels (or blocker searches) above which frameWarnings speaks.
constexpr double KERNEL_CLAMP_WARNING = 0.01;

/// Sentences a user should read about a frame's result, from its stats: perforated triangles a
/// method left out ("ignored_perforated_triangles"), PCSS's kernels (pcss_max_kernel) or blocker
/// searches (pcss_max_search) clamped, or PCF's taps spread (pcf_max_radius), for more than
/// KERNEL_CLAMP_WARNING of the pixels. The CLI prints them on stderr.
std::vector<std::string> frameWarnings(const nlohmann::json& stats);

/// Shared by every backend: ambient colour / background of a fresh frame, and scene counts.
void initFrameImages(const Scene& scene, const GBuffer& gbuffer, float ambient, Frame& frame);
nlohmann::json sceneStats(const Scene& scene);

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

} // namespace stsv
