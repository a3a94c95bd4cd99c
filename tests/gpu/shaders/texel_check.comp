// GPU half of the texel-rule check: one invocation per case, texelAt (scene/occlusion_rules_dh.h)
// of a coordinate pair given by its bits, so that NaNs and infinities reach the shader unchanged
// (tests/gpu/math_check_test.cpp compares it with the CPU's, exactly).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "scene/occlusion_rules_dh.h"
#include "math_check_dh.h"

layout(local_size_x = MATH_CHECK_GROUP_SIZE) in;

/// (u bits, v bits, width | height << 16, wrap)
layout(std430, binding = MATH_CHECK_BINDING_CASES) readonly buffer Cases { uvec4 cases[]; };
layout(std430, binding = MATH_CHECK_BINDING_RESULTS) writeonly buffer Results { ivec2 results[]; };
layout(push_constant) uniform Push { uint caseCount; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= caseCount) return;
    uvec4 k = cases[i];
    vec2 uv = uintBitsToFloat(k.xy);
    results[i] = texelAt(uv, ivec2(int(k.z & 0xffffu), int(k.z >> 16)), k.w);
}
