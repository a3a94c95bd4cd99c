// Pinhole camera conventions shared by the rasteriser (clipFromWorld) and the ray tracers
// (primaryRay): pixel (x, y) with row 0 at the top, rays through pixel centres, Vulkan clip
// space (y down, depth in [0, 1]).
#pragma once

#include "scene/scene.h"

namespace stsv {

struct Ray {
    vec3 origin;    ///< world units
    vec3 direction; ///< unit
};

/// World → view (right-handed, camera looks along −z).
mat4 viewFromWorld(const Camera& camera);

/// View → Vulkan clip space for a width/height aspect ratio; y points down in framebuffer.
mat4 clipFromView(const Camera& camera, float aspect, float zNear, float zFar);

/// View → Vulkan clip space with reversed depth and no far plane: depth = zNear / distance along
/// the view axis, 1 at the near plane and falling toward 0 at infinity. With a float depth buffer
/// the relative precision is the same at every distance, so no far plane has to be fitted to the
/// scene and the near plane can sit a millionth of the scene's reach from the eye.
mat4 clipFromViewReversedInfinite(const Camera& camera, float aspect, float zNear);

/// Ray from the eye through the centre of pixel (x, y) of a width × height image; agrees with
/// rasterising through clipFromView(...) · viewFromWorld(...).
Ray primaryRay(const Camera& camera, int x, int y, int width, int height);

} // namespace stsv
