// volumes/extrusion_dh.h and volumes/stsv_dh.h must compile as GLSL 4.50 too (DESIGN §3): a geometry
// shader that emits the STSV strips and a fragment shader that runs the per-pixel math, compiled with
// glslangValidator when it is installed (the GPU build compiles the real shaders).
#include "tests/support/glsl.h"

#include <gtest/gtest.h>

#include <string>

namespace {

const char* const GEOMETRY = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "volumes/extrusion_dh.h"
layout(triangles) in;
layout(triangle_strip, max_vertices = 20) out;
layout(location = 0) in vec3 inWorld[];
layout(location = 0) flat out uint outFlags;
layout(push_constant) uniform Push { mat4 clipFromWorld; vec4 lightSphere; vec4 boundsLo; vec4 boundsHi; } pc;
void main() {
    uint sides = stsvSideCount(inWorld[0], inWorld[1], inWorld[2], pc.lightSphere);
    for (uint side = 0u; side < sides; ++side) {
        StsvVolume v = stsvBuildVolume(inWorld[0], inWorld[1], inWorld[2], pc.lightSphere, vec3(pc.boundsLo),
                                       vec3(pc.boundsHi), side);
        if ((v.flags & STSV_VOLUME_EMPTY) != 0u) continue;
        for (uint i = 0u; i < STSV_STRIP_VERTEX_COUNT; ++i) {
            gl_Position = pc.clipFromWorld * v.vertices[i];
            outFlags = v.flags;
            EmitVertex();
        }
        EndPrimitive();
    }
}
)";

const char* const FRAGMENT_SHADER = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "volumes/extrusion_dh.h"
#include "volumes/stsv_dh.h"
layout(location = 0) in vec3 inP;
layout(location = 0) out vec4 color;
void main() {
    StsvVolume v = stsvBuildVolume(vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f),
                                   vec4(0.2f, 0.2f, 3.0f, 0.5f), vec3(-5.0f), vec3(5.0f), 0u);
    if (!stsvPointInVolume(v, inP)) discard;
    StsvTriangle t = stsvSetupTriangle(vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), vec2(0.0f),
                                       vec2(1.0f, 0.0f), vec2(0.0f, 1.0f), vec3(0.2f, 0.2f, 3.0f), 0u, 0u, 0u);
    StsvPixel px = stsvSetupPixel(t, inP, vec3(0.2f, 0.2f, 3.0f), vec3(0.5f, 0.0f, 0.0f), vec3(0.0f, 0.5f, 0.0f),
                                  shadowTMin(inP, vec3(0.2f, 0.2f, 3.0f), 10.0f));
    ivec2 texel;
    bool crosses = stsvSampleCrosses(t, px, vec2(0.1f, -0.3f), ivec2(64, 32), texel);
    ivec2 clamped = texelAt(vec2(-0.5f, 2.5f), ivec2(64, 32), WRAP_CLAMP);
    color = vec4(crosses ? 1.0f : 0.0f, float(texel.x + clamped.y), float(alphaBlocks(200u)), float(v.flags));
}
)";

TEST(VolumesGlsl, ExtrusionStripGeometryShaderCompiles) {
    EXPECT_EQ(stsv::test::glslCompileErrors("stsv_strip.geom", GEOMETRY), "");
}

TEST(VolumesGlsl, PointInVolumeAndTransmittanceFragmentShaderCompiles) {
    EXPECT_EQ(stsv::test::glslCompileErrors("stsv_volume.frag", FRAGMENT_SHADER), "");
}

} // namespace
