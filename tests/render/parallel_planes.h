// The parallel-planes set-up of DESIGN §6 for the image-based baselines' tests: a square light
// of width w at height h_l over an opaque ground, an opaque occluder parallel to both with a
// straight edge at height h_o, a camera looking straight down at the ground under the edge; and
// the penumbra profile across the edge, its 5 %…95 % width, and the analytic profiles it is held
// against (the linear ramp of the square light, the disk segment of a disk-shaped kernel or light).
#pragma once

#include "render/frame.h"
#include "scene/geometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace stsv::test {

inline constexpr float LIGHT_HEIGHT = 4.0f;    ///< h_l, world units
inline constexpr float LIGHT_WIDTH = 1.0f;     ///< w, world units
inline constexpr int WIDTH = 256, HEIGHT = 32; ///< columns across the edge, rows along it
inline constexpr int MAP_SIZE = 1024;

/// The penumbra width of DESIGN §6 under a straight edge at height h_o.
inline float penumbraWidth(float occluderHeight) {
    return LIGHT_WIDTH * occluderHeight / (LIGHT_HEIGHT - occluderHeight);
}

/// Horizontal opaque quad at height y over [x0, x1] × [z0, z1], facing up.
inline void addHorizontalQuad(Scene& s, float y, float x0, float x1, float z0, float z1,
                              std::uint32_t material) {
    const vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
    s.addTriangle(a, c, b, vec2(0, 0), vec2(1, 1), vec2(1, 0), material);
    s.addTriangle(a, d, c, vec2(0, 0), vec2(0, 1), vec2(1, 1), material);
}

/// Ground [−2, 2]² at y = 0; occluder [−1, 0] × [−1, 1] at h_o (its edge x = 0 runs along z);
/// the square light centred above the origin, edges along x and z. The camera sits under the
/// occluder (y = 0.3) looking straight down, image x along world x: every column is one x, and its
/// rows sample the same penumbra profile (the other occluder edges throw their penumbrae more
/// than 0.9 m away from the view's ±0.45 m).
inline Scene parallelPlanes(float occluderHeight, float groundHalf = 2.0f) {
    Scene s;
    s.source = "parallel-planes";
    s.materials.push_back({"ground", vec3(0.8f), -1, WrapMode::Repeat, false});
    s.materials.push_back({"occluder", vec3(0.5f), -1, WrapMode::Repeat, false});
    addHorizontalQuad(s, 0.0f, -groundHalf, groundHalf, -groundHalf, groundHalf, 0);
    addHorizontalQuad(s, occluderHeight, -1.0f, 0.0f, -1.0f, 1.0f, 1);
    s.lights.push_back(makeRectangleLight(vec3(0.0f, LIGHT_HEIGHT, 0.0f), vec3(0.0f, -1.0f, 0.0f),
                                          vec2(LIGHT_WIDTH), vec3(1.0f), vec3(1.0f, 0.0f, 0.0f)));
    s.camera.eye = vec3(0.0f, 0.3f, 0.0f);
    s.camera.target = vec3(0.0f);
    s.camera.up = vec3(0.0f, 0.0f, -1.0f);
    // 0.3·tan(fovY/2)·(256/32) = 0.45: the row spans ±0.45 m, 3.5 mm a column.
    s.camera.fovY = 2.0f * glm::degrees(std::atan(0.45f / (0.3f * float(WIDTH) / float(HEIGHT))));
    return s;
}

/// Visibility per column averaged over the rows (the rows see the same profile; averaging them
/// averages PCSS's per-pixel tap rotations and the reference's Monte-Carlo noise), with the
/// column's world x.
struct Profile {
    std::vector<double> x, v;
};

inline Profile columnProfile(const Frame& f) {
    Profile p;
    for (int x = 0; x < f.gbuffer.width; ++x) {
        double sx = 0.0, sv = 0.0;
        for (int y = 0; y < f.gbuffer.height; ++y) {
            const std::size_t i = f.gbuffer.index(x, y);
            EXPECT_TRUE(f.gbuffer.covered(i) && f.gbuffer.triangle[i] < 2)
                << "pixel (" << x << "," << y << ")";
            sx += f.gbuffer.position[i].x;
            sv += f.visibility.at(x, y, 0);
        }
        p.x.push_back(sx / f.gbuffer.height);
        p.v.push_back(sv / f.gbuffer.height);
    }
    return p;
}

/// Where the profile first rises through `level` (linear between columns); NaN if it never does.
inline double crossing(const Profile& p, double level) {
    for (std::size_t i = 1; i < p.v.size(); ++i)
        if (p.v[i - 1] < level && p.v[i] >= level)
            return p.x[i - 1] + (level - p.v[i - 1]) / (p.v[i] - p.v[i - 1]) * (p.x[i] - p.x[i - 1]);
    return std::nan("");
}

inline constexpr double LOW = 0.05, HIGH = 0.95;

/// Distance between the LOW and HIGH crossings.
inline double measuredWidth(const Profile& p) {
    return crossing(p, HIGH) - crossing(p, LOW);
}

/// The analytic visibility under the edge: a linear ramp of width W centred on x = 0, so its
/// LOW…HIGH crossings are (HIGH − LOW)·W = 0.9·W apart.
inline double linearRamp(double x, double width) {
    return std::clamp(0.5 + x / width, 0.0, 1.0);
}

/// Fraction of the unit disk on the far side of a chord at distance a from the centre.
inline double diskSegment(double a) {
    a = std::clamp(a, -1.0, 1.0);
    return (std::acos(a) - a * std::sqrt(1.0 - a * a)) / 3.14159265358979;
}

/// PCSS filters the hard shadow of the light centre (its edge at x = 0) over a disk of diameter
/// W: the lit fraction of the disk around x. Not a linear ramp: its LOW…HIGH crossings are
/// 2·a·W/2 apart, where the disk's segment beyond a chord at a is LOW (a ≈ 0.805).
inline double diskRamp(double x, double width) {
    return 1.0 - diskSegment(x / (0.5 * width));
}
inline double diskLevelWidth(double width) {
    double lo = 0.0, hi = 1.0;
    for (int k = 0; k < 60; ++k) ((diskSegment(0.5 * (lo + hi)) > LOW) ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi) * width;
}

/// Largest deviation of the profile from `expected` over the columns.
template <typename F> inline double maxDeviation(const Profile& p, F expected) {
    double worst = 0.0;
    for (std::size_t i = 0; i < p.v.size(); ++i) worst = std::max(worst, std::abs(p.v[i] - expected(p.x[i])));
    return worst;
}

} // namespace stsv::test
