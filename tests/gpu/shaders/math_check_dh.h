// Cases and results of the GPU-vs-CPU check of the STSV math (tests/gpu/math_check_test.cpp,
// tests/gpu/shaders/stsv_math_check.comp). runMathCheck() is the per-invocation body: the shader's
// main() and the CPU oracle call this same function (STYLE §4).
#ifndef STSV_SHADERS_MATH_CHECK_DH_H
#define STSV_SHADERS_MATH_CHECK_DH_H

#include "core/dh.h"
#include "volumes/stsv_dh.h"

DH_BEGIN

DH_CONST uint MATH_CHECK_BINDING_CASES = 0u;
DH_CONST uint MATH_CHECK_BINDING_RESULTS = 1u;
DH_CONST uint MATH_CHECK_GROUP_SIZE = 64u;

/// One (triangle, point, light frame, sample) case. std430: 10 × 16 bytes.
struct MathCheckCase {
    vec4 v0;        ///< triangle vertex 0, world (xyz); w unused
    vec4 v1;        ///< vertex 1
    vec4 v2;        ///< vertex 2
    vec4 uv01;      ///< texture coordinates of v0 (xy) and v1 (zw)
    vec4 uv2ab;     ///< texture coordinates of v2 (xy); light sample (a, b) in the frame (zw)
    vec4 p;         ///< visible point, world (xyz)
    vec4 c;         ///< light frame origin, world (xyz)
    vec4 tangent;   ///< light frame T, world (xyz): s = c + a·T + b·B
    vec4 bitangent; ///< light frame B, world (xyz)
    uvec4 texture;  ///< texture width, height (texels), wrap (WRAP_*), unused
};

/// What the GPU and the CPU both compute. std430: 3 × 16 bytes.
struct MathCheckResult {
    vec4 he;     ///< h = J·(s − p) (xyz) and e (w), STSV Eq. 1/3
    vec4 baryUv; ///< barycentrics of the crossing (xy), texture coordinates (zw); 0 when no hit
    ivec2 texel; ///< texelAt(uv); (0, 0) when no hit
    uint hit;    ///< 1 iff the segment p→s crosses the triangle
    uint pad;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(MathCheckCase) == 160);
DH_STATIC_ASSERT(sizeof(MathCheckResult) == 48);
#endif

DH_FUNC MathCheckResult runMathCheck(MathCheckCase k) {
    StsvTriangle tri = stsvSetupTriangle(vec3(k.v0), vec3(k.v1), vec3(k.v2), vec2(k.uv01),
                                         vec2(k.uv01.z, k.uv01.w), vec2(k.uv2ab), vec3(k.c), 0u, 0u, 0u);
    StsvPixel px =
        stsvSetupPixel(tri, vec3(k.p), vec3(k.c), vec3(k.tangent), vec3(k.bitangent), SHADOW_T_MIN);
    vec3 h = stsvSampleH(px, vec2(k.uv2ab.z, k.uv2ab.w));
    vec2 bary;
    bool hit = stsvSegmentHitsTriangle(h, px.e, px.tMin, bary);
    MathCheckResult r;
    r.he = vec4(h, px.e);
    r.baryUv = vec4(0.0f);
    r.texel = ivec2(0);
    r.hit = hit ? 1u : 0u;
    r.pad = 0u;
    if (hit) {
        vec2 uv = stsvTexcoord(tri, bary);
        r.baryUv = vec4(bary.x, bary.y, uv.x, uv.y);
        r.texel = texelAt(uv, ivec2(int(k.texture.x), int(k.texture.y)), k.texture.z);
    }
    return r;
}

DH_END

#endif // STSV_SHADERS_MATH_CHECK_DH_H
