// wedges/dcs_dh.h and wedges/pw_dh.h must compile as GLSL 4.50 too (DESIGN §3): a fragment shader
// running the per-pixel DCS edge loop and the PW coverage, compiled with glslangValidator when it
// is installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

const char* kFragment = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "wedges/dcs_dh.h"
#include "wedges/pw_dh.h"
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
    color = vec4(float(counts[3]), occlusion, px.valid, 1.0f);
}
)";

std::string compileErrors(const std::string& name, const char* source) {
    const auto dir = std::filesystem::temp_directory_path() / "stsv_wedges_glsl";
    std::filesystem::create_directories(dir);
    const auto file = dir / name;
    std::ofstream(file) << source;
    const auto log = dir / (name + ".log");
    const std::string cmd = "glslangValidator -V -I" + std::string(STSV_SOURCE_DIR) + " " + file.string() +
                            " -o " + (dir / (name + ".spv")).string() + " > " + log.string() + " 2>&1";
    if (std::system(cmd.c_str()) == 0) return "";
    std::ifstream logFile(log);
    return cmd + "\n" +
           std::string((std::istreambuf_iterator<char>(logFile)), std::istreambuf_iterator<char>());
}

TEST(WedgesGlsl, DcsAndPwFragmentShaderCompiles) {
    if (std::system("command -v glslangValidator > /dev/null 2>&1") != 0)
        GTEST_SKIP() << "glslangValidator not installed";
    EXPECT_EQ(compileErrors("wedges.frag", kFragment), "");
}

} // namespace
