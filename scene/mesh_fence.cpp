#include "scene/mesh_fence.h"

#include "core/error.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace stsv {

namespace {

/// Appends the closed box [lo, hi] with outward-facing (counter-clockwise) triangles.
void addBox(MeshData& mesh, vec3 lo, vec3 hi) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (int i = 0; i < 8; ++i) {
        mesh.positions.push_back(vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z));
        mesh.texcoords.push_back(vec2(0.0f));
    }
    // Quads as corner bits, counter-clockwise seen from outside.
    static const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
        mesh.triangles.push_back(uvec3(base + q[0], base + q[1], base + q[2]));
        mesh.triangles.push_back(uvec3(base + q[0], base + q[2], base + q[3]));
        mesh.triangleMaterial.insert(mesh.triangleMaterial.end(), 2, 0u);
    }
}

} // namespace

MeshData makeTexelBoxMesh(const Texture& texture, WrapMode wrap, vec2 size, vec2 uvRepeat,
                          const TexelBoxOptions& options) {
    if (texture.width < 1 || texture.height < 1 ||
        texture.rgba.size() < std::size_t(texture.width) * texture.height * 4)
        throw UsageError("texel boxes: texture '" + texture.name + "' is empty");
    if (!(size.x > 0.0f && size.y > 0.0f && uvRepeat.x > 0.0f && uvRepeat.y > 0.0f &&
          options.thickness > 0.0f))
        throw UsageError("texel boxes: quad size, texture repeat and thickness must be positive");
    MeshData mesh;
    Material material;
    material.name = "texel-boxes";
    mesh.materials.push_back(material);

    const double columnCount = std::ceil(double(uvRepeat.x) * texture.width);
    const double rowCount = std::ceil(double(uvRepeat.y) * texture.height);
    // The mesher visits every texel of the repeated texture; 2^28 of them take about ten seconds.
    if (columnCount * rowCount > double(MAX_TEXEL_BOX_TEXELS))
        throw UsageError("texel boxes: texture '" + texture.name + "' repeated " +
                         std::to_string(uvRepeat.x) + " x " + std::to_string(uvRepeat.y) + " times is " +
                         std::to_string(std::llround(columnCount)) + " x " +
                         std::to_string(std::llround(rowCount)) +
                         " texels, more than the 2^28 the mesher takes; "
                         "use a smaller repeat or texture_size");
    const int columns = static_cast<int>(columnCount);
    const int rows = static_cast<int>(rowCount);
    // Texel column i spans u ∈ [i, i+1]/width (clipped to the quad), x = −w/2 + u/U·w; row j spans
    // v ∈ [j, j+1]/height, y = h/2 − v/V·h (v runs down from the top edge, as in makeQuad).
    auto xOf = [&](int i) {
        const double u = std::min(double(i) / texture.width, double(uvRepeat.x));
        return float(-0.5 * size.x + u / uvRepeat.x * size.x);
    };
    auto yOf = [&](double j) {
        const double v = std::min(j / texture.height, double(uvRepeat.y));
        return float(0.5 * size.y - v / uvRepeat.y * size.y);
    };
    auto opaque = [&](int i, int j) {
        const int tx = wrap == WrapMode::Repeat ? i % texture.width : std::min(i, texture.width - 1);
        const int ty = wrap == WrapMode::Repeat ? j % texture.height : std::min(j, texture.height - 1);
        return texture.alpha(tx, ty) >= 128;
    };
    const float halfT = 0.5f * options.thickness;
    auto emit = [&](int i0, int i1, int j0, int j1) {
        if (mesh.triangles.size() % 49152 == 0) // every 4096 boxes, before the mesh outgrows the limit
            checkSceneMemory("texel boxes of texture '" + texture.name + "'",
                             double(mesh.triangles.size()) + 49152.0);
        addBox(mesh, vec3(xOf(i0), yOf(double(j1) - options.rowGap), -halfT),
               vec3(xOf(i1), yOf(double(j0) + options.rowGap), halfT));
    };

    std::map<std::pair<int, int>, int> open; // run [i0, i1) → first row of its rectangle
    std::vector<std::pair<int, int>> runs;
    for (int j = 0; j < rows; ++j) {
        runs.clear();
        for (int i = 0; i < columns;) {
            if (!opaque(i, j)) {
                ++i;
                continue;
            }
            const int i0 = i;
            while (i < columns && opaque(i, j)) ++i;
            runs.emplace_back(i0, i);
        }
        std::map<std::pair<int, int>, int> next;
        for (const auto& run : runs) {
            const auto it = open.find(run);
            if (options.mergeRows && it != open.end()) {
                next[run] = it->second;
                open.erase(it);
            } else {
                next[run] = j;
            }
        }
        for (const auto& [run, j0] : open) emit(run.first, run.second, j0, j);
        open = std::move(next);
    }
    for (const auto& [run, j0] : open) emit(run.first, run.second, j0, rows);
    return mesh;
}

Scene makeFenceMeshScene(const FenceParams& params, const TexelBoxOptions& options) {
    checkParam("fence-mesh", "light_size", FENCE_MESH_LIGHT_SIZE, params.lightSize);
    checkParam("fence-mesh", "repeat", FENCE_MESH_REPEAT, params.repeat);
    checkParam("fence-mesh", "texture_size", FENCE_MESH_TEXTURE_SIZE, params.textureSize);
    checkParam("fence-mesh", "thickness", TEXEL_BOX_THICKNESS, options.thickness);
    Scene scene = makeFenceScene(params);
    scene.source = "fence-mesh";
    if (scene.meshes.empty() || scene.meshes.back().name != "fence")
        throw Error("fence-mesh: the fence scene no longer ends with its fence quad");
    const Mesh fence = scene.meshes.back();
    scene.meshes.pop_back();
    const Material fenceMaterial = scene.materialOf(fence.firstTriangle);
    std::uint32_t firstVertex = static_cast<std::uint32_t>(scene.positions.size());
    for (std::uint32_t t = fence.firstTriangle; t < fence.firstTriangle + fence.triangleCount; ++t)
        for (int c = 0; c < 3; ++c) firstVertex = std::min(firstVertex, scene.triangles[t][c]);
    scene.triangles.resize(fence.firstTriangle);
    scene.triangleMaterial.resize(fence.firstTriangle);
    scene.positions.resize(firstVertex);
    scene.texcoords.resize(firstVertex);

    // The quad of makeFenceScene: 4 m × 2 m, centred 1 m up, repeat × max(1, repeat/2) tiles.
    const float repeatU = float(params.repeat), repeatV = std::max(1.0f, float(params.repeat) / 2.0f);
    const Texture& texture = scene.textures[std::size_t(fenceMaterial.alphaTexture)];
    const MeshData boxes =
        makeTexelBoxMesh(texture, fenceMaterial.wrap, vec2(4.0f, 2.0f), vec2(repeatU, repeatV), options);
    Material opaque;
    opaque.name = "chainlink-mesh";
    opaque.albedo = fenceMaterial.albedo;
    const std::uint32_t m = addMaterial(scene, opaque);
    appendMesh(scene, boxes, glm::translate(mat4(1.0f), vec3(0.0f, 1.0f, 0.0f)), "fence-mesh", int(m));
    scene.validate();
    return scene;
}

} // namespace stsv
