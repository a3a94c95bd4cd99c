// light_sampling_dh.h must compile as GLSL 4.50 too (DESIGN §3): a fragment shader that calls
// every function of the header, compiled with glslangValidator when it is installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

const char* kShader = R"(#version 450
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
    color = vec4(c + b1 + b2, float(h + off.x + DOMAIN_DISK) * SAMPLING_PI);
}
)";

TEST(LightSamplingGlsl, HeaderCompilesWithGlslang) {
    if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "glslangValidator not installed";
    const auto dir = std::filesystem::temp_directory_path() / "stsv_sampling_glsl";
    std::filesystem::create_directories(dir);
    const auto frag = dir / "light_sampling.frag";
    std::ofstream(frag) << kShader;
    const std::string cmd = "glslangValidator -V -I" + std::string(STSV_SOURCE_DIR) + " " + frag.string() +
                            " -o " + (dir / "light_sampling.spv").string() + " > " +
                            (dir / "log.txt").string() + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream logFile(dir / "log.txt");
    const std::string log((std::istreambuf_iterator<char>(logFile)), std::istreambuf_iterator<char>());
    EXPECT_EQ(rc, 0) << cmd << "\n" << log;
}

} // namespace
