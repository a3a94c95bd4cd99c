// The light-space map math of shadowmaps/shadow_map_dh.h and the host side of shadow_map.h
// against geometry written out here: texel-centre rays project back into their texel at their own
// depth, clip coordinates are the rasteriser's view of the same point, cube faces are orthonormal
// and hand taps across their edges to the face that looks the same way, fitted maps hold the whole
// scene box, and the Poisson-disk taps are a Poisson-disk set.
#include "core/error.h"
#include "sampling/light_sampling_dh.h"
#include "scene/geometry.h"
#include "shadowmaps/shadow_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <tuple>

namespace stsv {
namespace {

std::string str(vec3 v) {
    std::ostringstream out;
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}
std::string str(vec2 v) {
    std::ostringstream out;
    out << "(" << v.x << ", " << v.y << ")";
    return out.str();
}

Bounds box(vec3 lo, vec3 hi) {
    Bounds b;
    b.extend(lo);
    b.extend(hi);
    return b;
}

/// A grid of points through the box, corners and faces included (n per axis).
std::vector<vec3> boxPoints(const Bounds& b, int n) {
    std::vector<vec3> points;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const vec3 f(float(i) / float(n - 1), float(j) / float(n - 1), float(k) / float(n - 1));
                points.push_back(b.lo + f * (b.hi - b.lo));
            }
    return points;
}

/// Texels that exercise a face: its four corners, the middle, and a few in between.
std::vector<ivec2> someTexels(int size) {
    const int m = size - 1;
    return {ivec2(0, 0),     ivec2(m, 0),         ivec2(0, m),
            ivec2(m, m),     ivec2(m / 2, m / 2), ivec2(m / 3, 2 * m / 3),
            ivec2(1, m - 1), ivec2(m - 2, 5)};
}

const Bounds BOX = box(vec3(-1.0f, 0.0f, -1.5f), vec3(1.5f, 1.0f, 1.0f));

ShadowMapView perspectiveView() {
    return fitShadowMap(
        makeRectangleLight(vec3(0.2f, 5.0f, 0.1f), vec3(0.0f, -1.0f, 0.0f), vec2(1.0f), vec3(1.0f)), BOX,
        512);
}
ShadowMapView orthographicView() {
    return fitShadowMap(makeDirectionalLight(vec3(0.3f, 1.0f, -0.2f), 0.02f, vec3(1.0f)), BOX, 512);
}
/// A sphere light inside the box (near is then 1e-5 of the box's diameter), and one outside it.
ShadowMapView cubeView() {
    return fitShadowMap(makeSphereLight(vec3(0.3f, 0.5f, -0.2f), 0.1f, vec3(1.0f)), BOX, 256);
}
ShadowMapView outsideCubeView() {
    return fitShadowMap(makeSphereLight(vec3(4.0f, 3.0f, 2.0f), 0.1f, vec3(1.0f)), BOX, 256);
}

/// Checks a point at ray parameter t along the centre ray of texel `texel` of `face`.
void checkTexelRay(const ShadowMapView& v, uint face, ivec2 texel, float t) {
    vec3 o, d;
    shadowMapTexelRay(v, face, texel, o, d);
    vec3 X, Y, Z;
    shadowMapFaceBasis(v, face, X, Y, Z);
    const vec3 p = o + t * d;
    const std::string where = "face " + std::to_string(face) + " texel (" + std::to_string(texel.x) + ", " +
                              std::to_string(texel.y) + ") t=" + std::to_string(t) + " p=" + str(p);
    // The parameter is the axial depth by construction: d·Z = 1 (float round-off of a sum of three
    // products of unit-sized numbers: 1e-6).
    ASSERT_NEAR(dot(d, Z), 1.0f, 1e-6f) << where;
    const ShadowMapCoord c = shadowMapProject(v, p);
    EXPECT_EQ(c.face, face) << where;
    EXPECT_EQ(c.valid, 1.0f) << where;
    // uv back at the texel centre: the face coordinate s is a ratio of two depths of p, each
    // rounded to 1e-7 relative, then divided by a window of width ≥ 1/size-th of itself: within
    // 1e-2 of a texel for maps up to 2048 texels, far inside the half texel to its edges.
    const vec2 texels = c.uv * float(v.size);
    EXPECT_NEAR(texels.x, float(texel.x) + 0.5f, 1e-2f) << where << " uv=" << str(c.uv);
    EXPECT_NEAR(texels.y, float(texel.y) + 0.5f, 1e-2f) << where << " uv=" << str(c.uv);
    // Depth: the axial one is t; a cube map stores the distance from the centre. Round-off of
    // p − origin: 1e-6 of the scene's size (≤ 10 here).
    EXPECT_NEAR(c.axial, t, 1e-5f * (1.0f + t)) << where;
    const float expectedDepth = v.projection == SHADOW_MAP_CUBE ? length(p - v.origin) : t;
    EXPECT_NEAR(c.depth, expectedDepth, 1e-5f * (1.0f + t)) << where;
    // The rasteriser's view: NDC (x, y) = 2·uv − 1 at the texel centre, z from 0 (near) to 1
    // (far). Same round-off as uv, in NDC units (2/size per texel).
    const vec4 clip = shadowMapClip(v, face, p);
    ASSERT_GT(clip.w, 0.0f) << where;
    const vec2 ndc = vec2(clip.x, clip.y) / clip.w;
    const vec2 centre = 2.0f * (vec2(texel) + vec2(0.5f)) / float(v.size) - vec2(1.0f);
    EXPECT_NEAR(ndc.x, centre.x, 2e-2f / float(v.size)) << where;
    EXPECT_NEAR(ndc.y, centre.y, 2e-2f / float(v.size)) << where;
    const float z = clip.z / clip.w;
    if (t >= v.near && t <= v.far) {
        EXPECT_GE(z, -1e-6f) << where;
        EXPECT_LE(z, 1.0f + 1e-6f) << where;
    }
}

/// Points from near to far along the rays; at least 1 % of far from the centre, since a float
/// point o + t·d a few 1e-5 away from an origin of size 1 carries 1e-3 of relative error itself.
void checkTexelRays(const ShadowMapView& v) {
    const float first = std::max(v.near, 0.01f * v.far);
    for (uint face = 0; face < v.faces; ++face)
        for (const ivec2 texel : someTexels(int(v.size)))
            for (const float f : {0.0f, 0.3f, 1.0f})
                checkTexelRay(v, face, texel, first + f * (v.far - first));
}

TEST(ShadowMapProjection, PerspectiveTexelRayProjectsIntoItsTexelAtItsDepth) {
    const ShadowMapView v = perspectiveView();
    ASSERT_EQ(v.projection, SHADOW_MAP_PERSPECTIVE);
    checkTexelRays(v);
}

TEST(ShadowMapProjection, OrthographicTexelRayProjectsIntoItsTexelAtItsDepth) {
    const ShadowMapView v = orthographicView();
    ASSERT_EQ(v.projection, SHADOW_MAP_ORTHOGRAPHIC);
    checkTexelRays(v);
}

TEST(ShadowMapProjection, EveryCubeFaceTexelRayProjectsIntoItsTexelAtItsDepth) {
    for (const ShadowMapView& v : {cubeView(), outsideCubeView()}) {
        ASSERT_EQ(v.projection, SHADOW_MAP_CUBE);
        ASSERT_EQ(v.faces, 6u);
        checkTexelRays(v);
    }
}

TEST(ShadowMapProjection, ClipDepthIsZeroAtNearAndOneAtFar) {
    for (const ShadowMapView& v : {perspectiveView(), orthographicView(), outsideCubeView()}) {
        vec3 o, d;
        const ivec2 texel(int(v.size) / 3, int(v.size) / 2);
        shadowMapTexelRay(v, 0, texel, o, d);
        const vec4 atNear = shadowMapClip(v, 0, o + v.near * d), atFar = shadowMapClip(v, 0, o + v.far * d);
        // A difference of two depths rounded to 1e-7 relative, over far − near ≥ 1e-2 of far.
        EXPECT_NEAR(atNear.z / atNear.w, 0.0f, 1e-4f) << "projection " << v.projection;
        EXPECT_NEAR(atFar.z / atFar.w, 1.0f, 1e-4f) << "projection " << v.projection;
        float previous = -1.0f;
        for (int k = 0; k <= 16; ++k) {
            const float t = v.near + float(k) / 16.0f * (v.far - v.near);
            const vec4 c = shadowMapClip(v, 0, o + t * d);
            EXPECT_GT(c.z / c.w, previous)
                << "depth not increasing at t=" << t << " projection " << v.projection;
            previous = c.z / c.w;
        }
    }
}

TEST(ShadowMapCube, FaceBasesAreOrthonormalRightHandedAndCoverTheSixDirections) {
    // A tilted frame, so that the faces are not the world axes.
    ShadowMapView v = cubeView();
    const vec3 z = normalize(vec3(0.3f, -1.0f, 0.4f));
    vec3 x, y;
    orthonormalBasis(z, x, y);
    v.axisX = x;
    v.axisY = y;
    v.axisZ = z;
    const vec3 expectedZ[6] = {x, -x, y, -y, z, -z};
    for (uint f = 0; f < 6; ++f) {
        vec3 X, Y, Z;
        shadowMapFaceBasis(v, f, X, Y, Z);
        // Unit vectors from unit inputs by negation and swapping: exact up to the frame's round-off.
        EXPECT_NEAR(length(X), 1.0f, 1e-6f) << "face " << f;
        EXPECT_NEAR(length(Y), 1.0f, 1e-6f) << "face " << f;
        EXPECT_NEAR(length(Z), 1.0f, 1e-6f) << "face " << f;
        EXPECT_NEAR(dot(X, Y), 0.0f, 1e-6f) << "face " << f;
        EXPECT_NEAR(dot(X, Z), 0.0f, 1e-6f) << "face " << f;
        EXPECT_NEAR(dot(Y, Z), 0.0f, 1e-6f) << "face " << f;
        // One handedness on every face, so one triangle winding rasterises the same on all six.
        EXPECT_NEAR(length(cross(X, Y) - Z), 0.0f, 1e-6f) << "face " << f << " is left-handed";
        EXPECT_NEAR(length(Z - expectedZ[f]), 0.0f, 1e-6f) << "face " << f << " looks along " << str(Z);
        EXPECT_EQ(shadowMapCubeFace(v, Z), f);
    }
}

TEST(ShadowMapCube, TapsPastAFaceEdgeLandOnTheNeighbourTexelThatLooksTheSameWay) {
    ShadowMapView v = cubeView();
    const vec3 z = normalize(vec3(0.3f, -1.0f, 0.4f));
    vec3 x, y;
    orthonormalBasis(z, x, y);
    v.axisX = x;
    v.axisY = y;
    v.axisZ = z;
    const float size = float(v.size);
    // Angle of one texel at a face edge: the face plane z = 1 is 2 wide over `size` texels and
    // lies √2 away from the centre there, at 45° to the ray: (2/size)/2 = 1/size radians.
    const float texelAngle = 1.0f / size;
    int checked = 0;
    for (uint f = 0; f < 6; ++f) {
        vec3 X, Y, Z;
        shadowMapFaceBasis(v, f, X, Y, Z);
        for (int edge = 0; edge < 4; ++edge)
            for (const float along : {0.1f, 0.37f, 0.5f, 0.83f}) {
                // A quarter texel past the edge.
                const float past = edge % 2 == 0 ? -0.25f / size : 1.0f + 0.25f / size;
                const vec2 uv = edge < 2 ? vec2(past, along) : vec2(along, past);
                const vec2 s = shadowMapFacePoint(v, uv);
                const vec3 dir = normalize(s.x * X + s.y * Y + Z);
                uint face = 99u;
                ivec2 texel(-1);
                ASSERT_TRUE(shadowMapTexelOf(v, f, uv, face, texel));
                const std::string where = "face " + std::to_string(f) + " uv " + str(uv);
                EXPECT_NE(face, f) << where;
                vec3 X2, Y2, Z2;
                shadowMapFaceBasis(v, face, X2, Y2, Z2);
                EXPECT_NEAR(dot(Z2, Z), 0.0f, 1e-6f) << where << ": landed on the opposite face " << face;
                ASSERT_GE(texel.x, 0) << where;
                ASSERT_GE(texel.y, 0) << where;
                ASSERT_LT(texel.x, int(v.size)) << where;
                ASSERT_LT(texel.y, int(v.size)) << where;
                vec3 o, d;
                shadowMapTexelRay(v, face, texel, o, d);
                const float angle = std::acos(std::clamp(dot(normalize(d), dir), -1.0f, 1.0f));
                EXPECT_LT(angle, 2.0f * texelAngle)
                    << where << " → face " << face << " texel (" << texel.x << ", " << texel.y << ")";
                ++checked;
            }
    }
    EXPECT_EQ(checked, 96);
}

TEST(ShadowMapTexelOf, SingleFaceMapsHaveNothingOutsideTheirFace) {
    const ShadowMapView v = perspectiveView();
    uint face;
    ivec2 texel;
    EXPECT_FALSE(shadowMapTexelOf(v, 0, vec2(-0.01f, 0.5f), face, texel));
    EXPECT_FALSE(shadowMapTexelOf(v, 0, vec2(0.5f, 1.0f), face, texel));
    ASSERT_TRUE(shadowMapTexelOf(v, 0, vec2(0.0f, 0.9999f), face, texel));
    EXPECT_EQ(texel, ivec2(0, int(v.size) - 1));
}

TEST(FitShadowMap, RectangleLightAboveASmallBoxGetsOnePerspectiveFaceHoldingTheBox) {
    const ShadowMapView v = perspectiveView();
    ASSERT_EQ(v.projection, SHADOW_MAP_PERSPECTIVE);
    EXPECT_EQ(v.faces, 1u);
    EXPECT_EQ(v.size, 512u);
    EXPECT_FLOAT_EQ(v.window.z - v.window.x, v.window.w - v.window.y) << "the window must be square";
    EXPECT_FLOAT_EQ(v.lightWidth, 1.0f);
    EXPECT_GT(v.near, 0.0f);
    for (const vec3 p : boxPoints(BOX, 5)) {
        const ShadowMapCoord c = shadowMapProject(v, p);
        EXPECT_EQ(c.valid, 1.0f) << "p=" << str(p);
        EXPECT_GE(c.uv.x, 0.0f) << "p=" << str(p);
        EXPECT_GE(c.uv.y, 0.0f) << "p=" << str(p);
        EXPECT_LT(c.uv.x, 1.0f) << "p=" << str(p);
        EXPECT_LT(c.uv.y, 1.0f) << "p=" << str(p);
        EXPECT_GE(c.depth, v.near) << "p=" << str(p);
        EXPECT_LE(c.depth, v.far) << "p=" << str(p);
    }
    // Fitted, not merely enclosing: the top of the box (4 m below the light) spans the window
    // within its margin, so most texels see the box.
    const ShadowMapCoord a = shadowMapProject(v, vec3(-1.0f, 1.0f, -1.5f)),
                         b = shadowMapProject(v, vec3(1.5f, 1.0f, 1.0f));
    EXPECT_GT(std::max(b.uv.x - a.uv.x, b.uv.y - a.uv.y), 0.99f);
}

TEST(FitShadowMap, LightInsideTheBoxFallsBackToACubeMap) {
    const Light light =
        makeRectangleLight(vec3(0.0f, 0.5f, 0.0f), vec3(0.0f, -1.0f, 0.0f), vec2(0.2f), vec3(1.0f));
    const ShadowMapView v = fitShadowMap(light, BOX, 256);
    EXPECT_EQ(v.projection, SHADOW_MAP_CUBE);
    EXPECT_EQ(v.faces, 6u);
    EXPECT_FLOAT_EQ(v.lightWidth, 0.2f);
    // A disk beside a tall box: the box needs more than 120° of its view.
    const ShadowMapView beside = fitShadowMap(
        makeDiskLight(vec3(1.6f, 0.5f, 0.0f), vec3(-1.0f, -0.1f, 0.0f), 0.1f, vec3(1.0f)), BOX, 256);
    EXPECT_EQ(beside.projection, SHADOW_MAP_CUBE);
}

TEST(FitShadowMap, SphereLightGetsACubeMapWhoseDepthRangeHoldsTheBox) {
    for (const vec3 centre : {vec3(0.3f, 0.5f, -0.2f), vec3(4.0f, 3.0f, 2.0f)}) {
        const ShadowMapView v = fitShadowMap(makeSphereLight(centre, 0.1f, vec3(1.0f)), BOX, 256);
        ASSERT_EQ(v.projection, SHADOW_MAP_CUBE) << "centre " << str(centre);
        EXPECT_EQ(v.faces, 6u);
        EXPECT_FLOAT_EQ(v.lightWidth, 0.2f);
        EXPECT_GT(v.near, 0.0f);
        for (const vec3 p : boxPoints(BOX, 7)) {
            if (length(p - centre) < 1e-3f) continue;
            const ShadowMapCoord c = shadowMapProject(v, p);
            EXPECT_EQ(c.valid, 1.0f);
            // near bounds the axial depth on the point's face (the rasteriser's near plane).
            EXPECT_GE(c.axial, v.near) << "p=" << str(p) << " centre " << str(centre);
            EXPECT_LE(c.depth, v.far) << "p=" << str(p) << " centre " << str(centre);
            EXPECT_GE(c.uv.x, 0.0f);
            EXPECT_LE(c.uv.x, 1.0f);
            EXPECT_GE(c.uv.y, 0.0f);
            EXPECT_LE(c.uv.y, 1.0f);
        }
    }
}

TEST(FitShadowMap, DirectionalLightGetsAnOrthographicFaceHoldingTheBox) {
    const ShadowMapView v = orthographicView();
    ASSERT_EQ(v.projection, SHADOW_MAP_ORTHOGRAPHIC);
    EXPECT_EQ(v.faces, 1u);
    EXPECT_NEAR(v.lightWidth, 2.0f * std::tan(0.02f), 1e-6f);
    // The map looks along the light's travel: away from the direction towards the light.
    EXPECT_NEAR(dot(v.axisZ, normalize(vec3(0.3f, 1.0f, -0.2f))), -1.0f, 1e-6f);
    for (const vec3 p : boxPoints(BOX, 5)) {
        const ShadowMapCoord c = shadowMapProject(v, p);
        EXPECT_GE(c.uv.x, 0.0f) << "p=" << str(p);
        EXPECT_GE(c.uv.y, 0.0f) << "p=" << str(p);
        EXPECT_LT(c.uv.x, 1.0f) << "p=" << str(p);
        EXPECT_LT(c.uv.y, 1.0f) << "p=" << str(p);
        EXPECT_GE(c.depth, v.near) << "p=" << str(p);
        EXPECT_LE(c.depth, v.far) << "p=" << str(p);
    }
}

TEST(FitShadowMap, RejectsAnEmptyBoxAndSizesOutOfRange) {
    const Light light = makeSphereLight(vec3(0.0f, 3.0f, 0.0f), 0.1f, vec3(1.0f));
    EXPECT_THROW(fitShadowMap(light, Bounds{}, 256), UsageError);
    EXPECT_THROW(fitShadowMap(light, BOX, 0), UsageError);
    EXPECT_THROW(fitShadowMap(light, BOX, 16385), UsageError);
}

TEST(PoissonDiskTaps, CountUnitDiskMinimumDistanceAndDeterminism) {
    for (const int count : {1, 16, 32, 64, 256}) {
        float minDistance = -1.0f;
        const std::vector<vec2> taps = poissonDiskTaps(count, 0x5eed0001u, &minDistance);
        ASSERT_EQ(int(taps.size()), count);
        float maxRadius = 0.0f;
        for (std::size_t i = 0; i < taps.size(); ++i) {
            EXPECT_LE(length(taps[i]), 1.0f) << "tap " << i << " " << str(taps[i]);
            maxRadius = std::max(maxRadius, length(taps[i]));
            for (std::size_t j = 0; j < i; ++j)
                EXPECT_GE(length(taps[i] - taps[j]), minDistance) << "taps " << i << ", " << j;
        }
        if (count < 16) continue;
        // A Poisson-disk set, not white noise: the minimum distance is at least half that of the
        // densest (hexagonal) packing of `count` points over the disk's area π (white noise:
        // about 0.05 of it).
        const float hexagonal = std::sqrt(2.0f * 3.14159265f / (std::sqrt(3.0f) * float(count)));
        EXPECT_GE(minDistance, 0.5f * hexagonal) << count << " taps";
        // Uniform over the disk's area, so that a filter of radius R over the taps is a disk of
        // radius R: the mean of r² is the disk's ½ (white noise: ½ ± 0.29/√count, 0.036 for 64
        // taps; 0.01 asks for a stratified set) …
        double r2 = 0.0;
        for (const vec2 t : taps) r2 += double(dot(t, t));
        EXPECT_NEAR(r2 / count, 0.5, 0.01) << count << " taps";
        // … and, over all rotations of the set, the fraction of taps beyond a chord is the
        // disk's: 5 % beyond a = 0.8054 (PCSS's penumbra between its 5 % and 95 % levels is a·w_p).
        auto beyond = [&](double a) {
            double sum = 0.0;
            for (const vec2 t : taps)
                if (double(length(t)) > a) sum += std::acos(a / double(length(t))) / 3.14159265358979;
            return sum / count;
        };
        double lo = 0.0, hi = 1.0;
        for (int k = 0; k < 60; ++k) (beyond(0.5 * (lo + hi)) > 0.05 ? lo : hi) = 0.5 * (lo + hi);
        // 0.01: a tenth of a texel of a 20-texel kernel radius.
        EXPECT_NEAR(0.5 * (lo + hi), 0.8054, 0.01) << count << " taps";
        // The set reaches the rim: a filter of radius R spans 2R. For `count` uniform points,
        // P(all inside r = 0.9) = 0.81^count < 1e-2 from 16 on.
        EXPECT_GT(maxRadius, 0.9f) << count << " taps";
        EXPECT_EQ(poissonDiskTaps(count, 0x5eed0001u), taps) << "not deterministic";
        EXPECT_NE(poissonDiskTaps(count, 0x5eed0002u), taps) << "the seed changes nothing";
    }
    EXPECT_THROW(poissonDiskTaps(0, 1u), UsageError);
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

TEST(ShadowMapKnobs, EachNameSetsItsOwnMemberAndUnknownNamesAreErrors) {
    // Every knob, set to a value inside its range and unlike its default, changes exactly its
    // member: read back through the knob, and every other knob keeps its default.
    for (const ShadowMapKnob& knob : shadowMapKnobs()) {
        // The first variant that reads it.
        ShadowMapMethod filter = ShadowMapMethod::None;
        for (const ShadowMapVariant& v : shadowMapVariants())
            if (filter == ShadowMapMethod::None && knob.readBy(v.filter)) filter = v.filter;
        ASSERT_NE(filter, ShadowMapMethod::None) << knob.name << " is read by no variant";
        const ShadowMapSettings defaults = defaultShadowMapSettings(filter);
        const double value = knob.get(defaults) == knob.max ? knob.min : knob.max;
        const ShadowMapSettings s = shadowMapSettingsFrom(filter, {{knob.name, value}});
        // A float member holds the value rounded to float (0.01 is no float).
        EXPECT_EQ(knob.get(s), knob.integer ? value : double(float(value))) << knob.name;
        EXPECT_EQ(s.filter, filter);
        for (const ShadowMapKnob& other : shadowMapKnobs()) {
            if (std::string(other.name) == knob.name) continue;
            EXPECT_EQ(other.get(s), other.get(defaults)) << knob.name << " also moved " << other.name;
        }
        EXPECT_EQ(!std::holds_alternative<float ShadowMapSettings::*>(knob.member), knob.integer)
            << knob.name;
        EXPECT_LE(knob.min, knob.get(defaults)) << knob.name;
        EXPECT_GE(knob.max, knob.get(defaults)) << knob.name;
    }
    // A method's own defaults move only knobs that method reads, inside their ranges, and are
    // what a frame without parameters renders with.
    const ShadowMapSettings shared;
    for (const ShadowMapMethod filter :
         {ShadowMapMethod::Pcf, ShadowMapMethod::Pcss, ShadowMapMethod::Vsm, ShadowMapMethod::Esm,
          ShadowMapMethod::Evsm, ShadowMapMethod::Msm, ShadowMapMethod::Csm, ShadowMapMethod::Peel,
          ShadowMapMethod::Avsm, ShadowMapMethod::Vpcss}) {
        const ShadowMapSettings own = defaultShadowMapSettings(filter);
        const ShadowMapSettings unset = shadowMapSettingsFrom(filter, {});
        EXPECT_EQ(own.filter, filter);
        for (const ShadowMapKnob& knob : shadowMapKnobs()) {
            EXPECT_EQ(knob.get(unset), knob.get(own)) << knob.name;
            if (!knob.readBy(filter)) {
                EXPECT_EQ(knob.get(own), knob.get(shared))
                    << knob.name << " moved for a method that ignores it";
            }
            EXPECT_LE(knob.min, knob.get(own)) << knob.name;
            EXPECT_GE(knob.max, knob.get(own)) << knob.name;
        }
    }
    // The fairness sweep's choices (docs/measurements.md): VSM, ESM, EVSM bias less, volumetric
    // PCSS more, than the shared default; CSM and MSM keep it.
    EXPECT_EQ(defaultShadowMapSettings(ShadowMapMethod::Vsm).bias, 0.125f);
    EXPECT_EQ(defaultShadowMapSettings(ShadowMapMethod::Csm).bias, shared.bias);
    EXPECT_EQ(defaultShadowMapSettings(ShadowMapMethod::Msm).mip, shared.mip);
    EXPECT_EQ(defaultShadowMapSettings(ShadowMapMethod::Vpcss).normalOffset, 0.75f);
    // A misspelt name, and a PCSS knob given to PCF, are errors rather than silent defaults.
    EXPECT_THROW(shadowMapSettingsFrom(ShadowMapMethod::Pcss, {{"pcss_filter_tap", 8}}), UsageError);
    EXPECT_THROW(shadowMapSettingsFrom(ShadowMapMethod::Pcf, {{"pcss_filter_taps", 8}}), UsageError);
    EXPECT_EQ(shadowMapSettingsFrom(ShadowMapMethod::Pcf, {{"pcf_world_radius", 0.25}}).pcfWorldRadius,
              0.25f);
    // The knobs that counted texels are refused with the one that replaced them, never read as
    // metres: an old script's pcf_radius=5 would be a 5 m kernel.
    for (const auto& [filter, retired, replacement] :
         {std::tuple{ShadowMapMethod::Pcf, "pcf_radius", "pcf_world_radius"},
          std::tuple{ShadowMapMethod::Vsm, "fm_radius", "fm_world_radius"}}) {
        try {
            shadowMapSettingsFrom(filter, {{retired, 5}});
            ADD_FAILURE() << retired << " was accepted";
        } catch (const UsageError& e) {
            EXPECT_NE(std::string(e.what()).find(replacement), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("metres"), std::string::npos) << e.what();
        }
    }
}

} // namespace
} // namespace stsv
