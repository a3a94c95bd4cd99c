#include "volumes/stsv.h"

namespace stsv {

StsvTriangle stsvTriangleFor(const Scene& scene, std::size_t tri, vec3 lightCenter) {
    const uvec3 idx = scene.triangles[tri];
    const Material& material = scene.materialOf(tri);
    uint flags = material.wrap == WrapMode::Clamp ? STSV_FLAG_CLAMP : 0u;
    if (!material.perforated()) flags |= STSV_FLAG_OPAQUE;
    const uint texture = material.perforated() ? static_cast<uint>(material.alphaTexture) : 0u;
    return stsvSetupTriangle(scene.positions[idx.x], scene.positions[idx.y], scene.positions[idx.z],
                             scene.texcoords[idx.x], scene.texcoords[idx.y], scene.texcoords[idx.z],
                             lightCenter, texture, flags, static_cast<uint>(tri));
}

} // namespace stsv
