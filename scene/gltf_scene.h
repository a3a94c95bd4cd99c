// glTF 2.0 (.gltf with external or embedded buffers and images, .glb) through tinygltf: the
// default scene's node hierarchy flattened to triangles in world space, the materials' alpha
// (baseColorFactor alpha times baseColorTexture alpha, alphaMode, alphaCutoff), doubleSided and
// the first perspective camera. glTF lights (KHR_lights_punctual) are points without area, so
// lights come from the JSON scene or the command line.
#pragma once

#include "scene/geometry.h"

#include <optional>
#include <string>

namespace stsv {

/// The triangles of `path`'s default scene (scene 0 when none is named), node transforms
/// applied: a MeshData in world space. `camera`, when given, gets the first perspective camera met
/// in a depth-first walk of the nodes (std::nullopt when there is none). InputError naming the
/// file on malformed glTF, a primitive that is not an indexed or plain triangle list, an accessor
/// outside its buffer, a missing image, a sampler with mirrored repeat or different wraps in u
/// and v, or a scene without triangles.
MeshData loadGltf(const std::string& path, std::optional<Camera>* camera = nullptr);

} // namespace stsv
