// Host-side helpers around the STSV device/host math.
#pragma once

#include "scene/scene.h"
#include "volumes/stsv_dh.h"

namespace stsv {

/// The texture an S-triangle of `material` reads and its flags (STSV_FLAG_CLAMP, _OPAQUE,
/// _TRANSLUCENT): the blend texture of a translucent material with `transmittance`, else the
/// binary mask; no texture (index 0, STSV_FLAG_OPAQUE) where the material has none. The CPU
/// mirror and the Vulkan triangle table (render/vulkan/gpu_frame_resources.cpp) both take it.
struct StsvTexture {
    uint texture;
    uint flags;
};
StsvTexture stsvTextureFor(const Material& material, bool transmittance);

/// The StsvTriangle of scene triangle `tri` for a light centred at `lightCenter`. Opaque
/// materials become constant-opacity S-triangles (STSV_FLAG_OPAQUE). With `transmittance`, a
/// translucent (Blend) triangle reads its blend texture and optical-depth table
/// (STSV_FLAG_TRANSLUCENT); without, its binary stand-in, as every perforated triangle.
StsvTriangle stsvTriangleFor(const Scene& scene, std::size_t tri, vec3 lightCenter,
                             bool transmittance = false);

} // namespace stsv
