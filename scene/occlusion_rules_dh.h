// The rules every method and the reference share, so that they all answer the same question:
// which texel of an alpha texture a point falls in and whether it blocks (the texel rule), and
// where a shadow segment p → s starts and ends (the gaps at both ends). The Embree reference, the G-buffer,
// the shadow maps, STSV and the wedges all use these. Compiles as C++ and as GLSL (see core/dh.h).
#ifndef STSV_SCENE_OCCLUSION_RULES_DH_H
#define STSV_SCENE_OCCLUSION_RULES_DH_H

#include "core/dh.h"

DH_BEGIN

/// Shadow segments start at t = SHADOW_T_MIN (fraction of p→s) in every method, so a receiver
/// touching an occluder (a shared mesh edge) is not shadowed by it through round-off. For a
/// light frame centred farther than one scene diameter from p (directional lights sit 100
/// diameters away), shadowTMin lowers the start so that it stays within SHADOW_T_MIN·D of p.
DH_CONST float SHADOW_T_MIN = 1e-4f;

/// Start parameter of the segments p → s of the pixel whose light frame is centred at
/// `lightCenter` (world units; sceneDiameter = length of the scene box's extent): SHADOW_T_MIN
/// when |lightCenter − p| ≤ sceneDiameter, else SHADOW_T_MIN·sceneDiameter / |lightCenter − p|,
/// so the segments never start farther than SHADOW_T_MIN·sceneDiameter from p.
DH_FUNC float shadowTMin(vec3 p, vec3 lightCenter, float sceneDiameter) {
    float centerDistance = length(lightCenter - p);
    return centerDistance <= sceneDiameter ? SHADOW_T_MIN : SHADOW_T_MIN * (sceneDiameter / centerDistance);
}

/// End parameter of the segments p → s that start at tMin: they stop short of the light sample by
/// the same gap, as production ray tracers trace a shadow ray to a point on a light (pbrt-v4's
/// SpawnRayTo to t = 1 − ShadowEpsilon, ShadowEpsilon = 1e-4). A sample lying on a surface — a
/// light flush with its ceiling, coplanar with a box's face, set into a recess — is not occluded
/// by that surface, where ending exactly at s would leave the answer to round-off.
DH_FUNC float shadowTMax(float tMin) {
    return 1.0f - tMin;
}

/// Texture addressing, as Material::wrap.
DH_CONST uint WRAP_REPEAT = 0u;
DH_CONST uint WRAP_CLAMP = 1u;

/// The largest texel index magnitude the rule resolves exactly: floats hold every integer below
/// 2^24, and beyond it consecutive floats lie two or more texels apart, so uv·size no longer names
/// one texel. Scene::validate refuses texture coordinates whose |uv|·size reaches it.
DH_CONST float TEXEL_INDEX_LIMIT = 16777216.0f;

/// One axis of the texel rule: floor(coord·size) wrapped or clamped into [0, size − 1]. Total:
/// every float, finite or not, gives an index inside the texture, the same on every backend. The
/// float product is correctly rounded everywhere (IEEE 754 and Vulkan's SPIR-V precision rules), so
/// the float floor is the same; what follows runs on integers and bit patterns, where no compiler
/// may reorder a NaN comparison. A NaN (from a NaN coordinate or ±inf·0) is index 0; an infinite
/// product (a finite coordinate times the size may overflow) or any magnitude beyond
/// TEXEL_INDEX_LIMIT is taken as ±TEXEL_INDEX_LIMIT by its sign: the edge under clamp, a fixed texel
/// under repeat. Below the limit the result is the exact floor-and-wrap.
DH_FUNC int texelIndex(float coord, int size, uint wrap) {
    float index = floor(coord * float(size));
    uint bits = floatBitsToUint(index);
    uint magnitude = bits & 0x7fffffffu;
    int i = 0;
    if (magnitude < floatBitsToUint(TEXEL_INDEX_LIMIT)) {
        i = int(index);
    } else if (magnitude <= 0x7f800000u) { // beyond the limit, or infinite; NaN stays 0
        i = (bits & 0x80000000u) != 0u ? -int(TEXEL_INDEX_LIMIT) : int(TEXEL_INDEX_LIMIT);
    }
    if (wrap == WRAP_CLAMP) return clamp(i, 0, size - 1);
    // Repeat: a non-negative modulo, its operands kept non-negative (GLSL leaves % of a negative
    // operand undefined): −1 wraps to size − 1.
    return i >= 0 ? i % size : size - 1 - (-(i + 1)) % size;
}

/// The texel rule shared by GPU, CPU mirror and Embree: nearest texel of mip 0 at uv, with
/// the material's wrap mode (texelIndex on each axis). Row 0 of the texture is v = 0.
DH_FUNC ivec2 texelAt(vec2 uv, ivec2 size, uint wrap) {
    return ivec2(texelIndex(uv.x, size.x, wrap), texelIndex(uv.y, size.y, wrap));
}

/// Binary transmittance: alpha below one half (alpha8 < 128) is a hole.
DH_FUNC bool alphaBlocks(uint alpha8) {
    return alpha8 >= 128u;
}

/// Fractional transmittance is accumulated as optical depth, −ln(1 − α) summed over the triangles
/// a segment crosses, so that the product Π(1 − α) does not depend on their order: each crossing
/// adds an unsigned fixed-point count of 1/OPTICAL_DEPTH_SCALE units (integer sums are
/// associative, so every order and every backend gives the same bits). A texel with α = 1 is an
/// occlusion (OPTICAL_DEPTH_OPAQUE), kept apart in the occlusion bits; a sum that reaches 2^32
/// units (optical depth 65536) is one too.
DH_CONST float OPTICAL_DEPTH_SCALE = 65536.0f;
DH_CONST uint OPTICAL_DEPTH_OPAQUE = 0xffffffffu;

/// The transmittance exp(−units / OPTICAL_DEPTH_SCALE) of a sum of optical-depth units.
DH_FUNC float transmittanceOfDepth(uint units) {
    return exp(-float(units) * (1.0f / OPTICAL_DEPTH_SCALE));
}

DH_END

#endif
