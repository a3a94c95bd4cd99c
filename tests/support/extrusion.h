// Host-side STSV extrusion for the tests: the volumes of one triangle for one light (DESIGN §4.2),
// built with the same device/host functions the shaders call, and a volume's hull in world space.
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
inline std::vector<StsvVolume> buildTriangleVolumes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere,
                                                    const Bounds& bounds) {
    const uint sides = stsvSideCount(v0, v1, v2, lightSphere);
    std::vector<StsvVolume> volumes;
    for (uint side = 0; side < sides; ++side)
        volumes.push_back(stsvBuildVolume(v0, v1, v2, lightSphere, bounds.lo, bounds.hi, side));
    return volumes;
}

/// True iff p lies in any of the volumes.
inline bool pointInAnyVolume(const std::vector<StsvVolume>& volumes, vec3 p) {
    for (const StsvVolume& v : volumes)
        if (stsvPointInVolume(v, p)) return true;
    return false;
}

/// The hull of a volume (stsvVolumeHullSetup clipped by clipBox) in world space: what
/// volumes/shaders/stsv_hull.comp draws.
inline ClippedBox volumeHull(const StsvVolume& volume, const StsvLightPlanes& lightPlanes, vec3 v0, vec3 v1,
                             vec3 v2, const Bounds& bounds) {
    StsvHullSetup h = stsvVolumeHullSetup(volume, lightPlanes, v0, v1, v2, bounds.lo, bounds.hi);
    ClippedBox b = clipBox(h.lo, h.hi, h.planes, h.count, h.minCut);
    if (h.empty != 0u) b.faceCount = 0;
    for (uint f = 0; f < b.faceCount; ++f)
        for (uint i = 0; i < b.count[f]; ++i) {
            vec3& c = b.corner[f * CLIP_MAX_FACE_VERTICES + i];
            c = h.origin + h.scale * c;
        }
    return b;
}

} // namespace stsv
