// The Vulkan DCS and PW passes against the CPU mirror (wedges/cpu/cpu_wedges.cpp) fed the
// GPU's own G-buffer, and DCS against Embree: fence and foliage with their perforated triangles
// (dcs+stsv, pw+stsv), closed meshes, open and non-manifold soups, every light shape.
// Validation on (GpuRenderTest fails on any message).
#include "core/error.h"
#include "gpu_render_helpers.h"
#include "scene/geometry.h"
#include "scene/load.h"
#include "scene/mesh_fence.h"
#include "tests/support/wedge_composition.h"
#include "tests/wedges/wedge_test_util.h"
#include "wedges/cpu/cpu_wedges.h"
#include "wedges/vulkan/gpu_wedge_clusters.h"

#include "wedges/layer_bvh_dh.h"

#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>
#include <utility>

namespace stsv {
namespace {

using test::expectMatchesEmbree;
using test::gpuOptions;
using test::planOf;

/// The frame's ray_edges knob, as the mirror takes it.
float rayEdges(const RenderOptions& o) {
    return float(methodKnob(o, "ray_edges"));
}

class GpuWedges : public test::GpuRenderTest {
  protected:
    /// The mirror's counters on the GPU's G-buffer for every light: counts identical on every
    /// (pixel, sample) pair when `why` is empty, else on at least `minAgreement` of them, the
    /// differing pairs printed with the reason `why`. Returns the agreement.
    double expectDcsMatchesMirror(const Scene& scene, const Frame& frame, const RenderOptions& o,
                                  double minAgreement, const std::string& what, const std::string& why = {}) {
        const WedgeOccluders occ(scene);
        const float far = farDistanceFor(scene.bounds());
        double worst = 1.0;
        for (std::size_t l = 0; l < scene.lights.size(); ++l) {
            LightSampleBuffer mirror(o.width, o.height, o.samples, BufferKind::Counters);
            const WedgeCpuStats mirrorStats =
                o.method == Method::DcsStsv
                    ? dcsStsvCpuSamples(occ, frame.gbuffer, scene.lights[l], planOf(o), far, mirror, nullptr,
                                        rayEdges(o))
                    : dcsCpuSamples(occ, frame.gbuffer, scene.lights[l], planOf(o), far, mirror, rayEdges(o));
            // Both count the (pixel, edge) pairs that pass the bound and silhouette tests of
            // wedges/wedge_fragment_dh.h on the same points: the GPU per fragment, the mirror
            // per loop step (a tie at a bound's plane may tip one pair).
            const nlohmann::json& wedges = frame.stats["wedges"][l];
            const auto silhouettes = wedges["silhouette_fragments"].get<std::size_t>();
            std::cout << what << " light " << l << ": " << silhouettes << " silhouette fragments, mirror "
                      << mirrorStats.pixelEdgeVisits << "\n";
            if (why.empty())
                EXPECT_EQ(silhouettes, mirrorStats.pixelEdgeVisits) << what;
            else
                EXPECT_NEAR(double(silhouettes), double(mirrorStats.pixelEdgeVisits),
                            1e-3 * double(mirrorStats.pixelEdgeVisits))
                    << what;
            EXPECT_LE(silhouettes, wedges["fragments"].get<std::size_t>()) << what;
            EXPECT_EQ(wedges["samples_tested"].get<std::size_t>(), silhouettes * std::size_t(o.samples))
                << what;
            // The layer count at the light centre: a node visit tests at most two leaves' triangles.
            const nlohmann::json& center = frame.stats["wedges"][l]["center"];
            EXPECT_GT(center["nodes"].get<std::size_t>(), 0u) << what;
            EXPECT_GT(center["triangle_tests"].get<std::size_t>(), 0u) << what;
            EXPECT_LE(center["triangle_tests"].get<std::size_t>(),
                      2 * LAYER_BVH_LEAF_MAX * center["node_visits"].get<std::size_t>())
                << what;
            const LightSampleDiff diff = compareLightSamples(frame.lightSamples[l], mirror, 8, true);
            const double agreement = 1.0 - double(diff.differingSamples) / double(diff.comparedSamples);
            const std::string differences =
                test::describeDifferences(frame.lightSamples[l], mirror, frame.gbuffer, true);
            std::cout << what << " light " << l << ": " << diff.comparedSamples << " pairs, "
                      << test::occludedCount(mirror) << " occluded (mirror), " << diff.differingSamples
                      << " differ, agreement " << agreement << "\n";
            EXPECT_GT(test::occludedCount(mirror), diff.comparedSamples / 200)
                << what << ": no shadow to test";
            if (why.empty()) {
                EXPECT_EQ(diff.differingSamples, 0u)
                    << what << " light " << l << ": differing pairs" << differences;
            } else {
                if (diff.differingSamples > 0) std::cout << "  not exact: " << why << differences << "\n";
                EXPECT_GE(agreement, minAgreement)
                    << what << " light " << l << ": differing pairs" << differences;
            }
            worst = std::min(worst, agreement);
        }
        return worst;
    }

    /// PW: the GPU's visibility image against the mirror's v_coef (one light): per pixel within
    /// 1e-4 — the wedge terms are float sums in another order (blending vs a loop), each term a
    /// fraction ≤ 1 computed by the same dh code — on every pixel (measured: the largest
    /// difference 1.2·10⁻⁷ on the sphere, 0 with STSV on fence and foliage).
    void expectPwMatchesMirror(const Scene& scene, const Frame& frame, const RenderOptions& o,
                               const std::string& what) {
        ASSERT_EQ(scene.lights.size(), 1u);
        const WedgeOccluders occ(scene);
        const float far = farDistanceFor(scene.bounds());
        ImageF mirror;
        LightSampleBuffer bits(o.width, o.height, o.samples,
                               o.buffer == BufferKind::Counters ? BufferKind::Counters : BufferKind::Bitmask);
        if (o.method == Method::PwStsv)
            pwStsvCpuVisibility(occ, frame.gbuffer, scene.lights[0], planOf(o), far, mirror, bits);
        else
            pwCpuVisibility(occ, frame.gbuffer, scene.lights[0], far, mirror);
        std::size_t covered = 0, close = 0, penumbra = 0;
        double worst = 0.0;
        for (int y = 0; y < o.height; ++y)
            for (int x = 0; x < o.width; ++x) {
                if (!frame.gbuffer.covered(frame.gbuffer.index(x, y))) continue;
                ++covered;
                const float m = mirror.at(x, y, 0), g = frame.visibility.at(x, y, 0);
                penumbra += (m > 0.01f && m < 0.99f) ? 1 : 0;
                const double d = std::abs(double(m) - double(g));
                worst = std::max(worst, d);
                close += d <= 1e-4 ? 1 : 0;
            }
        std::cout << what << ": " << covered << " pixels, " << penumbra << " in penumbra (mirror), "
                  << covered - close << " differ by > 1e-4 (largest " << worst << ")\n";
        EXPECT_GT(penumbra, covered / 100) << what << ": no penumbra to test";
        EXPECT_EQ(close, covered) << what << ": pixels more than 1e-4 from the mirror";
    }
};

RenderOptions wedgeOptions(Method method, int width, int height, int samples) {
    RenderOptions o = gpuOptions(width, height, samples);
    o.method = method;
    return o;
}

// fence's opaque occluder is its ground, two coplanar triangles: a visible point on one of them
// lies in the plane of the other. The DCS part is clamped at 0 on both backends before STSV adds
// its layers; the counts must agree exactly.
TEST_F(GpuWedges, DcsStsvOnFenceAndFoliageMatchesMirror) {
    for (const char* name : {"fence", "foliage"})
        for (int samples : {16, 64}) {
            const Scene scene = loadScene(name);
            const RenderOptions o = wedgeOptions(Method::DcsStsv, 160, 120, samples);
            const Frame frame = renderGpu(scene, o);
            expectDcsMatchesMirror(scene, frame, o, 1.0,
                                   std::string(name) + " dcs+stsv N=" + std::to_string(samples));
        }
}

// dcs+stsv adds the STSV layers of the perforated triangles to DCS's count clamped at 0 on its own
// (Algorithm 2), on the GPU as on the CPU: a DCS count pushed below 0 by a tie (the coplanar
// ground above) must not eat STSV's layers. fence's only opaque triangles are its ground, which
// shadows nothing the camera sees: DCS alone counts no layer, STSV over every triangle (the stsv
// method) counts exactly the perforated triangles' layers, and per sample dcs+stsv = dcs + stsv.
// (When the GPU clamped after STSV had added, 17 samples of fence at 96 × 72, N = 64, seed 7 fell
// short: the tie pixels' DCS part of −1 took one layer each.)
TEST_F(GpuWedges, DcsStsvIsDcsPlusTheStsvOfThePerforatedTriangles) {
    const Scene scene = loadScene("fence");
    for (const auto& [w, h] : {std::pair{96, 72}, std::pair{160, 120}})
        for (int samples : {16, 64}) {
            std::map<Method, Frame> frames;
            for (Method m : {Method::Dcs, Method::Stsv, Method::DcsStsv}) {
                RenderOptions o = wedgeOptions(m, w, h, samples);
                o.buffer = BufferKind::Counters;
                frames[m] = renderGpu(scene, o);
            }
            const std::string what =
                std::to_string(w) + "x" + std::to_string(h) + " N=" + std::to_string(samples);
            const LightSampleBuffer& both = frames[Method::DcsStsv].lightSamples[0];
            const LightSampleBuffer& dcs = frames[Method::Dcs].lightSamples[0];
            const LightSampleBuffer& stsv = frames[Method::Stsv].lightSamples[0];
            std::size_t differing = 0, dcsLayers = 0, stsvLayers = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    for (int k = 0; k < samples; ++k) {
                        dcsLayers += dcs.count(x, y, k);
                        stsvLayers += stsv.count(x, y, k);
                        differing += both.count(x, y, k) != dcs.count(x, y, k) + stsv.count(x, y, k);
                    }
            EXPECT_EQ(differing, 0u) << what;
            EXPECT_EQ(dcsLayers, 0u) << what << ": the ground shadows nothing";
            EXPECT_GT(stsvLayers, std::size_t(w * h * samples / 100)) << what << ": no fence shadow to test";
        }
}

// Meshes with creases (the torus knot) and soups with intersecting triangles have visible points
// that lie on, or within the segments' start gap of, another triangle: both backends count D(r)
// there with the same function (wedges/layer_bvh_dh.h layerCount), so the
// counts agree exactly.
TEST_F(GpuWedges, DcsOnClosedMeshesMatchesMirrorAndEmbree) {
    const struct {
        const char* name;
        MeshData mesh;
        std::size_t measuredDiffering;
    } meshes[] = {{"sphere", test::makeSphereMesh(32, 16), 38},
                  {"torus knot", test::makeTorusKnotMesh(256, 12, 0.12f), 27}};
    for (const auto& m : meshes) {
        const Scene scene = makeMeshScene(m.mesh, m.name);
        const RenderOptions o = wedgeOptions(Method::Dcs, 128, 96, 32);
        const Frame frame = renderGpu(scene, o);
        expectDcsMatchesMirror(scene, frame, o, 1.0, std::string(m.name) + " dcs");
        // Measured 38 of 306 592 (sphere) and 27 of 321 248 (knot): a tie on the segment to the
        // light centre moves a whole pixel's bits.
        expectMatchesEmbree(scene, frame, o, 0, m.measuredDiffering, std::string(m.name) + " dcs", true);
    }
}

// fence-mesh's wires are closed boxes 0.5 mm deep about 5 m from the light centre, as thin as
// the segments' start gap SHADOW_T_MIN·distance. On the box's far side from the light, D(r)
// counts the near face at a crossing just beyond the gap, about 0.1 mm from the visible point.
// The counts must equal the mirror's on every (pixel, sample) pair.
TEST_F(GpuWedges, DcsOnClosedBoxesAsThinAsTheStartGapMatchesMirror) {
    for (int repeat : {1, 2}) {
        FenceParams params;
        params.repeat = repeat;
        params.textureSize = 16;
        const Scene scene = makeFenceMeshScene(params);
        const RenderOptions o = wedgeOptions(Method::Dcs, 128, 96, 32);
        const Frame frame = renderGpu(scene, o);
        // The case this test is about: visible points on the wires' far side from the light
        // whose crossing of the near side lies within a factor two of the start gap.
        const TexelBoxOptions boxes;
        const GBuffer& g = frame.gbuffer;
        const vec3 r = scene.lights[0].position;
        std::size_t thin = 0;
        for (std::size_t i = 0; i < g.position.size(); ++i) {
            if (!g.covered(i) || g.triangle[i] < scene.meshes.back().firstTriangle) continue;
            const vec3 p = g.position[i];
            const vec3 toLight = r - p;
            const bool farSide = p.z * toLight.z < 0.0f; // the box spans z ∈ ±thickness/2
            const float crossing = boxes.thickness / std::abs(normalize(toLight).z);
            const float gap = SHADOW_T_MIN * length(toLight);
            thin += farSide && crossing > 0.5f * gap && crossing < 2.0f * gap ? 1 : 0;
        }
        EXPECT_GT(thin, 100u) << "repeat " << repeat << ": no visible point at the thin-box tie";
        const std::string what = "fence-mesh repeat " + std::to_string(repeat) + " dcs";
        expectDcsMatchesMirror(scene, frame, o, 1.0, what);
        expectMatchesEmbree(scene, frame, o, 0, 0, what, true); // measured 0 of 288 512, both repeats
    }
}

// fence-mesh with larger chain-link tiles: many wire edges a few millimetres long, whose
// wedges are slivers a fraction of a pixel wide on the ground behind the fence. The DCS counts
// must equal the mirror's on every (pixel, sample) pair, and no pixel of PW may tip (its hard
// shadow at the light centre is the same D(r)).
TEST_F(GpuWedges, DcsWithManyMillimetreEdgesMatchesMirror) {
    FenceParams params;
    params.repeat = 4;
    params.textureSize = 32;
    const Scene scene = makeFenceMeshScene(params);
    for (Method method : {Method::Dcs, Method::Pw}) {
        const RenderOptions o = wedgeOptions(method, 128, 96, 32);
        const Frame frame = renderGpu(scene, o);
        const std::string what = std::string("fence-mesh tiles 32 ") + (method == Method::Dcs ? "dcs" : "pw");
        if (method == Method::Dcs) {
            expectDcsMatchesMirror(scene, frame, o, 1.0, what);
            continue;
        }
        // PW shades the light centre's hard shadow [D(r) > 0] before its wedges: a pixel a
        // different D(r) tips differs by most of its visibility, where the wedges' float sums
        // differ by rounding.
        RenderOptions cpuOptions = o;
        cpuOptions.backend = Backend::Cpu;
        const Frame cpu = makeRenderer(scene, cpuOptions)->render();
        std::size_t tipped = 0;
        for (int y = 0; y < o.height; ++y)
            for (int x = 0; x < o.width; ++x) {
                const std::size_t i = frame.gbuffer.index(x, y);
                if (frame.gbuffer.triangle[i] != cpu.gbuffer.triangle[i]) continue; // another point
                tipped += std::abs(frame.visibility.at(x, y, 0) - cpu.visibility.at(x, y, 0)) > 0.5f ? 1 : 0;
            }
        EXPECT_EQ(tipped, 0u) << what;
    }
}

/// Random open strips and non-manifold fans (random winding) above the ground: edges with one
/// face and with 3–4 faces, inconsistent orientation.
MeshData makeOpenSoup(std::uint64_t seed, int pieces) {
    test::Rng rng(seed);
    MeshData mesh;
    Material opaque;
    opaque.name = "soup";
    opaque.doubleSided = true;
    mesh.materials.push_back(opaque);
    auto vertex = [&](vec3 p) {
        mesh.positions.push_back(p);
        mesh.texcoords.push_back(vec2(0.0f));
        return static_cast<std::uint32_t>(mesh.positions.size() - 1);
    };
    for (int i = 0; i < pieces; ++i) {
        const vec3 center = rng.inBox(vec3(-1.0f, 0.0f, -1.0f), vec3(1.0f, 1.0f, 1.0f));
        auto near = [&] { return vertex(center + 0.4f * rng.inBox(vec3(-1.0f), vec3(1.0f))); };
        std::uint32_t a = near(), b = near();
        const bool fan = i % 2 == 1;
        const int count = fan ? 3 + rng.index(2) : 1 + rng.index(3);
        for (int k = 0; k < count; ++k) {
            const std::uint32_t c = near();
            mesh.triangles.push_back(rng.index(2) ? uvec3(a, b, c) : uvec3(a, c, b));
            mesh.triangleMaterial.push_back(0);
            if (!fan) {
                a = b;
                b = c;
            }
        }
    }
    return mesh;
}

TEST_F(GpuWedges, DcsEveryLightShapeAndOpenNonManifoldSoupMatchMirror) {
    for (int shape = 0; shape < 4; ++shape) {
        Scene scene =
            makeMeshScene(shape % 2 ? makeOpenSoup(11, 16) : test::makeTorusMesh(40, 12, 1.0f, 0.35f),
                          shape % 2 ? "soup" : "torus");
        const Light rect = scene.lights[0];
        if (shape == 1) scene.lights[0] = makeDiskLight(rect.position, rect.normal, 0.6f, rect.radiance);
        if (shape == 2) scene.lights[0] = makeSphereLight(rect.position, 0.5f, rect.radiance);
        if (shape == 3) scene.lights[0] = makeDirectionalLight(-rect.normal, 0.1f, vec3(1.0f));
        const RenderOptions o = wedgeOptions(Method::Dcs, 128, 96, 32);
        const Frame frame = renderGpu(scene, o);
        const std::string what =
            std::string(shape % 2 ? "soup" : "torus") + " light shape " + std::to_string(shape);
        expectDcsMatchesMirror(scene, frame, o, 1.0, what);
        // Measured 0 of 327 648 (torus, shapes 0 and 2), 0 of 315 328 (soup, disk) and 6 of
        // 315 328 (soup, directional).
        expectMatchesEmbree(scene, frame, o, 0, shape == 3 ? 6 : 0, what, true);
    }
}

TEST_F(GpuWedges, DcsWithTwoLightsAndPerforatedQuadMatchesMirror) {
    Scene scene = loadScene("fence");
    const Light first = scene.lights[0];
    scene.lights.push_back(makeSphereLight(first.position + vec3(3.0f, 0.0f, 1.0f), 0.4f, first.radiance));
    const RenderOptions o = wedgeOptions(Method::DcsStsv, 120, 90, 32);
    const Frame frame = renderGpu(scene, o);
    ASSERT_EQ(frame.lightSamples.size(), 2u);
    expectDcsMatchesMirror(scene, frame, o, 1.0, "fence, two lights, dcs+stsv");
}

TEST_F(GpuWedges, PwMatchesMirrorOnConvexMeshAndFence) {
    {
        const Scene scene = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
        const RenderOptions o = wedgeOptions(Method::Pw, 128, 96, 32);
        expectPwMatchesMirror(scene, renderGpu(scene, o), o, "sphere pw");
    }
    for (const char* name : {"fence", "foliage"}) {
        const Scene scene = loadScene(name);
        const RenderOptions o = wedgeOptions(Method::PwStsv, 128, 96, 64);
        expectPwMatchesMirror(scene, renderGpu(scene, o), o, std::string(name) + " pw+stsv");
    }
}

TEST_F(GpuWedges, HullsAndPrismsGiveTheSameCountersCoverageAndSilhouettes) {
    // The wedge hulls (--extrusion hull) against the carriers' prisms (geometry shader): both enclose every
    // point a wedge fragment accepts, so DCS counters and PW coverage are identical and so are the
    // silhouette fragments; the hulls rasterise far fewer fragments. The torus knot under its
    // rectangle light (light planes) and a sphere mesh under a sphere light (none).
    Scene knot = makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot");
    Scene sphere = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
    sphere.lights[0] = makeSphereLight(sphere.lights[0].position, 0.3f, sphere.lights[0].radiance);
    const struct {
        const char* name;
        const Scene* scene;
        double maxFragmentRatio; ///< hull fragments / prism fragments, at most (measured 0.0095, 0.18)
    } cases[] = {{"knot", &knot, 0.02}, {"sphere light", &sphere, 0.3}};
    for (const auto& c : cases)
        for (Method method : {Method::Dcs, Method::Pw}) {
            const RenderOptions o = wedgeOptions(method, 96, 72, 32);
            const Frame hull = renderGpu(*c.scene, o, ExtrusionStage::Hull);
            const Frame prism = renderGpu(*c.scene, o, ExtrusionStage::Geometry);
            const std::string what = std::string(c.name) + " " + toString(method);
            EXPECT_EQ(hull.lightSamples[0].counters(), prism.lightSamples[0].counters()) << what;
            // PW sums float coverages by additive blending in primitive order, which the two
            // draws do not share: equal up to the rounding of a few dozen additions of terms ≤ 1.
            ASSERT_EQ(hull.visibility.pixels.size(), prism.visibility.pixels.size());
            for (std::size_t i = 0; i < hull.visibility.pixels.size(); ++i)
                ASSERT_NEAR(hull.visibility.pixels[i], prism.visibility.pixels[i], 1e-5f)
                    << what << " pixel " << i;
            const nlohmann::json& h = hull.stats["wedges"][0];
            const nlohmann::json& p = prism.stats["wedges"][0];
            EXPECT_EQ(h["silhouette_fragments"], p["silhouette_fragments"]) << what;
            EXPECT_GT(h["silhouette_fragments"].get<std::size_t>(), 0u) << what;
            std::cout << "[hull] " << what << ": fragments " << h["fragments"] << ", prism " << p["fragments"]
                      << "\n";
            EXPECT_LE(double(h["fragments"].get<std::size_t>()),
                      c.maxFragmentRatio * double(p["fragments"].get<std::size_t>()))
                << what;
            EXPECT_GT(h["hull_volumes"].get<std::size_t>(), 0u) << what;
        }
}

TEST_F(GpuWedges, TheClusterWalkListsThePairsTheWedgeDrawAccepts) {
    // DCS with the auto extrusion walks the light's cluster tree per 4 × 4 block (dcs_clusters.comp)
    // instead of drawing the wedge hulls: its culling is conservative and its per-pixel tests are
    // the wedge fragment's, so the counters and the silhouette pairs are the hull draw's. It lists
    // only those pairs (the draw lists every fragment whose edge is a silhouette seen from p),
    // identical in the next frame. A finer knot needs more pairs than the lists start with (64 a
    // block): they grow, and the frame is rendered again.
    Scene knot = makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot");
    Scene sphere = makeMeshScene(test::makeSphereMesh(32, 16), "sphere");
    sphere.lights[0] = makeSphereLight(sphere.lights[0].position, 0.3f, sphere.lights[0].radiance);
    for (const auto& [name, scene] :
         {std::pair<const char*, const Scene*>{"knot", &knot}, {"sphere light", &sphere}}) {
        const RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
        VulkanRenderer renderer(*scene, o, {&device()});
        const Frame walk = renderer.render();
        const Frame again = renderer.render();
        const Frame hull = renderGpu(*scene, o, ExtrusionStage::Hull);
        EXPECT_EQ(walk.lightSamples[0].counters(), hull.lightSamples[0].counters()) << name;
        EXPECT_EQ(again.lightSamples[0].counters(), walk.lightSamples[0].counters()) << name;
        const nlohmann::json& w = walk.stats["wedges"][0];
        const nlohmann::json& h = hull.stats["wedges"][0];
        std::cout << name << ": " << w.dump() << "\n";
        EXPECT_EQ(w["path"], "clusters") << name;
        EXPECT_EQ(h["path"], "volumes") << name;
        EXPECT_EQ(w["silhouette_fragments"], h["silhouette_fragments"]) << name;
        EXPECT_GT(w["silhouette_fragments"].get<std::size_t>(), 0u) << name;
        EXPECT_EQ(w["listed_fragments"], w["silhouette_fragments"]) << name;
        EXPECT_GE(w["fragments"].get<std::size_t>(), w["silhouette_fragments"].get<std::size_t>()) << name;
        EXPECT_GT(w["clusters_rejected"].get<std::size_t>(), 0u) << name;
        EXPECT_LT(w["clusters_rejected"].get<std::size_t>(), w["cluster_tests"].get<std::size_t>()) << name;
        EXPECT_EQ(again.stats["wedges"][0], w) << name;
        EXPECT_EQ(walk.stats["passes"].contains("light0/dcs_clusters"), true) << name;
        EXPECT_EQ(walk.stats["passes"].contains("light0/dcs_wedges"), false) << name;
    }
    // A finer knot's lists grow past their start (64 pairs a block: the 262 k-triangle knot's
    // candidates need about 200); the frame rendered again has the hull draw's counters.
    const Scene fine = makeMeshScene(test::makeTorusKnotMesh(8192, 16, 0.12f), "fine torus knot");
    const RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
    VulkanRenderer renderer(fine, o, {&device()});
    const Frame frame = renderer.render();
    EXPECT_GT(frame.stats["wedges"][0]["list_capacity"].get<std::uint64_t>(), std::uint64_t(24 * 18 * 64));
    EXPECT_EQ(frame.stats["wedges"][0]["parts"], 1);
    EXPECT_EQ(frame.lightSamples[0].counters(),
              renderGpu(fine, o, ExtrusionStage::Hull).lightSamples[0].counters());
    EXPECT_EQ(renderer.device().validationMessageCount(), 0u);
}

/// A tilted square of two opaque triangles: open edges, two of them silhouettes for any pixel.
MeshData squareMesh() {
    MeshData m;
    m.positions = {{-0.5f, 0.6f, -0.5f}, {0.5f, 0.7f, -0.5f}, {0.5f, 0.8f, 0.5f}, {-0.5f, 0.7f, 0.5f}};
    m.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 2, 1}, {0, 3, 2}};
    m.triangleMaterial = {0, 0};
    Material opaque;
    opaque.name = "square";
    m.materials = {opaque};
    return m;
}

TEST_F(GpuWedges, BlocksThatCastRaysCountAsTheReference) {
    // A block whose kept edges exceed ray_edges per sample counts its samples' segments through
    // the layer tree (dcsBlockCastsRays; dcs_rays.comp on Vulkan) instead of D(r) and the
    // crossings: the reference's count, with the reference's robust crossing test. ray_edges = 0:
    // every block with an edge casts rays; 1e9 (the default): only the pixels whose segments' gaps
    // meet a triangle (layerCountGaps) do. On a square above the ground, whose blocks keep at
    // most their nine edges, no gap is met and the two ways give the same counters. On the fine
    // knot, whose blocks keep about 1 100 edges each, two pixels on its tube's terminator meet
    // the start gap (there the crossings alone got 13 samples of one of them wrong); the rays
    // give Embree's bits exactly, and so do the crossings elsewhere. Each way is the mirror's bit
    // for bit, with the same pixels casting rays, on both backends.
    const Scene knot = makeMeshScene(test::makeTorusKnotMesh(4096, 16, 0.12f), "fine torus knot");
    const Scene square = makeMeshScene(squareMesh(), "square");
    struct Case {
        const char* name;
        const Scene* scene;
        std::size_t gapPixels;       ///< pixels whose gaps meet a triangle (measured)
        std::size_t leastBlockEdges; ///< edges the blocks keep in all: measured 1 120 (knot) and 6.9
        std::size_t mostBlockEdges;  ///< (square) a block, within a factor of 2 (square: the most)
    };
    const std::size_t blocks = (96u / 4u) * (72u / 4u);
    for (const Case& c : {Case{"knot", &knot, 2, 550 * blocks, 2250 * blocks},
                          Case{"square", &square, 0, 3 * blocks, 9 * blocks}}) {
        RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
        const EmbreeScene embree(*c.scene);
        LightSampleBuffer reference(o.width, o.height, o.samples, BufferKind::Bitmask);
        const float far = farDistanceFor(c.scene->bounds());
        const Frame crossings = renderGpu(*c.scene, o);
        traceReferenceSamples(embree, crossings.gbuffer, c.scene->lights[0], planOf(o), far, reference);
        for (double rayEdges : {1e9, 0.0}) {
            o.params["ray_edges"] = rayEdges;
            const Frame frame = renderGpu(*c.scene, o);
            const std::string what = std::string(c.name) + " ray_edges=" + std::to_string(rayEdges);
            expectDcsMatchesMirror(*c.scene, frame, o, 1.0, what);
            LightSampleBuffer mirror(o.width, o.height, o.samples, BufferKind::Counters);
            const WedgeCpuStats cpu =
                dcsCpuSamples(WedgeOccluders(*c.scene), frame.gbuffer, c.scene->lights[0], planOf(o), far,
                              mirror, float(rayEdges));
            const nlohmann::json& w = frame.stats["wedges"][0];
            EXPECT_EQ(w["ray_pixels"].get<std::size_t>(), cpu.rayPixels) << what;
            EXPECT_EQ(w["crossing_pixels"].get<std::size_t>(), cpu.crossingPixels) << what;
            std::cout << what << ": " << cpu.blockEdges << " block edges, " << cpu.rayPixels
                      << " ray pixels\n";
            EXPECT_GE(cpu.blockEdges, c.leastBlockEdges) << what;
            EXPECT_LE(cpu.blockEdges, c.mostBlockEdges) << what;
            const LightSampleBuffer& counts = frame.lightSamples[0];
            std::size_t differing = 0, waysDiffer = 0;
            for (int y = 0; y < o.height; ++y)
                for (int x = 0; x < o.width; ++x)
                    for (int k = 0; k < o.samples; ++k) {
                        const bool wrong = reference.occluded(x, y, k) != (counts.count(x, y, k) != 0);
                        differing += wrong ? 1 : 0;
                        const bool crossed = crossings.lightSamples[0].count(x, y, k) != 0;
                        if (crossed != (counts.count(x, y, k) != 0)) ++waysDiffer;
                    }
            // Either way the bits are Embree's, and the two ways give the same counters.
            EXPECT_EQ(differing, 0u) << what;
            EXPECT_EQ(waysDiffer, 0u) << what;
            EXPECT_EQ(counts.counters(), crossings.lightSamples[0].counters()) << what;
            if (rayEdges > 0.0) {
                EXPECT_EQ(cpu.rayPixels, c.gapPixels) << what;
                EXPECT_GT(cpu.pixelEdgeVisits, 0u) << what;
            } else {
                // Every covered pixel whose block kept an edge casts rays: most of the frame's.
                EXPECT_GT(cpu.rayPixels, cpu.crossingPixels) << what;
                EXPECT_EQ(cpu.pixelEdgeVisits, 0u) << what;
            }
        }
    }
    // The wedge draw's path (an explicit extrusion, no walk) casts the rays of the pixels that meet
    // a gap too, and counts no pair of theirs (wedge_samples.comp): the walk's counters.
    RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
    const Frame walked = renderGpu(knot, o);
    o.extrusion = ExtrusionStage::Hull;
    const Frame drawn = renderGpu(knot, o);
    EXPECT_EQ(drawn.stats["wedges"][0]["ray_pixels"].get<std::size_t>(), 2u);
    EXPECT_EQ(drawn.lightSamples[0].counters(), walked.lightSamples[0].counters());
}

TEST(DcsPixelStage, KeepsAnInvocationsLoopsWithinHalfOfLavapipesLimit) {
    // A kept (block, leaf) pair loops up to 1105 + 512·max(F, 1) times in dcs_clusters.comp's
    // pixel stage for edges of at most F faces; an invocation's pairs must stay within 32 768
    // iterations (half of lavapipe's 65 535), and an edge of more faces than one pair can take is
    // refused with the scene's name rather than drawn with samples lost.
    for (std::uint32_t faces = 0; faces <= 125; ++faces) {
        const std::uint32_t pairs = dcsKeptPairsPerInvocation(faces, "mesh.obj");
        EXPECT_GE(pairs, 1u) << faces;
        EXPECT_LE(pairs * (1105u + 512u * std::max(faces, 1u)), 32768u + (pairs == 1 ? 32768u : 0u)) << faces;
    }
    EXPECT_EQ(dcsKeptPairsPerInvocation(2, "mesh.obj"), 15u);
    try {
        dcsKeptPairsPerInvocation(126, "mesh.obj");
        ADD_FAILURE() << "an edge of 126 faces was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("mesh.obj"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("126"), std::string::npos) << e.what();
    }
}

/// The torus knot with a second, spherical light beside its own.
Scene twoLightKnot() {
    Scene knot = makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot");
    knot.lights.push_back(
        makeSphereLight(knot.lights[0].position + vec3(0.5f, 0.0f, 0.3f), 0.2f, knot.lights[0].radiance));
    return knot;
}

TEST_F(GpuWedges, AClusterWalkWhoseListsCannotHoldItTakesTheTilesInParts) {
    // Lists limited to 3 000 pairs, fewer than the torus knot's walk needs in one list (as
    // a storage buffer's range limits them on a large frame): the walk takes the tiles in parts,
    // each with the lists to itself, and the counters are those of the hull draw, with two lights.
    const Scene knot = twoLightKnot();
    const RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
    VulkanRendererConfig config{&device()};
    config.clusterListLimit = 3000;
    VulkanRenderer limited(knot, o, config);
    const Frame parts = limited.render();
    const Frame again = limited.render();
    const Frame hull = renderGpu(knot, o, ExtrusionStage::Hull);
    ASSERT_EQ(parts.lightSamples.size(), 2u);
    for (std::size_t l = 0; l < 2; ++l) {
        const nlohmann::json& w = parts.stats["wedges"][l];
        std::cout << "light " << l << ": " << w.dump() << "\n";
        EXPECT_EQ(parts.lightSamples[l].counters(), hull.lightSamples[l].counters()) << "light " << l;
        EXPECT_EQ(again.lightSamples[l].counters(), hull.lightSamples[l].counters()) << "light " << l;
        EXPECT_EQ(w["silhouette_fragments"], hull.stats["wedges"][l]["silhouette_fragments"])
            << "light " << l;
        EXPECT_GT(w["parts"].get<std::uint32_t>(), 1u) << "light " << l;
        EXPECT_LE(w["list_capacity"].get<std::uint64_t>(), 3000u) << "light " << l;
    }
    EXPECT_EQ(limited.device().validationMessageCount(), 0u);
}

TEST_F(GpuWedges, AWalkListingMoreThanTheSampleListHoldsSamplesItPartByPart) {
    // The sample list limited to 200 fragments, fewer than the knot's walk lists for the frame
    // (as 2²⁶ are fewer than the 75 M of fence-mesh at 256²): the walk takes the tiles in parts,
    // each part's fragments sampled before the next part lists its own, and the counters are the
    // hull draw's, with two lights, in this frame and the next.
    const Scene knot = twoLightKnot();
    const RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
    VulkanRendererConfig config{&device()};
    config.deferredLimit = 200;
    VulkanRenderer limited(knot, o, config);
    const Frame parts = limited.render();
    const Frame again = limited.render();
    const Frame whole = renderGpu(knot, o);
    const Frame hull = renderGpu(knot, o, ExtrusionStage::Hull);
    ASSERT_EQ(parts.lightSamples.size(), 2u);
    for (std::size_t l = 0; l < 2; ++l) {
        const nlohmann::json& w = parts.stats["wedges"][l];
        std::cout << "light " << l << ": " << w.dump() << "\n";
        EXPECT_GT(whole.stats["wedges"][l]["listed_fragments"].get<std::uint64_t>(), config.deferredLimit)
            << "light " << l;
        EXPECT_EQ(parts.lightSamples[l].counters(), hull.lightSamples[l].counters()) << "light " << l;
        EXPECT_EQ(again.lightSamples[l].counters(), hull.lightSamples[l].counters()) << "light " << l;
        EXPECT_GT(w["parts"].get<std::uint32_t>(), 1u) << "light " << l;
        // Every part's fragments, listed and sampled once.
        EXPECT_EQ(w["listed_fragments"], whole.stats["wedges"][l]["listed_fragments"]) << "light " << l;
        EXPECT_EQ(w["silhouette_fragments"], whole.stats["wedges"][l]["silhouette_fragments"])
            << "light " << l;
    }
    EXPECT_TRUE(parts.stats["passes"].contains("light1/dcs_wedge_samples"));
    EXPECT_EQ(limited.device().validationMessageCount(), 0u);
    // A list of one pair: one 4 × 4 block lists more, and no part is smaller than a block.
    VulkanRendererConfig single{&device()};
    single.deferredLimit = 1;
    try {
        VulkanRenderer(knot, o, single).render();
        ADD_FAILURE() << "a walk listing more than one pair a block rendered into a list of one";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("4x4 block"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("sample list"), std::string::npos) << e.what();
    }
}

TEST_F(GpuWedges, AShortSilhouetteListGrowsAndTheFrameIsRenderedAgain) {
    // A list with room for 50 fragments: the DCS wedge draw lists far more, drops those past the
    // end, and the renderer grows the list and renders the frame again; the counters and counts
    // are those of a renderer whose list had room from the start, in this frame and the next.
    constexpr std::uint64_t CAPACITY = 50;
    const Scene scene = makeMeshScene(test::makeTorusKnotMesh(256, 12, 0.12f), "torus knot");
    // The wedge hulls drawn (the cluster pass, auto's DCS path, lists nothing).
    RenderOptions o = wedgeOptions(Method::Dcs, 96, 72, 32);
    o.extrusion = ExtrusionStage::Hull;
    VulkanRenderer small(scene, o, {&device(), CAPACITY});
    const Frame first = small.render();
    const Frame second = small.render();
    const Frame roomy = renderGpu(scene, o);
    EXPECT_EQ(first.lightSamples[0].counters(), roomy.lightSamples[0].counters());
    EXPECT_EQ(second.lightSamples[0].counters(), roomy.lightSamples[0].counters());
    const nlohmann::json& w = first.stats["wedges"][0];
    EXPECT_EQ(w, roomy.stats["wedges"][0]);
    EXPECT_EQ(second.stats["wedges"][0], roomy.stats["wedges"][0]);
    EXPECT_GT(w["listed_fragments"].get<std::uint64_t>(), 10 * CAPACITY);
    EXPECT_LE(w["silhouette_fragments"].get<std::uint64_t>(), w["listed_fragments"].get<std::uint64_t>());
    EXPECT_GT(w["silhouette_fragments"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(small.device().validationMessageCount(), 0u);
}

TEST_F(GpuWedges, MakeRendererChoosesVulkanForEveryWedgeMethod) {
    const Scene scene = makeMeshScene(test::makeSphereMesh(16, 8), "sphere");
    for (Method m : {Method::Pw, Method::Dcs, Method::PwStsv, Method::DcsStsv}) {
        RenderOptions o = wedgeOptions(m, 32, 24, 16);
        const Frame frame = renderGpu(scene, o);
        EXPECT_EQ(frame.stats["gpu"]["device"].get<std::string>(), device().info().name) << toString(m);
        ASSERT_TRUE(frame.stats.contains("wedges")) << toString(m);
        // The sphere's welded edges: 32 × 8 quads less the pole fans' collapsed edges.
        EXPECT_GT(frame.stats["wedges"][0]["edges"].get<std::size_t>(), 300u) << toString(m);
        EXPECT_GT(frame.stats["wedges"][0]["silhouette_fragments"].get<std::size_t>(), 0u) << toString(m);
        // The sphere has no perforated triangles: no STSV pass, and the buffer read back is the
        // cleared one (PW: every sample lit; its occlusion is in the visibility image).
        if (methodInfo(m).output == MethodOutput::Visibility) {
            EXPECT_EQ(test::occludedCount(frame.lightSamples[0]), 0u) << toString(m);
        }
    }
}

// Every Vulkan method, both buffer kinds, two lights, three frames from one renderer: the
// barriers of the later frames (after the previous frame's readback) are derived from a
// different history than the first frame's, so each frame runs under synchronisation validation
// (TearDown fails on any message) and must read back the same bits and colours. The per-pass
// timer names are the stats contract of the bench.
TEST_F(GpuWedges, RepeatedFramesOfEveryMethodAreIdenticalAndNamedPerPass) {
    Scene scene = loadScene("fence");
    const Light first = scene.lights[0];
    scene.lights.push_back(makeSphereLight(first.position + vec3(3.0f, 0.0f, 1.0f), 0.4f, first.radiance));
    for (const MethodInfo& method : methodTable()) {
        if (!method.implementedOn(Backend::Vulkan)) continue;
        for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters}) {
            RenderOptions o = wedgeOptions(method.id, 40, 30, 64);
            o.buffer = kind;
            // The sphere light's cube map at 256²: CSM's 32 summed-area planes per face at the
            // default 2048² would need 6.4 GB.
            // peel's grid at 64² keeps the cube's six faces small.
            // The transmittance functions at 256² too.
            if (method.shadowMap == ShadowMapMethod::Peel)
                o.params = parseMethodParams(method, {"peel_size=64"});
            else if (readsTransmittanceFunctions(method.shadowMap))
                o.params = parseMethodParams(method, {"avsm_size=256"});
            else if (method.shadowMap != ShadowMapMethod::None)
                o.params = parseMethodParams(method, {"sm_size=256"});
            const std::string what = method.name + " " + toString(kind);
            VulkanRenderer renderer(scene, o, {&device()});
            const Frame frame0 = renderer.render();
            for (int repeat = 1; repeat < 3; ++repeat) {
                const Frame frame = renderer.render();
                ASSERT_EQ(frame.lightSamples.size(), 2u) << what;
                for (std::size_t l = 0; l < 2; ++l) {
                    EXPECT_EQ(frame.lightSamples[l].words(), frame0.lightSamples[l].words())
                        << what << " light " << l;
                    EXPECT_EQ(frame.lightSamples[l].counters(), frame0.lightSamples[l].counters())
                        << what << " light " << l;
                }
                EXPECT_EQ(frame.color.pixels, frame0.color.pixels) << what << " frame " << repeat;
                EXPECT_EQ(frame.visibility.pixels, frame0.visibility.pixels) << what << " frame " << repeat;
                for (const char* key : {"stsv", "wedges", "shadow_maps"})
                    EXPECT_EQ(frame.stats.value(key, nlohmann::json()),
                              frame0.stats.value(key, nlohmann::json()))
                        << what << " " << key;
                // Not vacuous: the frame reports the counts of the families its method runs.
                EXPECT_TRUE(frame0.stats.contains("stsv") || frame0.stats.contains("wedges") ||
                            frame0.stats.contains("shadow_maps"))
                    << what;
            }
            const nlohmann::json& passes = frame0.stats["passes"];
            std::vector<std::string> expected = {"gbuffer", "copy", "readback"};
            for (const std::string light : {"light0/", "light1/"}) {
                expected.push_back(light + "resolve");
                if (method.stsv != StsvTriangles::None) {
                    // Auto extrusion: the volumes' records, the walk of the triangles' tree, the
                    // deferred samples, for bitmasks their merge (DCS writes counters whichever
                    // kind is asked for).
                    expected.push_back(light + "stsv_volumes");
                    expected.push_back(light + "stsv_clusters");
                    expected.push_back(light + "stsv_samples");
                    if (method.bufferKind(kind) == BufferKind::Bitmask)
                        expected.push_back(light + "stsv_merge");
                }
                if (method.shadowMap == ShadowMapMethod::Peel) {
                    // The depth grid's two draws, then the march.
                    expected.push_back(light + "depth_grid");
                    expected.push_back(light + "peel_march");
                } else if (readsTransmittanceFunctions(method.shadowMap)) {
                    // The fragment lists, the functions built from them, then the lookup or
                    // vpcss's search and filter.
                    expected.push_back(light + "avsm_fragments");
                    expected.push_back(light + "avsm_build");
                    expected.push_back(light + "shadow_filter");
                    if (method.shadowMap == ShadowMapMethod::Vpcss)
                        expected.push_back(light + "vpcss_blocker");
                } else if (method.shadowMap != ShadowMapMethod::None) {
                    expected.push_back(light + "shadow_map");
                    expected.push_back(light + "shadow_filter");
                    // PCSS, and the filtered maps with their default kernel from the blocker search.
                    if (method.shadowMap == ShadowMapMethod::Pcss ||
                        isFilteredRepresentation(method.shadowMap))
                        expected.push_back(light + "pcss_blocker");
                    if (isFilteredRepresentation(method.shadowMap))
                        expected.push_back(light + "filtered_map");
                }
                if (method.wedges == WedgeVariant::None) continue;
                const std::string technique = method.wedges == WedgeVariant::Pw ? "pw_" : "dcs_";
                expected.push_back(light + technique + "center");
                // Auto extrusion: DCS walks the cluster tree and lists the (pixel, edge) pairs for
                // their samples, and lists the blocks that cast rays (none at the default) for
                // theirs; PW builds the wedge hulls and draws them.
                if (method.wedges == WedgeVariant::Dcs) {
                    expected.push_back(light + "dcs_clusters");
                    expected.push_back(light + "dcs_wedge_samples");
                    expected.push_back(light + "dcs_rays");
                } else {
                    expected.push_back(light + "pw_wedge_hulls");
                    expected.push_back(light + "pw_wedges");
                }
                expected.push_back(light + "fold");
            }
            EXPECT_EQ(passes.size(), expected.size()) << what << ": " << passes.dump();
            for (const std::string& name : expected)
                EXPECT_TRUE(passes.contains(name)) << what << ": " << name;
            EXPECT_EQ(frame0.stats.contains("wedges"), method.wedges != WedgeVariant::None) << what;
        }
    }
}

} // namespace
} // namespace stsv
