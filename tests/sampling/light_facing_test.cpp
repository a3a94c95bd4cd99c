// Which receivers face a light (receiverFacesLight of light_sampling_dh.h) and the per-pixel mask
// made of it (lightFacingPixels): the pixels where visibility can change the lit image, which
// compare's headline error counts.
#include "core/error.h"
#include "sampling/light_sampling.h"
#include "sampling/light_sampling_dh.h"

#include <glm/gtx/io.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace stsv {
namespace {

Light makeRect(vec3 centre, vec3 u, vec3 v) {
    Light l{};
    l.type = LIGHT_RECTANGLE;
    l.position = centre;
    l.axisU = u;
    l.axisV = v;
    l.normal = normalize(cross(u, v));
    l.radius = length(u + v);
    l.radiance = vec3(1.0f);
    return l;
}

Light makeDisk(vec3 centre, vec3 normal, float radius) {
    Light l{};
    l.type = LIGHT_DISK;
    l.position = centre;
    l.normal = normal;
    l.radius = radius;
    l.radiance = vec3(1.0f);
    return l;
}

Light makeSphere(vec3 centre, float radius) {
    Light l{};
    l.type = LIGHT_SPHERE;
    l.position = centre;
    l.normal = vec3(0.0f, 1.0f, 0.0f);
    l.radius = radius;
    l.radiance = vec3(1.0f);
    return l;
}

Light makeDirectional(vec3 towardsLight, float angularRadius) {
    Light l{};
    l.type = LIGHT_DIRECTIONAL;
    l.normal = normalize(towardsLight);
    l.angularRadius = angularRadius;
    l.radiance = vec3(1.0f);
    return l;
}

constexpr float FAR = 1000.0f;

bool faces(const Light& light, vec3 p, vec3 n) {
    return receiverFacesLight(light, lightFrame(light, p, FAR), p, n);
}

/// Light reaching p through frame point (a, b) of its frame (sampleContribution, red channel).
float contributionAt(const Light& light, vec3 p, vec3 n, vec2 ab) {
    const LightFrame f = lightFrame(light, p, FAR);
    return sampleContribution(light, f, p, n, lightSamplePosition(f, ab)).x;
}

/// Frame points covering the domain densely: for the square its corners, edges and a grid; for
/// the disk its rim at 0.5° steps and rings inside.
std::vector<vec2> densePoints(uint domain) {
    std::vector<vec2> points;
    if (domain == DOMAIN_SQUARE) {
        for (int i = 0; i <= 40; ++i)
            for (int j = 0; j <= 40; ++j)
                points.push_back(vec2(-1.0f + 0.05f * float(i), -1.0f + 0.05f * float(j)));
        return points;
    }
    points.push_back(vec2(0.0f));
    for (int ring = 1; ring <= 10; ++ring)
        for (int k = 0; k < 720; ++k) {
            const float angle = float(k) * float(M_PI) / 360.0f;
            points.push_back(float(ring) / 10.0f * vec2(std::cos(angle), std::sin(angle)));
        }
    return points;
}

/// Some frame point lights the receiver (sampleContribution > 0).
bool someSampleLights(const Light& light, vec3 p, vec3 n) {
    for (const vec2 ab : densePoints(lightFrame(light, p, FAR).domain))
        if (contributionAt(light, p, n, ab) > 0.0f) return true;
    return false;
}

// The rectangle faces down (normal −y) at height 1: its corners (±0.5, 1, ±0.5).
const Light RECT = makeRect(vec3(0, 1, 0), vec3(0.5f, 0, 0), vec3(0, 0, 0.5f));

TEST(LightFacing, RectangleHasTheNormalItEmitsAlong) {
    ASSERT_EQ(RECT.normal, vec3(0, -1, 0)); // the cases below rely on it
}

TEST(LightFacing, ReceiverBehindOrEdgeOnToARectanglesPlaneDoesNotFaceIt) {
    // Under the light, turned up to it: faces.
    EXPECT_TRUE(faces(RECT, vec3(0, 0, 0), vec3(0, 1, 0)));
    // Above it (behind its emitting side), turned down to it: the light emits downwards only.
    EXPECT_FALSE(faces(RECT, vec3(0, 2, 0), vec3(0, -1, 0)));
    EXPECT_EQ(contributionAt(RECT, vec3(0, 2, 0), vec3(0, -1, 0), vec2(0.0f)), 0.0f);
    // In the light's plane beside it, turned towards it (edge-on): cosθl = 0 for every point.
    EXPECT_FALSE(faces(RECT, vec3(3, 1, 0), vec3(-1, 0, 0)));
    EXPECT_FALSE(faces(RECT, vec3(3, 1, 0), normalize(vec3(-1, -1, 0))));
    // A little below the plane, turned towards it: the whole light is in front.
    EXPECT_TRUE(faces(RECT, vec3(3, 0.999f, 0), vec3(-1, 0, 0)));
    // Under the light, turned away from it.
    EXPECT_FALSE(faces(RECT, vec3(0, 0, 0), vec3(0, -1, 0)));
}

TEST(LightFacing, RectangleCountsWhereOnlyACornerIsInFront) {
    // n = (1, −0.9, 1)/|…| at the origin: n·s = 0.5 − 0.9 + 0.5 = 0.1 > 0 for the corner
    // (0.5, 1, 0.5), and < 0 for the other corners (−0.9, −0.9, −1.9 before scaling) and the centre.
    const vec3 p(0.0f);
    const vec3 tilted = normalize(vec3(1.0f, -0.9f, 1.0f));
    EXPECT_TRUE(faces(RECT, p, tilted));
    EXPECT_GT(contributionAt(RECT, p, tilted, vec2(1, 1)), 0.0f);
    for (const vec2 ab : {vec2(-1, 1), vec2(1, -1), vec2(-1, -1), vec2(0, 0)})
        EXPECT_EQ(contributionAt(RECT, p, tilted, ab), 0.0f) << ab;
    // n = (1, −1, 1)/√3: that corner lies in the receiver's plane (n·s = 0 exactly: the terms are
    // ±1/√3 and 1/√3 · 0.5 twice, all exact in float), so no point is strictly in front.
    EXPECT_FALSE(faces(RECT, p, normalize(vec3(1.0f, -1.0f, 1.0f))));
}

TEST(LightFacing, DiskCountsItsRimNotTheSquareAroundIt) {
    const Light disk = makeDisk(vec3(0, 1, 0), vec3(0, -1, 0), 0.5f);
    const vec3 p(0.0f);
    // Tilted by θ from +y towards the diagonal (1, 0, 1)/√2: the disk's highest point gives
    // cosθ + 0.5·sinθ, zero at θ = 180° − atan 2 = 116.57°; the square around the disk, whose
    // corner lies along the diagonal, would give cosθ + 0.5·√2·sinθ, zero at 125.26°.
    const auto tilt = [](float degrees) {
        const float t = degrees * float(M_PI) / 180.0f;
        return vec3(std::sin(t) / std::sqrt(2.0f), std::cos(t), std::sin(t) / std::sqrt(2.0f));
    };
    EXPECT_TRUE(faces(disk, p, tilt(110.0f)));
    EXPECT_TRUE(someSampleLights(disk, p, tilt(110.0f)));
    EXPECT_FALSE(faces(disk, p, tilt(120.0f)));
    EXPECT_FALSE(someSampleLights(disk, p, tilt(120.0f)));
    // Behind the disk's plane.
    EXPECT_FALSE(faces(disk, vec3(0, 1.5f, 0), vec3(0, -1, 0)));
}

TEST(LightFacing, DirectionalLightCountsItsCone) {
    // Light from +y, cone of half-angle 0.1 rad. n at angle θ from +y: faces while θ < 90° + 0.1.
    const Light sun = makeDirectional(vec3(0, 1, 0), 0.1f);
    const auto at = [](float theta) { return vec3(std::sin(theta), std::cos(theta), 0.0f); };
    const float right = float(M_PI) / 2.0f;
    const vec3 p(2.0f, -1.0f, 3.0f);
    EXPECT_TRUE(faces(sun, p, at(0.0f)));
    EXPECT_TRUE(faces(sun, p, at(right)));         // half the cone above the plane
    EXPECT_TRUE(faces(sun, p, at(right + 0.05f))); // part of it
    EXPECT_TRUE(someSampleLights(sun, p, at(right + 0.05f)));
    EXPECT_FALSE(faces(sun, p, at(right + 0.15f))); // none of it
    EXPECT_FALSE(someSampleLights(sun, p, at(right + 0.15f)));
    EXPECT_FALSE(faces(sun, p, at(float(M_PI))));
    // A point sun (no cone): edge-on receivers do not face it, those tilted a little towards it do.
    const Light point = makeDirectional(vec3(0, 1, 0), 0.0f);
    EXPECT_FALSE(faces(point, p, vec3(1, 0, 0)));
    EXPECT_TRUE(faces(point, p, at(right - 0.01f)));
    EXPECT_FALSE(faces(point, p, at(right + 0.01f)));
}

TEST(LightFacing, SphereCountsTheSilhouetteDiskItsSamplesLieOn) {
    // Sphere of radius 1 at distance 5 above p. n tilted β below the horizontal: the silhouette
    // disk (radius 1 through the centre, what every method samples) reaches above the receiver's
    // plane while β < atan(1/5) = 0.1974; the sphere itself while β < asin(1/5) = 0.2014.
    const Light sphere = makeSphere(vec3(0, 5, 0), 1.0f);
    const vec3 p(0.0f);
    const auto below = [](float beta) { return vec3(std::cos(beta), -std::sin(beta), 0.0f); };
    EXPECT_TRUE(faces(sphere, p, vec3(0, 1, 0)));
    EXPECT_TRUE(faces(sphere, p, below(0.0f)));
    EXPECT_TRUE(faces(sphere, p, below(0.15f)));
    EXPECT_FALSE(faces(sphere, p, below(0.25f)));
    // Between the two: a cap of the sphere is above the plane (n·(c + r·n − p) = 1 − 5·sin β > 0),
    // but no sample lights the receiver, so visibility changes nothing there: it does not face.
    const vec3 between = below(0.199f);
    EXPECT_GT(dot(between, sphere.position + sphere.radius * between - p), 0.0f);
    EXPECT_FALSE(someSampleLights(sphere, p, between));
    EXPECT_FALSE(faces(sphere, p, between));
    // A sphere lights all around: above it, looking down.
    EXPECT_TRUE(faces(sphere, vec3(0, 7, 0), vec3(0, -1, 0)));
    EXPECT_FALSE(faces(sphere, vec3(0, 7, 0), vec3(0, 1, 0)));
}

TEST(LightFacing, AgreesWithSomeSampleLightingTheReceiver) {
    // Random receivers around four lights: the rule holds exactly where some point of the light's
    // frame gives sampleContribution > 0. Receivers whose best point is within 1e-3 (relative to
    // their distance to the light) of their plane or of the light's plane are left out: there the
    // dense points (0.05 apart, 0.5° on the rim) may miss the one point that lights them.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const Light lights[] = {
        makeRect(vec3(0.5f, 3, -0.5f), vec3(1.0f, 0.2f, 0), vec3(0, 0.1f, 0.7f)),
        makeDisk(vec3(-1, 3, 0), normalize(vec3(0.3f, -1.0f, 0.2f)), 0.8f),
        makeSphere(vec3(0, 2, 1), 0.7f),
        makeDirectional(vec3(0.3f, 1.0f, -0.4f), 0.2f),
    };
    for (const Light& light : lights) {
        int checked = 0, facing = 0;
        for (int i = 0; i < 400; ++i) {
            const vec3 p(3.0f * u(rng), 3.0f * u(rng), 3.0f * u(rng));
            vec3 n(u(rng), u(rng), u(rng));
            if (length(n) < 0.1f) continue;
            n = normalize(n);
            const LightFrame f = lightFrame(light, p, FAR);
            const float scale = length(f.center - p) + length(f.T) + length(f.B);
            const float nt = dot(n, f.T), nb = dot(n, f.B);
            const float reach =
                f.domain == DOMAIN_SQUARE ? std::abs(nt) + std::abs(nb) : std::sqrt(nt * nt + nb * nb);
            if (std::abs(dot(n, f.center - p) + reach) < 1e-3f * scale) continue;
            if (light.type != LIGHT_SPHERE && light.type != LIGHT_DIRECTIONAL &&
                std::abs(dot(light.normal, p - f.center)) < 1e-3f * scale)
                continue;
            ++checked;
            const bool rule = receiverFacesLight(light, f, p, n);
            facing += rule ? 1 : 0;
            ASSERT_EQ(rule, someSampleLights(light, p, n))
                << "light type " << light.type << " p=" << p << " n=" << n;
        }
        EXPECT_GE(checked, 350) << "light type " << light.type;
        EXPECT_GT(facing, 20) << "light type " << light.type;
        EXPECT_LT(facing, checked - 20) << "light type " << light.type;
    }
}

/// A G-buffer point at index (x, y): position p, normal n, some triangle.
void setPoint(GBuffer& g, int x, int y, vec3 p, vec3 n) {
    const std::size_t i = g.index(x, y);
    g.position[i] = p;
    g.normal[i] = n;
    g.triangle[i] = 0;
}

TEST(LightFacingPixels, APixelFacesWhereOneOfItsPointsFacesSomeLight) {
    // A 2×2 image of a frame supersampled 2×2: a 4×4 G-buffer. The rectangle above the origin
    // faces down; points at the origin face it when turned up, not when turned down.
    GBuffer g(4, 4);
    const vec3 up(0, 1, 0), down(0, -1, 0);
    setPoint(g, 1, 1, vec3(0.0f), up);   // pixel (0, 0): one facing point beside background
    setPoint(g, 0, 2, vec3(0.0f), down); // pixel (0, 1): every point faces away
    setPoint(g, 1, 3, vec3(0.0f), down);
    setPoint(g, 2, 2, vec3(0.0f), down); // pixel (1, 1): one away, one facing
    setPoint(g, 3, 3, vec3(0.0f), up);
    // pixel (1, 0): background only
    const std::vector<PixelFacing> pixels = lightFacingPixels(g, {RECT}, FAR, 2, 2);
    EXPECT_EQ(pixels, (std::vector<PixelFacing>{PixelFacing::Facing, PixelFacing::Background,
                                                PixelFacing::Away, PixelFacing::Facing}));
    // Without supersampling: one point per pixel; a point facing only the second light faces.
    GBuffer one(3, 1);
    setPoint(one, 0, 0, vec3(0.0f), down);
    setPoint(one, 1, 0, vec3(0.0f), up);
    const Light below = makeDisk(vec3(0, -1, 0), vec3(0, 1, 0), 0.5f); // emits upwards, under the origin
    EXPECT_EQ(lightFacingPixels(one, {RECT}, FAR, 3, 1),
              (std::vector<PixelFacing>{PixelFacing::Away, PixelFacing::Facing, PixelFacing::Background}));
    EXPECT_EQ(lightFacingPixels(one, {RECT, below}, FAR, 3, 1),
              (std::vector<PixelFacing>{PixelFacing::Facing, PixelFacing::Facing, PixelFacing::Background}));
    // No light: nothing faces.
    EXPECT_EQ(lightFacingPixels(one, {}, FAR, 3, 1),
              (std::vector<PixelFacing>{PixelFacing::Away, PixelFacing::Away, PixelFacing::Background}));
    // A G-buffer that is not the image's point grid.
    EXPECT_THROW(lightFacingPixels(g, {RECT}, FAR, 3, 2), Error);
    EXPECT_THROW(lightFacingPixels(one, {RECT}, FAR, 2, 1), Error);
    EXPECT_THROW(lightFacingPixels(one, {RECT}, FAR, 0, 1), Error);
}

} // namespace
} // namespace stsv
