#include "volumes/stsv.h"

namespace stsv {

StsvTriangle stsvTriangleFor(const Scene& scene, std::size_t tri, vec3 lightCenter, bool transmittance) {
    const uvec3 idx = scene.triangles[tri];
    const Material& material = scene.materialOf(tri);
    uint flags = material.wrap == WrapMode::Clamp ? STSV_FLAG_CLAMP : 0u;
    // The texture whose alpha the crossing reads: the blend texture of a translucent triangle
    // with a transmittance buffer, else the binary mask.
    const bool translucent = transmittance && material.translucent();
    const int textureIndex = translucent ? material.blendTexture : material.alphaTexture;
    if (textureIndex < 0) flags |= STSV_FLAG_OPAQUE;
    if (translucent) flags |= STSV_FLAG_TRANSLUCENT;
    StsvTriangle t = stsvSetupTriangle(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z],
                                       scene.texcoords[idx.x], scene.texcoords[idx.y], scene.texcoords[idx.z],
                                       lightCenter, textureIndex < 0 ? 0u : static_cast<uint>(textureIndex),
                                       flags, static_cast<uint>(tri));
    t.material = scene.triangleMaterial[tri];
    return t;
}

} // namespace stsv
