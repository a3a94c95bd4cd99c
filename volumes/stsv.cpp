#include "volumes/stsv.h"

namespace stsv {

StsvTexture stsvTextureFor(const Material& material, bool transmittance) {
    uint flags = material.wrap == WrapMode::Clamp ? STSV_FLAG_CLAMP : 0u;
    const bool translucent = transmittance && material.translucent();
    const int texture = translucent ? material.blendTexture : material.alphaTexture;
    if (texture < 0) flags |= STSV_FLAG_OPAQUE;
    if (translucent) flags |= STSV_FLAG_TRANSLUCENT;
    return {texture < 0 ? 0u : static_cast<uint>(texture), flags};
}

StsvTriangle stsvTriangleFor(const Scene& scene, std::size_t tri, vec3 lightCenter, bool transmittance) {
    const uvec3 idx = scene.triangles[tri];
    const StsvTexture texture = stsvTextureFor(scene.materialOf(tri), transmittance);
    StsvTriangle t = stsvSetupTriangle(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z],
                                       scene.texcoords[idx.x], scene.texcoords[idx.y], scene.texcoords[idx.z],
                                       lightCenter, texture.texture, texture.flags, static_cast<uint>(tri));
    t.material = scene.triangleMaterial[tri];
    return t;
}

} // namespace stsv
