#include "scene/procedural.h"

#include "core/error.h"
#include "core/memory_budget.h"
#include "scene/geometry.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>

namespace stsv {

namespace {

constexpr float PI = 3.14159265358979f;

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
    checkParam(what, "texture size", GENERATED_TEXTURE_SIZE, size);
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

namespace {
/// "1000000", "0.0001", "1e-05": whole numbers in full (as `--set` takes an integer), others in
/// their shortest round-trip form.
std::string numberText(double value) {
    char buffer[32];
    const char* end =
        std::abs(value) < 1e15 && value == std::floor(value)
            ? std::to_chars(buffer, buffer + sizeof buffer, static_cast<long long>(value)).ptr
            : std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general).ptr;
    return std::string(static_cast<const char*>(buffer), end);
}
} // namespace

std::string rangeText(const ParamRange& range) {
    return "[" + numberText(range.lo) + ", " + numberText(range.hi) + "]";
}

void checkParam(const std::string& scene, const std::string& name, const ParamRange& range, double value) {
    if (!range.contains(value))
        throw UsageError(scene + ": " + name + " must be in " + rangeText(range) + ", got " +
                         numberText(value));
}

double generatedTextureBytes(int size) {
    return 4.0 * double(size) * double(size);
}

void checkGeneratedTextureMemory(const std::string& what, int size, double heldBytes) {
    checkMemory(what + " of " + std::to_string(size) + "x" + std::to_string(size) + " texels" +
                    (heldBytes > 0.0 ? " (beside the scene's other textures)" : ""),
                heldBytes + generatedTextureBytes(size), "use a smaller texture size");
}

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
        const float attachV = 0.30f + 0.08f * float(i);              // top leaves first
        const float length = 0.22f + 0.025f * float(i);              // lower leaves are longer
        const float angle = (35.0f + 2.0f * float(i)) * PI / 180.0f; // above horizontal
        const vec2 dir(side * std::cos(angle), -std::sin(angle));    // v points down
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
    checkParam("fence", "light_size", FENCE_LIGHT_SIZE, params.lightSize);
    checkParam("fence", "repeat", FENCE_REPEAT, params.repeat);
    checkParam("fence", "fabric", FENCE_FABRIC, params.fabric);
    checkTextureSize(params.textureSize, "fence: chain-link");
    // The texel coordinate at the fence's right edge must name a texel (MAX_TEXEL_COORDINATE).
    if (!(double(params.repeat) * params.textureSize < MAX_TEXEL_COORDINATE))
        throw UsageError("fence: repeat x texture_size = " + std::to_string(params.repeat) + " x " +
                         std::to_string(params.textureSize) +
                         " texels across the fence, not below the 2^24 where a float texel coordinate "
                         "is exact; use a smaller repeat or texture_size");
    checkGeneratedTextureMemory("fence: chain-link texture", params.textureSize);
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
    if (params.fabric > 0.0f) {
        // A translucent fabric of constant α on the light's side of the fence.
        Material fabric;
        fabric.name = "fabric";
        fabric.albedo = vec3(0.6f, 0.2f, 0.2f);
        fabric.doubleSided = true;
        setMaterialAlpha(fabric, scene.textures, AlphaMode::Blend, -1, params.fabric, 0.5f);
        const std::uint32_t f = addMaterial(scene, fabric);
        appendMesh(scene, makeQuad(vec2(4.0f, 1.6f), vec2(1.0f)),
                   glm::translate(mat4(1.0f), vec3(0.0f, 1.1f, -0.3f)), "fabric", int(f));
    }

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
    checkParam("foliage", "count", FOLIAGE_COUNT, params.count);
    checkParam("foliage", "spacing", FOLIAGE_SPACING, params.spacing);
    checkParam("foliage", "light_size", FOLIAGE_LIGHT_SIZE, params.lightSize);
    checkTextureSize(params.textureSize, "foliage: leaf");
    checkGeneratedTextureMemory("foliage: leaf texture", params.textureSize);
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
        const int row = cell / g;
        const float cz = (float(row) + 0.5f) * params.spacing - 0.5f * side;
        const vec3 base(cx + rng.uniform(-0.3f, 0.3f) * params.spacing, 0.0f,
                        cz + rng.uniform(-0.3f, 0.3f) * params.spacing);
        const float height = rng.uniform(0.7f, 1.2f) * std::min(1.0f, params.spacing / 0.75f);
        const float halfWidth = 0.45f * height;
        const float yaw = rng.uniform(0.0f, PI);
        for (int q = 0; q < 2; ++q) { // two crossed quads
            const float a = yaw + float(q) * 0.5f * PI;
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
    const vec3 aim(0.0f, 0.0f, 0.1f * side);
    vec3 lightCenter(-0.45f * side - 1.0f, 0.6f * side + 3.0f, -0.7f * side - 1.5f);
    const vec3 lightNormal = normalize(aim - lightCenter);
    // A light too large for that place reaches down through the plants and the ground (and the
    // picture turns dark and noisy): it moves back along its direction until its lowest corner is
    // twice as high as the tallest plant. The automatic size never needs it.
    float tallest = 0.0f;
    for (std::size_t v = scene.triangles[first].x; v < scene.positions.size(); ++v)
        tallest = std::max(tallest, scene.positions[v].y);
    const Light unmoved =
        makeRectangleLight(lightCenter, lightNormal, vec2(lightSize), vec3(1.0f), vec3(1.0f, 0.0f, 0.0f));
    const float lowest = lightCenter.y - std::abs(unmoved.axisU.y) - std::abs(unmoved.axisV.y);
    if (lowest < 2.0f * tallest) lightCenter -= lightNormal * ((2.0f * tallest - lowest) / -lightNormal.y);
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

Texture makeGaussianTexture(int size) {
    checkTextureSize(size, "gaussian");
    Texture t;
    t.name = "gaussian " + std::to_string(size);
    t.width = t.height = size;
    t.rgba.assign(std::size_t(size) * size * 4, 255);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double u = (x + 0.5) / size * 2.0 - 1.0, v = (y + 0.5) / size * 2.0 - 1.0;
            const double r2 = u * u + v * v;
            const double a = r2 >= 1.0 ? 0.0 : 255.0 * std::exp(-r2 / (2.0 * 0.4 * 0.4));
            t.rgba[(std::size_t(y) * size + x) * 4 + 3] = std::uint8_t(std::lround(a));
        }
    return t;
}

Scene makeParticlesScene(const ParticlesParams& params) {
    checkParam("particles", "count", PARTICLES_COUNT, params.count);
    checkParam("particles", "opacity", PARTICLES_OPACITY, params.opacity);
    checkParam("particles", "height", PARTICLES_HEIGHT, params.height);
    Scene scene;
    scene.source = "particles";
    addGround(scene, vec3(0.0f), 8.0f, vec3(0.7f));

    // The opaque cube, 1 m, right of the cloud.
    Material box;
    box.name = "cube";
    box.albedo = vec3(0.3f, 0.4f, 0.6f);
    const std::uint32_t boxMaterial = addMaterial(scene, box);
    const vec3 lo(0.9f, 0.0f, -0.5f), hi(1.9f, 1.0f, 0.5f);
    const auto corner = [&](int i) {
        return vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
    };
    // Faces as corner quadruples, counter-clockwise seen from outside.
    const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    const auto boxFirst = static_cast<std::uint32_t>(scene.triangles.size());
    for (const auto& f : faces) {
        scene.addTriangle(corner(f[0]), corner(f[1]), corner(f[2]), {0, 0}, {1, 0}, {1, 1}, boxMaterial);
        scene.addTriangle(corner(f[0]), corner(f[2]), corner(f[3]), {0, 0}, {1, 1}, {0, 1}, boxMaterial);
    }
    scene.meshes.push_back({"cube", boxFirst, 12});

    const vec3 lightCenter(-1.0f, 6.0f, -2.5f);
    Material particle;
    particle.name = "particle";
    particle.albedo = vec3(0.85f);
    particle.wrap = WrapMode::Clamp;
    particle.doubleSided = true;
    setMaterialAlpha(particle, scene.textures, AlphaMode::Blend, addTexture(scene, makeGaussianTexture(64)),
                     params.opacity, 0.5f);
    const std::uint32_t m = addMaterial(scene, particle);
    Rng rng(params.seed);
    const vec3 cloud(-0.6f, params.height, 0.0f);
    const float radius = 1.2f, half = 0.25f;
    const auto first = static_cast<std::uint32_t>(scene.triangles.size());
    for (int i = 0; i < params.count; ++i) {
        // In the ball, and (a cloud resting on the ground) with the billboard's centre a half-width
        // above the ground.
        vec3 offset;
        do {
            offset = vec3(rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f), rng.uniform(-1.0f, 1.0f));
        } while (dot(offset, offset) > 1.0f || params.height + radius * offset.y < half);
        const vec3 c = cloud + radius * offset;
        // Facing the light centre: the billboard's axes span the plane normal to c → light.
        const vec3 n = normalize(lightCenter - c);
        const vec3 u = normalize(cross(vec3(0.0f, 0.0f, 1.0f), n));
        const vec3 v = cross(n, u);
        const vec3 a = c - half * u - half * v, b = c + half * u - half * v, d = c + half * u + half * v,
                   e = c - half * u + half * v;
        scene.addTriangle(a, b, d, {0, 0}, {1, 0}, {1, 1}, m);
        scene.addTriangle(a, d, e, {0, 0}, {1, 1}, {0, 1}, m);
    }
    scene.meshes.push_back({"particles", first, static_cast<std::uint32_t>(scene.triangles.size()) - first});

    const float lightSize = 1.0f;
    const vec3 lightNormal = normalize(vec3(0.0f, 0.0f, 1.0f) - lightCenter);
    const float radiance = radianceForOutgoing(lightCenter, lightNormal, lightSize * lightSize,
                                               vec3(2.5f, 0.0f, 2.5f), vec3(0.0f, 1.0f, 0.0f), 0.7f, 0.6f);
    scene.lights.push_back(makeRectangleLight(lightCenter, lightNormal, vec2(lightSize), vec3(radiance),
                                              vec3(1.0f, 0.0f, 0.0f)));
    scene.camera.eye = vec3(2.5f, 4.5f, 7.5f);
    scene.camera.target = vec3(0.0f, 0.6f, 1.3f);
    scene.camera.up = vec3(0.0f, 1.0f, 0.0f);
    scene.camera.fovY = 50.0f;
    scene.validate();
    return scene;
}

} // namespace stsv
