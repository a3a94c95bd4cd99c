#include "scene/procedural.h"

#include "core/error.h"
#include "scene/geometry.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace stsv {

namespace {

constexpr float kPi = 3.14159265358979f;

/// splitmix64: tiny, portable (std distributions differ between standard libraries).
class Rng {
  public:
    explicit Rng(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); } ///< [0, 1)
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }

  private:
    std::uint64_t m_state;
};

void checkTextureSize(int size, const char* what) {
    if (size < 8 || size > 8192)
        throw UsageError(std::string(what) + " texture size must be in [8, 8192], got " +
                         std::to_string(size));
}

/// Opaque ground: a square of half-edge `half` at height y, centred at (cx, cz), facing +y.
void addGround(Scene& scene, vec3 center, float half, vec3 albedo) {
    Material ground;
    ground.name = "ground";
    ground.albedo = albedo;
    const std::uint32_t m = addMaterial(scene, ground);
    const vec3 a = center + vec3(-half, 0.0f, -half), b = center + vec3(-half, 0.0f, half),
               c = center + vec3(half, 0.0f, half), d = center + vec3(half, 0.0f, -half);
    const auto first = static_cast<std::uint32_t>(scene.triangles.size());
    scene.addTriangle(a, b, c, {0.0f, 0.0f}, {0.0f, 1.0f}, {1.0f, 1.0f}, m);
    scene.addTriangle(a, c, d, {0.0f, 0.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, m);
    scene.meshes.push_back({"ground", first, 2});
}

} // namespace

Texture makeChainLinkTexture(int size) {
    checkTextureSize(size, "chain-link");
    // Wires along the two diagonal families a = sx + sy ∈ ℤ and b = sx − sy ∈ ℤ, in units of the
    // diamond period (4 diamonds per tile, so the tile edge is a whole number of periods and the
    // pattern continues across the wrap). A wire covers |a − round(a)| < h; the open fraction of
    // a period cell is (1 − 2h)², so h = (1 − √0.65) / 2 aims at 0.65 open.
    constexpr int kDiamonds = 4;
    const double h = (1.0 - std::sqrt(0.65)) / 2.0;
    Texture texture;
    texture.name = "chainlink(" + std::to_string(size) + ")";
    texture.width = texture.height = size;
    texture.rgba.resize(std::size_t(size) * size * 4);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double sx = (x + 0.5) * kDiamonds / size, sy = (y + 0.5) * kDiamonds / size;
            const double a = sx + sy, b = sx - sy;
            const double da = std::abs(a - std::round(a)), db = std::abs(b - std::round(b));
            const bool wire = da < h || db < h;
            // Galvanised grey, slightly brighter at the wire centre (only for display).
            const double shade = wire ? 1.0 - 0.35 * std::min(da, db) / h : 0.0;
            std::uint8_t* texel = &texture.rgba[(std::size_t(y) * size + x) * 4];
            texel[0] = static_cast<std::uint8_t>(std::lround(150.0 * shade));
            texel[1] = static_cast<std::uint8_t>(std::lround(155.0 * shade));
            texel[2] = static_cast<std::uint8_t>(std::lround(160.0 * shade));
            texel[3] = wire ? 255 : 0;
        }
    return texture;
}

Texture makeLeafTexture(int size) {
    checkTextureSize(size, "leaf");
    // In texture space (u right, v down, both in [0, 1]): a stem up the middle from the bottom edge
    // and leaves as ellipses on alternating sides, pointing up and out.
    struct Leaf {
        float cu, cv, cosA, sinA, halfLength, halfWidth;
    };
    std::vector<Leaf> leaves;
    constexpr int kLeafPairs = 4;
    for (int i = 0; i < 2 * kLeafPairs; ++i) {
        const float side = (i % 2 == 0) ? -1.0f : 1.0f;
        const float attachV = 0.30f + 0.08f * float(i);               // top leaves first
        const float length = 0.22f + 0.025f * float(i);               // lower leaves are longer
        const float angle = (35.0f + 2.0f * float(i)) * kPi / 180.0f; // above horizontal
        const vec2 dir(side * std::cos(angle), -std::sin(angle));     // v points down
        const vec2 c = vec2(0.5f, attachV) + 0.5f * length * dir;
        leaves.push_back({c.x, c.y, dir.x, dir.y, 0.5f * length, 0.17f * length});
    }
    leaves.push_back({0.5f, 0.17f, 0.0f, -1.0f, 0.13f, 0.05f}); // the top leaf
    Texture texture;
    texture.name = "leaf(" + std::to_string(size) + ")";
    texture.width = texture.height = size;
    texture.rgba.resize(std::size_t(size) * size * 4);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float u = (float(x) + 0.5f) / float(size), v = (float(y) + 0.5f) / float(size);
            bool solid = std::abs(u - 0.5f) < 0.018f && v > 0.2f; // stem, down to the bottom edge
            for (const Leaf& leaf : leaves) {
                const float du = u - leaf.cu, dv = v - leaf.cv;
                const float along = du * leaf.cosA + dv * leaf.sinA;
                const float across = -du * leaf.sinA + dv * leaf.cosA;
                const float e = (along * along) / (leaf.halfLength * leaf.halfLength) +
                                (across * across) / (leaf.halfWidth * leaf.halfWidth);
                solid = solid || e < 1.0f;
            }
            std::uint8_t* texel = &texture.rgba[(std::size_t(y) * size + x) * 4];
            texel[0] = 60;
            texel[1] = static_cast<std::uint8_t>(110 + std::lround(60.0f * v));
            texel[2] = 40;
            texel[3] = solid ? 255 : 0;
        }
    // Transparent border (clamp mode repeats edge texels) except the stem's foot on the bottom row.
    for (int i = 0; i < size; ++i) {
        texture.rgba[(std::size_t(0) * size + i) * 4 + 3] = 0;
        texture.rgba[(std::size_t(i) * size + 0) * 4 + 3] = 0;
        texture.rgba[(std::size_t(i) * size + size - 1) * 4 + 3] = 0;
    }
    return texture;
}

double openFraction(const Texture& texture) {
    const std::size_t n = std::size_t(texture.width) * texture.height;
    if (n == 0) return 0.0;
    std::size_t open = 0;
    for (std::size_t i = 0; i < n; ++i) open += texture.rgba[i * 4 + 3] < 128 ? 1 : 0;
    return double(open) / double(n);
}

Scene makeFenceScene(const FenceParams& params) {
    if (!(params.lightSize > 0.0f) || params.lightSize > 100.0f)
        throw UsageError("fence: light_size must be in (0, 100] m, got " + std::to_string(params.lightSize));
    if (params.repeat < 1 || params.repeat > 4096)
        throw UsageError("fence: repeat must be in [1, 4096], got " + std::to_string(params.repeat));
    Scene scene;
    scene.source = "fence";
    addGround(scene, vec3(0.0f), 15.0f, vec3(0.7f));

    Material fence;
    fence.name = "chainlink";
    fence.albedo = vec3(0.55f, 0.57f, 0.6f);
    fence.alphaTexture = addTexture(scene, makeChainLinkTexture(params.textureSize));
    fence.wrap = WrapMode::Repeat;
    fence.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, fence);
    // 4 m × 2 m in the plane z = 0, bottom edge on the ground, facing the camera (+z).
    const float repeatU = float(params.repeat), repeatV = std::max(1.0f, float(params.repeat) / 2.0f);
    MeshData quad = makeQuad(vec2(4.0f, 2.0f), vec2(repeatU, repeatV));
    appendMesh(scene, quad, glm::translate(mat4(1.0f), vec3(0.0f, 1.0f, 0.0f)), "fence", int(m));

    // Light behind (−z), above and a little to the left: seen from its centre the fence's top edge
    // falls on the ground at z ≈ 1.7, x ∈ [−3, 3.3] (in front of the fence, camera side).
    const vec3 lightCenter(-0.3f, 5.5f, -3.0f);
    const vec3 aim(0.2f, 0.0f, 1.0f);
    const vec3 lightNormal = normalize(aim - lightCenter);
    const float area = params.lightSize * params.lightSize;
    // Radiance such that the unshadowed ground beside the shadow reflects ≈ 0.8.
    const float radiance = radianceForOutgoing(lightCenter, lightNormal, area, vec3(3.0f, 0.0f, 1.0f),
                                               vec3(0.0f, 1.0f, 0.0f), 0.7f, 0.5f);
    scene.lights.push_back(makeRectangleLight(lightCenter, lightNormal, vec2(params.lightSize),
                                              vec3(radiance), vec3(1.0f, 0.0f, 0.0f)));

    scene.camera.eye = vec3(2.2f, 3.2f, 8.0f);
    scene.camera.target = vec3(0.3f, 0.5f, 0.9f);
    scene.camera.up = vec3(0.0f, 1.0f, 0.0f);
    scene.camera.fovY = 50.0f;
    scene.validate();
    return scene;
}

Scene makeFoliageScene(const FoliageParams& params) {
    if (params.count < 1 || params.count > 1000000)
        throw UsageError("foliage: count must be in [1, 1000000], got " + std::to_string(params.count));
    if (!(params.spacing > 0.0f) || params.spacing > 100.0f)
        throw UsageError("foliage: spacing must be in (0, 100] m");
    if (!(params.lightSize >= 0.0f) || params.lightSize > 1000.0f)
        throw UsageError("foliage: light_size must be in [0, 1000] m (0 = automatic)");
    Scene scene;
    scene.source = "foliage";

    // Jittered grid: g × g cells of `spacing`, `count` of them chosen by a seeded shuffle.
    const int g = static_cast<int>(std::ceil(std::sqrt(double(params.count))));
    const float side = params.spacing * float(g);
    addGround(scene, vec3(0.0f), side + 4.0f, vec3(0.45f, 0.38f, 0.3f));

    Material leaf;
    leaf.name = "leaf";
    leaf.albedo = vec3(0.25f, 0.5f, 0.15f);
    leaf.alphaTexture = addTexture(scene, makeLeafTexture(params.textureSize));
    leaf.wrap = WrapMode::Clamp;
    leaf.doubleSided = true;
    const std::uint32_t m = addMaterial(scene, leaf);

    Rng rng(params.seed);
    std::vector<int> cells(std::size_t(g) * g);
    std::iota(cells.begin(), cells.end(), 0);
    for (std::size_t i = cells.size() - 1; i > 0; --i) std::swap(cells[i], cells[rng.next() % (i + 1)]);

    const auto first = static_cast<std::uint32_t>(scene.triangles.size());
    for (int i = 0; i < params.count; ++i) {
        const int cell = cells[std::size_t(i)];
        const float cx = (float(cell % g) + 0.5f) * params.spacing - 0.5f * side;
        const float cz = (float(cell / g) + 0.5f) * params.spacing -
                         0.5f * side; // NOLINT(bugprone-integer-division): row index
        const vec3 base(cx + rng.uniform(-0.3f, 0.3f) * params.spacing, 0.0f,
                        cz + rng.uniform(-0.3f, 0.3f) * params.spacing);
        const float height = rng.uniform(0.7f, 1.2f) * std::min(1.0f, params.spacing / 0.75f);
        const float halfWidth = 0.45f * height;
        const float yaw = rng.uniform(0.0f, kPi);
        for (int q = 0; q < 2; ++q) { // two crossed quads
            const float a = yaw + float(q) * 0.5f * kPi;
            const vec3 dir(std::cos(a) * halfWidth, 0.0f, std::sin(a) * halfWidth);
            const vec3 top(0.0f, height, 0.0f);
            // u left → right, v top (0) → bottom (1).
            const vec3 tl = base - dir + top, bl = base - dir, br = base + dir, tr = base + dir + top;
            scene.addTriangle(tl, bl, br, {0.0f, 0.0f}, {0.0f, 1.0f}, {1.0f, 1.0f}, m);
            scene.addTriangle(tl, br, tr, {0.0f, 0.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, m);
        }
    }
    scene.meshes.push_back({"plants", first, static_cast<std::uint32_t>(scene.triangles.size()) - first});

    // Light behind the patch (−z), high and to the left; shadows fall towards the camera.
    const float lightSize = params.lightSize > 0.0f ? params.lightSize : std::max(1.0f, 0.25f * side);
    const vec3 lightCenter(-0.45f * side - 1.0f, 0.6f * side + 3.0f, -0.7f * side - 1.5f);
    const vec3 lightNormal = normalize(vec3(0.0f, 0.0f, 0.1f * side) - lightCenter);
    const float radiance = radianceForOutgoing(lightCenter, lightNormal, lightSize * lightSize, vec3(0.0f),
                                               vec3(0.0f, 1.0f, 0.0f), 0.45f, 0.7f);
    scene.lights.push_back(makeRectangleLight(lightCenter, lightNormal, vec2(lightSize), vec3(radiance),
                                              vec3(1.0f, 0.0f, 0.0f)));

    // Frame the plants and the darker half of their shadows (the shadows of the plants' lower
    // halves, seen from the light centre) tightly; the ground is larger.
    std::vector<vec3> framed(scene.positions.begin() + scene.triangles[first].x, scene.positions.end());
    for (std::size_t v = scene.triangles[first].x; v < scene.positions.size(); ++v) {
        const vec3 p = scene.positions[v] * vec3(1.0f, 0.5f, 1.0f);
        if (p.y > 0.0f)
            framed.push_back(lightCenter + (lightCenter.y / (lightCenter.y - p.y)) * (p - lightCenter));
    }
    Bounds framedBox;
    for (const vec3& p : framed) framedBox.extend(p);
    scene.camera = framePoints(framed, framedBox.center(), vec3(0.35f, 0.62f, 1.0f), 45.0f, 0.95f);
    scene.validate();
    return scene;
}

} // namespace stsv
