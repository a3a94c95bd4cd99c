// GPU half of the STSV math check: one invocation per case, the same runMathCheck() the
// CPU oracle calls (tests/gpu/math_check_test.cpp).
#version 450
#extension GL_GOOGLE_include_directive : require

#include "volumes/stsv_dh.h"
#include "math_check_dh.h"

layout(local_size_x = MATH_CHECK_GROUP_SIZE) in;

layout(std430, binding = MATH_CHECK_BINDING_CASES) readonly buffer Cases { MathCheckCase cases[]; };
layout(std430, binding = MATH_CHECK_BINDING_RESULTS) writeonly buffer Results { MathCheckResult results[]; };
layout(push_constant) uniform Push { uint caseCount; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= caseCount) return;
    results[i] = runMathCheck(cases[i]);
}
