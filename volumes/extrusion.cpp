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

} // namespace stsv
