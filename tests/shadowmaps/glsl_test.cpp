// shadowmaps/shadow_map_dh.h and shadowmaps/shadow_filter_dh.h must compile as GLSL 4.50 too
// (DESIGN §3): a compute shader that supplies the filter's data access from storage buffers, as
// the GPU's filter pass does, and calls the map projection, PCF and every PCSS step.
#include "tests/support/glsl.h"

#include <gtest/gtest.h>

namespace {

const char* const COMPUTE_SHADER = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "shadowmaps/shadow_map_dh.h"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer MapDepths { float depths[]; };
layout(std430, binding = 1) readonly buffer Taps { vec2 taps[]; };
layout(std430, binding = 2) readonly buffer View { ShadowMapView view; };
layout(std430, binding = 3) writeonly buffer Result { vec4 result[]; };
struct ShadowMapSource { uint size; };
float shadowMapSourceDepth(ShadowMapSource s, uint face, ivec2 texel) {
    return depths[(face * s.size + uint(texel.y)) * s.size + uint(texel.x)];
}
vec2 shadowMapSourceTap(ShadowMapSource s, uint i) { return taps[i]; }
#define SHADOW_MAP_SOURCE
#include "shadowmaps/shadow_filter_dh.h"
void main() {
    ShadowMapView v = view;
    ShadowMapSource src;
    src.size = v.size;
    vec3 p = vec3(gl_GlobalInvocationID) * 0.01f;
    ShadowReceiver r = shadowReceiver(v, p, vec3(0.0f, 1.0f, 0.0f), 1.0f, 0.5f,
                                      shadowTapRotation(gl_GlobalInvocationID.xy, 7u, true));
    float pcf = pcfVisibility(v, src, r, 0.01f, 16);
    float blocker = pcssAverageBlocker(v, src, r, 32u, 64.0f);
    float pcss = blocker < 0.0f ? 1.0f : pcssFilter(v, src, r, pcssFilterRadius(v, r, blocker, 64.0f), 32u, 64u);
    ShadowMapCoord c = shadowMapProject(v, p);
    vec4 clip = shadowMapClip(v, c.face, p);
    vec3 o;
    vec3 d;
    shadowMapTexelRay(v, c.face, ivec2(3, 4), o, d);
    uint face;
    ivec2 texel;
    bool inside = shadowMapTexelOf(v, c.face, c.uv, face, texel);
    float plane = shadowMapPlaneDepth(v, face, texel, p, r.n, r.depth);
    result[gl_GlobalInvocationID.x] = vec4(pcf, pcss, clip.z / clip.w + plane + shadowMapDepthAlong(v, d, 1.0f),
                                           inside ? shadowMapTexelWorld(v, c.axial) : 0.0f);
}
)";

TEST(ShadowMapsGlsl, MapAndFilterHeadersCompileInAComputeShader) {
    EXPECT_EQ(stsv::test::glslCompileErrors("shadow_filter.comp", COMPUTE_SHADER), "");
}

} // namespace
