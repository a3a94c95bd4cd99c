// `--shadow-map FILE.npy` as the user guide gives it: float32 [faces, size, size], the linear
// depth along the map's axis, inf where a texel sees no surface, row j the face's v, with the
// map's frame in --stats (shadow_map_views). Each texel is checked against a ray cast by hand
// through a scene of known planes, on both backends.
#include "cli_test_util.h"

#include "core/image.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace stsv::test {
namespace {

/// A 2 m square ground at y = 0 around the origin, a 0.5 m square occluder at y = 2 over
/// x, z in [0.2, 0.7] (off centre, so a flipped or transposed map fails), a tiny triangle at
/// (3, 0, 3) that only widens the scene box, and a rectangle light at (0, 4, 0) facing down.
constexpr const char* SCENE_JSON = R"({
  "materials": [{ "name": "grey", "albedo": [0.5, 0.5, 0.5] }],
  "meshes": [
    { "name": "ground", "material": "grey",
      "vertices": [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]],
      "texcoords": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "triangles": [[0, 2, 1], [0, 3, 2]] },
    { "name": "occluder", "material": "grey",
      "vertices": [[0.2, 2, 0.2], [0.7, 2, 0.2], [0.7, 2, 0.7], [0.2, 2, 0.7]],
      "texcoords": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "triangles": [[0, 2, 1], [0, 3, 2]] },
    { "name": "marker", "material": "grey",
      "vertices": [[3, 0, 3], [3.05, 0, 3], [3, 0, 3.05]],
      "texcoords": [[0, 0], [1, 0], [0, 1]],
      "triangles": [[0, 2, 1]] }
  ],
  "lights": [{ "type": "rectangle", "position": [0, 4, 0], "normal": [0, -1, 0], "size": [0.5, 0.5],
               "radiance": [10, 10, 10] }],
  "camera": { "eye": [0, 3, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fovY": 50 }
})";

struct Vec {
    double x, y, z;
};
Vec vecOf(const nlohmann::json& j) {
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

void checkMap(const std::string& backend) {
    SCOPED_TRACE(backend);
    ScratchDir dir;
    std::ofstream(dir.file("planes.json")) << SCENE_JSON;
    const std::vector<std::string> args = {"render",
                                           dir.file("planes.json"),
                                           "--method",
                                           "pcf",
                                           "--backend",
                                           backend,
                                           "--size",
                                           "16x12",
                                           "--samples",
                                           "16",
                                           "--param",
                                           "sm_size=256",
                                           "--param",
                                           "sm_fit=0", // the scene box: ground and empty texels too
                                           "--shadow-map",
                                           dir.file("map.npy"),
                                           "--stats",
                                           dir.file("stats.json"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    nlohmann::json stats;
    std::ifstream(dir.file("stats.json")) >> stats;
    ASSERT_TRUE(stats.contains("shadow_map_views")) << stats.dump(1);
    const nlohmann::json& view = stats["shadow_map_views"][0];
    ASSERT_EQ(view["projection"], "perspective") << view.dump();
    const int size = view["size"].get<int>();
    ASSERT_EQ(size, 256);
    const Vec o = vecOf(view["origin"]), X = vecOf(view["axis_x"]), Y = vecOf(view["axis_y"]),
              Z = vecOf(view["axis_z"]);
    EXPECT_NEAR(Z.y, -1.0, 1e-6) << "a downward light's map looks down";
    const double u0 = view["window"][0].get<double>(), v0 = view["window"][1].get<double>(),
                 width = view["window"][2].get<double>() - u0;

    const NpyArray map = readNpy(dir.file("map.npy"));
    EXPECT_EQ(map.dtype, "<f4");
    ASSERT_EQ(map.shape, (std::vector<std::size_t>{1, std::size_t(size), std::size_t(size)}));
    std::vector<float> depth(map.bytes.size() / 4);
    std::memcpy(depth.data(), map.bytes.data(), map.bytes.size());

    // Texel (i, j): its centre's ray o + a·(X·su + Y·sv + Z) has axial depth a. It meets the
    // plane y = h at a = (h − o.y)/d.y. Texels whose ray passes within a texel of a square's
    // border are left out (coverage of a rasterised edge).
    const double texel = width / size * 4.0; // axial depth ≈ 4: a texel's footprint in metres
    int ground = 0, occluder = 0, empty = 0, mismatches = 0;
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double su = u0 + (i + 0.5) / size * width, sv = v0 + (j + 0.5) / size * width;
            const Vec d{X.x * su + Y.x * sv + Z.x, X.y * su + Y.y * sv + Z.y, X.z * su + Y.z * sv + Z.z};
            auto hit = [&](double h, double lo, double hi, double& a) {
                a = (h - o.y) / d.y;
                const double x = o.x + a * d.x, z = o.z + a * d.z, margin = texel * (4.0 - h) / 4.0 + 1e-3;
                if (x < lo - margin || x > hi + margin || z < lo - margin || z > hi + margin)
                    return 0; // outside
                if (x < lo + margin || x > hi - margin || z < lo + margin || z > hi - margin)
                    return 1; // border
                return 2;     // inside
            };
            double aOcc = 0.0, aGround = 0.0;
            const int occ = hit(2.0, 0.2, 0.7, aOcc), gnd = hit(0.0, -1.0, 1.0, aGround);
            const float got = depth[std::size_t(j) * size + i];
            if (occ == 1 || (occ == 0 && gnd == 1)) continue;
            // The marker triangle near (3, 0, 3) is left out too.
            const double mx = o.x + aGround * d.x - 3.0, mz = o.z + aGround * d.z - 3.0;
            if (std::abs(mx) < 0.2 && std::abs(mz) < 0.2) continue;
            bool ok = false;
            if (occ == 2) {
                ok = std::abs(got - aOcc) <= 1e-4 * aOcc; // float depth of a rasterised plane
                ++occluder;
            } else if (gnd == 2) {
                ok = std::abs(got - aGround) <= 1e-4 * aGround;
                ++ground;
            } else {
                ok = std::isinf(got) && got > 0.0f;
                ++empty;
            }
            if (!ok && ++mismatches <= 5)
                ADD_FAILURE() << "texel (" << i << ", " << j << "): " << got << ", expected "
                              << (occ == 2   ? aOcc
                                  : gnd == 2 ? aGround
                                             : INFINITY);
        }
    std::printf("%s: %d occluder, %d ground and %d empty texels checked, %d wrong\n", backend.c_str(),
                occluder, ground, empty, mismatches);
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(occluder, 300);
    EXPECT_GT(ground, 3000);
    EXPECT_GT(empty, 3000);
}

TEST(ShadowMapCli, NpyHoldsAxialDepthInfWhereEmptyAndRowsAlongV) {
    checkMap("cpu");
    checkMap("vulkan");
}

} // namespace
} // namespace stsv::test

namespace stsv::test {
namespace {

TEST(ShadowMapCli, AFilteredMapTooLargeForOneVulkanAllocationIsRefusedWithWhatToChange) {
    // A sphere light's cube map at 2048²: CSM's 32 summed-area planes per face need 6 GiB, more
    // than one allocation of lavapipe (2 GiB) may hold.
    const std::vector<std::string> args = {
        "render",   "fence",
        "--method", "csm",
        "--size",   "16x16",
        "--light",  R"({"type": "sphere", "position": [0, 4, 0], "radius": 0.3, "radiance": [10, 10, 10]})",
        "-q"};
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("more than one allocation"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("lower sm_size or csm_terms"), std::string::npos) << r.err;
}

} // namespace
} // namespace stsv::test
