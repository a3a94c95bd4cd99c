// The DCS identity (DESIGN §4.5): per light sample, depth complexity from the centre count plus
// the signed crossings of the projected silhouette edges (wedges/dcs_dh.h) equals brute-force
// counting of the triangles on the segment, exactly, on random soups and all light shapes.
#include "sampling/light_bounds.h"
#include "sampling/light_sampling_dh.h"
#include "scene/geometry.h"
#include "volumes/stsv_dh.h"
#include "wedge_test_util.h"
#include "wedges/adjacency.h"
#include "wedges/dcs_dh.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace stsv {
namespace {

using test::Rng;

enum class Soup { Closed, Open, NonManifold };

/// Random soups in [−1, 1]³: closed = random tetrahedra (random winding per face), open = random
/// triangles and strips of triangles sharing edges, non-manifold = fans of 3–4 triangles on one edge.
Scene makeSoup(Soup kind, std::uint64_t seed, int pieces) {
    Rng rng(seed);
    Scene scene;
    Material m;
    m.name = "opaque";
    scene.materials.push_back(m);
    auto add = [&](vec3 a, vec3 b, vec3 c) {
        scene.addTriangle(a, b, c, vec2(0.0f), vec2(0.0f), vec2(0.0f), 0);
    };
    for (int i = 0; i < pieces; ++i) {
        const vec3 center = rng.inBox(vec3(-1.0f), vec3(1.0f));
        const float size = rng.uniform(0.15f, 0.6f);
        auto near = [&] { return center + size * rng.inBox(vec3(-1.0f), vec3(1.0f)); };
        if (kind == Soup::Closed) {
            const vec3 v[4] = {near(), near(), near(), near()};
            const int faces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
            for (const auto& f : faces) {
                if (rng.index(2))
                    add(v[f[0]], v[f[1]], v[f[2]]);
                else
                    add(v[f[0]], v[f[2]], v[f[1]]);
            }
        } else if (kind == Soup::Open) {
            vec3 a = near(), b = near();
            const int strip = 1 + rng.index(3);
            for (int k = 0; k < strip; ++k) {
                const vec3 c = near();
                add(a, b, c);
                a = b;
                b = c;
            }
        } else {
            const vec3 a = near(), b = near();
            const int fan = 3 + rng.index(2);
            for (int k = 0; k < fan; ++k) add(a, b, near());
        }
    }
    return scene;
}

std::vector<Light> allLights() {
    return {makeRectangleLight(vec3(0.3f, 4.0f, -0.2f), vec3(0.1f, -1.0f, 0.2f), vec2(2.0f, 1.2f), vec3(1.0f),
                               vec3(1.0f, 0.0f, 0.3f)),
            makeDiskLight(vec3(-0.4f, 3.5f, 0.5f), vec3(0.0f, -1.0f, -0.1f), 1.1f, vec3(1.0f)),
            makeSphereLight(vec3(0.2f, 3.8f, 0.1f), 0.9f, vec3(1.0f)),
            makeDirectionalLight(normalize(vec3(0.2f, 1.0f, 0.3f)), 0.25f, vec3(1.0f))};
}

struct IdentityResult {
    std::size_t samples = 0;
    std::size_t mismatches = 0;
    std::size_t occluded = 0;
    std::size_t filteredMismatches = 0; ///< with the potential-silhouette prefilter
};

IdentityResult checkIdentity(const Scene& scene, const Light& light, std::uint64_t seed, int points,
                             int samplesPerPoint) {
    const EdgeAdjacency adj = buildEdgeAdjacency(scene);
    const float farDistance = 50.0f;
    Bounds box;
    box.extend(vec3(-3.0f, -4.0f, -3.0f));
    box.extend(vec3(3.0f, 1.6f, 3.0f));
    const vec4 sphere = lightBoundingSphere(light, box, farDistance);
    const std::vector<std::uint32_t> potential = potentialSilhouetteEdges(adj, sphere);
    std::vector<bool> isPotential(adj.edges.size(), false);
    for (std::uint32_t e : potential) isPotential[e] = true;
    Rng rng(seed);
    IdentityResult result;
    std::vector<int> count, filtered;
    std::vector<vec2> ab;
    for (int i = 0; i < points; ++i) {
        // Receivers below and among the soup (never on a triangle: measure zero).
        const vec3 p = rng.inBox(vec3(-3.0f, -4.0f, -3.0f), vec3(3.0f, 1.5f, 3.0f));
        const LightFrame frame = lightFrame(light, p, farDistance);
        const DcsPixel px = dcsSetupPixel(p, frame.center, frame.T, frame.B, SHADOW_T_MIN);
        EXPECT_EQ(px.valid, 1.0f) << "p=" << test::str(p);
        ab.clear();
        for (int s = 0; s < samplesPerPoint; ++s) {
            vec2 u(rng.uniform(), rng.uniform());
            ab.push_back(domainPoint(u, frame.domain));
        }
        const int base = test::countCrossings(scene, p, frame.center, SHADOW_T_MIN);
        count.assign(ab.size(), base);
        filtered.assign(ab.size(), base);
        for (std::uint32_t e = 0; e < adj.edges.size(); ++e) {
            const MeshEdge& edge = adj.edges[e];
            vec3 h0 = dcsProject(px, adj.positions[edge.v0]);
            vec3 h1 = dcsProject(px, adj.positions[edge.v1]);
            const vec3 l = cross(h0, h1);
            int k = 0;
            for (std::uint32_t f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f)
                k += dcsFaceSide(l, dcsProject(px, adj.positions[adj.faces[f].opposite]));
            if (k == 0 || !dcsClipEdge(px.tMin, h0, h1)) continue;
            for (std::size_t s = 0; s < ab.size(); ++s) {
                const int c = k * dcsSampleCrossing(l, h0, h1, ab[s]);
                count[s] += c;
                if (isPotential[e]) filtered[s] += c;
            }
        }
        for (std::size_t s = 0; s < ab.size(); ++s) {
            const vec3 x = lightSamplePosition(frame, ab[s]);
            const int brute = test::countCrossings(scene, p, x, SHADOW_T_MIN);
            ++result.samples;
            result.occluded += brute > 0 ? 1 : 0;
            if (count[s] != brute) {
                ++result.mismatches;
                if (result.mismatches <= 3)
                    ADD_FAILURE() << "light type " << light.type << " p=" << test::str(p)
                                  << " x=" << test::str(x) << " D(r)=" << base << " dcs=" << count[s]
                                  << " brute=" << brute;
            }
            if (filtered[s] != brute) ++result.filteredMismatches;
        }
    }
    return result;
}

TEST(DcsIdentity, RandomSoupsAllLightShapes) {
    const char* names[] = {"closed", "open", "non-manifold"};
    std::size_t total = 0;
    for (Soup kind : {Soup::Closed, Soup::Open, Soup::NonManifold})
        for (std::uint64_t seed = 1; seed <= 3; ++seed) {
            const Scene scene = makeSoup(kind, seed * 7 + std::uint64_t(kind), 30);
            for (const Light& light : allLights()) {
                const IdentityResult r = checkIdentity(scene, light, seed, 100, 64);
                EXPECT_EQ(r.mismatches, 0u)
                    << names[int(kind)] << " seed " << seed << " light " << light.type;
                EXPECT_EQ(r.filteredMismatches, 0u)
                    << "potential-silhouette prefilter dropped a contributing edge: " << names[int(kind)];
                // Sanity: the soups occlude a share of the samples (≥ 1 %), so the check is not vacuous.
                EXPECT_GT(r.occluded, r.samples / 100) << names[int(kind)];
                total += r.samples;
            }
        }
    std::printf("DCS identity: %zu (p, sample) pairs checked\n", total);
}

} // namespace
} // namespace stsv
