// `avsm` and `vpcss` on Vulkan against the CPU backend (DESIGN §4.6): the transmittance functions
// built from per-texel fragment lists (avsm_fragments.frag, avsm_build.comp) against those built
// from Embree rays through the texel centres, texel by texel; their independence of the order the
// rasteriser lists fragments in; lists that grow when a frame needs more room; and the visibility
// of both methods.
#include "gpu_render_helpers.h"

#include "render/renderer.h"
#include "scene/load.h"
#include "shadowmaps/kept_maps.h"
#include "tests/support/translucent_scene.h"

#include <cstdio>

namespace stsv::test {
namespace {

struct FunctionDiff {
    std::size_t texels = 0, withNodes = 0, overflowed = 0, differing = 0;
    float maxRelative = 0.0f; ///< largest relative depth difference of matching nodes
};

/// Texels agree when they hold as many nodes, with the same optical depths, at depths within 1e-4
/// relative: the rasteriser interpolates the point at the texel centre (perspective-correct,
/// float), Embree intersects the same ray; both round in float, a few ulp of the depth apart.
FunctionDiff compareFunctions(const AvsmMap& gpu, const AvsmMap& cpu) {
    FunctionDiff d;
    const std::size_t nodes = cpu.maxNodes;
    for (std::size_t t = 0; t < cpu.counts.size(); ++t) {
        ++d.texels;
        d.withNodes += cpu.counts[t] > 0 ? 1 : 0;
        d.overflowed += cpu.overflowed[t];
        bool same = gpu.counts[t] == cpu.counts[t] && gpu.overflowed[t] == cpu.overflowed[t];
        for (std::size_t j = 0; same && j < cpu.counts[t]; ++j) {
            const float a = gpu.depth[t * nodes + j], b = cpu.depth[t * nodes + j];
            const float rel = std::abs(a - b) / std::max(b, 1e-6f);
            same = gpu.units[t * nodes + j] == cpu.units[t * nodes + j] && rel <= 1e-4f;
            if (same) d.maxRelative = std::max(d.maxRelative, rel);
        }
        d.differing += same ? 0 : 1;
    }
    return d;
}

// NOLINTNEXTLINE(bugprone-exception-escape): json's move cannot throw (its invariant check is unmarked)
struct Renders {
    Frame gpu, cpu;
};

class AvsmGpu : public GpuRenderTest {
  protected:
    /// `o` on both backends, with the functions kept.
    Renders renderBoth(const Scene& scene, RenderOptions o) {
        o.keepShadowMaps = true;
        Renders r;
        r.gpu = renderGpu(scene, o);
        RenderOptions cpu = o;
        cpu.backend = Backend::Cpu;
        r.cpu = makeRenderer(scene, cpu)->render();
        return r;
    }
};

RenderOptions avsmOptions(Method method, int size, const std::vector<std::string>& params) {
    RenderOptions o = gpuOptions(size, size, 16);
    o.method = method;
    o.params = parseMethodParams(methodInfo(method), params);
    return o;
}

/// The visibility of two frames: the mean |dv| over the covered pixels and those off by more
/// than 1/16.
struct VisibilityDiff {
    double mean = 0.0;
    std::size_t off = 0, covered = 0;
};
VisibilityDiff compareVisibility(const Frame& gpu, const Frame& cpu) {
    VisibilityDiff d;
    double sum = 0.0;
    for (std::size_t i = 0; i < gpu.visibility.pixels.size(); ++i) {
        if (!cpu.gbuffer.covered(i)) continue;
        ++d.covered;
        const double dv = std::abs(double(gpu.visibility.pixels[i]) - double(cpu.visibility.pixels[i]));
        sum += dv;
        d.off += dv > 1.0 / 16.0 ? 1 : 0;
    }
    d.mean = sum / double(std::max<std::size_t>(d.covered, 1));
    return d;
}

/// `veils` veils of α = 0.2, 0.22, … stacked over the ground between heights 0.4 and 1.9,
/// nearly as wide as it: veils + 1 surfaces a texel under them.
Scene veilStack(int veils) {
    Scene s = groundScene(0.2f);
    for (int i = 0; i < veils; ++i)
        addVeil(s, 0.4f + 1.5f * float(i) / float(veils), 1.9f, addBlend(s, 0.2f + 0.02f * float(i)));
    s.validate();
    return s;
}

TEST_F(AvsmGpu, VeilStackFunctionsAreTheCpuMirrorsAndTheListsGrow) {
    // 11 or 21 surfaces a texel: the first frame's lists (four fragments a texel) overflow, so the
    // frame grows them and runs again; 21 take avsm_build.comp two walks of its list (16 a walk).
    // With 16 nodes and 11 surfaces every surface is a node; otherwise the least area goes, on
    // both backends alike. Texel centres on the diagonal a veil's two triangles share count both
    // triangles on the CPU (the inclusive rule of its rays) and one on the GPU (the rasteriser's
    // top-left rule): those texels, a diagonal of each veil, may differ.
    for (const auto& [veils, nodes] : {std::pair{10, 16}, std::pair{20, 16}, std::pair{20, 4}}) {
        const Scene scene = veilStack(veils);
        const RenderOptions o =
            avsmOptions(Method::Avsm, 48, {"avsm_size=128", "avsm_nodes=" + std::to_string(nodes)});
        const Renders r = renderBoth(scene, o);
        ASSERT_EQ(keptMaps(r.gpu.keptMaps).avsmMaps.size(), 1u);
        ASSERT_EQ(keptMaps(r.cpu.keptMaps).avsmMaps.size(), 1u);
        const FunctionDiff d =
            compareFunctions(keptMaps(r.gpu.keptMaps).avsmMaps[0], keptMaps(r.cpu.keptMaps).avsmMaps[0]);
        const nlohmann::json& a = r.gpu.stats["shadow_maps"][0]["avsm"];
        std::printf(
            "%d veils, %d nodes: %zu of %zu texels differ, %zu with nodes, %zu overflowed; max relative "
            "depth difference %.2g; gpu stats %s\n",
            veils, nodes, d.differing, d.texels, d.withNodes, d.overflowed, double(d.maxRelative),
            a.dump().c_str());
        EXPECT_GT(d.withNodes, d.texels / 2) << "the veils cover the map";
        EXPECT_LE(d.differing, std::size_t(veils * 128)) << veils << " veils, " << nodes << " nodes";
        EXPECT_GT(a["fragments_listed"].get<std::size_t>(), 4 * d.texels) << "the first lists were too small";
        EXPECT_GE(a["fragment_capacity"].get<std::size_t>(), a["fragments_listed"].get<std::size_t>());
        EXPECT_EQ(a["nodes_max"].get<int>(), std::min(nodes, veils + 1)); // the ground and the veils
        EXPECT_EQ(a["nodes_max"], r.cpu.stats["shadow_maps"][0]["avsm"]["nodes_max"]);
        if (nodes < veils + 1) {
            EXPECT_GT(d.overflowed, d.texels / 4) << "fewer nodes than surfaces under every veil";
        } else {
            EXPECT_EQ(d.overflowed, 0u);
        }
        const VisibilityDiff v = compareVisibility(r.gpu, r.cpu);
        std::printf("visibility: mean |dv| %.5f, %zu of %zu pixels off by more than 1/16\n", v.mean, v.off,
                    v.covered);
        EXPECT_LE(v.mean, 0.001);
        EXPECT_LE(v.off, v.covered / 200);
    }
}

TEST_F(AvsmGpu, ShuffledTrianglesGiveTheSameFunctions) {
    // The lists are ordered by (depth, triangle) before they are appended, so neither the order
    // the scene lists its triangles in nor the order the rasteriser's threads push fragments
    // changes a node (no two veils share a depth); with 4 nodes for 21 surfaces the lossy
    // compression too gives the same nodes.
    const Scene scene = veilStack(20);
    const Scene shuffled = test::shuffledTriangles(scene, 11u);
    RenderOptions o = avsmOptions(Method::Avsm, 48, {"avsm_size=128", "avsm_nodes=4"});
    o.keepShadowMaps = true;
    const Frame a = renderGpu(scene, o);
    const Frame b = renderGpu(shuffled, o);
    ASSERT_EQ(keptMaps(a.keptMaps).avsmMaps.size(), 1u);
    ASSERT_EQ(keptMaps(b.keptMaps).avsmMaps.size(), 1u);
    EXPECT_EQ(keptMaps(a.keptMaps).avsmMaps[0].counts, keptMaps(b.keptMaps).avsmMaps[0].counts);
    EXPECT_EQ(keptMaps(a.keptMaps).avsmMaps[0].overflowed, keptMaps(b.keptMaps).avsmMaps[0].overflowed);
    EXPECT_EQ(keptMaps(a.keptMaps).avsmMaps[0].units, keptMaps(b.keptMaps).avsmMaps[0].units);
    EXPECT_EQ(keptMaps(a.keptMaps).avsmMaps[0].depth, keptMaps(b.keptMaps).avsmMaps[0].depth);
    EXPECT_EQ(a.visibility.pixels, b.visibility.pixels);
}

TEST_F(AvsmGpu, ParticlesMatchTheCpuMirror) {
    // Textured translucent billboards: besides the silhouettes, texels whose centre falls on a
    // texel-rule boundary of a billboard's texture may read the neighbouring alpha on one
    // backend (interpolated against intersected barycentrics); a texel differs when any of its
    // surfaces does. avsm's lookups and vpcss's filter then agree but for those texels' pixels.
    const Scene scene = loadScene("particles", SceneOptions{{{"count", "300"}}});
    for (const Method method : {Method::Avsm, Method::Vpcss}) {
        const RenderOptions o = avsmOptions(method, 64, {"avsm_size=256"});
        const Renders r = renderBoth(scene, o);
        ASSERT_EQ(keptMaps(r.gpu.keptMaps).avsmMaps.size(), 1u);
        ASSERT_EQ(keptMaps(r.cpu.keptMaps).avsmMaps.size(), 1u);
        const FunctionDiff d =
            compareFunctions(keptMaps(r.gpu.keptMaps).avsmMaps[0], keptMaps(r.cpu.keptMaps).avsmMaps[0]);
        const VisibilityDiff v = compareVisibility(r.gpu, r.cpu);
        std::printf("%s: %zu of %zu texels differ (%zu with nodes, %zu overflowed), max relative depth "
                    "difference %.2g; visibility mean |dv| %.5f, %zu of %zu pixels off by more than 1/16\n",
                    toString(method).c_str(), d.differing, d.texels, d.withNodes, d.overflowed,
                    double(d.maxRelative), v.mean, v.off, v.covered);
        EXPECT_GT(d.withNodes, d.texels / 20) << "the map sees the particles";
        EXPECT_LE(d.differing, d.withNodes / 100);
        EXPECT_LE(v.mean, 0.002);
        EXPECT_LE(v.off, v.covered / 100);
        const nlohmann::json& g = r.gpu.stats["shadow_maps"][0]["avsm"];
        const nlohmann::json& c = r.cpu.stats["shadow_maps"][0]["avsm"];
        EXPECT_EQ(g["texels"], c["texels"]);
        EXPECT_EQ(g["bytes"], c["bytes"]);
        EXPECT_NEAR(g["texels_with_nodes"].get<double>(), c["texels_with_nodes"].get<double>(),
                    double(d.differing));
    }
}

} // namespace
} // namespace stsv::test
