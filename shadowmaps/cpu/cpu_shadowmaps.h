// The image-based baselines on the CPU (DESIGN §4.6): the light-space map traced with Embree
// rays through the texel centres (the same alpha test as every method), then PCF or PCSS per
// pixel with the functions of shadowmaps/shadow_filter_dh.h that shadowmaps/shaders/shadow_filter.comp runs.
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/options.h"
#include "sampling/light_sampling.h"
#include "sampling/ls_buffer.h"
#include "shadowmaps/avsm.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace stsv {

class EmbreeScene;

/// The map of `view`, one Embree ray per texel centre (shadowMapTexelRay), hits between near and
/// far, holes of perforated triangles let through.
ShadowMap traceShadowMap(const EmbreeScene& embree, const ShadowMapView& view);

struct ShadowMapCpuStats {
    double mapMs = 0.0;     ///< tracing the map
    double buildMs = 0.0;   ///< filtered representations: channels and summed-area tables or mips
    double blockerMs = 0.0; ///< the blocker search (PCSS; filtered maps with fm_kernel=1)
    double filterMs = 0.0;  ///< PCF, or PCSS's filter
    /// pixels whose kernel pcss_max_kernel cut; PCF: whose taps pcf_max_radius spread more than three
    /// texels apart
    std::uint64_t kernelClamped = 0;
    std::uint64_t searchClamped = 0;     ///< pixels whose blocker search pcss_max_search cut
    std::size_t representationBytes = 0; ///< filtered representations: filteredMapBytes
};

/// PCF, PCSS or a filtered representation's visibility, through the map of `view` (fitFrameShadowMap), of
/// every covered pixel into `vcoef` (v_coef; uncovered pixels untouched), with the per-pixel tap rotation of
/// `seed` when `decorrelate` (the sub-pixels of a supersampled G-buffer take their pixel's rotation).
ShadowMapCpuStats shadowMapCpuVisibility(const EmbreeScene& embree, const GBuffer& gbuffer,
                                         const ShadowMapView& view, const ShadowMapSettings& settings,
                                         std::uint32_t seed, bool decorrelate, ImageF& vcoef,
                                         ShadowMap* keep = nullptr, int supersample = 1);

/// The filter step alone, for a given map (tests feed both backends the same map).
void shadowMapFilterPixels(const ShadowMap& map, const std::vector<vec2>& taps, const GBuffer& gbuffer,
                           const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate,
                           ImageF& vcoef, ShadowMapCpuStats* stats = nullptr, int supersample = 1);

/// The depth grid of `view` (`peel`, shadowmaps/depth_grid_dh.h): every surface each texel-centre
/// ray meets between near and far, holes of perforated triangles let through, front or back by
/// the triangle's winding against the ray.
DepthGrid traceDepthGrid(const EmbreeScene& embree, const ShadowMapView& view, uint bins);

struct PeelCpuStats {
    double gridMs = 0.0;  ///< tracing the grid
    double marchMs = 0.0; ///< marching every sample's ray
    std::size_t gridBytes = 0;
    PeelMarchCounts march;
};

/// `peel`: each covered pixel's light-sample rays marched through the grid (peelRayMarch, with
/// the receiver as the filters take it: sm_bias, sm_normal_offset) into `out`: the occluded
/// samples' bits, or in a counters buffer the surfaces each ray crosses as the grid holds them.
PeelMarchCounts peelMarchSamples(const DepthGrid& grid, const GBuffer& gbuffer, const Light& light,
                                 const SamplePlan& plan, float farDistance, const ShadowMapSettings& settings,
                                 LightSampleBuffer& out);

/// The grid of `view` and the march, timed.
PeelCpuStats peelCpuSamples(const EmbreeScene& embree, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, const ShadowMapView& view,
                            const ShadowMapSettings& settings, LightSampleBuffer& out,
                            DepthGrid* keep = nullptr);

/// The transmittance functions of `view` (`avsm`, `vpcss`): every surface each texel-centre ray
/// crosses between near and far with the light it takes (EmbreeScene::surfaceCrossings), appended
/// nearest first into at most settings.avsmNodes nodes.
AvsmMap traceAvsm(const EmbreeScene& embree, const ShadowMapView& view, uint maxNodes);

struct AvsmCpuStats {
    double mapMs = 0.0;              ///< tracing and building the functions
    double blockerMs = 0.0;          ///< vpcss: the blocker search
    double filterMs = 0.0;           ///< the lookups (avsm), the filter (vpcss)
    std::uint64_t kernelClamped = 0; ///< vpcss: pixels whose filter radius pcss_max_kernel clamped
    std::uint64_t searchClamped = 0; ///< vpcss: pixels whose blocker search pcss_max_search cut
    AvsmStats map;
    std::size_t bytes = 0; ///< avsmBytes
};

/// `avsm` (one lookup) or `vpcss` (blocker search, then filtered lookups) of every covered pixel
/// into `vcoef`, on a given map (tests feed it maps of their own); the tap rotation as
/// shadowMapFilterPixels'.
void avsmFilterPixels(const AvsmMap& map, const std::vector<vec2>& taps, const GBuffer& gbuffer,
                      const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate, ImageF& vcoef,
                      AvsmCpuStats* stats = nullptr, int supersample = 1);

/// The functions of `view` (fitFrameShadowMap), then avsmFilterPixels, timed.
AvsmCpuStats avsmCpuVisibility(const EmbreeScene& embree, const GBuffer& gbuffer, const ShadowMapView& view,
                               const ShadowMapSettings& settings, std::uint32_t seed, bool decorrelate,
                               ImageF& vcoef, AvsmMap* keep = nullptr, int supersample = 1);

} // namespace stsv
