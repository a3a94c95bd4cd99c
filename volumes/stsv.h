// Host-side helpers around the STSV device/host math.
#pragma once

#include "scene/scene.h"
#include "volumes/stsv_dh.h"

namespace stsv {

/// The StsvTriangle of scene triangle `tri` for a light centred at `lightCenter`. Opaque
/// materials become constant-opacity S-triangles (STSV_FLAG_OPAQUE). With `transmittance`, a
/// translucent (Blend) triangle reads its blend texture and optical-depth table
/// (STSV_FLAG_TRANSLUCENT); without, its binary stand-in, as every perforated triangle.
StsvTriangle stsvTriangleFor(const Scene& scene, std::size_t tri, vec3 lightCenter,
                             bool transmittance = false);

} // namespace stsv
