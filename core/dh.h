// Prelude of every device/host header (*_dh.h): the same text compiles as C++20 (with GLM)
// and as GLSL 4.50 (included by the shaders through glslang's include callback).
//
// Rules for *_dh.h files (DESIGN §3):
//  - include guards, not #pragma once (GLSL has none);
//  - open with DH_BEGIN and close with DH_END; mark functions DH_FUNC;
//  - parameters: DH_OUT(T) name / DH_INOUT(T) name for outputs, plain T for inputs;
//  - DH_DEFAULT(v) after a struct member: its default value on the host (`= v`), nothing in GLSL;
//  - DH_PRECISE on a variable whose rounding must not depend on where the expression is inlined
//    (GLSL's precise: no fused multiply-adds; C++ builds as ISO C++, which does not contract);
//  - no swizzles (GLM has no .xyz members): truncate with constructors, vec3(v4), vec2(v3);
//  - float literals with a trailing f (1.0f), unsigned with u; no templates, references,
//    pointers, overloads on int/uint, recursion or C++-only library calls;
//  - structs shared with the GPU are std430-friendly (vec4-aligned vec3 + scalar pairs);
//    C++-only checks go inside #ifdef __cplusplus (DH_STATIC_ASSERT).
#ifndef STSV_CORE_DH_H
#define STSV_CORE_DH_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/bitfield.hpp>
#include <glm/integer.hpp>

namespace stsv {
using namespace glm;
using uint = glm::uint;
} // namespace stsv

#define DH_BEGIN namespace stsv {
#define DH_END }
#define DH_FUNC inline
#define DH_OUT(T) T&
#define DH_INOUT(T) T&
#define DH_CONST inline constexpr
#define DH_STATIC_ASSERT(cond) static_assert(cond, #cond)
#define DH_PRECISE
#define DH_DEFAULT(value) = value
#else
#define DH_BEGIN
#define DH_END
#define DH_FUNC
#define DH_OUT(T) out T
#define DH_INOUT(T) inout T
#define DH_CONST const
#define DH_STATIC_ASSERT(cond)
#define DH_PRECISE precise
#define DH_DEFAULT(value)
#endif

#endif // STSV_CORE_DH_H
