// Shared helpers of the volumes tests: seeded random inputs and printing.
#pragma once

#include "core/dh.h"

#include <glm/gtx/string_cast.hpp>

#include <cmath>
#include <cstdint>
#include <ostream>
#include <random>
#include <string>

namespace stsv::test {

inline std::string str(vec2 v) {
    return glm::to_string(v);
}
inline std::string str(vec3 v) {
    return glm::to_string(v);
}
inline std::string str(vec4 v) {
    return glm::to_string(v);
}
inline std::string str(dvec3 v) {
    return glm::to_string(v);
}

class Rng {
  public:
    explicit Rng(std::uint64_t seed) : m_engine(seed) {}
    double uniform(double lo = 0.0, double hi = 1.0) {
        return std::uniform_real_distribution<double>(lo, hi)(m_engine);
    }
    float uniformf(float lo = 0.0f, float hi = 1.0f) { return static_cast<float>(uniform(lo, hi)); }
    /// log-uniform in [lo, hi]
    float logUniform(float lo, float hi) {
        return static_cast<float>(std::exp(uniform(std::log(double(lo)), std::log(double(hi)))));
    }
    int index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(m_engine); }
    bool chance(double p) { return uniform() < p; }
    vec3 inBox(vec3 lo, vec3 hi) {
        return vec3(uniformf(lo.x, hi.x), uniformf(lo.y, hi.y), uniformf(lo.z, hi.z));
    }
    vec3 inCube(float halfSide) { return inBox(vec3(-halfSide), vec3(halfSide)); }
    /// Uniform in the unit ball.
    vec3 inBall() {
        for (;;) {
            const vec3 v = inCube(1.0f);
            if (dot(v, v) <= 1.0f) return v;
        }
    }
    /// Uniform on the unit sphere.
    vec3 onSphere() {
        for (;;) {
            const vec3 v = inCube(1.0f);
            const float l = length(v);
            if (l > 0.1f && l <= 1.0f) return v / l;
        }
    }
    /// Uniform barycentrics (b1, b2) of a triangle.
    vec2 barycentric() {
        float a = uniformf(), b = uniformf();
        if (a + b > 1.0f) {
            a = 1.0f - a;
            b = 1.0f - b;
        }
        return vec2(a, b);
    }

  private:
    std::mt19937_64 m_engine;
};

} // namespace stsv::test
