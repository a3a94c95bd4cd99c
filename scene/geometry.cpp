#include "scene/geometry.h"

#include "core/error.h"
#include "scene/camera.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace stsv {

int addTexture(Scene& scene, Texture texture) {
    scene.textures.push_back(std::move(texture));
    return static_cast<int>(scene.textures.size() - 1);
}

std::uint32_t addMaterial(Scene& scene, Material material) {
    scene.materials.push_back(std::move(material));
    return static_cast<std::uint32_t>(scene.materials.size() - 1);
}

namespace {

/// The binary mask of "a/255 · factor ≥ cutoff" over `texture` (−1: α = factor everywhere):
/// −1 when every texel blocks (opaque), the texture itself when the rule is a ≥ 128, else a
/// baked texture of alpha 255 (blocks) or 0 appended to `textures`.
int binaryMask(std::vector<Texture>& textures, int texture, float factor, float cutoff) {
    // The smallest alpha byte that blocks, 256 when none does.
    int threshold = 256;
    for (int a = 255; a >= 0; --a)
        if (double(a) / 255.0 * double(factor) >= double(cutoff)) threshold = a;
    if (texture < 0) {
        if (threshold <= 255) return -1;
    } else {
        if (threshold == 0) return -1;
        if (threshold == 128) return texture;
    }
    Texture mask;
    if (texture < 0) {
        mask.name = "constant alpha " + std::to_string(factor) + " below cutoff " + std::to_string(cutoff);
        mask.width = mask.height = 1;
        mask.rgba = {255, 255, 255, 0};
    } else {
        mask = textures[std::size_t(texture)];
        mask.name += " (alpha byte ≥ " + std::to_string(threshold) + ")";
        for (std::size_t i = 3; i < mask.rgba.size(); i += 4)
            mask.rgba[i] = mask.rgba[i] >= threshold ? 255 : 0;
    }
    textures.push_back(std::move(mask));
    return static_cast<int>(textures.size() - 1);
}

} // namespace

void setMaterialAlpha(Material& material, std::vector<Texture>& textures, AlphaMode mode, int texture,
                      float factor, float cutoff) {
    material.alphaMode = mode;
    material.blendTexture = -1;
    material.alphaFactor = 1.0f;
    if (mode == AlphaMode::Opaque) {
        material.alphaTexture = -1;
        return;
    }
    if (mode == AlphaMode::Mask) {
        material.alphaTexture = binaryMask(textures, texture, factor, cutoff);
        // A mask that blocks everywhere is an opaque material.
        if (material.alphaTexture < 0) material.alphaMode = AlphaMode::Opaque;
        return;
    }
    material.blendTexture = texture;
    material.alphaFactor = factor;
    material.alphaTexture = binaryMask(textures, texture, factor, 0.5f);
}

std::size_t appendMesh(Scene& scene, const MeshData& mesh, const mat4& worldFromObject,
                       const std::string& name, int materialOverride) {
    const auto textureBase = static_cast<int>(scene.textures.size());
    const auto materialBase = static_cast<std::uint32_t>(scene.materials.size());
    if (materialOverride < 0 && mesh.triangleMaterial.size() != mesh.triangles.size())
        throw UsageError("mesh '" + name + "': " + std::to_string(mesh.triangleMaterial.size()) +
                         " triangle materials for " + std::to_string(mesh.triangles.size()) + " triangles");
    if (materialOverride < 0) {
        scene.textures.insert(scene.textures.end(), mesh.textures.begin(), mesh.textures.end());
        for (Material m : mesh.materials) {
            if (m.alphaTexture >= 0) m.alphaTexture += textureBase;
            if (m.blendTexture >= 0) m.blendTexture += textureBase;
            scene.materials.push_back(std::move(m));
        }
    }
    const auto vertexBase = static_cast<std::uint32_t>(scene.positions.size());
    for (const vec3& p : mesh.positions) scene.positions.push_back(vec3(worldFromObject * vec4(p, 1.0f)));
    if (mesh.texcoords.size() == mesh.positions.size())
        scene.texcoords.insert(scene.texcoords.end(), mesh.texcoords.begin(), mesh.texcoords.end());
    else
        scene.texcoords.resize(scene.positions.size(), vec2(0.0f));

    Mesh placed;
    placed.name = name;
    placed.firstTriangle = static_cast<std::uint32_t>(scene.triangles.size());
    placed.triangleCount = static_cast<std::uint32_t>(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        scene.triangles.push_back(mesh.triangles[t] + uvec3(vertexBase));
        scene.triangleMaterial.push_back(materialOverride >= 0 ? static_cast<std::uint32_t>(materialOverride)
                                                               : materialBase + mesh.triangleMaterial[t]);
    }
    scene.meshes.push_back(placed);
    scene.skippedFaces += mesh.skippedFaces;
    scene.warnings.insert(scene.warnings.end(), mesh.warnings.begin(), mesh.warnings.end());
    return scene.meshes.size() - 1;
}

MeshData makeQuad(vec2 size, vec2 uvRepeat) {
    MeshData quad;
    const float hx = 0.5f * size.x, hy = 0.5f * size.y;
    quad.positions = {{-hx, hy, 0.0f}, {-hx, -hy, 0.0f}, {hx, -hy, 0.0f}, {hx, hy, 0.0f}};
    quad.texcoords = {{0.0f, 0.0f}, {0.0f, uvRepeat.y}, {uvRepeat.x, uvRepeat.y}, {uvRepeat.x, 0.0f}};
    quad.triangles = {{0, 1, 2}, {0, 2, 3}};
    quad.triangleMaterial = {0, 0};
    return quad;
}

MeshData makeTubeMesh(int segments, int sides, float radius, const std::function<vec3(float)>& curve) {
    if (segments < 3 || sides < 3) throw UsageError("a tube needs at least 3 segments and 3 sides");
    MeshData m;
    for (int i = 0; i < segments; ++i) {
        const float u = float(i) / float(segments);
        const vec3 c = curve(u);
        const vec3 t = normalize(curve(u + 1e-3f) - c);
        const vec3 n =
            normalize(cross(t, std::abs(t.y) < 0.9f ? vec3(0.0f, 1.0f, 0.0f) : vec3(1.0f, 0.0f, 0.0f)));
        const vec3 b = cross(t, n);
        for (int j = 0; j < sides; ++j) {
            const float a = 6.2831853f * float(j) / float(sides);
            m.positions.push_back(c + radius * (std::cos(a) * n + std::sin(a) * b));
            m.texcoords.push_back(vec2(0.0f));
        }
    }
    auto index = [&](int i, int j) { return std::uint32_t((i % segments) * sides + (j % sides)); };
    for (int i = 0; i < segments; ++i)
        for (int j = 0; j < sides; ++j) {
            // Counter-clockwise seen from outside: (i, j) → (i, j + 1) runs around the tube (b
            // after n, b = t × n), (i, j) → (i + 1, j) along it, and (around) × (along) points out.
            m.triangles.push_back(uvec3(index(i, j), index(i + 1, j + 1), index(i + 1, j)));
            m.triangles.push_back(uvec3(index(i, j), index(i, j + 1), index(i + 1, j + 1)));
            m.triangleMaterial.insert(m.triangleMaterial.end(), 2, 0);
        }
    Material material;
    material.name = "tube";
    m.materials.push_back(material);
    return m;
}

MeshData makeTorusKnotMesh(int segments, int sides, float tube, int p, int q) {
    return makeTubeMesh(segments, sides, tube, [&](float u) {
        const float a = 6.2831853f * u;
        const float r = 0.6f + 0.3f * std::cos(float(q) * a);
        return vec3(r * std::cos(float(p) * a), 0.3f * std::sin(float(q) * a), r * std::sin(float(p) * a));
    });
}

vec3 perpendicularTo(vec3 n) {
    const vec3 a = std::abs(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 0.0f, 1.0f);
    return normalize(a - dot(a, n) * n);
}

Light makeRectangleLight(vec3 center, vec3 normal, vec2 size, vec3 radiance, vec3 tangent) {
    const vec3 n = normalize(normal);
    vec3 u = tangent - dot(tangent, n) * n;
    u = length(u) > 1e-6f * (1.0f + length(tangent)) ? normalize(u) : perpendicularTo(n);
    const vec3 v = cross(n, u); // (u, v, n) right-handed
    Light light{};
    light.type = LIGHT_RECTANGLE;
    light.position = center;
    light.normal = n;
    light.axisU = 0.5f * size.x * u;
    light.axisV = 0.5f * size.y * v;
    light.radius = length(light.axisU + light.axisV);
    light.radiance = radiance;
    return light;
}

Light makeDiskLight(vec3 center, vec3 normal, float radius, vec3 radiance) {
    Light light{};
    light.type = LIGHT_DISK;
    light.position = center;
    light.normal = normalize(normal);
    light.radius = radius;
    // Axes span the disk plane (handy for samplers; not required by the type).
    light.axisU = radius * perpendicularTo(light.normal);
    light.axisV = cross(light.normal, light.axisU);
    light.radiance = radiance;
    return light;
}

Light makeSphereLight(vec3 center, float radius, vec3 radiance) {
    Light light{};
    light.type = LIGHT_SPHERE;
    light.position = center;
    light.normal = vec3(0.0f, 1.0f, 0.0f);
    light.radius = radius;
    light.radiance = radiance;
    return light;
}

Light makeDirectionalLight(vec3 towardsLight, float angularRadius, vec3 irradiance) {
    Light light{};
    light.type = LIGHT_DIRECTIONAL;
    light.position = vec3(0.0f);
    light.normal = normalize(towardsLight);
    light.radius = 0.0f;
    light.angularRadius = angularRadius;
    light.radiance = irradiance;
    return light;
}

float radianceForOutgoing(vec3 lightCenter, vec3 lightNormal, float area, vec3 p, vec3 n, float albedo,
                          float outgoing) {
    const vec3 d = lightCenter - p;
    const float dist2 = dot(d, d);
    const vec3 w = d / std::sqrt(dist2);
    const float cosP = std::max(dot(n, w), 0.05f);
    const float cosL = std::max(-dot(normalize(lightNormal), w), 0.05f);
    return outgoing * 3.14159265f * dist2 / (albedo * area * cosL * cosP);
}

Camera frameSphere(vec3 target, float radius, vec3 fromTarget, float fovY) {
    Camera camera;
    camera.target = target;
    camera.eye = target + normalize(fromTarget) * (radius / std::sin(0.5f * glm::radians(fovY)));
    camera.up = vec3(0.0f, 1.0f, 0.0f);
    camera.fovY = fovY;
    return camera;
}

Camera framePoints(const std::vector<vec3>& points, vec3 target, vec3 fromTarget, float fovY, float fill) {
    Bounds box;
    for (const vec3& p : points) box.extend(p);
    const float size = std::max(length(box.extent()), 1e-6f);
    Camera camera = frameSphere(target, 1.0f, fromTarget, fovY);
    const vec3 dir = normalize(fromTarget);
    auto fits = [&](float distance) {
        camera.eye = target + dir * distance;
        const mat4 clipFromWorld =
            clipFromView(camera, 1.0f, 1e-4f * size, 1e4f * size) * viewFromWorld(camera);
        for (const vec3& p : points) {
            const vec4 clip = clipFromWorld * vec4(p, 1.0f);
            if (clip.w <= 1e-4f * size) return false;
            if (std::abs(clip.x) > fill * clip.w || std::abs(clip.y) > fill * clip.w) return false;
        }
        return true;
    };
    // Once every point is in front, projected extents shrink with distance: bisect.
    float lo = 0.0f, hi = size + length(target - box.center());
    for (int i = 0; i < 60 && !fits(hi); ++i) hi *= 2.0f;
    for (int i = 0; i < 40; ++i) {
        const float mid = 0.5f * (lo + hi);
        (fits(mid) ? hi : lo) = mid;
    }
    camera.eye = target + dir * hi;
    return camera;
}

Camera frameBox(const Bounds& box, vec3 target, vec3 fromTarget, float fovY, float fill) {
    std::vector<vec3> corners;
    corners.reserve(8);
    for (int c = 0; c < 8; ++c)
        corners.emplace_back((c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                             (c & 4) ? box.hi.z : box.lo.z);
    return framePoints(corners, target, fromTarget, fovY, fill);
}

Scene makeMeshScene(const MeshData& mesh, const std::string& source) {
    Bounds b;
    for (const vec3& p : mesh.positions) b.extend(p);
    const float d = length(b.extent());
    if (b.empty() || !(d > 0.0f) || !std::isfinite(d))
        throw InputError(source, "mesh has zero or non-finite extent");
    Scene scene;
    scene.source = source;
    appendMesh(scene, mesh, mat4(1.0f), std::filesystem::path(source).stem().string());

    const vec3 c = b.center();
    const float groundY = b.lo.y - 1e-3f * d; // just below the mesh: no coplanar faces with it
    Material ground;
    ground.name = "ground";
    ground.albedo = vec3(0.7f);
    const std::uint32_t m = addMaterial(scene, ground);
    const float half = 3.0f * d;
    const vec3 g(c.x, groundY, c.z);
    const vec3 p0 = g + vec3(-half, 0.0f, -half), p1 = g + vec3(-half, 0.0f, half),
               p2 = g + vec3(half, 0.0f, half), p3 = g + vec3(half, 0.0f, -half);
    const auto first = static_cast<std::uint32_t>(scene.triangles.size());
    scene.addTriangle(p0, p1, p2, {0.0f, 0.0f}, {0.0f, 1.0f}, {1.0f, 1.0f}, m);
    scene.addTriangle(p0, p2, p3, {0.0f, 0.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, m);
    scene.meshes.push_back({"ground", first, 2});

    // Light above, behind (−z) and left of the mesh: the shadow falls forward-right, in view.
    const vec3 lightCenter(c.x - 0.5f * d, b.hi.y + 1.2f * d, c.z - 0.8f * d);
    const vec3 aim(c.x + 0.1f * d, groundY, c.z + 0.3f * d);
    const vec3 lightNormal = normalize(aim - lightCenter);
    const float size = 0.3f * d;
    const float radiance =
        radianceForOutgoing(lightCenter, lightNormal, size * size, vec3(c.x + 0.8f * d, groundY, c.z),
                            vec3(0.0f, 1.0f, 0.0f), 0.7f, 0.5f);
    scene.lights.push_back(
        makeRectangleLight(lightCenter, lightNormal, vec2(size), vec3(radiance), vec3(1.0f, 0.0f, 0.0f)));

    // The framed sphere holds the mesh's bounding sphere (centre c, radius d/2) and the ground in
    // front of it where the shadow falls.
    scene.camera = frameSphere(c + vec3(0.0f, 0.0f, 0.2f * d), 0.75f * d, vec3(0.45f, 0.5f, 1.0f), 40.0f);
    scene.validate();
    return scene;
}

} // namespace stsv
