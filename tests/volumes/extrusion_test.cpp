// STSV extrusion (DESIGN §4.2, volumes/extrusion_dh.h): conservativeness against Embree, tightness,
// the edge cases, and the ten-vertex strip as a closed, outward-oriented convex surface.
#include "core/error.h"
#include "sampling/light_sampling_dh.h"
#include "scene/surface_dh.h"
#include "tests/support/extrusion.h"
#include "volume_test_util.h"
#include "volumes/stsv_dh.h"

#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace stsv {
namespace {

using test::Rng;
using test::str;

// ---------------------------------------------------------------------------------------------
// Embree: one triangle, occlusion of segment p → s exactly as the reference renderer casts it.

class EmbreeTriangle {
  public:
    EmbreeTriangle(RTCDevice device, vec3 v0, vec3 v1, vec3 v2, bool robust) {
        m_scene = rtcNewScene(device);
        if (robust) rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_ROBUST);
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3));
        const vec3 v[3] = {v0, v1, v2};
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) vertices[3 * i + k] = v[i][k];
        auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 1));
        indices[0] = 0;
        indices[1] = 1;
        indices[2] = 2;
        rtcCommitGeometry(geom);
        rtcAttachGeometry(m_scene, geom);
        rtcReleaseGeometry(geom);
        rtcCommitScene(m_scene);
    }
    ~EmbreeTriangle() { rtcReleaseScene(m_scene); }
    EmbreeTriangle(const EmbreeTriangle&) = delete;
    EmbreeTriangle& operator=(const EmbreeTriangle&) = delete;

    /// rtcOccluded1 from p along the unnormalised s − p, t ∈ [SHADOW_T_MIN, shadowTMax(SHADOW_T_MIN)].
    bool occluded(vec3 p, vec3 s) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay ray{};
        ray.org_x = p.x;
        ray.org_y = p.y;
        ray.org_z = p.z;
        const vec3 d = s - p;
        ray.dir_x = d.x;
        ray.dir_y = d.y;
        ray.dir_z = d.z;
        ray.tnear = SHADOW_T_MIN;
        ray.tfar = shadowTMax(SHADOW_T_MIN);
        ray.mask = 0xFFFFFFFFu;
        ray.flags = 0;
        ray.time = 0.0f;
        rtcOccluded1(m_scene, &context, &ray);
        return ray.tfar == -std::numeric_limits<float>::infinity();
    }

  private:
    RTCScene m_scene = nullptr;
};

class EmbreeDevice {
  public:
    EmbreeDevice() : m_device(rtcNewDevice(nullptr)) {}
    ~EmbreeDevice() { rtcReleaseDevice(m_device); }
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
    RTCDevice get() const { return m_device; }

  private:
    RTCDevice m_device;
};

// ---------------------------------------------------------------------------------------------
// Random configurations.

enum Family : int {
    FarLight,        ///< light 3–10 triangle sizes away
    NearLight,       ///< light close and large: vertices in the sphere, edge lines through it
    Straddling,      ///< centre within ±r/2 of the plane: two volumes
    CentreInPlane,   ///< centre on the plane (up to float rounding)
    PointLight,      ///< r = 0
    EdgeTowardLight, ///< the light sits on the extension of an edge
    Scaled,          ///< far light at scale 1e-3…1e3, 1…10⁵ scales away from the origin
    Directional, ///< a directional light's bounding sphere (sampling/light_bounds.h): 100 box diagonals away
    FamilyCount
};
const char* const FAMILY_NAMES[] = {"far light",   "near light",        "straddling", "centre in plane",
                                    "point light", "edge toward light", "scaled",     "directional"};

struct Config {
    vec3 v0, v1, v2;
    vec4 light; ///< centre, radius
    Bounds bounds;
    int family;
    float scale; ///< length scale of the configuration
};

std::ostream& operator<<(std::ostream& os, const Config& c) {
    return os << "family=" << FAMILY_NAMES[c.family] << " v0=" << str(c.v0) << " v1=" << str(c.v1)
              << " v2=" << str(c.v2) << " light=" << str(c.light) << " box=" << str(c.bounds.lo) << ".."
              << str(c.bounds.hi);
}

Config makeConfig(Rng& rng, int family) {
    Config c{};
    c.family = family;
    float scale = 1.0f;
    vec3 offset(0.0f);
    if (family == Scaled) {
        scale = rng.logUniform(1e-3f, 1e3f);
        offset = rng.onSphere() * rng.logUniform(1.0f, 1e5f) * scale; // up to 10⁵ sizes from the origin
    }
    c.scale = scale;
    c.v0 = offset + rng.inCube(1.0f) * scale;
    c.v1 = offset + rng.inCube(1.0f) * scale;
    c.v2 = offset + rng.inCube(1.0f) * scale;
    const vec3 centroid = (c.v0 + c.v1 + c.v2) / 3.0f;
    const vec3 n = normalize(cross(c.v1 - c.v0, c.v2 - c.v0));
    float r = rng.logUniform(0.01f, 2.0f) * scale;
    vec3 centre = centroid + rng.onSphere() * rng.uniformf(3.0f, 10.0f) * scale;
    switch (family) {
    case NearLight:
        centre = centroid + rng.onSphere() * rng.uniformf(0.3f, 2.0f) * scale;
        r = rng.uniformf(0.1f, 1.5f) * scale;
        break;
    case Straddling:
        centre = centroid + rng.inCube(2.0f) * scale;
        centre += n * (rng.uniformf(-0.5f, 0.5f) * r - dot(n, centre - c.v0));
        break;
    case CentreInPlane:
        centre = centroid + rng.inCube(3.0f) * scale;
        centre -= n * dot(n, centre - c.v0);
        break;
    case PointLight:
        r = 0.0f;
        break;
    case Directional: {
        // As lightBoundingSphere places it for a box of diagonal 10√3 ≈ 17.3: far distance F = 100
        // diagonals, radius F·tan(angular radius) + the box's half diagonal.
        const float far = 100.0f * 17.32f * scale;
        centre = rng.onSphere() * far;
        r = far * std::tan(rng.uniformf(0.005f, 0.1f)) + 8.66f * scale;
        break;
    }
    case EdgeTowardLight: {
        const vec3 a = rng.chance(0.5) ? c.v0 : c.v1;
        const vec3 b = a == c.v0 ? c.v1 : c.v2;
        centre = b + (b - a) * rng.uniformf(0.5f, 3.0f) + rng.inCube(0.01f) * scale;
        r = rng.logUniform(0.01f, 0.5f) * scale;
        break;
    }
    default:
        break;
    }
    c.light = vec4(centre, r);
    c.bounds.extend(offset - vec3(5.0f * scale));
    c.bounds.extend(offset + vec3(5.0f * scale));
    for (vec3 v : {c.v0, c.v1, c.v2}) c.bounds.extend(v);
    return c;
}

std::vector<StsvVolume> volumesOf(const Config& c) {
    return buildTriangleVolumes(c.v0, c.v1, c.v2, c.light, c.bounds);
}

bool finiteVolume(const StsvVolume& v) {
    for (const vec4& p : v.planes)
        if (!stsvFiniteVec(vec3(p)) || !std::isfinite(p.w)) return false;
    for (const vec4& p : v.vertices)
        if (!stsvFiniteVec(vec3(p)) || !std::isfinite(p.w)) return false;
    return true;
}

/// A point of the light: in the ball, or (half the time) on its surface.
vec3 lightPoint(Rng& rng, vec4 light) {
    const vec3 u = rng.chance(0.5) ? rng.onSphere() : rng.inBall();
    return vec3(light) + u * light.w;
}

vec3 trianglePoint(Rng& rng, const Config& c) {
    vec2 b = rng.barycentric();
    const double pick = rng.uniform();
    if (pick < 0.1)
        b = vec2(b.x, 0.0f); // on edge v0v1
    else if (pick < 0.2)
        b = vec2(0.0f, b.y); // on edge v0v2
    else if (pick < 0.3)
        b = vec2(b.x, 1.0f - b.x); // on edge v1v2
    else if (pick < 0.35)
        b = vec2(float(rng.index(2)), 0.0f); // a vertex
    return c.v0 + b.x * (c.v1 - c.v0) + b.y * (c.v2 - c.v0);
}

bool inBox(const Bounds& b, vec3 p) {
    return all(lessThanEqual(b.lo, p)) && all(lessThanEqual(p, b.hi));
}

// ---------------------------------------------------------------------------------------------
// (b) Conservativeness and tightness.

struct FamilyStats {
    long configs = 0, volumes = 0, noTangent = 0, triangleCap = 0, cone = 0, box = 0;
    long pairs = 0, occludedPairs = 0, misses = 0;
    long uniformInVolume = 0, uniformInVolumeShadowed = 0;
};

TEST(Extrusion, ConservativeAgainstEmbree) {
    EmbreeDevice device;
    Rng rng(4242);
    std::array<FamilyStats, FamilyCount> stats{};
    constexpr int kConfigsPerFamily = 500;
    constexpr int kConstructed = 30; // receivers behind the triangle, p = y + λ(y − x)
    constexpr int kUniform = 30;     // receivers uniform in the box (tightness)
    constexpr int kSamples = 8;
    int printed = 0;
    for (int family = 0; family < FamilyCount; ++family) {
        FamilyStats& st = stats[family];
        for (int config = 0; config < kConfigsPerFamily; ++config) {
            const Config c = makeConfig(rng, family);
            const std::vector<StsvVolume> volumes = volumesOf(c);
            if (volumes[0].flags & STSV_VOLUME_DEGENERATE) continue;
            ++st.configs;
            for (const StsvVolume& v : volumes) {
                ASSERT_TRUE(finiteVolume(v)) << c;
                ++st.volumes;
                st.noTangent += (v.flags & STSV_VOLUME_NO_TANGENT) != 0;
                st.triangleCap += (v.flags & STSV_VOLUME_TRIANGLE_CAP) != 0;
                st.cone += (v.flags & STSV_VOLUME_CONE_STRIP) != 0;
                st.box += (v.flags & STSV_VOLUME_BOX) != 0;
            }
            const EmbreeTriangle embree(device.get(), c.v0, c.v1, c.v2, config % 2 == 0);
            for (int i = 0; i < kConstructed + kUniform; ++i) {
                const bool constructed = i < kConstructed;
                vec3 p;
                vec3 x(0.0f);
                if (constructed) {
                    const vec3 y = trianglePoint(rng, c);
                    x = lightPoint(rng, c.light);
                    p = y + rng.logUniform(1e-4f, 20.0f) * (y - x);
                    if (!inBox(c.bounds, p)) continue;
                } else {
                    p = rng.inBox(c.bounds.lo, c.bounds.hi);
                }
                const bool inside = pointInAnyVolume(volumes, p);
                bool shadowed = false;
                const int sampleCount = constructed ? kSamples : 4 * kSamples;
                for (int k = 0; k < sampleCount; ++k) {
                    const vec3 s = constructed && k == 0 ? x : lightPoint(rng, c.light);
                    ++st.pairs;
                    if (!embree.occluded(p, s)) continue;
                    ++st.occludedPairs;
                    shadowed = true;
                    if (!inside) {
                        ++st.misses;
                        if (printed++ < 10)
                            ADD_FAILURE() << "Embree occludes p→s but p is in no volume: p=" << str(p)
                                          << " s=" << str(s) << " flags=" << volumes[0].flags
                                          << " sides=" << volumes.size() << " " << c;
                    }
                }
                if (!constructed && inside) {
                    ++st.uniformInVolume;
                    st.uniformInVolumeShadowed += shadowed;
                }
            }
        }
    }
    FamilyStats total;
    for (int f = 0; f < FamilyCount; ++f) {
        const FamilyStats& s = stats[f];
        std::printf(
            "[conservative] %-17s configs %3ld volumes %4ld (no tangent %3ld, triangle cap %3ld, cone strip "
            "%3ld, "
            "box %2ld)  pairs %6ld, occluded %5ld, misses %ld; tightness: %4ld/%4ld = %.2f of uniform p in a "
            "volume are shadowed\n",
            FAMILY_NAMES[f], s.configs, s.volumes, s.noTangent, s.triangleCap, s.cone, s.box, s.pairs,
            s.occludedPairs, s.misses, s.uniformInVolumeShadowed, s.uniformInVolume,
            s.uniformInVolume ? double(s.uniformInVolumeShadowed) / double(s.uniformInVolume) : 0.0);
        total.occludedPairs += s.occludedPairs;
        total.misses += s.misses;
    }
    EXPECT_GE(total.occludedPairs, 100'000);
    EXPECT_EQ(total.misses, 0);
    // Tightness sanity where the paper's construction applies (far lights: fallbacks only for the
    // few that straddle the plane): half the volume points see the triangle over part of the light.
    const FamilyStats& far = stats[FarLight];
    EXPECT_GT(double(far.uniformInVolumeShadowed), 0.4 * double(far.uniformInVolume));
    EXPECT_LT(double(far.box), 0.1 * double(far.volumes));
    const FamilyStats& point = stats[PointLight];
    EXPECT_GT(double(point.uniformInVolumeShadowed), 0.9 * double(point.uniformInVolume));
}

// ---------------------------------------------------------------------------------------------
// (e) The strip: closed, outward, convex, enclosing the plane region inside the box.

struct Strip {
    std::vector<std::array<dvec3, 3>> triangles; ///< the eight strip triangles, strip winding applied
    std::vector<std::array<int, 3>> ids;         ///< distinct-vertex ids of each triangle
    int distinct = 0;
};

Strip stripOf(const StsvVolume& v) {
    Strip s;
    std::vector<vec3> unique;
    std::array<int, 10> id{};
    for (int i = 0; i < 10; ++i) {
        const vec3 p(v.vertices[i]);
        int k = 0;
        while (k < int(unique.size()) && unique[k] != p) ++k;
        if (k == int(unique.size())) unique.push_back(p);
        id[i] = k;
    }
    s.distinct = int(unique.size());
    for (int k = 0; k < 8; ++k) {
        int a = k, b = k + 1;
        if (k % 2 == 1) std::swap(a, b); // odd strip triangles are wound (k+1, k, k+2)
        s.triangles.push_back(
            {dvec3(vec3(v.vertices[a])), dvec3(vec3(v.vertices[b])), dvec3(vec3(v.vertices[k + 2]))});
        s.ids.push_back({id[a], id[b], id[k + 2]});
    }
    return s;
}

TEST(Extrusion, StripIsClosedOutwardAndEnclosesTheVolume) {
    Rng rng(99);
    long checked = 0, apexes = 0, pointsInside = 0;
    long kinds[3] = {}, boxSamples[3] = {}, stripHits[3] = {}, planeHits[3] = {};
    for (int family = 0; family < FamilyCount; ++family) {
        for (int config = 0; config < 2000; ++config) {
            const Config c = makeConfig(rng, family);
            for (const StsvVolume& v : volumesOf(c)) {
                if (v.flags & STSV_VOLUME_EMPTY) continue;
                ++checked;
                const Strip s = stripOf(v);
                // A prism has six distinct corners; a volume closed at the apex of its side planes
                // is a tetrahedron (the back cap collapses to one point).
                ASSERT_TRUE(s.distinct == 6 || s.distinct == 4)
                    << s.distinct << " corners; flags=" << v.flags << " " << c;
                apexes += s.distinct == 4;
                // Closed and consistently oriented: after dropping the collapsed triangles, every
                // directed edge once and its reverse once (prism: 9 edges + 3 quad diagonals;
                // tetrahedron: 6 edges).
                std::map<std::pair<int, int>, int> edges;
                for (const auto& t : s.ids) {
                    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
                    for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
                }
                ASSERT_EQ(edges.size(), s.distinct == 6 ? 24u : 12u) << c;
                for (const auto& [edge, count] : edges) {
                    EXPECT_EQ(count, 1) << c;
                    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << c;
                }
                // Outward: positive signed volume, each face's normal away from the centroid.
                dvec3 centroid(0.0);
                for (int i = 0; i < 10; ++i) centroid += dvec3(vec3(v.vertices[i]));
                centroid /= 10.0; // F0, F1, B0, B2 appear twice: still strictly inside the convex hull
                double volume = 0.0;
                double extent = 0.0;
                for (const auto& t : s.triangles) {
                    volume += dot(t[0] - centroid, cross(t[1] - centroid, t[2] - centroid)) / 6.0;
                    extent = std::max({extent, length(t[0] - centroid), length(t[1] - centroid)});
                }
                EXPECT_GT(volume, 0.0) << "flags=" << v.flags << " " << c;
                std::vector<dvec4> facePlanes; // outward unit normal, offset
                for (const auto& t : s.triangles) {
                    const dvec3 nRaw = cross(t[1] - t[0], t[2] - t[0]);
                    if (length(nRaw) <= 1e-9 * extent * extent)
                        continue; // sliver from a near-degenerate side
                    const dvec3 n = normalize(nRaw);
                    EXPECT_GT(dot(n, (t[0] + t[1] + t[2]) / 3.0 - centroid), 0.0)
                        << "flags=" << v.flags << " " << c;
                    facePlanes.push_back(dvec4(n, -dot(n, t[0])));
                }
                // Encloses {points passing the planes} ∩ box, up to float rounding of the vertices.
                // Also measures how much of the box the strip and the planes take (rasterisation and
                // fragment cost), by strip kind.
                const int kind = (v.flags & STSV_VOLUME_BOX) ? 2 : (v.flags & STSV_VOLUME_CONE_STRIP) ? 1 : 0;
                ++kinds[kind];
                for (int i = 0; i < 200; ++i) {
                    const bool uniform = i < 100;
                    const vec3 p =
                        uniform ? rng.inBox(c.bounds.lo, c.bounds.hi)
                                : trianglePoint(rng, c) + (trianglePoint(rng, c) - lightPoint(rng, c.light)) *
                                                              rng.uniformf(0.0f, 3.0f);
                    if (!inBox(c.bounds, p)) continue;
                    bool inStrip = true;
                    for (const dvec4& f : facePlanes)
                        inStrip = inStrip && dot(dvec3(f), dvec3(p)) + f.w <= 1e-6 * extent;
                    const bool inPlanes = stsvPointInVolume(v, p);
                    if (uniform) {
                        ++boxSamples[kind];
                        stripHits[kind] += inStrip;
                        planeHits[kind] += inPlanes;
                    }
                    if (!inPlanes) continue;
                    ++pointsInside;
                    EXPECT_TRUE(inStrip)
                        << "p=" << str(p) << " outside the strip; flags=" << v.flags << " " << c;
                }
            }
        }
    }
    std::printf(
        "[strip] %ld volumes checked (%ld closed at an apex), %ld in-volume points inside their strip\n",
        checked, apexes, pointsInside);
    const char* const kindNames[] = {"paper prism", "cone strip", "box fallback"};
    for (int k = 0; k < 3; ++k)
        std::printf("[strip] %-12s %5ld volumes: strip covers %.3f of the box, planes %.3f\n", kindNames[k],
                    kinds[k], boxSamples[k] ? double(stripHits[k]) / double(boxSamples[k]) : 0.0,
                    boxSamples[k] ? double(planeHits[k]) / double(boxSamples[k]) : 0.0);
    EXPECT_GT(checked, 2000);
    EXPECT_GT(pointsInside, 10000);
}

// ---------------------------------------------------------------------------------------------
// The paper's construction where it applies (STSV §2.2).

/// The smallest angle (radians) of the triangle t' (vertices pulled to the nearest vertex's
/// distance from `centre`, STSV §2.2), computed in double.
double minAngleOfTPrime(const Config& c) {
    const dvec3 centre(vec3(c.light));
    dvec3 v[3] = {dvec3(c.v0), dvec3(c.v1), dvec3(c.v2)};
    const double R = std::min({distance(v[0], centre), distance(v[1], centre), distance(v[2], centre)});
    for (dvec3& p : v) p = centre + (p - centre) * (R / distance(p, centre));
    double smallest = 4.0;
    for (int i = 0; i < 3; ++i)
        smallest = std::min(smallest, std::acos(std::clamp(dot(normalize(v[(i + 1) % 3] - v[i]),
                                                               normalize(v[(i + 2) % 3] - v[i])),
                                                           -1.0, 1.0)));
    return smallest;
}

TEST(Extrusion, FarLightFollowsThePaper) {
    Rng rng(5);
    int checked = 0, stripChecked = 0;
    for (int i = 0; i < 500; ++i) {
        const Config c = makeConfig(rng, FarLight);
        const StsvVolume v = stsvBuildVolume(c.v0, c.v1, c.v2, c.light, c.bounds.lo, c.bounds.hi, 0u);
        if (v.flags != 0u) continue;
        ++checked;
        const double diag = length(c.bounds.extent());
        const double planeTol = 1e-4 * diag; // the planes' slack (1e-5 diag) and float rounding
        // t' in double (§2.2): the vertex closest to the centre kept, the others pulled along their
        // rays from the centre to the same distance.
        const dvec3 centre(vec3(c.light));
        dvec3 q[3] = {dvec3(c.v0), dvec3(c.v1), dvec3(c.v2)};
        const double R = std::min({distance(q[0], centre), distance(q[1], centre), distance(q[2], centre)});
        for (dvec3& p : q) p = centre + (p - centre) * (R / distance(p, centre));
        // Thin t' (an angle below 20°): its third vertex may lie within the tolerance of an edge's plane.
        const bool thin = minAngleOfTPrime(c) < 20.0 * 3.14159265 / 180.0;
        auto value = [&](uint k, dvec3 p) {
            return dot(dvec3(vec3(v.planes[k])), p) + double(v.planes[k].w);
        };
        // planes: [0] triangle plane, [1] t' plane (front cap), [2..4] outer planes.
        ASSERT_EQ(v.planeCount, 5u) << c;
        for (const dvec3& p : q)
            EXPECT_NEAR(value(1, p), 0.0, planeTol) << "t' vertex off the front cap; " << c;
        EXPECT_LT(value(1, centre), -double(c.light.w)) << "light not in front of t'; " << c;
        for (uint k = 2; k < 5; ++k) {
            // Through an edge of t' (two vertices on it, the third inside), tangent to the sphere.
            int onPlane = 0, inside = 0;
            for (const dvec3& p : q) {
                onPlane += std::abs(value(k, p)) < planeTol;
                inside += value(k, p) > planeTol;
            }
            EXPECT_GE(onPlane, 2) << "plane " << k << "; " << c;
            if (!thin) {
                EXPECT_EQ(onPlane, 2) << "plane " << k << "; " << c;
                EXPECT_EQ(inside, 1) << "plane " << k << "; " << c;
            }
            EXPECT_NEAR(value(k, centre), -double(c.light.w), planeTol)
                << "plane " << k << " not tangent; " << c;
            EXPECT_NEAR(length(vec3(v.planes[k])), 1.0f, 1e-5f);
        }
        // The strip's front cap (Fig. 6: vertices 0, 1, 2) is t', up to the strip's expansion (4.2e-4
        // diag) amplified by 1/sin(half the angle between adjacent side planes): checked where t''s
        // angles are ≥ 20° (≤ 1/sin 10° ≈ 5.8, so < 2.5e-3 diag; 5e-3 allowed).
        if (!thin) {
            ++stripChecked;
            for (int k = 0; k < 3; ++k) {
                double nearest = 1e30;
                for (const dvec3& p : q) nearest = std::min(nearest, distance(dvec3(vec3(v.vertices[k])), p));
                EXPECT_LT(nearest, 5e-3 * diag) << "front vertex " << k << "; " << c;
            }
        }
        // Back cap beyond the box: every box corner in front of it (strip vertices 3, 5, 7 are B2, B0, B1).
        const vec3 b0(v.vertices[5]), b1(v.vertices[7]), b2(v.vertices[3]);
        const vec3 backOut =
            -normalize(cross(b1 - b0, b2 - b0)); // back cap faces away: B wound CW from the light
        for (uint k = 0; k < 8; ++k) {
            const vec3 corner = stsvBoxCorner(c.bounds.lo, c.bounds.hi, k);
            EXPECT_LT(dot(backOut, corner - b0), 0.0f)
                << "corner " << str(corner) << " beyond the back cap; " << c;
        }
    }
    EXPECT_GT(checked, 400);
    EXPECT_GT(stripChecked, 200);
}

TEST(Extrusion, PointLightVolumeIsTheHardShadow) {
    // r = 0: the outer planes are the shadow frustum's sides (through the centre and an edge), so a
    // point 1e-3 box diagonals outside a side of the hard shadow (5× the planes' slack and radius
    // inflation, 2e-4) is outside the volume, and the hard shadow itself is inside.
    Rng rng(6);
    int outsideChecked = 0;
    for (int i = 0; i < 300; ++i) {
        const Config c = makeConfig(rng, PointLight);
        const StsvVolume v = stsvBuildVolume(c.v0, c.v1, c.v2, c.light, c.bounds.lo, c.bounds.hi, 0u);
        if (v.flags & STSV_VOLUME_EMPTY) continue;
        const dvec3 centre(vec3(c.light));
        const dvec3 t[3] = {dvec3(c.v0), dvec3(c.v1), dvec3(c.v2)};
        const dvec3 centroid = (t[0] + t[1] + t[2]) / 3.0;
        const double delta = 1e-3 * length(c.bounds.extent());
        for (int e = 0; e < 3; ++e) {
            const dvec3 a = t[e], b = t[(e + 1) % 3];
            dvec3 out = normalize(cross(a - centre, b - centre)); // frustum side through the edge
            if (dot(out, centroid - a) > 0.0) out = -out;
            const dvec3 mid = 0.5 * (a + b);
            for (double lambda : {0.1, 1.0, 3.0}) {
                const vec3 shadowed(centroid + lambda * (centroid - centre));
                const vec3 lit(mid + lambda * (mid - centre) + delta * out);
                if (inBox(c.bounds, shadowed)) {
                    EXPECT_TRUE(stsvPointInVolume(v, shadowed)) << c;
                }
                if (inBox(c.bounds, lit)) {
                    EXPECT_FALSE(stsvPointInVolume(v, lit)) << "lit point " << str(lit) << " inside; " << c;
                    ++outsideChecked;
                }
            }
        }
    }
    EXPECT_GT(outsideChecked, 1000);
}

// ---------------------------------------------------------------------------------------------
// (d) Edge cases.

void expectContainsNothing(const StsvVolume& v, Rng& rng, const std::string& what) {
    EXPECT_TRUE(v.flags & STSV_VOLUME_EMPTY) << what;
    EXPECT_TRUE(finiteVolume(v)) << what;
    for (int i = 0; i < 100; ++i) EXPECT_FALSE(stsvPointInVolume(v, rng.inCube(10.0f))) << what;
}

TEST(ExtrusionEdgeCases, DegenerateTrianglesAreEmpty) {
    Rng rng(7);
    const vec4 light(0.0f, 5.0f, 0.0f, 1.0f);
    const vec3 lo(-10.0f), hi(10.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    struct Tri {
        const char* name;
        vec3 a, b, c;
    };
    const Tri tris[] = {
        {"collinear", vec3(0, 0, 0), vec3(1, 0, 0), vec3(2, 0, 0)},
        {"repeated vertex", vec3(0, 0, 0), vec3(1, 0, 1), vec3(0, 0, 0)},
        {"point", vec3(1, 2, 3), vec3(1, 2, 3), vec3(1, 2, 3)},
        {"needle below 1e-7", vec3(0, 0, 0), vec3(1, 0, 0), vec3(0.5f, 1e-9f, 0)},
        {"NaN vertex", vec3(0, 0, 0), vec3(nan, 0, 0), vec3(0, 0, 1)},
        {"infinite vertex", vec3(0, 0, 0), vec3(inf, 0, 0), vec3(0, 0, 1)},
    };
    for (const Tri& t : tris) {
        for (uint side = 0; side < 2; ++side) {
            const StsvVolume v = stsvBuildVolume(t.a, t.b, t.c, light, lo, hi, side);
            expectContainsNothing(v, rng, t.name);
            EXPECT_TRUE(v.flags & STSV_VOLUME_DEGENERATE) << t.name;
        }
        EXPECT_EQ(stsvSideCount(t.a, t.b, t.c, light), 1u) << t.name;
        // The transmittance setup agrees: a degenerate triangle blocks nothing.
        const StsvTriangle s =
            stsvSetupTriangle(t.a, t.b, t.c, vec2(0), vec2(1, 0), vec2(0, 1), vec3(light), 0, 0, 0);
        EXPECT_TRUE(s.flags & STSV_FLAG_DEGENERATE) << t.name;
    }
    // NaN light or bounds: empty, never NaN.
    const vec3 a(0, 0, 0), b(1, 0, 0), c(0, 0, 1);
    expectContainsNothing(stsvBuildVolume(a, b, c, vec4(nan), lo, hi, 0u), rng, "NaN light");
    expectContainsNothing(stsvBuildVolume(a, b, c, light, vec3(nan), hi, 0u), rng, "NaN bounds");
}

TEST(ExtrusionEdgeCases, SideCount) {
    const vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);                          // plane z = 0
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, 2.0f, 1.0f)), 1u);    // above, clear of the plane
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, -2.0f, 1.0f)), 1u);   // below, clear
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, 0.5f, 1.0f)), 2u);    // straddles
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(5.0f, 5.0f, -0.99f, 1.0f)), 2u);  // straddles, far to the side
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, 0.0f, 0.5f)), 2u);    // centre in the plane
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, 1.0001f, 1.0f)), 1u); // just clear
    EXPECT_EQ(stsvSideCount(a, b, c, vec4(0.3f, 0.3f, 0.9999f, 1.0f)), 2u); // just crossing
    // Winding does not matter.
    EXPECT_EQ(stsvSideCount(a, c, b, vec4(0.3f, 0.3f, 0.5f, 1.0f)), 2u);
    EXPECT_EQ(stsvSideCount(a, c, b, vec4(0.3f, 0.3f, 2.0f, 1.0f)), 1u);
    // Side 1 of a light that does not straddle is empty (no light on that side), not degenerate.
    const StsvVolume v = stsvBuildVolume(a, b, c, vec4(0.3f, 0.3f, 2.0f, 1.0f), vec3(-5), vec3(5), 1u);
    EXPECT_EQ(v.flags, STSV_VOLUME_EMPTY);
    EXPECT_FALSE(stsvPointInVolume(v, vec3(0.2f, 0.2f, -1.0f)));
    // Side 0 of it contains the umbra below the triangle, side 0 never the lit side above.
    const StsvVolume v0 = stsvBuildVolume(a, b, c, vec4(0.3f, 0.3f, 2.0f, 1.0f), vec3(-5), vec3(5), 0u);
    EXPECT_TRUE(stsvPointInVolume(v0, vec3(0.25f, 0.25f, -0.01f)));
    EXPECT_FALSE(stsvPointInVolume(v0, vec3(0.25f, 0.25f, 0.01f)));
}

TEST(ExtrusionEdgeCases, CentreInPlaneGivesTwoMirroredVolumes) {
    const vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    const vec4 light(2.0f, 0.5f, 0.0f, 0.5f); // beside the triangle, in its plane
    ASSERT_EQ(stsvSideCount(a, b, c, light), 2u);
    const StsvVolume up = stsvBuildVolume(a, b, c, light, vec3(-5), vec3(5), 0u);
    const StsvVolume down = stsvBuildVolume(a, b, c, light, vec3(-5), vec3(5), 1u);
    EXPECT_TRUE(finiteVolume(up));
    EXPECT_TRUE(finiteVolume(down));
    EXPECT_FALSE(up.flags & STSV_VOLUME_EMPTY);
    EXPECT_FALSE(down.flags & STSV_VOLUME_EMPTY);
    // A ray from the light's upper half grazing over the triangle shadows a point below it towards
    // −x, and symmetrically: each side's volume holds its own shadow and not the other's.
    const vec3 below(-1.0f, 0.4f, -0.2f), above(-1.0f, 0.4f, 0.2f);
    EXPECT_TRUE(stsvPointInVolume(up, below) || stsvPointInVolume(down, below));
    EXPECT_TRUE(stsvPointInVolume(up, above) || stsvPointInVolume(down, above));
    EXPECT_NE(stsvPointInVolume(up, below), stsvPointInVolume(up, above));
    EXPECT_NE(stsvPointInVolume(down, below), stsvPointInVolume(down, above));
}

TEST(ExtrusionEdgeCases, EdgeLineThroughTheLightIsFlaggedAndConservative) {
    // t' = t (vertices equidistant from the centre); the line of edge v1v2 passes 0.3 from the
    // centre, inside the sphere of radius 0.5: that edge has no outer plane.
    const vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
    const vec4 light(1.0f, 1.0f, 0.3f, 0.5f);
    const StsvVolume v = stsvBuildVolume(a, b, c, light, vec3(-5), vec3(5), 0u);
    EXPECT_TRUE(finiteVolume(v));
    EXPECT_TRUE(v.flags & STSV_VOLUME_NO_TANGENT) << v.flags;
    EXPECT_FALSE(v.flags & STSV_VOLUME_EMPTY);
    // A light point just above the plane beyond edge v1v2 (the sphere reaches z = −0.2) casts a
    // shadow of a triangle point far along −(1,1) behind the plane.
    const vec3 x(1.3f, 1.3f, 0.05f), y(0.9f, 0.9f, 0.0f);
    const vec3 p = y + 3.0f * (y - x);
    EXPECT_TRUE(stsvPointInVolume(v, p)) << str(p);
}

TEST(ExtrusionEdgeCases, VertexInsideTheLight) {
    const vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
    const vec4 light(0.1f, 0.1f, 0.2f, 0.5f); // contains vertex a
    for (uint side = 0; side < stsvSideCount(a, b, c, light); ++side) {
        const StsvVolume v = stsvBuildVolume(a, b, c, light, vec3(-5), vec3(5), side);
        EXPECT_TRUE(finiteVolume(v));
        EXPECT_TRUE(v.flags & STSV_VOLUME_NO_TANGENT);
        // Everything just behind the triangle (on the side away from the light) may be shadowed.
        const float z = side == 0 ? -0.01f : 0.01f;
        for (vec3 p : {vec3(0.5f, 0.5f, z), vec3(-4.0f, 3.0f, 4 * z), vec3(4.0f, -4.0f, 300 * z)})
            EXPECT_TRUE(stsvPointInVolume(v, p)) << "side " << side << " p=" << str(p);
    }
}

TEST(ExtrusionEdgeCases, ExtremeScalesStayFiniteAndExact) {
    // The same configuration at scales 1e-4 … 1e4, shifted by 10 scales: identical inside/outside
    // answers for points well away from the boundaries (relative positions are scale-free).
    const vec3 a(0, 0, 0), b(1, 0, 0.2f), c(0.1f, 1, 0);
    const vec4 light(0.3f, 0.4f, 3.0f, 0.4f);
    Rng rng(8);
    std::vector<vec3> probes;
    for (int i = 0; i < 200; ++i) probes.push_back(rng.inCube(4.0f));
    const StsvVolume unit = stsvBuildVolume(a, b, c, light, vec3(-5), vec3(5), 0u);
    for (float scale : {1e-4f, 1e-2f, 1e2f, 1e4f}) {
        const vec3 o(10.0f * scale, -20.0f * scale, 5.0f * scale);
        const StsvVolume v = stsvBuildVolume(o + a * scale, o + b * scale, o + c * scale,
                                             vec4(o + vec3(light) * scale, light.w * scale),
                                             o + vec3(-5 * scale), o + vec3(5 * scale), 0u);
        EXPECT_TRUE(finiteVolume(v)) << scale;
        EXPECT_EQ(v.flags, unit.flags) << scale;
        EXPECT_EQ(v.planeCount, unit.planeCount) << scale;
        for (vec3 p : probes) {
            // Skip probes within 1e-3 of a plane of the unit volume: the slack (≈ 2e-4 here) and
            // rounding may decide those.
            bool nearBoundary = false;
            for (uint k = 0; k < unit.planeCount; ++k)
                nearBoundary |= std::abs(dot(vec3(unit.planes[k]), p) + unit.planes[k].w) < 1e-3f;
            if (nearBoundary) continue;
            EXPECT_EQ(stsvPointInVolume(v, o + p * scale), stsvPointInVolume(unit, p))
                << "scale " << scale << " p=" << str(p);
        }
    }
    // Absurd magnitudes (products overflow): finite output; the triangle counts as degenerate, as
    // for stsvSetupTriangle, so it blocks nothing anywhere.
    const StsvVolume huge =
        stsvBuildVolume(a * 1e30f, b * 1e30f, c * 1e30f, light * 1e30f, vec3(-5e30f), vec3(5e30f), 0u);
    EXPECT_TRUE(finiteVolume(huge) || (huge.flags & STSV_VOLUME_EMPTY));
}

TEST(ExtrusionEdgeCases, TriangleBehindTheLight) {
    // A one-sided emitter facing −y at y = 5, a triangle above it: the extrusion does not know the
    // emission and stays conservative (a volume away from the light, above the triangle).
    const vec3 a(-1, 8, -1), b(1, 8, -1), c(0, 8, 1);
    const vec4 light(0.0f, 5.0f, 0.0f, 1.0f);
    const StsvVolume v = stsvBuildVolume(a, b, c, light, vec3(-10), vec3(10), 0u);
    EXPECT_EQ(v.flags, 0u);
    EXPECT_TRUE(stsvPointInVolume(v, vec3(0.0f, 9.0f, -0.2f)));
    EXPECT_FALSE(stsvPointInVolume(v, vec3(0.0f, 7.0f, -0.2f)));
}

// ---------------------------------------------------------------------------------------------
// The prism's ends cut at the box (stsvCutPrismAtBox).

/// True iff p lies in the convex hull of the prism f_i → b_i, judged by the planes of its five
/// faces (normals away from the centroid), within `tol`.
bool inPrism(const vec3 f[3], const vec3 b[3], vec3 p, double tol) {
    dvec3 centroid(0.0);
    for (int i = 0; i < 3; ++i) centroid += (dvec3(f[i]) + dvec3(b[i])) / 6.0;
    const dvec3 faces[5][3] = {{dvec3(f[0]), dvec3(f[1]), dvec3(f[2])},
                               {dvec3(b[0]), dvec3(b[1]), dvec3(b[2])},
                               {dvec3(f[0]), dvec3(f[1]), dvec3(b[0])},
                               {dvec3(f[1]), dvec3(f[2]), dvec3(b[1])},
                               {dvec3(f[2]), dvec3(f[0]), dvec3(b[2])}};
    for (const auto& t : faces) {
        dvec3 n = normalize(cross(t[1] - t[0], t[2] - t[0]));
        if (dot(n, centroid - t[0]) > 0.0) n = -n;
        if (dot(n, dvec3(p) - t[0]) > tol) return false;
    }
    return true;
}

TEST(ExtrusionCut, APrismLeavingThroughOneFaceEndsOnIt) {
    // A flat box (a patch of ground and plants) and a prism leaning down and sideways from a small
    // triangle inside it, its far end 20 box heights below: the end moves onto the bottom face,
    // `margin` below it, each corner along its side edge.
    const vec3 lo(-4.0f, 0.0f, -4.0f), hi(4.0f, 1.0f, 4.0f);
    const float margin = 1e-3f;
    const vec3 f[3] = {vec3(0.0f, 0.8f, 0.0f), vec3(0.3f, 0.8f, 0.1f), vec3(0.1f, 0.9f, 0.3f)};
    const vec3 dir(0.4f, -1.0f, 0.7f);
    const vec3 b[3] = {f[0] + 20.0f * dir, f[1] + 21.0f * dir + vec3(0.5f, 0.0f, 0.0f),
                       f[2] + 19.0f * dir + vec3(0.0f, 0.0f, 0.5f)};
    vec3 cut[3] = {b[0], b[1], b[2]};
    stsvCutPrismAtBox(f[0], f[1], f[2], cut[0], cut[1], cut[2], lo, hi, margin);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(cut[i].y, lo.y - margin) << "corner " << i << " " << str(cut[i]);
        // On the side edge f_i → b_i, between its ends.
        const vec3 along = cut[i] - f[i], edge = b[i] - f[i];
        EXPECT_LT(length(cross(along, edge)), 1e-5f * dot(edge, edge)) << "corner " << i;
        EXPECT_GT(dot(along, edge), 0.0f);
        EXPECT_LT(dot(along, edge), dot(edge, edge));
    }
    // The cut prism keeps every point of the prism inside the box.
    Rng rng(31);
    int inside = 0;
    for (int k = 0; k < 20000; ++k) {
        const vec3 p = rng.inBox(vec3(-0.2f, lo.y, -0.2f), vec3(1.0f, hi.y, 1.4f)); // around the prism
        if (!inPrism(f, b, p, 0.0)) continue;
        ++inside;
        EXPECT_TRUE(inPrism(f, cut, p, 1e-5)) << "p=" << str(p);
    }
    EXPECT_GT(inside, 200);
}

TEST(ExtrusionCut, PrismsLeavingThroughSeveralFacesAreUnchanged) {
    // Side edges fanning out of the box through its top and bottom: no one face crosses all
    // three, and the end stays where it was.
    const vec3 lo(-4.0f, 0.0f, -4.0f), hi(4.0f, 1.0f, 4.0f);
    const vec3 f[3] = {vec3(0.0f, 0.5f, 0.0f), vec3(0.3f, 0.5f, 0.0f), vec3(0.0f, 0.5f, 0.3f)};
    const vec3 b[3] = {vec3(-30.0f, -40.0f, -30.0f), vec3(30.0f, 25.0f, 60.0f), vec3(5.0f, -20.0f, 2.0f)};
    vec3 cut[3] = {b[0], b[1], b[2]};
    stsvCutPrismAtBox(f[0], f[1], f[2], cut[0], cut[1], cut[2], lo, hi, 1e-3f);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(cut[i], b[i]) << "corner " << i;
    // An end that lies inside the box already is not moved either.
    const vec3 inner[3] = {vec3(0.0f, 0.1f, 0.0f), vec3(0.3f, 0.1f, 0.0f), vec3(0.0f, 0.1f, 0.3f)};
    vec3 kept[3] = {inner[0], inner[1], inner[2]};
    stsvCutPrismAtBox(f[0], f[1], f[2], kept[0], kept[1], kept[2], lo, hi, 1e-3f);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(kept[i], inner[i]) << "corner " << i;
}

TEST(ExtrusionCut, FoliageStripsEndAtTheGround) {
    // A leaf under a high oblique light over a wide, flat box (the foliage scene's shape): the back
    // cap perpendicular to the light would pass the far corner of the box, tens of metres below
    // the ground; the strip ends `margin` (1e-3 box diagonals) below it instead, and still
    // encloses the volume there (StripIsClosedOutwardAndEnclosesTheVolume checks every family).
    const vec3 lo(-28.0f, 0.0f, -28.0f), hi(28.0f, 1.2f, 28.0f);
    const vec4 light(-11.8f, 17.4f, -18.3f, 4.2f);
    const vec3 a(2.0f, 1.0f, 3.0f), b(2.0f, 0.0f, 3.0f), c(2.6f, 0.0f, 3.5f);
    const StsvVolume v = stsvBuildVolume(a, b, c, light, lo, hi, 0u);
    ASSERT_EQ(v.flags, 0u);
    const float diag = length(hi - lo);
    for (int i = 0; i < 10; ++i)
        EXPECT_GE(v.vertices[i].y, lo.y - 1.01e-3f * diag)
            << "strip vertex " << i << " " << str(v.vertices[i]);
}

// ---------------------------------------------------------------------------------------------
// Light planes (stsvLightPlanes): the shadow's hull from a square light.

/// A square light c ± T ± B inside the configuration's sphere, turned at random; every third one
/// is a thin rectangle.
struct SquareLight {
    vec3 c, T, B;
};

SquareLight squareIn(Rng& rng, const Config& c) {
    vec3 t, b;
    orthonormalBasis(rng.onSphere(), t, b);
    const float halfDiagonal = c.light.w * rng.uniformf(0.3f, 1.0f);
    const float aspect = rng.index(3) == 0 ? rng.uniformf(0.05f, 0.3f) : 1.0f;
    const float u = halfDiagonal / std::sqrt(1.0f + aspect * aspect);
    return {vec3(c.light), t * u, b * (u * aspect)};
}

/// A point of the square: inside, on an edge or at a corner.
vec3 squarePoint(Rng& rng, const SquareLight& l) {
    vec2 ab(rng.uniformf(-1.0f, 1.0f), rng.uniformf(-1.0f, 1.0f));
    const double pick = rng.uniform();
    if (pick < 0.2)
        ab.x = rng.chance(0.5) ? 1.0f : -1.0f;
    else if (pick < 0.3)
        ab = vec2(rng.chance(0.5) ? 1.0f : -1.0f, rng.chance(0.5) ? 1.0f : -1.0f);
    return l.c + ab.x * l.T + ab.y * l.B;
}

TEST(LightPlanes, ConservativeAgainstEmbreeAndTighterThanTheSphere) {
    // Every configuration family of the volume tests, with a square light inside the sphere: every
    // pair (p, s) Embree finds occluded has p inside the light planes. Tightness: of the uniform
    // points in the box inside the volume of the sphere, how many the light planes keep, and how
    // many of those the triangle shadows for some of 32 light samples.
    EmbreeDevice device;
    Rng rng(777);
    long occluded = 0, misses = 0, planes = 0, configs = 0;
    std::array<long, FamilyCount> inVolume{}, inBoth{}, shadowed{};
    int printed = 0;
    for (int family = 0; family < FamilyCount; ++family) {
        for (int config = 0; config < 400; ++config) {
            const Config c = makeConfig(rng, family);
            const SquareLight light = squareIn(rng, c);
            const StsvLightPlanes lp =
                stsvLightPlanes(c.v0, c.v1, c.v2, light.c, light.T, light.B, c.bounds.lo, c.bounds.hi);
            if (stsvTriangleIsDegenerate(c.v0, c.v1, c.v2)) {
                EXPECT_EQ(lp.count, 0u);
                continue;
            }
            ++configs;
            planes += lp.count;
            for (uint i = 0; i < lp.count; ++i) {
                ASSERT_TRUE(stsvFiniteVec(vec3(lp.planes[i])) && std::isfinite(lp.planes[i].w)) << c;
                ASSERT_NEAR(length(vec3(lp.planes[i])), 1.0f, 1e-4f) << c;
            }
            const std::vector<StsvVolume> volumes = volumesOf(c);
            const EmbreeTriangle embree(device.get(), c.v0, c.v1, c.v2, config % 2 == 0);
            for (int i = 0; i < 60; ++i) {
                const bool constructed = i < 30;
                vec3 p, x(0.0f);
                if (constructed) {
                    const vec3 y = trianglePoint(rng, c);
                    x = squarePoint(rng, light);
                    p = y + rng.logUniform(1e-4f, 20.0f) * (y - x);
                    if (!inBox(c.bounds, p)) continue;
                } else {
                    p = rng.inBox(c.bounds.lo, c.bounds.hi);
                }
                const bool inside = stsvPointInLightPlanes(lp, p);
                bool anyOccluded = false;
                for (int k = 0; k < (constructed ? 8 : 32); ++k) {
                    const vec3 s = constructed && k == 0 ? x : squarePoint(rng, light);
                    if (!embree.occluded(p, s)) continue;
                    ++occluded;
                    anyOccluded = true;
                    if (inside) continue;
                    ++misses;
                    if (printed++ < 10)
                        ADD_FAILURE()
                            << "Embree occludes p→s but p is outside the light planes: p=" << str(p)
                            << " s=" << str(s) << " square c=" << str(light.c) << " T=" << str(light.T)
                            << " B=" << str(light.B) << " planes=" << lp.count << " " << c;
                }
                if (constructed || !pointInAnyVolume(volumes, p)) continue;
                ++inVolume[family];
                inBoth[family] += inside;
                shadowed[family] += inside && anyOccluded;
            }
        }
    }
    std::printf("[light planes] %ld configurations, %.2f planes each, %ld occluded pairs, %ld misses\n",
                configs, double(planes) / double(configs), occluded, misses);
    for (int f = 0; f < FamilyCount; ++f)
        std::printf(
            "[light planes] %-17s uniform p in the sphere's volume %5ld, in the light planes too %5ld, "
            "shadowed %5ld\n",
            FAMILY_NAMES[f], inVolume[f], inBoth[f], shadowed[f]);
    EXPECT_GE(occluded, 50'000);
    EXPECT_EQ(misses, 0);
    // Far lights: the light planes keep at most half of the sphere volume's points, and at least
    // half of what they keep is shadowed (the volume's own tightness is about 0.5 with the sphere's
    // samples, ConservativeAgainstEmbree; with the square's samples it is lower still).
    EXPECT_LT(double(inBoth[FarLight]), 0.5 * double(inVolume[FarLight]));
    EXPECT_GT(double(shadowed[FarLight]), 0.5 * double(inBoth[FarLight]));
}

TEST(LightPlanes, AFarLightGivesAllSevenAndAPointLightTheHardShadow) {
    // A small triangle under a square light far above: every edge of the triangle and of the square
    // has its plane.
    const vec3 a(0.0f, 1.0f, 0.0f), b(1.0f, 1.0f, 0.0f), c(0.0f, 1.2f, 1.0f);
    const vec3 lo(-10.0f, 0.0f, -10.0f), hi(10.0f, 5.0f, 10.0f);
    const StsvLightPlanes lp = stsvLightPlanes(a, b, c, vec3(2.0f, 20.0f, 1.0f), vec3(1.0f, 0.0f, 0.0f),
                                               vec3(0.0f, 0.0f, 1.0f), lo, hi);
    EXPECT_EQ(lp.count, 7u);
    // A point light (T = B = 0): the planes are those of the hard shadow's frustum. On the ground,
    // every point of the projected triangle is inside them, and every point farther than 1e-3 box
    // diagonals from it (5× the planes' slack and touching radius) is outside.
    const vec3 light(0.5f, 10.0f, 0.3f);
    const StsvLightPlanes hard = stsvLightPlanes(a, b, c, light, vec3(0.0f), vec3(0.0f), lo, hi);
    ASSERT_GE(hard.count, 3u);
    const auto onGround = [&](vec3 v) {
        return vec2(light.x, light.z) +
               (vec2(v.x, v.z) - vec2(light.x, light.z)) * (light.y / (light.y - v.y));
    };
    const vec2 s0 = onGround(a), s1 = onGround(b), s2 = onGround(c);
    // Distance from q to the projected triangle (0 inside).
    const auto distance = [&](vec2 q) {
        const vec2 corners[3] = {s0, s1, s2};
        const float turn = (s1.x - s0.x) * (s2.y - s0.y) - (s1.y - s0.y) * (s2.x - s0.x);
        bool inside = true;
        float nearest = 1e30f;
        for (int i = 0; i < 3; ++i) {
            const vec2 e0 = corners[i], e1 = corners[(i + 1) % 3];
            const float side = (e1.x - e0.x) * (q.y - e0.y) - (e1.y - e0.y) * (q.x - e0.x);
            inside = inside && side * turn >= 0.0f;
            const float t = std::clamp(dot(q - e0, e1 - e0) / dot(e1 - e0, e1 - e0), 0.0f, 1.0f);
            nearest = std::min(nearest, length(q - (e0 + t * (e1 - e0))));
        }
        return inside ? 0.0f : nearest;
    };
    const float diag = length(hi - lo);
    Rng rng(12);
    int in = 0, out = 0;
    for (int i = 0; i < 20000; ++i) {
        const vec2 q(rng.uniformf(-2.0f, 3.0f), rng.uniformf(-2.0f, 3.0f));
        const float d = distance(q);
        const vec3 p(q.x, 0.0f, q.y);
        if (d == 0.0f) {
            ++in;
            EXPECT_TRUE(stsvPointInLightPlanes(hard, p)) << "p=" << str(p);
        } else if (d > 1e-3f * diag) {
            ++out;
            EXPECT_FALSE(stsvPointInLightPlanes(hard, p))
                << "p=" << str(p) << " " << d << " from the hard shadow";
        }
    }
    EXPECT_GT(in, 300);
    EXPECT_GT(out, 5000);
}

// ---------------------------------------------------------------------------------------------
// Host builder.

TEST(ExtrusionHost, SecondVolumeExactlyWhenTheLightStraddlesThePlane) {
    Bounds bounds;
    bounds.extend(vec3(-6));
    bounds.extend(vec3(6));
    const vec4 light(0.0f, 1.0f, 3.0f, 0.5f);
    // A triangle in the plane x = 2: the light's sphere (centre x = 0, radius 0.5) lies on one side.
    const vec3 a(2, 0, 0), b(2, 0, 2), c(2, 2, 0);
    const std::vector<StsvVolume> oneSide = buildTriangleVolumes(a, b, c, light, bounds);
    ASSERT_EQ(oneSide.size(), 1u);
    EXPECT_TRUE(finiteVolume(oneSide[0]));
    EXPECT_EQ(oneSide[0].flags & (STSV_VOLUME_EMPTY | STSV_VOLUME_DEGENERATE), 0u);
    // The light moved into the plane (x = 2.3 ± 0.5): both sides (STSV §6), both non-empty.
    const std::vector<StsvVolume> straddled =
        buildTriangleVolumes(a, b, c, vec4(2.3f, 1.0f, 0.5f, 0.5f), bounds);
    ASSERT_EQ(straddled.size(), 2u);
    for (const StsvVolume& v : straddled) {
        EXPECT_TRUE(finiteVolume(v));
        EXPECT_EQ(v.flags & (STSV_VOLUME_EMPTY | STSV_VOLUME_DEGENERATE), 0u);
    }
    // A zero-area triangle: one volume, flagged degenerate (the renderers skip it).
    const std::vector<StsvVolume> degenerate =
        buildTriangleVolumes(vec3(0), vec3(0), vec3(1), vec4(2.3f, 1.0f, 0.5f, 0.5f), bounds);
    ASSERT_EQ(degenerate.size(), 1u);
    EXPECT_NE(degenerate[0].flags & STSV_VOLUME_DEGENERATE, 0u);
}

// The set-up both backends' STSV volumes and wedge bounds share (stsvSideVolume,
// stsvTriangleLightPlanes), against the geometry of the light: which sides it sees, and the
// segments from its samples.

/// A point behind q as seen from light point l: q + t·(q − l), t from 2 % to 100 % of |q − l|
/// (away from the triangle's start gap), or nothing when it leaves the box.
bool behind(Rng& rng, vec3 l, vec3 q, const Bounds& box, vec3& p) {
    p = q + rng.uniformf(0.02f, 1.0f) * (q - l);
    return p.x > box.lo.x && p.y > box.lo.y && p.z > box.lo.z && p.x < box.hi.x && p.y < box.hi.y &&
           p.z < box.hi.z;
}

TEST(ExtrusionSides, ASideHasAVolumeExactlyWhenTheLightSeesIt) {
    Rng rng(4711);
    Bounds box;
    box.extend(vec3(-8.0f));
    box.extend(vec3(8.0f));
    int straddling = 0, oneSided = 0, shadowPoints = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const vec3 v0 = rng.inCube(2.0f), v1 = rng.inCube(2.0f), v2 = rng.inCube(2.0f);
        const vec3 n = cross(v1 - v0, v2 - v0);
        if (length(n) < 0.1f) continue; // well away from degenerate
        const vec4 sphere(rng.inCube(4.0f), rng.logUniform(0.01f, 1.5f));
        const vec3 c(sphere);
        // The sphere must not touch the triangle itself (a light inside the occluder).
        if (length(c - v0) < 2.0f * sphere.w || length(c - v1) < 2.0f * sphere.w ||
            length(c - v2) < 2.0f * sphere.w)
            continue;
        // The plane's distance from the centre, against the radius, away from the 1e-6 slack.
        const double d = std::abs(dot(dvec3(normalize(n)), dvec3(c) - dvec3(v0)));
        const bool straddles = d < 0.999 * sphere.w;
        if (!straddles && d < 1.001 * sphere.w) continue;
        (straddles ? straddling : oneSided)++;
        StsvVolume vol[2];
        const bool has0 = stsvSideVolume(v0, v1, v2, sphere, box.lo, box.hi, 0u, true, vol[0]);
        const bool has1 = stsvSideVolume(v0, v1, v2, sphere, box.lo, box.hi, 1u, true, vol[1]);
        StsvVolume none;
        EXPECT_FALSE(stsvSideVolume(v0, v1, v2, sphere, box.lo, box.hi, 2u, true, none));
        ASSERT_TRUE(has0) << "trial " << trial;
        ASSERT_EQ(has1, straddles) << "trial " << trial << " d/r=" << d / sphere.w;
        // The hull passes take the planes alone: the same sides, the same planes bit for bit.
        for (uint side = 0; side < 2; ++side) {
            StsvVolume planes;
            ASSERT_EQ(stsvSideVolume(v0, v1, v2, sphere, box.lo, box.hi, side, false, planes),
                      side == 0 || has1);
            if (side == 1 && !has1) continue;
            ASSERT_EQ(planes.planeCount, vol[side].planeCount);
            // Bit for bit (NaN payloads and signed zeros included); a vec4 has no padding.
            // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison)
            EXPECT_EQ(std::memcmp(planes.planes, vol[side].planes, sizeof planes.planes), 0)
                << "trial " << trial << " side " << side;
        }
        // A point a segment from the centre crosses the triangle to is in side 0's volume; from a
        // point of the sphere beyond the plane (there is one when it straddles), in side 1's.
        for (int k = 0; k < 4; ++k) {
            const vec3 q = stsv::trianglePoint(v0, v1, v2, rng.barycentric());
            vec3 p;
            if (behind(rng, c, q, box, p)) {
                ++shadowPoints;
                EXPECT_TRUE(stsvPointInVolume(vol[0], p)) << "trial " << trial << " p=" << str(p);
            }
            if (!straddles) continue;
            const vec3 toPlane = normalize(n) * float(dot(dvec3(normalize(n)), dvec3(v0) - dvec3(c)));
            const vec3 beyond = c + toPlane + normalize(toPlane) * 0.5f * float(sphere.w - d);
            if (behind(rng, beyond, q, box, p)) {
                EXPECT_TRUE(stsvPointInVolume(vol[1], p)) << "trial " << trial << " p=" << str(p);
            }
        }
        if (!has1) {
            for (int k = 0; k < 20; ++k) EXPECT_FALSE(stsvPointInVolume(vol[1], rng.inBox(box.lo, box.hi)));
        }
    }
    EXPECT_GT(straddling, 150);
    EXPECT_GT(oneSided, 1000);
    EXPECT_GT(shadowPoints, 4000);
}

TEST(ExtrusionSides, TheLightPlanesOfALightHoldEveryShadowSegmentOfItsSamples) {
    Rng rng(99);
    Bounds box;
    box.extend(vec3(-8.0f));
    box.extend(vec3(8.0f));
    int checked = 0;
    for (int trial = 0; trial < 600; ++trial) {
        Light light{};
        light.type = trial % 2 == 0 ? LIGHT_RECTANGLE : LIGHT_DISK;
        light.position = vec3(rng.uniformf(-2.0f, 2.0f), rng.uniformf(3.0f, 6.0f), rng.uniformf(-2.0f, 2.0f));
        light.normal = vec3(0.0f, -1.0f, 0.0f);
        light.axisU = vec3(rng.uniformf(0.05f, 1.0f), 0.0f, 0.0f);
        light.axisV = vec3(0.0f, 0.0f, rng.uniformf(0.05f, 1.0f));
        light.radius =
            light.type == LIGHT_DISK ? rng.uniformf(0.05f, 1.0f) : length(light.axisU + light.axisV);
        const vec3 v0 = rng.inCube(2.0f) * vec3(1.0f, 0.3f, 1.0f),
                   v1 = rng.inCube(2.0f) * vec3(1.0f, 0.3f, 1.0f),
                   v2 = rng.inCube(2.0f) * vec3(1.0f, 0.3f, 1.0f);
        if (length(cross(v1 - v0, v2 - v0)) < 0.1f) continue;
        const StsvLightPlanes lp = stsvTriangleLightPlanes(v0, v1, v2, light, 100.0f, box.lo, box.hi);
        ASSERT_GT(lp.count, 0u) << "trial " << trial;
        for (int k = 0; k < 20; ++k) {
            vec3 sample;
            if (light.type == LIGHT_RECTANGLE) {
                sample = light.position + rng.uniformf(-1.0f, 1.0f) * light.axisU +
                         rng.uniformf(-1.0f, 1.0f) * light.axisV;
            } else {
                const vec3 d = rng.inBall() * light.radius;
                sample = light.position + vec3(d.x, 0.0f, d.z);
            }
            vec3 p;
            if (!behind(rng, sample, stsv::trianglePoint(v0, v1, v2, rng.barycentric()), box, p)) continue;
            ++checked;
            EXPECT_TRUE(stsvPointInLightPlanes(lp, p)) << "trial " << trial << " p=" << str(p);
        }
    }
    EXPECT_GT(checked, 5000);
    // A sphere or a directional light turns its frame towards each receiver: no planes hold for
    // every receiver, so there are none.
    for (uint type : {LIGHT_SPHERE, LIGHT_DIRECTIONAL}) {
        Light light{};
        light.type = type;
        light.position = vec3(0.0f, 4.0f, 0.0f);
        light.normal = vec3(0.0f, 1.0f, 0.0f);
        light.radius = 0.5f;
        light.angularRadius = 0.01f;
        EXPECT_EQ(stsvTriangleLightPlanes(vec3(0.0f), vec3(1.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, 1.0f), light,
                                          100.0f, box.lo, box.hi)
                      .count,
                  0u)
            << "light type " << type;
    }
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

TEST(ExtrusionCulling, ABoxTheVolumeMissesHoldsNoPointTheTestAccepts) {
    // Random boxes, from 1e-6 of the scene box to half of it, some with a corner pulled onto one of
    // the volume's planes (where the per-point test sits at its rounding): whenever
    // stsvVolumeMissesBox culls a box, none of its corners, face centres or random points passes
    // stsvPointInVolume.
    Rng rng(2024);
    long culled = 0, kept = 0, onPlane = 0, pointsChecked = 0;
    for (int family = 0; family < FamilyCount; ++family) {
        for (int config = 0; config < 300; ++config) {
            const Config c = makeConfig(rng, family);
            for (const StsvVolume& v : volumesOf(c)) {
                if (v.flags & STSV_VOLUME_EMPTY) continue;
                const float diag = length(c.bounds.extent());
                for (int b = 0; b < 20; ++b) {
                    vec3 centre = rng.inBox(c.bounds.lo, c.bounds.hi);
                    const vec3 half = vec3(rng.logUniform(1e-6f, 0.5f), rng.logUniform(1e-6f, 0.5f),
                                           rng.logUniform(1e-6f, 0.5f)) *
                                      diag;
                    if (b % 2 == 1 && v.planeCount > 0) {
                        // Put the box's far corner (along the plane normal) on plane k.
                        const vec4 plane = v.planes[uint(b / 2) % v.planeCount];
                        const vec3 n = vec3(plane);
                        const vec3 corner = centre + sign(n) * half;
                        centre -= (dot(n, corner) + plane.w) * n;
                        ++onPlane;
                    }
                    const vec3 lo = centre - half, hi = centre + half;
                    if (!stsvVolumeMissesBox(v, lo, hi)) {
                        ++kept;
                        continue;
                    }
                    ++culled;
                    std::vector<vec3> points;
                    for (uint k = 0; k < 8; ++k) points.push_back(stsvBoxCorner(lo, hi, k));
                    for (int axis = 0; axis < 3; ++axis) {
                        vec3 a = centre, b2 = centre;
                        a[axis] = lo[axis];
                        b2[axis] = hi[axis];
                        points.push_back(a);
                        points.push_back(b2);
                    }
                    for (int k = 0; k < 20; ++k) points.push_back(rng.inBox(lo, hi));
                    for (const vec3& p : points) {
                        ++pointsChecked;
                        if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z)
                            continue; // rounding put the sample outside the box
                        ASSERT_FALSE(stsvPointInVolume(v, p))
                            << c << " box " << str(lo) << ".." << str(hi) << " culled, but holds " << str(p);
                    }
                }
            }
        }
    }
    std::printf("boxes culled %ld, kept %ld (%ld with a corner on a plane), points checked %ld\n", culled,
                kept, onPlane, pointsChecked);
    EXPECT_GT(culled, 10000);
    EXPECT_GT(kept, 10000);
}

TEST(ExtrusionCulling, ABoxAroundAPointInsideIsKept) {
    Rng rng(7);
    long checked = 0;
    for (int family = 0; family < FamilyCount; ++family) {
        for (int config = 0; config < 300; ++config) {
            const Config c = makeConfig(rng, family);
            for (const StsvVolume& v : volumesOf(c)) {
                if (v.flags & STSV_VOLUME_EMPTY) continue;
                for (int k = 0; k < 50; ++k) {
                    const vec3 p = rng.inBox(c.bounds.lo, c.bounds.hi);
                    if (!stsvPointInVolume(v, p)) continue;
                    ++checked;
                    ASSERT_FALSE(stsvVolumeMissesBox(v, p, p)) << c << " point " << str(p);
                    const vec3 pad(1e-3f * length(c.bounds.extent()));
                    ASSERT_FALSE(stsvVolumeMissesBox(v, p - pad, p + pad)) << c << " point " << str(p);
                }
            }
        }
    }
    EXPECT_GT(checked, 1000);
}

} // namespace
} // namespace stsv
