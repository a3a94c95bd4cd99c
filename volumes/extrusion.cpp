#include "volumes/extrusion.h"

namespace stsv {

std::vector<StsvVolume> buildTriangleVolumes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere,
                                             const Bounds& bounds) {
    const uint sides = stsvSideCount(v0, v1, v2, lightSphere);
    std::vector<StsvVolume> volumes;
    for (uint side = 0; side < sides; ++side)
        volumes.push_back(stsvBuildVolume(v0, v1, v2, lightSphere, bounds.lo, bounds.hi, side));
    return volumes;
}

bool pointInAnyVolume(const std::vector<StsvVolume>& volumes, vec3 p) {
    for (const StsvVolume& v : volumes)
        if (stsvPointInVolume(v, p)) return true;
    return false;
}

ClippedBox volumeHull(const StsvVolume& volume, const StsvLightPlanes& lightPlanes, vec3 v0, vec3 v1, vec3 v2,
                      const Bounds& bounds) {
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
