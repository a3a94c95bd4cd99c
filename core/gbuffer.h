// The per-pixel visible surface every method shades: produced by Embree primary rays (CPU)
// or by the rasteriser's G-buffer pass (GPU), consumed by every shadow method.
#pragma once

#include "core/dh.h"

#include <cstdint>
#include <vector>

namespace stsv {

inline constexpr std::uint32_t NO_TRIANGLE = 0xffffffffu;

struct GBuffer {
    int width = 0;
    int height = 0;
    std::vector<vec3> position;          ///< world units; visible point p
    std::vector<vec3> normal;            ///< unit, world space; shading normal (see Material::doubleSided)
    std::vector<std::uint32_t> triangle; ///< visible scene triangle, NO_TRIANGLE for background

    GBuffer() = default;
    GBuffer(int w, int h)
        : width(w), height(h), position(std::size_t(w) * h, vec3(0.0f)),
          normal(std::size_t(w) * h, vec3(0.0f)), triangle(std::size_t(w) * h, NO_TRIANGLE) {}
    std::size_t index(int x, int y) const { return std::size_t(y) * width + x; }
    bool covered(std::size_t i) const { return triangle[i] != NO_TRIANGLE; }
};

} // namespace stsv
