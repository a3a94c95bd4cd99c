// Host-side companions of light_sampling_dh.h: bounding spheres for shadow-volume extrusion,
// the far distance of directional lights, and per-pixel sample points and direct lighting
// from a SamplePlan (the one way host code turns (pixel, k) into a light sample).
#pragma once

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/ls_buffer.h"
#include "sampling/pattern.h"
#include "scene/scene.h"

namespace stsv {

/// Distance at which directional lights are placed: 100 × the scene diameter (at least 1).
/// Larger values make the light's bounding sphere (what STSV extrudes against) hug the true
/// cone of directions better — its extra half-angle is about sceneRadius/farDistance = 0.5 %
/// of a radian here — but every sample then sits ~farDistance from p, where float spacing is
/// farDistance·2⁻²⁴ ≈ 1.2e-5 scene diameters: still far below a pixel, and J·(s − p) stays
/// well conditioned. 100× keeps both errors small.
float farDistanceFor(const Bounds& sceneBounds);

/// A sphere (centre xyz, radius w; world units) containing every light sample of every
/// receiver inside `sceneBounds`. Rectangle: its centre and half-diagonal; disk and sphere:
/// centre and radius (the sphere's silhouette disks pass through its centre); directional:
/// centre = sceneCentre + normal·farDistance, radius = farDistance·tan(angularRadius) +
/// scene radius. UsageError for an unknown light type.
vec4 lightBoundingSphere(const Light& light, const Bounds& sceneBounds, float farDistance);

/// Frame coordinates (a, b) of sample k of pixel (x, y): interleaved set, decorrelation and
/// domain map exactly as samplePoint() on the GPU.
vec2 pixelSamplePoint(const SamplePlan& plan, int x, int y, int k, uint domain);

/// World position of sample k of pixel (x, y) for receiver p.
vec3 pixelLightSample(const SamplePlan& plan, int x, int y, int k, const LightFrame& frame);

/// Monte-Carlo direct lighting with a Lambertian BRDF (DESIGN §4.4, the paper's "Direct MC"):
/// albedo/π · (1/N) Σ_k sampleContribution_k · V_k, with V_k from the buffer. Linear RGB.
vec3 resolveDirect(const LightSampleBuffer& buffer, const SamplePlan& plan, int x, int y, const Light& light,
                   vec3 p, vec3 n, vec3 albedo, float farDistance);

} // namespace stsv
