// Host-side companions of light_sampling_dh.h: per-pixel sample points and direct lighting
// from a SamplePlan (the one way host code turns (pixel, k) into a light sample). Bounding
// spheres and the far distance of directional lights are in light_bounds.h.
#pragma once

#include "core/dh.h"
#include "core/gbuffer.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/ls_buffer.h"
#include "sampling/pattern.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// Frame coordinates (a, b) of sample k of pixel (x, y): interleaved set, decorrelation and
/// domain map exactly as samplePoint() on the GPU.
vec2 pixelSamplePoint(const SamplePlan& plan, int x, int y, int k, uint domain);

/// Every sample of pixel (x, y), plan.count of them into `out`: pixelSamplePoint's values, the
/// pixel's decorrelation offset computed once.
void pixelSamplePoints(const SamplePlan& plan, int x, int y, uint domain, vec2* out);

/// World position of sample k of pixel (x, y) for receiver p.
vec3 pixelLightSample(const SamplePlan& plan, int x, int y, int k, const LightFrame& frame);

/// Monte-Carlo direct lighting with a Lambertian BRDF (DESIGN §4.4, the paper's "Direct MC"):
/// albedo/π · (1/N) Σ_k sampleContribution_k · V_k, with V_k from the buffer, times `scale`
/// (PW's v_coef). Linear RGB. The functions of sampling/resolve_dh.h, as render/shaders/resolve.comp.
vec3 resolveDirect(const LightSampleBuffer& buffer, const SamplePlan& plan, int x, int y, const Light& light,
                   vec3 p, vec3 n, vec3 albedo, float farDistance, float scale = 1.0f);

/// What a pixel shows to the lights, for the error figures that count only what lighting can
/// change (compare's light-facing visibility error).
enum class PixelFacing : std::uint8_t {
    Background, ///< no visible surface
    Away,       ///< a surface that faces no light: visibility changes nothing in the lit image
    Facing,     ///< a surface that faces some light (receiverFacesLight)
};

/// Per pixel of a width × height image rendered with G-buffer `gbuffer` (row-major): Facing where
/// one of the pixel's visible points faces some light of `lights` (receiverFacesLight, frames at
/// `farDistance` as every method's), Background where none of its points shows a surface, else
/// Away. A supersampled frame's G-buffer holds K×K points per pixel (K·width × K·height); a pixel
/// faces where any of them does. Error (not a UsageError) where the G-buffer is not such a grid.
std::vector<PixelFacing> lightFacingPixels(const GBuffer& gbuffer, const std::vector<Light>& lights,
                                           float farDistance, int width, int height);

} // namespace stsv
