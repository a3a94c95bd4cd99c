// Host-side STSV extrusion: all volumes of a scene for one light (DESIGN §4.2), built with the
// same device/host function the geometry shader calls.
#pragma once

#include "scene/scene.h"
#include "volumes/extrusion_dh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace stsv {

struct StsvVolumeOptions {
    bool perforatedOnly = true; ///< skip opaque triangles (PW/DCS handle them); false: every triangle
    /// Second volume (STSV §6) whenever the light straddles the plane, whatever Material::doubleSided
    /// says. Off: only double-sided materials get it (single-sided ones keep the paper's artifact).
    bool allDoubleSided = false;
};

/// The volumes of one light, in triangle order (side 0 before side 1), and their counts.
struct StsvVolumeSet {
    std::vector<StsvVolume> volumes;
    std::vector<std::uint32_t> triangleOf; ///< scene triangle index of each volume
    std::vector<std::uint32_t> sideOf;     ///< 0 or 1, the `side` argument of stsvBuildVolume
    std::size_t degenerate = 0;            ///< triangles skipped as degenerate (empty volumes not stored)
    std::size_t noTangent = 0;             ///< volumes with STSV_VOLUME_NO_TANGENT
    std::size_t coneStrip = 0;             ///< volumes with STSV_VOLUME_CONE_STRIP
    std::size_t boxFallback = 0;           ///< volumes with STSV_VOLUME_BOX
};

/// Builds the volumes of the scene's S-triangles for a light of bounding sphere `lightSphere`
/// (centre xyz, radius w; see sampling/light_bounds.h), extruded to `bounds` (usually
/// scene.bounds()). Empty volumes (degenerate triangles, unlit sides) are not stored.
StsvVolumeSet buildStsvVolumes(const Scene& scene, vec4 lightSphere, const Bounds& bounds,
                               const StsvVolumeOptions& options = {});

/// The volumes of one triangle (one or two, STSV §6), empty ones included.
std::vector<StsvVolume> buildTriangleVolumes(vec3 v0, vec3 v1, vec3 v2, vec4 lightSphere,
                                             const Bounds& bounds, bool doubleSided = true);

/// True iff p lies in any of the volumes.
bool pointInAnyVolume(const std::vector<StsvVolume>& volumes, vec3 p);

} // namespace stsv
