// light_sampling_dh.h must compile as GLSL 4.50 too (DESIGN §3): a fragment shader that calls
// every function of the header, compiled with glslangValidator.
#include "tests/support/glsl.h"

#include <gtest/gtest.h>

namespace {

const char* const SHADER = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "sampling/light_sampling_dh.h"
layout(location = 0) out vec4 color;
void main() {
    Light l;
    l.position = vec3(0.0f); l.type = LIGHT_DISK; l.normal = vec3(0.0f, -1.0f, 0.0f); l.radius = 1.0f;
    l.axisU = vec3(1.0f, 0.0f, 0.0f); l.angularRadius = 0.01f; l.axisV = vec3(0.0f, 0.0f, 1.0f);
    l.pad0 = 0.0f; l.radiance = vec3(1.0f); l.pad1 = 0.0f;
    vec3 p = vec3(0.0f, -2.0f, 0.0f);
    LightFrame f = lightFrame(l, p, 100.0f);
    uvec2 px = uvec2(gl_FragCoord.xy);
    uint h = pixelHash(px, 7u) + pcgHash(3u) + interleaveSet(px, 2u);
    uvec2 off = decorrelationOffset(px, 1u);
    vec2 u = decorrelate(vec2(0.25f), px, 7u);
    vec2 ab = samplePoint(u, px, 7u, true, f.domain) + domainPoint(u, DOMAIN_SQUARE);
    vec3 s = lightSamplePosition(f, ab);
    vec3 c = sampleContribution(l, f, p, vec3(0.0f, 1.0f, 0.0f), s);
    vec3 b1;
    vec3 b2;
    orthonormalBasis(vec3(0.0f, 0.0f, 1.0f), b1, b2);
    bool facing = receiverFacesLight(l, f, p, vec3(0.0f, 1.0f, 0.0f));
    color = vec4(c + b1 + b2, float(h + off.x + DOMAIN_DISK + (facing ? 1u : 0u)) * SAMPLING_PI);
}
)";

TEST(LightSamplingGlsl, HeaderCompilesWithGlslang) {
    EXPECT_EQ(stsv::test::glslCompileErrors("light_sampling.frag", SHADER), "");
}

} // namespace
