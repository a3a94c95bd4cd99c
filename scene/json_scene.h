// JSON scene files (format documented in docs/user-guide.md, example in tests/data/scene/example.json).
#pragma once

#include "scene/scene.h"

#include <string>

namespace stsv {

/// The deepest nesting of arrays and objects a scene file may have.
constexpr int MAX_JSON_DEPTH = 64;

/// Reads a JSON scene: materials, meshes (inline quads/triangles or .obj/.off files relative to
/// the JSON file) placed with transforms, camera, lights. Unknown keys, missing or mistyped
/// fields, non-finite numbers, non-positive sizes, light sizes outside [MIN_LIGHT_SIZE,
/// MAX_LIGHT_SIZE], texture coordinates that name no texel, zero normals and missing files throw
/// InputError naming the file and the JSON path of the value (syntax errors and keys given twice
/// in one object: the line; nesting deeper than MAX_JSON_DEPTH is refused while parsing). A
/// generated texture is counted against the memory limit before it is generated (UsageError).
Scene loadJsonScene(const std::string& path);

/// A light object of the scene format given as JSON text (the command line's --light); `what`
/// names it in errors, with the key at fault ("--light: radius: 0 is outside the accepted light
/// size [1e-09, 1e+09] world units ...").
Light parseLightJson(const std::string& what, const std::string& text);
/// A camera object of the scene format given as JSON text (the command line's --camera).
Camera parseCameraJson(const std::string& what, const std::string& text);

} // namespace stsv
