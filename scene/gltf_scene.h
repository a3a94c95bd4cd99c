// glTF 2.0 (.gltf with external or embedded buffers and images, .glb) through tinygltf: the
// default scene's node trees flattened to triangles in world space (triangle lists, strips and
// fans; morph targets at their weights, skins in the pose the nodes give), the materials' alpha
// (baseColorFactor alpha times baseColorTexture alpha, alphaMode, alphaCutoff, the texture
// coordinate set the texture names, KHR_texture_transform), doubleSided and the first perspective
// camera. glTF lights (KHR_lights_punctual) are points without area, so lights come from the JSON
// scene or the command line.
#pragma once

#include "scene/geometry.h"

#include <optional>
#include <string>

namespace stsv {

/// The triangles of `path`'s default scene (scene 0 when none is named), node transforms
/// applied: a MeshData in world space, with a warning when points or lines (modes 0 to 3, which
/// cast no shadow) were skipped. `camera`, when given, gets the first perspective camera met in a
/// depth-first walk of the nodes (std::nullopt when there is none).
///
/// InputError naming the file and the place on malformed glTF: a .glb container too short,
/// truncated or with chunks out of place; JSON that does not parse or nests deeper than 128
/// levels; a field stsv reads of the wrong type or length, named by its JSON path
/// ("nodes[3].matrix: expected 16 numbers, got 15"); an asset.version other than 2.x
/// or a minVersion above 2.0; an extensionsRequired stsv does not implement (all but
/// KHR_texture_transform); a buffer or image uri that names no regular file; a node reached twice
/// (two parents, listed twice, a cycle); an accessor outside its buffer; a texture coordinate set
/// a material reads that its primitive lacks; an image that is not PNG or JPEG; a sampler with
/// mirrored repeat or different wraps in u and v; a vertex beyond the scene range; a scene without
/// triangles. UsageError (core/memory_budget.h) when the scene's instances, or an image from its
/// header, would not fit the memory limit: checked before flattening and before decoding.
MeshData loadGltf(const std::string& path, std::optional<Camera>* camera = nullptr);

} // namespace stsv
