// wedges/dcs_dh.h, wedges/pw_dh.h and wedges/edge_cluster_dh.h must compile as GLSL 4.50 too (DESIGN §3): a
// fragment shader running the per-pixel DCS edge loop and the PW coverage, compiled with glslangValidator.
#include "tests/support/glsl.h"

#include <gtest/gtest.h>

#include <string>

namespace {

const char* const FRAGMENT_SHADER = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "wedges/dcs_dh.h"
#include "wedges/pw_dh.h"
#include "wedges/edge_cluster_dh.h"
layout(location = 0) in vec3 inP;
layout(location = 0) out vec4 color;
layout(std430, binding = 0) readonly buffer Edges { vec4 edgeData[]; };
void main() {
    DcsPixel px = dcsSetupPixel(inP, vec3(0.0f, 5.0f, 0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), 1e-4f);
    int counts[16];
    for (int s = 0; s < 16; ++s) counts[s] = 0;
    float occlusion = 0.0f;
    for (int e = 0; e < 4; ++e) {
        vec3 h0 = dcsProject(px, vec3(edgeData[3 * e]));
        vec3 h1 = dcsProject(px, vec3(edgeData[3 * e + 1]));
        vec3 l = cross(h0, h1);
        int k = dcsFaceSide(l, dcsProject(px, vec3(edgeData[3 * e + 2])));
        if (k == 0 || !dcsClipEdge(px.tMin, h0, h1)) continue;
        for (int s = 0; s < 16; ++s) counts[s] += k * dcsSampleCrossing(l, h0, h1, vec2(float(s) / 16.0f - 0.5f, 0.25f));
        occlusion += float(k) * pwEdgeCoverage(l, h0, h1, DOMAIN_DISK) + pwEdgeCoverage(l, h0, h1, DOMAIN_SQUARE);
    }
    LightHull hull = lightHull(vec4(inP, 0.0f), vec4(0.0f, 5.0f, 0.0f, 0.5f));
    bool meets = ballMeetsLightHull(edgeBall(vec3(edgeData[0]), vec3(edgeData[1])), hull);
    bool cone = clusterMayHaveSilhouette(edgeData[4], edgeData[5], vec4(inP, 0.1f), 1e-5f);
    color = vec4(float(counts[3]), occlusion, px.valid, meets && cone ? 1.0f : 0.0f);
}
)";

TEST(WedgesGlsl, DcsAndPwFragmentShaderCompiles) {
    EXPECT_EQ(stsv::test::glslCompileErrors("wedges.frag", FRAGMENT_SHADER), "");
}

} // namespace
