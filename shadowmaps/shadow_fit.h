// Fitting a light's map to what a frame can see (DESIGN §4.6), as engines fit their shadow
// cameras: the receivers are the scene's triangles clipped to the camera's view frustum, the
// casters the triangles that can stand between one of those receivers and a point of the light.
// The map's window then holds the casters only, so its texels go where shadows can fall, not to
// a ground plane far from everything.
#pragma once

#include "core/gbuffer.h"
#include "scene/scene.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

namespace stsv {

/// Bounds of the scene's triangles clipped to the camera's view frustum for an image of
/// width/height `aspect` (near plane a millionth of the scene's diameter from the eye, no far
/// plane); empty when the camera sees no triangle.
Bounds shadowReceiverBounds(const Scene& scene, float aspect);

/// Bounds of what can shadow a point of `receivers` from `light`: every triangle that meets the
/// box of the receivers and the light (for a directional light, the receivers swept towards it
/// across the scene) and whose plane separates a point of the light from a receiver, clipped to
/// that box. A triangle in the receivers' plane with the light on one side (a ground plane) casts
/// nothing onto them, so it widens no map. Conservative: the receivers and a disk light count as
/// their bounding boxes.
Bounds shadowCasterBounds(const Scene& scene, const Light& light, const Bounds& receivers);

/// The map a frame renders for `light` with `settings` (sm_size, sm_fit): the scene box
/// (fitShadowMap), or the receivers in view and their casters (fitShadowMapToRegion) with
/// `receivers` from shadowReceiverBounds.
ShadowMapView fitFrameShadowMap(const Scene& scene, const Light& light, const Bounds& receivers,
                                const ShadowMapSettings& settings);

/// How coarse a map is where the camera looks: over the covered pixels of `gbuffer`, the world size of one
/// map texel at the receiver (shadowMapTexelWorld) and its ratio to the world size of one G-buffer pixel
/// there; medians and 90th percentiles. A ratio above 1: one texel spans several pixels (blocky edges, and a
/// filter kernel of r texels is wider than r pixels).
nlohmann::json shadowTexelFootprint(const ShadowMapView& view, const Camera& camera, const GBuffer& gbuffer);

} // namespace stsv
