// Host-side light extents: the sphere every light sample lies in (what STSV extrudes against,
// DESIGN §4.2) and the distance at which directional lights are placed.
#pragma once

#include "core/dh.h"
#include "scene/light_dh.h"
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

} // namespace stsv
