// Host-side STSV extrusion: the volumes of one triangle for one light (DESIGN §4.2), built with
// the same device/host function the geometry shader calls.
#pragma once

#include "scene/scene.h"
#include "volumes/extrusion_dh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace stsv {

/// The volumes of one triangle, empty ones included: two when the light's sphere straddles its
/// plane (the STSV paper's §6 fix), else one. A triangle blocks light whichever face the light
/// sees, so every renderer builds the second volume for every triangle; Material::doubleSided
/// only decides which way the shading normal faces.
std::vector<StsvVolume> buildTriangleVolumes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere,
                                             const Bounds& bounds);

/// True iff p lies in any of the volumes.
bool pointInAnyVolume(const std::vector<StsvVolume>& volumes, vec3 p);

/// The hull of a volume (stsvVolumeHullSetup clipped by clipBox) in world space: what
/// shaders/stsv/stsv_hull.comp draws.
ClippedBox volumeHull(const StsvVolume& volume, const StsvLightPlanes& lightPlanes, vec3 v0, vec3 v1, vec3 v2,
                      const Bounds& bounds);

} // namespace stsv
