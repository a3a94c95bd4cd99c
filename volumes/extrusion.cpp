#include "volumes/extrusion.h"

#include "core/error.h"

namespace stsv {

std::vector<StsvVolume> buildTriangleVolumes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere,
                                             const Bounds& bounds, bool doubleSided) {
    const uint sides = doubleSided ? stsvSideCount(v0, v1, v2, lightSphere) : 1u;
    std::vector<StsvVolume> volumes;
    for (uint side = 0; side < sides; ++side)
        volumes.push_back(stsvBuildVolume(v0, v1, v2, lightSphere, bounds.lo, bounds.hi, side));
    return volumes;
}

StsvVolumeSet buildStsvVolumes(const Scene& scene, vec4 lightSphere, const Bounds& bounds,
                               const StsvVolumeOptions& options) {
    if (bounds.empty()) throw UsageError("STSV extrusion needs non-empty scene bounds");
    StsvVolumeSet set;
    for (std::size_t tri = 0; tri < scene.triangleCount(); ++tri) {
        const Material& material = scene.materialOf(tri);
        if (options.perforatedOnly && !material.perforated()) continue;
        const uvec3 idx = scene.triangles[tri];
        const bool doubleSided = options.allDoubleSided || material.doubleSided;
        const std::vector<StsvVolume> volumes =
            buildTriangleVolumes(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z],
                                 lightSphere, bounds, doubleSided);
        for (std::size_t side = 0; side < volumes.size(); ++side) {
            const StsvVolume& v = volumes[side];
            if (v.flags & STSV_VOLUME_DEGENERATE) {
                ++set.degenerate;
                break;
            }
            if (v.flags & STSV_VOLUME_EMPTY) continue;
            if (v.flags & STSV_VOLUME_NO_TANGENT) ++set.noTangent;
            if (v.flags & STSV_VOLUME_CONE_STRIP) ++set.coneStrip;
            if (v.flags & STSV_VOLUME_BOX) ++set.boxFallback;
            set.volumes.push_back(v);
            set.triangleOf.push_back(static_cast<std::uint32_t>(tri));
            set.sideOf.push_back(static_cast<std::uint32_t>(side));
        }
    }
    return set;
}

bool pointInAnyVolume(const std::vector<StsvVolume>& volumes, vec3 p) {
    for (const StsvVolume& v : volumes)
        if (stsvPointInVolume(v, p)) return true;
    return false;
}

} // namespace stsv
