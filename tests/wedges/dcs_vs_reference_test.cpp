// dcs and dcs+stsv (CPU mirror) against Embree shadow rays at equal light samples, on closed
// meshes (sphere, torus, torus knot, a loaded 10k+ triangle OBJ) with and without perforated
// triangles. The bits may differ only at a boundary, and every differing bit is checked to be at
// one: the sample's segment, or the light centre's segment (the count every sample of the pixel
// starts from), passes within round-off of a triangle edge, or a triangle lies within the
// segments' start gap of the visible point. The differing bits are printed with their class.
#include "core/progress.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"
#include "render/cpu/cpu_wedges.h"
#include "sampling/light_bounds.h"
#include "sampling/light_sampling.h"
#include "scene/geometry.h"
#include "scene/load.h"
#include "scene/procedural.h"
#include "tests/support/boundary.h"
#include "volumes/stsv_dh.h"
#include "wedge_test_util.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

namespace stsv {
namespace {

/// A chain-link quad (perforated, double-sided) between the mesh and its light.
void addPerforatedQuad(Scene& scene) {
    const Bounds b = scene.bounds();
    const vec3 c = 0.5f * (vec3(scene.lights[0].position) + b.center());
    Material fence;
    fence.name = "chainlink";
    fence.alphaTexture = addTexture(scene, makeChainLinkTexture(64));
    fence.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, fence);
    const float size = 0.6f * length(vec3(b.extent()) * vec3(1.0f, 0.0f, 1.0f)) * 0.25f;
    mat4 placement = glm::translate(mat4(1.0f), c) * glm::rotate(mat4(1.0f), 1.2f, vec3(1.0f, 0.0f, 0.2f));
    appendMesh(scene, makeQuad(vec2(size), vec2(3.0f)), placement, "fence", int(m));
    scene.validate();
}

struct Agreement {
    std::size_t compared = 0;
    std::size_t differing = 0;
    std::size_t occluded = 0;
    // Where the differing bits lie (a bit may be in more than one class).
    std::size_t sampleGrazes = 0;  ///< the sample's segment within round-off of an edge
    std::size_t centreGrazes = 0;  ///< the centre's segment within round-off of an edge
    std::size_t inStartGap = 0;    ///< a triangle within the start gap of the visible point
    std::size_t texelBoundary = 0; ///< the sample's segment crosses a perforated triangle at a texel boundary
    std::size_t unexplained = 0;   ///< none of these: a fault
    double worstDistance = 0.0;    ///< largest relative edge distance that explained a bit
    double fraction() const { return compared ? 1.0 - double(differing) / double(compared) : 0.0; }
};

using dvec3 = glm::dvec3;

/// Distance between the segments [a0, a1] and [b0, b1] (closest points clamped to both; Ericson,
/// Real-Time Collision Detection, 5.1.9), in double precision.
double segmentDistance(dvec3 a0, dvec3 a1, dvec3 b0, dvec3 b1) {
    const dvec3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
    const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    double sParam = 0.0, tParam = 0.0;
    if (a <= 1e-30 && e <= 1e-30) return glm::length(r);
    if (a <= 1e-30) {
        tParam = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = glm::dot(d1, r);
        if (e <= 1e-30) {
            sParam = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = glm::dot(d1, d2), denom = a * e - b * b;
            sParam = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            tParam = (b * sParam + f) / e;
            if (tParam < 0.0) {
                tParam = 0.0;
                sParam = std::clamp(-c / a, 0.0, 1.0);
            } else if (tParam > 1.0) {
                tParam = 1.0;
                sParam = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    return glm::length((a0 + d1 * sParam) - (b0 + d2 * tParam));
}

/// Smallest distance from the segment p + t(q − p), t in [tMin, 1], to an edge of any triangle
/// but `ignore`, relative to |q − p|.
double nearestEdge(const Scene& scene, vec3 p, vec3 q, float tMin, std::uint32_t ignore) {
    const dvec3 a0 = dvec3(p) + double(tMin) * (dvec3(q) - dvec3(p)), a1 = dvec3(q);
    double best = std::numeric_limits<double>::infinity();
    for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
        if (t == ignore) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 v[3] = {dvec3(scene.positions[idx.x]), dvec3(scene.positions[idx.y]),
                            dvec3(scene.positions[idx.z])};
        for (int e = 0; e < 3; ++e) best = std::min(best, segmentDistance(a0, a1, v[e], v[(e + 1) % 3]));
    }
    return best / glm::length(dvec3(q) - dvec3(p));
}

/// True iff a triangle but `ignore` has a point within `gap` of p (|p − x| over the triangle,
/// bounded below by the distance to its plane and its edges: the exact point-triangle distance).
bool triangleWithin(const Scene& scene, vec3 p, double gap, std::uint32_t ignore) {
    const dvec3 x(p);
    for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
        if (t == ignore) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 a(scene.positions[idx.x]), b(scene.positions[idx.y]), c(scene.positions[idx.z]);
        double d =
            std::min({segmentDistance(x, x, a, b), segmentDistance(x, x, b, c), segmentDistance(x, x, c, a)});
        const dvec3 n = glm::cross(b - a, c - a);
        const double n2 = glm::dot(n, n);
        if (n2 > 0.0) {
            // The foot of the perpendicular, if inside the triangle, is the closest point.
            const dvec3 foot = x - n * (glm::dot(x - a, n) / n2);
            const double u = glm::dot(glm::cross(b - a, foot - a), n),
                         v = glm::dot(glm::cross(c - b, foot - b), n),
                         w = glm::dot(glm::cross(a - c, foot - c), n);
            if (u >= 0.0 && v >= 0.0 && w >= 0.0) d = std::min(d, glm::length(x - foot));
        }
        if (d <= gap) return true;
    }
    return false;
}

/// Where the segment p + t(q − p), t in [tMin, 1], crosses a perforated triangle (but `ignore`):
/// the smallest distance, in texels, from the crossing's texel coordinate to a texel boundary
/// (infinity when it crosses none). The texel rule decides such a crossing by round-off.
double nearestTexelBoundary(const Scene& scene, vec3 p, vec3 q, float tMin, std::uint32_t ignore) {
    double best = std::numeric_limits<double>::infinity();
    const dvec3 o(p), d = dvec3(q) - dvec3(p);
    for (std::uint32_t t = 0; t < scene.triangles.size(); ++t) {
        if (t == ignore || !scene.perforated(t)) continue;
        const uvec3 idx = scene.triangles[t];
        const dvec3 a(scene.positions[idx.x]), b(scene.positions[idx.y]), c(scene.positions[idx.z]);
        // Möller–Trumbore in double precision.
        const dvec3 e1 = b - a, e2 = c - a, h = glm::cross(d, e2);
        const double det = glm::dot(e1, h);
        if (std::abs(det) < 1e-300) continue;
        const dvec3 sv = o - a;
        const double u = glm::dot(sv, h) / det;
        const dvec3 qv = glm::cross(sv, e1);
        const double v = glm::dot(d, qv) / det, tt = glm::dot(e2, qv) / det;
        if (u < -1e-6 || v < -1e-6 || u + v > 1.0 + 1e-6 || tt < double(tMin) || tt > 1.0) continue;
        const glm::dvec2 uv0(scene.texcoords[idx.x]), uv1(scene.texcoords[idx.y]),
            uv2(scene.texcoords[idx.z]);
        const glm::dvec2 uv = uv0 + u * (uv1 - uv0) + v * (uv2 - uv0);
        const Texture& texture = scene.textures[std::size_t(scene.materialOf(t).alphaTexture)];
        const glm::dvec2 texel = uv * glm::dvec2(texture.width, texture.height);
        best = std::min(
            {best, std::abs(texel.x - std::round(texel.x)), std::abs(texel.y - std::round(texel.y))});
    }
    return best;
}

/// Texel-coordinate distance below which float round-off decides a crossing's texel: texel
/// coordinates reach a few hundred here (float ulp about 3e-5 at 256), after a transform and a
/// barycentric interpolation that each lose a few bits.
constexpr double kTexelGrazing = 1e-3;

/// Relative distance from a segment to an edge below which float round-off can decide the
/// segment's side: the segments are tested in float (ulp 6e-8 relative) after transforms and
/// plane equations that lose a few bits each; 1e-4 leaves a wide margin over the worst measured
/// (printed below) while a fault, which moves whole penumbrae, is far above it.
constexpr double kGrazing = 1e-4;

Agreement compareWithReference(const Scene& scene, int size, int samples, bool withStsv,
                               WedgeCpuStats* statsOut = nullptr) {
    Progress::setEnabled(false);
    const EmbreeScene embree(scene);
    const GBuffer g = embree.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 3);
    const float farDistance = farDistanceFor(scene.bounds());
    const OpaqueOccluders occ(scene);
    Agreement a;
    for (const Light& light : scene.lights) {
        LightSampleBuffer dcs(size, size, samples, BufferKind::Counters);
        const WedgeCpuStats stats = withStsv ? dcsStsvCpuSamples(occ, g, light, plan, farDistance, dcs)
                                             : dcsCpuSamples(occ, g, light, plan, farDistance, dcs);
        if (statsOut) *statsOut = stats;
        LightSampleBuffer ref(size, size, samples, BufferKind::Bitmask);
        traceReferenceSamples(embree, g, light, plan, farDistance, ref);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                if (!g.covered(g.index(x, y))) continue;
                const std::size_t i = g.index(x, y);
                const vec3 p = g.position[i];
                const LightFrame frame = lightFrame(light, p, farDistance);
                const float tMin = shadowTMin(p, frame.center, length(scene.bounds().extent()));
                double centreDistance = -1.0; // computed once per pixel, when a bit differs
                for (int k = 0; k < samples; ++k) {
                    ++a.compared;
                    a.occluded += ref.occluded(x, y, k) ? 1 : 0;
                    if (ref.occluded(x, y, k) == dcs.occluded(x, y, k)) continue;
                    ++a.differing;
                    const vec3 s = lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
                    const double sampleDistance = nearestEdge(scene, p, s, tMin, g.triangle[i]);
                    if (centreDistance < 0.0)
                        centreDistance = nearestEdge(scene, p, frame.center, tMin, g.triangle[i]);
                    const bool grazes = sampleDistance < kGrazing, centre = centreDistance < kGrazing;
                    // The start gap: tMin·|s − p|, twice over for the round-off of the start point.
                    const bool gap =
                        triangleWithin(scene, p, 2.0 * double(tMin) * double(length(s - p)), g.triangle[i]);
                    const double texelDistance = nearestTexelBoundary(scene, p, s, tMin, g.triangle[i]);
                    const bool texel = texelDistance < kTexelGrazing;
                    a.texelBoundary += texel ? 1 : 0;
                    a.sampleGrazes += grazes ? 1 : 0;
                    a.centreGrazes += centre ? 1 : 0;
                    a.inStartGap += gap ? 1 : 0;
                    if (grazes) a.worstDistance = std::max(a.worstDistance, sampleDistance);
                    if (centre) a.worstDistance = std::max(a.worstDistance, centreDistance);
                    if (!grazes && !centre && !gap && !texel) {
                        ++a.unexplained;
                        std::printf(
                            "  unexplained: pixel (%d, %d) sample %d: reference %d, dcs %d; sample's segment "
                            "%.3g, centre's %.3g of its length from an edge; %.3g texels from a texel "
                            "boundary\n",
                            x, y, k, int(ref.occluded(x, y, k)), int(dcs.occluded(x, y, k)), sampleDistance,
                            centreDistance, texelDistance);
                    }
                }
            }
    }
    return a;
}

/// `measured`: the differing bits when the test was written (test::allowedDifferingBits).
void expectAgreement(const char* name, const Scene& scene, bool withStsv, std::size_t measured, int size = 80,
                     int samples = 32) {
    WedgeCpuStats stats;
    const Agreement a = compareWithReference(scene, size, samples, withStsv, &stats);
    std::printf(
        "%-28s %s: %zu of %zu samples differ (%.4f %% identical), %zu occluded; %zu edges, %zu potential "
        "silhouettes, %zu negative counts\n"
        "  differing bits: %zu with the sample's segment grazing an edge, %zu with the centre's, %zu with a "
        "triangle in the start gap, %zu at a texel boundary, %zu unexplained; worst grazing distance %.3g\n",
        name, withStsv ? "dcs+stsv" : "dcs     ", a.differing, a.compared, 100.0 * a.fraction(), a.occluded,
        stats.edges, stats.potentialSilhouettes, stats.negativeCounts, a.sampleGrazes, a.centreGrazes,
        a.inStartGap, a.texelBoundary, a.unexplained, a.worstDistance);
    // Every differing bit is at a boundary; and few of them (a guard against a fault that moves
    // many bits onto boundaries, as a broken tie rule would).
    EXPECT_EQ(a.unexplained, 0u) << name;
    EXPECT_LE(a.differing, test::allowedDifferingBits(measured)) << name << ": " << measured << " measured";
    // Not vacuous: a real shadow is in view.
    EXPECT_GT(a.occluded, a.compared / 50) << name;
}

Scene meshScene(const MeshData& mesh, const char* name, bool perforated) {
    Scene scene = makeMeshScene(mesh, name);
    if (perforated) addPerforatedQuad(scene);
    return scene;
}

// The potential silhouettes, their cluster tree and their carriers' bounds are made by the first
// frame of a light and reused by later ones (OpaqueOccluders::silhouettes): a second frame gives
// the same counters, another light its own (those a fresh OpaqueOccluders gives it), and the
// first light again its first counters.
TEST(DcsVsReference, LaterFramesReuseEachLightsSilhouettes) {
    Progress::setEnabled(false);
    Scene scene = meshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "knot", false);
    Light moved = scene.lights[0];
    moved.position += vec3(1.5f, 0.0f, -1.0f);
    const EmbreeScene embree(scene);
    const int size = 96, samples = 32;
    const GBuffer g = embree.traceGBuffer(size, size);
    const SamplePlan plan = makeSamplePlan(PatternKind::Poisson, samples, 3);
    const float farDistance = farDistanceFor(scene.bounds());
    const auto frame = [&](const OpaqueOccluders& occ, const Light& light, WedgeCpuStats& stats) {
        LightSampleBuffer counters(size, size, samples, BufferKind::Counters);
        stats = dcsCpuSamples(occ, g, light, plan, farDistance, counters);
        std::vector<int> out;
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x)
                for (int k = 0; k < samples; ++k) out.push_back(int(counters.count(x, y, k)));
        return out;
    };
    const OpaqueOccluders occ(scene);
    WedgeCpuStats first, second, other, fresh, again;
    const std::vector<int> a = frame(occ, scene.lights[0], first);
    const std::vector<int> b = frame(occ, scene.lights[0], second);
    const std::vector<int> c = frame(occ, moved, other);
    const std::vector<int> d = frame(OpaqueOccluders(scene), moved, fresh);
    const std::vector<int> e = frame(occ, scene.lights[0], again);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a, e);
    EXPECT_EQ(c, d);
    EXPECT_NE(a, c) << "the moved light casts other shadows";
    EXPECT_GT(std::count_if(a.begin(), a.end(), [](int v) { return v > 0; }), size * size);
    EXPECT_EQ(first.potentialSilhouettes, second.potentialSilhouettes);
    EXPECT_EQ(first.clusters, again.clusters);
    EXPECT_EQ(other.potentialSilhouettes, fresh.potentialSilhouettes);
    EXPECT_EQ(first.pixelEdgeVisits, second.pixelEdgeVisits);
    // The second frame builds no bound the first did not.
    EXPECT_EQ(first.volumes, second.volumes);
}

TEST(DcsVsReference, Sphere) {
    // Measured 18 of 162 016 (dcs) and 10 of 165 504 (dcs+stsv).
    for (bool perforated : {false, true})
        expectAgreement("sphere 32x16", meshScene(test::makeSphereMesh(32, 16), "sphere", perforated),
                        perforated, perforated ? 10 : 18);
}

TEST(DcsVsReference, Torus) {
    for (bool perforated : {false, true}) // measured 0 of 172 672 and 0 of 178 816
        expectAgreement("torus 48x16",
                        meshScene(test::makeTorusMesh(48, 16, 1.0f, 0.35f), "torus", perforated), perforated,
                        0);
}

TEST(DcsVsReference, TorusKnot) {
    for (bool perforated : {false, true}) // measured 3 of 169 376 and 3 of 174 848
        expectAgreement("torus knot 256x12",
                        meshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "knot", perforated), perforated,
                        3);
}

TEST(DcsVsReference, OtherLightShapes) {
    for (int shape = 0; shape < 3; ++shape) {
        Scene scene = meshScene(test::makeTorusMesh(40, 12, 1.0f, 0.35f), "torus", shape == 1);
        const Light rect = scene.lights[0];
        if (shape == 0) scene.lights[0] = makeDiskLight(rect.position, rect.normal, 0.6f, rect.radiance);
        if (shape == 1) scene.lights[0] = makeSphereLight(rect.position, 0.5f, rect.radiance);
        if (shape == 2) scene.lights[0] = makeDirectionalLight(-rect.normal, 0.1f, vec3(1.0f));
        const char* names[] = {"torus, disk light", "torus+fence, sphere light", "torus, directional"};
        // Measured 0, 0 and 16 differing bits of about 175 000.
        expectAgreement(names[shape], scene, shape == 1, shape == 2 ? 16 : 0);
    }
}

TEST(DcsVsReference, LoadedObjOver10kTriangles) {
    const MeshData knot = test::makeTorusKnotMesh(480, 12, 0.12f, 3, 4); // 11,520 triangles
    const auto dir = std::filesystem::temp_directory_path() / "stsv_wedges_obj";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "knot.obj").string();
    {
        std::ofstream out(path);
        for (const vec3& p : knot.positions) out << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
        for (const uvec3& t : knot.triangles)
            out << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
    }
    Scene scene = loadScene(path);
    std::filesystem::remove_all(dir);
    ASSERT_GE(scene.triangleCount(), 10000u);
    expectAgreement("loaded knot.obj (11.5k)", scene, false, 6); // measured 6 of 169 952
    addPerforatedQuad(scene);
    expectAgreement("loaded knot.obj + fence", scene, true, 6); // measured 6 of 175 232
}

} // namespace
} // namespace stsv
