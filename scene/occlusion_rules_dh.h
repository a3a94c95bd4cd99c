// The rules every method and the reference share, so that they all answer the same question:
// which texel of an alpha texture a point falls in and whether it blocks (the texel rule), and
// where a shadow segment p → s starts (the start gap). The Embree reference, the G-buffer, the
// shadow maps, STSV and the wedges all use these. Compiles as C++ and as GLSL (see core/dh.h).
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

/// Texture addressing, as Material::wrap.
DH_CONST uint WRAP_REPEAT = 0u;
DH_CONST uint WRAP_CLAMP = 1u;

/// The texel rule shared by GPU, CPU mirror and Embree: nearest texel of mip 0 at uv, with
/// the material's wrap mode. Row 0 of the texture is v = 0.
DH_FUNC ivec2 texelAt(vec2 uv, ivec2 size, uint wrap) {
    // Index arithmetic in float, clamped before the conversion to int: beyond |uv·size| = 2^24
    // texel/size rounds (the modulo could come out negative) and beyond 2^31 an int overflows.
    // Below 2^24 every step is exact, so the result is the exact floor-and-wrap.
    vec2 sizeF = vec2(size);
    vec2 texel = floor(uv * sizeF);
    // Repeat: a non-negative modulo.
    if (wrap != WRAP_CLAMP) texel = texel - sizeF * floor(texel / sizeF);
    return ivec2(clamp(texel, vec2(0.0f), sizeF - vec2(1.0f)));
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
