// Mesh files: Wavefront OBJ (+ MTL) and OFF, read through OpenMesh.
//
// Every file is first scanned line by line by our own validator so that bad input is reported
// as file:line (OpenMesh reports no line numbers and accepts NaN, skips bad faces silently).
// OBJ texture coordinates are flipped on load (v' = 1 − v): OBJ puts v = 0 at the bottom of the
// image, stsv puts v = 0 at texture row 0 (the top row as stored).
#pragma once

#include "core/image.h"
#include "scene/geometry.h"

#include <string>

namespace stsv {

/// Reads an OBJ file, its `mtllib` files (Kd, map_Kd, map_d, -clamp) and the textures they name
/// (paths relative to the MTL file). Faces are fan-triangulated; materials follow `usemtl`. A face
/// that names a vertex twice is degenerate: skipped and counted in skippedFaces (a file without
/// any other face is refused at its line). Throws InputError(file, line, problem) on malformed
/// input, missing MTL or texture files.
MeshData loadObj(const std::string& path);

/// Reads an ASCII OFF file ([ST][C][N]OFF headers); one opaque material named "default". Faces
/// that name a vertex twice are skipped as in loadObj.
MeshData loadOff(const std::string& path);

/// loadObj or loadOff by (case-insensitive) extension; UsageError for any other extension.
MeshData loadMeshFile(const std::string& path);

/// Parses one MTL file, appending its materials and the textures they reference to `into`.
void loadMtl(const std::string& path, MeshData& into);

/// Which channel of an image becomes the alpha (transmittance mask) of a Texture.
enum class AlphaSource {
    Auto,      ///< the alpha channel if any texel has alpha < 255, else luminance
    Alpha,     ///< the alpha channel
    Red,       ///< the red channel
    Green,     ///< the green channel
    Blue,      ///< the blue channel
    Luminance, ///< Rec. 709 luma of RGB
};

/// A Texture whose alpha is taken from `source`; RGB is kept. Row 0 of the image is v = 0.
Texture textureFromImage(const Image8& image, const std::string& name, AlphaSource source);

/// True if some texel has alpha < 255.
bool hasTransparency(const Image8& image);

} // namespace stsv
