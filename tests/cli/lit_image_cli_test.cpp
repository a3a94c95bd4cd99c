// The lit image and the visibility against values worked out by hand, on both backends: a ground
// square seen from straight above, an opaque roof over part of it, two small lights. Each pixel's
// expectation comes from the camera's geometry and the point-light formula, not from the renderer:
// background colour off the ground, ambient · albedo in the roof's shadow, and there
// albedo · (ambient + Σ_lights L·A·cos²/(π d²)) in the light; row 0 is the top of the view.
#include "cli_test_util.h"

#include "core/image.h"
#include "tests/failure_images.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace stsv::test {
namespace {

// Ground: 2 m square at y = 0, albedo (0.5, 0.4, 0.3) (distinct channels catch a swapped order).
// Roof: opaque, at y = 1 over z < −0.2, above the camera (which looks down from y = 0.8 with
// up = −z, so the top of the view is −z). Lights: 2 cm squares at (0, 4, 0) and (0.5, 4, 0), facing
// down, radiance (300, 300, 300) and (0, 600, 0). The roof shadows the ground where the segment to
// either light crosses y = 1 at z < −0.2: z_p + (0 − z_p)/4 < −0.2, i.e. z_p < −0.8/3.
constexpr const char* SCENE_JSON = R"({
  "materials": [{ "name": "ground", "albedo": [0.5, 0.4, 0.3] }, { "name": "roof", "albedo": [0.9, 0.9, 0.9] }],
  "meshes": [
    { "name": "ground", "material": "ground",
      "vertices": [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]],
      "texcoords": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "triangles": [[0, 2, 1], [0, 3, 2]] },
    { "name": "roof", "material": "roof",
      "vertices": [[-4, 1, -4], [4, 1, -4], [4, 1, -0.2], [-4, 1, -0.2]],
      "texcoords": [[0, 0], [1, 0], [1, 1], [0, 1]],
      "triangles": [[0, 1, 2], [0, 2, 3]] }
  ],
  "lights": [
    { "type": "rectangle", "position": [0, 4, 0], "normal": [0, -1, 0], "size": [0.02, 0.02],
      "radiance": [300, 300, 300] },
    { "type": "rectangle", "position": [0.5, 4, 0], "normal": [0, -1, 0], "size": [0.02, 0.02],
      "radiance": [0, 600, 0] }
  ],
  "camera": { "eye": [0, 0.8, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fovY": 120 }
})";

constexpr int W = 48, H = 36;
constexpr double AMBIENT = 0.05;
const double ALBEDO[3] = {0.5, 0.4, 0.3};
const double EXPECTED_BACKGROUND[3] = {0.02, 0.02, 0.03}; // the documented background colour

struct Expected {
    enum { Background, Shadow, Lit, Unsure } kind = Unsure;
    double rgb[3] = {0, 0, 0};
    double visibility = 1.0;
};

/// The pixel's centre ray from the camera (right = +x, up = −z, forward = −y, vertical field of
/// view 120°), its ground point, and what the image must hold there.
Expected expected(int x, int y) {
    const double tanHalf = std::tan(60.0 * M_PI / 180.0), aspect = double(W) / H;
    const double sx = (2.0 * (x + 0.5) / W - 1.0) * tanHalf * aspect,
                 sy = (1.0 - 2.0 * (y + 0.5) / H) * tanHalf;
    // direction (sx, −1, −sy): right·sx + up·sy + forward, up = (0, 0, −1); the ground at t = 0.8.
    const double px = 0.8 * sx, pz = -0.8 * sy;
    const double pixel = 0.8 * 2.0 * tanHalf / H; // a pixel's footprint on the ground, metres
    Expected e;
    const double edge = std::max(std::abs(px), std::abs(pz));
    if (std::abs(edge - 1.0) < 1.5 * pixel || std::abs(pz + 0.8 / 3.0) < 1.5 * pixel + 0.01)
        return e; // borders
    if (edge > 1.0) {
        e.kind = Expected::Background;
        for (int c = 0; c < 3; ++c) e.rgb[c] = EXPECTED_BACKGROUND[c];
        return e;
    }
    if (pz < -0.8 / 3.0) {
        e.kind = Expected::Shadow;
        e.visibility = 0.0;
        for (int c = 0; c < 3; ++c) e.rgb[c] = AMBIENT * ALBEDO[c];
        return e;
    }
    // Small lights: E = L·A·cosP·cosL/d² with cosP = cosL = 4/d; outgoing radiance albedo/π · E.
    e.kind = Expected::Lit;
    const double lights[2][4] = {{0.0, 300, 300, 300}, {0.5, 0, 600, 0}}; // x, radiance
    for (int c = 0; c < 3; ++c) e.rgb[c] = AMBIENT * ALBEDO[c];
    for (const auto& l : lights) {
        const double dx = l[0] - px, dz = -pz, d2 = dx * dx + 16.0 + dz * dz;
        const double geometry = 0.02 * 0.02 * 16.0 / (d2 * d2);
        for (int c = 0; c < 3; ++c) e.rgb[c] += ALBEDO[c] / M_PI * l[1 + c] * geometry;
    }
    return e;
}

void checkImages(const std::string& backend) {
    SCOPED_TRACE(backend);
    ScratchDir dir;
    std::ofstream(dir.file("roof.json")) << SCENE_JSON;
    const std::vector<std::string> args = {"render",
                                           dir.file("roof.json"),
                                           "--method",
                                           "stsv",
                                           "--backend",
                                           backend,
                                           "--size",
                                           std::to_string(W) + "x" + std::to_string(H),
                                           "--samples",
                                           "16",
                                           "-o",
                                           dir.file("lit.exr"),
                                           "--visibility",
                                           dir.file("v.npy"),
                                           "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const ImageF lit = readExr(dir.file("lit.exr"));
    ASSERT_EQ(lit.width, W);
    ASSERT_EQ(lit.height, H);
    ASSERT_EQ(lit.channels, 3);
    const NpyArray v = readNpy(dir.file("v.npy"));
    ASSERT_EQ(v.shape, (std::vector<std::size_t>{std::size_t(H), std::size_t(W)}));
    std::vector<float> visibility(std::size_t(W) * H);
    std::memcpy(visibility.data(), v.bytes.data(), v.bytes.size());
    int counts[3] = {0, 0, 0}, wrong = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const Expected e = expected(x, y);
            if (e.kind == Expected::Unsure) continue;
            ++counts[e.kind];
            bool ok = visibility[std::size_t(y) * W + x] == float(e.visibility);
            for (int c = 0; c < 3; ++c)
                // Half floats (relative 2^-11) and the point-light formula for a 2 cm light at
                // 4 m (relative (0.02/4)² = 2.5e-5): 2e-3 relative.
                ok = ok && std::abs(lit.at(x, y, c) - e.rgb[c]) <= 2e-3 * e.rgb[c] + 1e-6;
            if (!ok && ++wrong <= 5)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "): lit (" << lit.at(x, y, 0) << ", "
                              << lit.at(x, y, 1) << ", " << lit.at(x, y, 2) << ") visibility "
                              << visibility[std::size_t(y) * W + x] << "; expected (" << e.rgb[0] << ", "
                              << e.rgb[1] << ", " << e.rgb[2] << ") visibility " << e.visibility;
        }
    // The expectation as an image, for writeFailureImages (unsure pixels: the actual value).
    ImageF expectedLit(W, H, 3), expectedVisibility(W, H, 1), actualVisibility(W, H, 1);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const Expected e = expected(x, y);
            const float have = visibility[std::size_t(y) * W + x];
            actualVisibility.at(x, y, 0) = have;
            expectedVisibility.at(x, y, 0) = e.kind == Expected::Unsure ? have : float(e.visibility);
            for (int c = 0; c < 3; ++c)
                expectedLit.at(x, y, c) = e.kind == Expected::Unsure ? lit.at(x, y, c) : float(e.rgb[c]);
        }
    std::printf("%s: %d background, %d shadow, %d lit pixels checked, %d wrong\n", backend.c_str(), counts[0],
                counts[1], counts[2], wrong);
    EXPECT_EQ(wrong, 0);
    for (int k = 0; k < 3; ++k) EXPECT_GT(counts[k], 100) << "class " << k;
    writeFailureImages(backend + "_lit", lit, expectedLit, true, 40.0f);
    writeFailureImages(backend + "_visibility", actualVisibility, expectedVisibility);
}

TEST(LitImageCli, AmbientBackgroundLightSumAndRowOrderAsWorkedOutByHand) {
    checkImages("cpu");
    checkImages("vulkan");
}

} // namespace
} // namespace stsv::test
