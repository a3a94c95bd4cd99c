// glTF 2.0 loading (scene/gltf_scene.h): files built here, as .gltf with an external buffer and
// image, as .gltf with both embedded as data URIs, and as .glb, each against the same scene in
// the JSON format; the alpha modes; node transforms and the camera; node trees, the memory limit
// on instances and images; texture coordinate sets and KHR_texture_transform; primitive modes;
// required extensions and versions; malformed files, .glb containers and fields of the wrong
// type or length, refused by JSON path; every glTF model of Debian's assimp-testmodels.
#include "core/image.h"
#include "core/memory_budget.h"
#include "scene/geometry.h"
#include "scene/gltf_scene.h"
#include "scene/json_scene.h"
#include "scene/load.h"
#include "tests/scene/scene_test_util.h"
#include "tests/support/zero_png.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace stsv {
namespace {

using test::expectError;
using test::TempDir;
using Json = nlohmann::json;

enum class Packing { External, Embedded, Binary };

std::string base64(const std::vector<std::uint8_t>& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t v = (std::uint32_t(bytes[i]) << 16) |
                                (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                                (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The test scene's alpha texture: 4 × 4 texels of alpha 0, 16, …, 240 in row order (row 0 at v = 0).
Image8 alphaRamp() {
    Image8 image;
    image.width = image.height = 4;
    image.channels = 4;
    for (int i = 0; i < 16; ++i)
        image.pixels.insert(image.pixels.end(), {200, 100, 50, std::uint8_t(16 * i)});
    return image;
}

/// A glTF of two quads: a ground (y = 0, opaque material) and a 1 m veil at y = 1 under a
/// parent node translated by (0, 1, 0), with `material` (its alpha fields) and the ramp texture.
/// `tweak` edits the JSON before it is written.
std::string writeGltf(const TempDir& dir, const std::string& name, Packing packing, const Json& material,
                      const std::function<void(Json&)>& tweak = {}) {
    writePng(dir.path("ramp.png"), alphaRamp());
    // Buffer: ground positions, veil positions, uvs (shared), indices (uint16).
    std::vector<float> floats = {-2, 0,     -2,   2, 0,    -2,    2, 0,    2, -2, 0, 2, -0.5f, 0, -0.5f, 0.5f,
                                 0,  -0.5f, 0.5f, 0, 0.5f, -0.5f, 0, 0.5f, 0, 0,  1, 0, 1,     1, 0,     1};
    const std::vector<std::uint16_t> indices = {0, 2, 1, 0, 3, 2};
    std::vector<std::uint8_t> bin(floats.size() * 4 + indices.size() * 2);
    std::memcpy(bin.data(), floats.data(), floats.size() * 4);
    std::memcpy(bin.data() + floats.size() * 4, indices.data(), indices.size() * 2);
    const std::size_t imageOffset = bin.size();
    const std::vector<std::uint8_t> png = readBytes(dir.path("ramp.png"));
    if (packing == Packing::Binary) bin.insert(bin.end(), png.begin(), png.end());
    while (bin.size() % 4) bin.push_back(0);

    Json j;
    j["asset"] = {{"version", "2.0"}};
    j["scene"] = 0;
    j["scenes"] = Json::array({{{"nodes", {0, 1}}}});
    j["nodes"] = Json::array({{{"mesh", 0}}, {{"translation", {0, 1, 0}}, {"children", {2}}}, {{"mesh", 1}}});
    const auto prim = [](int position, int materialIndex) {
        return Json{{"attributes", {{"POSITION", position}, {"TEXCOORD_0", 2}}},
                    {"indices", 3},
                    {"material", materialIndex}};
    };
    j["meshes"] = Json::array({{{"primitives", {prim(0, 0)}}}, {{"primitives", {prim(1, 1)}}}});
    j["accessors"] = Json::array({
        {{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
        {{"bufferView", 0}, {"byteOffset", 48}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
        {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
    });
    j["bufferViews"] = Json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 96}},
                                    {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
                                    {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}}});
    Json veil = {{"name", "veil"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};
    veil.update(material);
    j["materials"] = Json::array({{{"name", "ground"}}, veil});
    j["samplers"] = Json::array({{{"wrapS", 33071}, {"wrapT", 33071}}});
    j["textures"] = Json::array({{{"sampler", 0}, {"source", 0}}});
    Json buffer = {{"byteLength", bin.size()}};
    if (packing == Packing::External) {
        std::ofstream(dir.path(name + ".bin"), std::ios::binary)
            .write(reinterpret_cast<const char*>(bin.data()), std::streamsize(bin.size()));
        buffer["uri"] = name + ".bin";
        j["images"] = Json::array({{{"uri", "ramp.png"}}});
    } else if (packing == Packing::Embedded) {
        buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
        j["images"] = Json::array({{{"uri", "data:image/png;base64," + base64(png)}}});
    } else {
        j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", imageOffset}, {"byteLength", png.size()}});
        j["images"] = Json::array({{{"bufferView", 3}, {"mimeType", "image/png"}}});
    }
    j["buffers"] = Json::array({buffer});
    if (tweak) tweak(j);
    if (packing != Packing::Binary) return dir.write(name + ".gltf", j.dump());
    std::string text = j.dump();
    while (text.size() % 4) text += ' ';
    const auto u32 = [](std::string& out, std::uint32_t v) {
        out.append(reinterpret_cast<const char*>(&v), 4);
    };
    std::string glb = "glTF";
    u32(glb, 2);
    u32(glb, std::uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    u32(glb, std::uint32_t(text.size()));
    glb += "JSON" + text;
    u32(glb, std::uint32_t(bin.size()));
    glb += std::string("BIN\0", 4) + std::string(bin.begin(), bin.end());
    return dir.write(name + ".glb", glb);
}

/// The same two quads in the JSON scene format, the veil material given by `material`.
Scene jsonTwin(const TempDir& dir, const Json& material) {
    Json m = {{"name", "veil"}, {"alphaTexture", "ramp.png"}, {"alphaChannel", "alpha"}, {"wrap", "clamp"}};
    m.update(material);
    const Json quad = {{"vertices", {{-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}}},
                       {"texcoords", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
                       {"triangles", {{0, 2, 1}, {0, 3, 2}}}};
    Json veil = {{"vertices", {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}}},
                 {"texcoords", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
                 {"triangles", {{0, 2, 1}, {0, 3, 2}}}};
    Json ground = quad;
    ground["material"] = "ground";
    ground["name"] = "ground";
    veil["material"] = "veil";
    veil["name"] = "veil";
    const Json scene = {
        {"materials", {{{"name", "ground"}, {"albedo", 1.0}}, m}},
        {"meshes", {ground, veil}},
        {"lights", {{{"type", "sphere"}, {"position", {0, 3, 0}}, {"radius", 0.1}, {"radiance", 1}}}}};
    return loadJsonScene(dir.write("twin.json", scene.dump()));
}

/// The materials' alpha as the renderers see it, with the textures' alpha bytes they read.
void expectSameAlpha(const Scene& a, const MeshData& b) {
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t t = 0; t < a.triangles.size(); ++t) {
        const Material& ma = a.materialOf(t);
        const Material& mb = b.materials[b.triangleMaterial[t]];
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(a.positions[a.triangles[t][k]], b.positions[b.triangles[t][k]]) << "triangle " << t;
            EXPECT_EQ(a.texcoords[a.triangles[t][k]], b.texcoords[b.triangles[t][k]]) << "triangle " << t;
        }
        EXPECT_EQ(ma.alphaMode, mb.alphaMode);
        EXPECT_EQ(ma.alphaFactor, mb.alphaFactor);
        if (ma.alphaTexture >= 0 || ma.blendTexture >= 0) {
            EXPECT_EQ(ma.wrap, mb.wrap);
        }
        for (auto [ia, ib] :
             {std::pair(ma.alphaTexture, mb.alphaTexture), std::pair(ma.blendTexture, mb.blendTexture)}) {
            ASSERT_EQ(ia < 0, ib < 0);
            if (ia < 0) continue;
            const Texture& ta = a.textures[std::size_t(ia)];
            const Texture& tb = b.textures[std::size_t(ib)];
            ASSERT_EQ(ta.width, tb.width);
            for (int y = 0; y < ta.height; ++y)
                for (int x = 0; x < ta.width; ++x) EXPECT_EQ(ta.alpha(x, y), tb.alpha(x, y)) << x << "," << y;
        }
    }
}

TEST(Gltf, EveryPackingLoadsAsTheJsonTwin) {
    const TempDir dir;
    const Json modes[] = {
        {{"alphaMode", "BLEND"}}, {{"alphaMode", "MASK"}, {"alphaCutoff", 0.3}}, {{"alphaMode", "OPAQUE"}}};
    const Json jsonModes[] = {
        {{"alphaMode", "blend"}}, {{"alphaMode", "mask"}, {"alphaCutoff", 0.3}}, {{"alphaMode", "opaque"}}};
    for (int m = 0; m < 3; ++m)
        for (Packing packing : {Packing::External, Packing::Embedded, Packing::Binary}) {
            SCOPED_TRACE(modes[m].dump() + " packing " + std::to_string(int(packing)));
            const MeshData mesh =
                loadGltf(writeGltf(dir, "s" + std::to_string(int(packing)), packing, modes[m]));
            expectSameAlpha(jsonTwin(dir, jsonModes[m]), mesh);
        }
}

TEST(Gltf, AlphaModesFollowTheSpecification) {
    const TempDir dir;
    // BLEND: the texture's alpha times baseColorFactor's; the stand-in mask is α ≥ 0.5.
    MeshData blend =
        loadGltf(writeGltf(dir, "blend", Packing::External,
                           {{"alphaMode", "BLEND"},
                            {"pbrMetallicRoughness",
                             {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 1, 1, 0.5}}}}}));
    const Material& b = blend.materials[blend.triangleMaterial[2]];
    EXPECT_TRUE(b.translucent());
    EXPECT_EQ(b.alphaFactor, 0.5f);
    ASSERT_GE(b.blendTexture, 0);
    EXPECT_EQ(blend.textures[std::size_t(b.blendTexture)].alpha(1, 2), 16 * 9);
    // 144/255 · 0.5 < 0.5 and 240/255 · 0.5 < 0.5: the stand-in never blocks.
    ASSERT_GE(b.alphaTexture, 0);
    for (int i = 0; i < 16; ++i)
        EXPECT_EQ(blend.textures[std::size_t(b.alphaTexture)].alpha(i % 4, i / 4), 0);
    // MASK with cutoff 0.3: alpha bytes ≥ 76.5 block (80 and up).
    MeshData mask =
        loadGltf(writeGltf(dir, "mask", Packing::External, {{"alphaMode", "MASK"}, {"alphaCutoff", 0.3}}));
    const Material& k = mask.materials[mask.triangleMaterial[2]];
    ASSERT_GE(k.alphaTexture, 0);
    for (int i = 0; i < 16; ++i)
        EXPECT_EQ(mask.textures[std::size_t(k.alphaTexture)].alpha(i % 4, i / 4), 16 * i >= 77 ? 255 : 0)
            << i;
    // MASK at the default cutoff keeps the texture as it is (alpha byte ≥ 128 blocks).
    MeshData half = loadGltf(writeGltf(dir, "half", Packing::External, {{"alphaMode", "MASK"}}));
    EXPECT_EQ(half.textures[std::size_t(half.materials[half.triangleMaterial[2]].alphaTexture)].alpha(1, 0),
              16);
    // OPAQUE ignores the texture's alpha; the ground (default OPAQUE) too.
    MeshData opaque = loadGltf(writeGltf(dir, "opaque", Packing::External, {{"alphaMode", "OPAQUE"}}));
    EXPECT_EQ(opaque.materials[opaque.triangleMaterial[2]].alphaTexture, -1);
    EXPECT_EQ(opaque.materials[opaque.triangleMaterial[0]].alphaTexture, -1);
    EXPECT_FALSE(opaque.materials[opaque.triangleMaterial[0]].doubleSided);
}

TEST(Gltf, NodeTransformsAndTheCameraApply) {
    const TempDir dir;
    const std::string path =
        writeGltf(dir, "camera", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
            // The veil's parent: scaled by 2 and turned 90° about y; a camera node looking down −z from z
            // = 5.
            j["nodes"][1] = {{"translation", {0, 1, 0}},
                             {"rotation", {0, 0.70710678, 0, 0.70710678}},
                             {"scale", {2, 2, 2}},
                             {"children", {2}}};
            j["nodes"].push_back({{"camera", 0}, {"translation", {0, 0.5, 5}}});
            j["scenes"][0]["nodes"].push_back(3);
            j["cameras"] =
                Json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}});
        });
    std::optional<Camera> camera;
    const MeshData mesh = loadGltf(path, &camera);
    // Veil corner (−0.5, 0, −0.5): scaled (−1, 0, −1), turned +90° about y (x → −z, z → x): (−1, 0, 1),
    // lifted.
    const vec3 corner = mesh.positions[4];
    EXPECT_NEAR(corner.x, -1.0f, 1e-5f);
    EXPECT_NEAR(corner.y, 1.0f, 1e-5f);
    EXPECT_NEAR(corner.z, 1.0f, 1e-5f);
    ASSERT_TRUE(camera.has_value());
    EXPECT_EQ(camera->eye, vec3(0.0f, 0.5f, 5.0f));
    EXPECT_EQ(camera->target, vec3(0.0f, 0.5f, 4.0f));
    EXPECT_NEAR(camera->fovY, 28.6479f, 1e-3f);
    // As a scene: the file's camera, the default light, a ground under the mesh.
    const Scene scene = loadScene(path);
    EXPECT_EQ(scene.camera.eye, vec3(0.0f, 0.5f, 5.0f));
    EXPECT_EQ(scene.lights.size(), 1u);
}

TEST(Gltf, AsAMeshOfAJsonScene) {
    const TempDir dir;
    writeGltf(dir, "part", Packing::Binary, {{"alphaMode", "BLEND"}});
    const Json scene = {
        {"meshes", {{{"name", "part"}, {"file", "part.glb"}}}},
        {"lights", {{{"type", "sphere"}, {"position", {0, 3, 0}}, {"radius", 0.1}, {"radiance", 1}}}}};
    const Scene s = loadJsonScene(dir.write("scene.json", scene.dump()));
    EXPECT_EQ(s.triangleCount(), 4u);
    EXPECT_TRUE(s.hasTranslucent());
}

TEST(Gltf, BadFilesNameTheFileAndTheProblem) {
    const TempDir dir;
    const Json mask = {{"alphaMode", "MASK"}};
    const auto bad = [&](const std::string& name, const std::function<void(Json&)>& tweak,
                         const std::vector<std::string>& parts) {
        const std::string path = writeGltf(dir, name, Packing::External, mask, tweak);
        std::vector<std::string> all = parts;
        all.push_back(path);
        expectError<InputError>([&] { loadGltf(path); }, all);
    };
    bad("mode", [](Json& j) { j["meshes"][0]["primitives"][0]["mode"] = 7; },
        {"meshes[0].primitives[0].mode: expected a primitive mode, an integer from 0 to 6, got 7"});
    bad("outside", [](Json& j) { j["accessors"][1]["count"] = 400; }, {"reaches outside its buffer"});
    bad("stride", [](Json& j) { j["bufferViews"][0]["byteStride"] = 8; }, {"byte stride"});
    bad("index", [](Json& j) { j["accessors"][3]["count"] = 5; }, {"not a multiple of 3"});
    bad("mirror",
        [](Json& j) {
            j["samplers"][0] = {{"wrapS", 33648}, {"wrapT", 33648}};
        },
        {"wrap mode 33648"});
    bad("mixed",
        [](Json& j) {
            j["samplers"][0] = {{"wrapS", 33071}, {"wrapT", 10497}};
        },
        {"different wrap modes"});
    bad("alpha", [](Json& j) { j["materials"][1]["alphaMode"] = "GLASS"; }, {"alphaMode"});
    bad("beyond",
        [](Json& j) {
            j["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
            j["accessors"][0]["count"] = 2;
        },
        {"index 2 is beyond its 2 vertices"});
    bad("empty", [](Json& j) { j["scenes"][0]["nodes"] = Json::array(); }, {"has no triangles"});
    bad("image", [](Json& j) { j["images"][0]["uri"] = "missing.png"; }, {"missing.png"});
    bad("cycle", [](Json& j) { j["nodes"][2]["children"] = Json::array({1}); },
        {"node 1 is a root of scene 0 and a child of node 2"});
    bad("infinite",
        [](Json& j) {
            j["nodes"][0]["translation"] = {1e30, 0, 0};
        },
        {"mesh 0 primitive 0 vertex 0 of node 0", "beyond"});
    expectError<InputError>([&] { loadGltf(dir.write("garbage.gltf", "{ not json")); },
                            {"garbage.gltf", "glTF: invalid JSON: parse error at line 1, column"});
    expectError<InputError>([&] { loadGltf(dir.write("garbage.glb", "glTF\x02")); },
                            {"garbage.glb", "is 5 bytes long, too short for the 12-byte header"});
    expectError<InputError>([&] { loadGltf(dir.path("absent.glb")); }, {"absent.glb"});
}

/// A glTF made in a test: accessors over one buffer embedded as a data URI, meshes, nodes under
/// scene 0, written as .gltf.
struct GltfBuilder {
    Json j = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", Json::array({{{"nodes", Json::array()}}})},
              {"nodes", Json::array()},
              {"meshes", Json::array()},
              {"accessors", Json::array()},
              {"bufferViews", Json::array()}};
    std::vector<std::uint8_t> bin;

    /// An accessor of `type` ("VEC3", "VEC2", "SCALAR") over `values`, floats or (`indices`)
    /// uint16; its index.
    int accessor(const std::vector<float>& values, const char* type, bool indices = false) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        for (float v : values) {
            if (indices) {
                const auto u = std::uint16_t(v);
                bin.insert(bin.end(), {std::uint8_t(u & 0xff), std::uint8_t(u >> 8)});
            } else {
                std::uint8_t b[4];
                std::memcpy(b, &v, 4);
                bin.insert(bin.end(), b, b + 4);
            }
        }
        const int components = std::string(type) == "VEC3" ? 3 : std::string(type) == "VEC2" ? 2 : 1;
        j["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bin.size() - offset}});
        j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1},
                                  {"componentType", indices ? 5123 : 5126},
                                  {"count", values.size() / std::size_t(components)},
                                  {"type", type}});
        return int(j["accessors"].size() - 1);
    }
    /// A mesh of `primitives` drawn by a new root node; the mesh's index.
    int mesh(const Json& primitives) {
        j["meshes"].push_back({{"primitives", primitives}});
        j["nodes"].push_back({{"mesh", j["meshes"].size() - 1}});
        j["scenes"][0]["nodes"].push_back(j["nodes"].size() - 1);
        return int(j["meshes"].size() - 1);
    }
    std::string write(const TempDir& dir, const std::string& name) {
        j["buffers"] = Json::array(
            {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return dir.write(name + ".gltf", j.dump());
    }
};

/// Sets the memory limit for one test and restores the default after it.
struct MemoryLimitForTest {
    explicit MemoryLimitForTest(std::uint64_t bytes) { setMemoryLimit(bytes); }
    ~MemoryLimitForTest() { setMemoryLimit(0); }
};

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(Gltf, NodesReachedTwiceAreRefusedByIndex) {
    const TempDir dir;
    // `levels` nodes, each listing the next twice: 2^levels paths to the last one, which draws the
    // ground quad (2 triangles).
    const auto doubling = [&](int levels) {
        return writeGltf(dir, "doubling" + std::to_string(levels), Packing::External, {{"alphaMode", "MASK"}},
                         [levels](Json& j) {
                             j["nodes"] = Json::array();
                             for (int i = 0; i + 1 < levels; ++i)
                                 j["nodes"].push_back({{"children", {i + 1, i + 1}}});
                             j["nodes"].push_back({{"mesh", 0}});
                             j["scenes"][0]["nodes"] = {0};
                         });
    };
    // 10 levels (1024 instances of the quad) first: read as it stands, it would load.
    ASSERT_NO_FATAL_FAILURE(expectError<InputError>([&] { loadGltf(doubling(10)); },
                                                    {"node 1 is listed twice among node 0's children"}));
    // 40 levels, 2^40 instances from a file of 2 KB: refused at once, not after flattening.
    const auto start = std::chrono::steady_clock::now();
    expectError<InputError>([&] { loadGltf(doubling(40)); }, {"doubling40.gltf", "node 1 is listed twice"});
    EXPECT_LT(secondsSince(start), 2.0);
    // Two parents; a node listed twice among a scene's roots.
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "parents", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
                j["nodes"].push_back({{"children", {2}}});
                j["scenes"][0]["nodes"].push_back(3);
            }));
        },
        {"node 2 has two parents, nodes 1 and 3"});
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "roots", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
                j["scenes"][0]["nodes"] = {0, 1, 0};
            }));
        },
        {"node 0 is listed twice among scene 0's nodes"});
}

TEST(Gltf, InstancesAreHeldToTheMemoryLimitBeforeFlattening) {
    const TempDir dir;
    // 2000 nodes drawing the same quad (a valid glTF: meshes may be shared): 4000 triangles, about
    // 10 MB at SCENE_BYTES_PER_TRIANGLE, above a limit of 4 MiB, though each primitive alone
    // (4 vertices) is far below it.
    const std::string path = writeGltf(dir, "many", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
        j["nodes"] = Json::array();
        for (int i = 0; i < 2000; ++i) j["nodes"].push_back({{"mesh", 0}, {"translation", {3.0 * i, 0, 0}}});
        j["scenes"][0]["nodes"] = Json::array();
        for (int i = 0; i < 2000; ++i) j["scenes"][0]["nodes"].push_back(i);
    });
    EXPECT_EQ(loadGltf(path).triangles.size(), 4000u);
    const MemoryLimitForTest limit(std::uint64_t(4) << 20);
    expectError<UsageError>([&] { loadGltf(path); },
                            {"many.gltf", "2000 mesh instances, 4000 triangles", "memory limit of 4.0 MiB"});
}

TEST(Gltf, ImagesAreHeldToTheMemoryLimitBeforeDecoding) {
    const TempDir dir;
    // 4096² grey texels in 106 KB (tests/support/zero_png.h), 64 MiB as RGBA8 and about 128 MiB
    // at the decoder's peak (8 bytes a texel, PNG8_PEAK_BYTES_PER_PIXEL): refused below that,
    // named with its size and the limit, before anything is decoded.
    dir.write("big.png", test::zeroPng(4096));
    const std::string path = writeGltf(dir, "big", Packing::External, {{"alphaMode", "MASK"}},
                                       [](Json& j) { j["images"][0]["uri"] = "big.png"; });
    {
        const MemoryLimitForTest limit(std::uint64_t(100) << 20);
        expectError<UsageError>([&] { loadGltf(path); }, {"big.gltf", "image 0 'big.png'", "4096x4096 pixels",
                                                          "memory limit of 100.0 MiB"});
    }
    // Under the default limit it loads: the veil's mask is the image's alpha, 255 for grey.
    const MeshData mesh = loadGltf(path);
    const Material& veil = mesh.materials[mesh.triangleMaterial[2]];
    ASSERT_GE(veil.alphaTexture, 0);
    const Texture& mask = mesh.textures[std::size_t(veil.alphaTexture)];
    EXPECT_EQ(mask.width, 4096);
    EXPECT_EQ(mask.height, 4096);
    EXPECT_EQ(mask.alpha(4095, 4095), 255);
    EXPECT_EQ(mask.rgba[0], 0);
    // 2048² texels decode within 48 MiB (32 MiB at the peak), but a cutoff of 0.3 bakes a second
    // texture from the first, and the scene copies both: 64 MiB, refused before the copy.
    dir.write("mid.png", test::zeroPng(2048));
    const std::string baked =
        writeGltf(dir, "baked", Packing::External, {{"alphaMode", "MASK"}, {"alphaCutoff", 0.3}},
                  [](Json& j) { j["images"][0]["uri"] = "mid.png"; });
    const MemoryLimitForTest limit(std::uint64_t(48) << 20);
    expectError<UsageError>([&] { loadGltf(baked); },
                            {"baked.gltf", "textures, held twice while the scene is assembled", "64.0 MiB"});
}

TEST(Gltf, TexCoordNamesTheSetTheAlphaReads) {
    const TempDir dir;
    GltfBuilder b;
    const int positions = b.accessor({0, 0, 0, 1, 0, 0, 1, 1, 0}, "VEC3");
    const int uv0 = b.accessor({0, 0, 1, 0, 1, 1}, "VEC2");
    const int uv1 = b.accessor({0.25f, 0.5f, 0.75f, 0.5f, 0.75f, 1}, "VEC2");
    b.j["images"] = Json::array({{{"uri", "ramp.png"}}});
    b.j["textures"] = Json::array({{{"source", 0}}});
    b.j["materials"] =
        Json::array({{{"name", "veil"},
                      {"alphaMode", "MASK"},
                      {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}});
    writePng(dir.path("ramp.png"), alphaRamp());
    b.mesh(Json::array({{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}},
                         {"material", 0}}}));
    const MeshData mesh = loadGltf(b.write(dir, "set1"));
    ASSERT_EQ(mesh.texcoords.size(), 3u);
    EXPECT_EQ(mesh.texcoords[0], vec2(0.25f, 0.5f));
    EXPECT_EQ(mesh.texcoords[2], vec2(0.75f, 1.0f));
    // Without TEXCOORD_1 the mask would read texel (0, 0) everywhere: refused, by name.
    b.j["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_1");
    expectError<InputError>([&] { loadGltf(b.write(dir, "missing")); },
                            {"missing.gltf", "material 0 'veil'", "TEXCOORD_1", "mesh 0 primitive 0 lacks"});
}

TEST(Gltf, TextureTransformMovesTheTexcoordsTheAlphaReads) {
    const TempDir dir;
    const auto transformed = [&](const std::string& name, const Json& transform) {
        const std::string path =
            writeGltf(dir, name, Packing::External, {{"alphaMode", "MASK"}}, [&](Json& j) {
                j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
                    {"KHR_texture_transform", transform}};
                j["extensionsUsed"] = {"KHR_texture_transform"};
                j["extensionsRequired"] = {"KHR_texture_transform"};
            });
        // The veil's corners (its texcoords (0, 0), (1, 0), (1, 1), (0, 1)) as the scene gets them.
        const Scene scene = loadScene(path);
        std::vector<vec2> corners;
        for (std::size_t v = 4; v < 8; ++v) corners.push_back(scene.texcoords[v]);
        return corners;
    };
    const auto expectNear = [](const std::vector<vec2>& got, const std::vector<vec2>& want) {
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t i = 0; i < got.size(); ++i) {
            // float products of sines and cosines: a few ulps of 1.
            EXPECT_NEAR(got[i].x, want[i].x, 1e-6f) << "corner " << i;
            EXPECT_NEAR(got[i].y, want[i].y, 1e-6f) << "corner " << i;
        }
    };
    // The extension's own example: offset [0, 1], rotation π/2, scale 0.5 read the lower left
    // quadrant turned a quarter (u' = cos·0.5u + sin·0.5v, v' = −sin·0.5u + cos·0.5v + 1):
    // (0, 0) → (0, 1), (1, 0) → (0, 0.5), (1, 1) → (0.5, 0.5), (0, 1) → (0.5, 1).
    expectNear(
        transformed("example", {{"offset", {0, 1}}, {"rotation", 1.5707963267948966}, {"scale", {0.5, 0.5}}}),
        {{0.0f, 1.0f}, {0.0f, 0.5f}, {0.5f, 0.5f}, {0.5f, 1.0f}});
    // Scale before rotation (T·R·S): scale [2, 1] then a quarter turn takes (1, 0) to (0, −2),
    // where rotation first would give (0, −1); (0, 1) to (1, 0); offset [0.25, 0] after both.
    expectNear(
        transformed("order", {{"offset", {0.25, 0}}, {"rotation", 1.5707963267948966}, {"scale", {2, 1}}}),
        {{0.25f, 0.0f}, {0.25f, -2.0f}, {1.25f, -2.0f}, {1.25f, 0.0f}});
    // Offset alone moves the hole: the ramp's alpha-0 texel (0, 0) is read at uv (0.5, 0.5) − offset.
    expectNear(transformed("offset", {{"offset", {0.5, -0.25}}}),
               {{0.5f, -0.25f}, {1.5f, -0.25f}, {1.5f, 0.75f}, {0.5f, 0.75f}});
    // The extension's texCoord overrides the reference's; malformed values are refused.
    const std::string two = writeGltf(dir, "two", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
        j["accessors"].push_back(
            {{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
        j["meshes"][1]["primitives"][0]["attributes"]["TEXCOORD_3"] = 4;
        j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
            {"KHR_texture_transform", {{"texCoord", 3}}}};
    });
    // TEXCOORD_3 reads the ground's first floats as pairs: (−2, 0), (−2, 2), (0, −2), (2, 0).
    const MeshData mesh = loadGltf(two);
    EXPECT_EQ(mesh.texcoords[4], vec2(-2.0f, 0.0f));
    EXPECT_EQ(mesh.texcoords[7], vec2(2.0f, 0.0f));
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "bad", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
                j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
                    {"KHR_texture_transform", {{"scale", {1, "wide"}}}}};
            }));
        },
        {"material 1 'veil' baseColorTexture KHR_texture_transform scale must be a finite number"});
}

TEST(Gltf, StripsAndFansAreReadPointsAndLinesSkippedWithAWarning) {
    const TempDir dir;
    // Five vertices on the unit square's corners and its centre.
    const std::vector<float> square = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0.5f, 0.5f, 0};
    const auto corners = [](const MeshData& mesh) {
        std::vector<std::uint32_t> out;
        for (const uvec3& t : mesh.triangles) out.insert(out.end(), {t.x, t.y, t.z});
        return out;
    };
    // A strip 0 1 2 3 (not indexed): triangles (0 1 2) and (1 3 2), the second's order swapped so
    // both are wound counter-clockwise seen from +z.
    GltfBuilder strip;
    strip.mesh(Json::array({{{"attributes", {{"POSITION", strip.accessor(square, "VEC3")}}}, {"mode", 5}}}));
    // 5 vertices: (0 1 2), (1 3 2), (2 3 4).
    EXPECT_EQ(corners(loadGltf(strip.write(dir, "strip"))),
              (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
    // Indexed strip 4 0 1 3: (4 0 1), (0 3 1).
    GltfBuilder indexedStrip;
    indexedStrip.mesh(Json::array({{{"attributes", {{"POSITION", indexedStrip.accessor(square, "VEC3")}}},
                                    {"indices", indexedStrip.accessor({4, 0, 1, 3}, "SCALAR", true)},
                                    {"mode", 5}}}));
    EXPECT_EQ(corners(loadGltf(indexedStrip.write(dir, "indexed_strip"))),
              (std::vector<std::uint32_t>{4, 0, 1, 0, 3, 1}));
    // Fan around the centre, indexed 4 0 1 3 2 0: (0 1 4), (1 3 4), (3 2 4), (2 0 4).
    GltfBuilder fan;
    fan.mesh(Json::array({{{"attributes", {{"POSITION", fan.accessor(square, "VEC3")}}},
                           {"indices", fan.accessor({4, 0, 1, 3, 2, 0}, "SCALAR", true)},
                           {"mode", 6}}}));
    EXPECT_EQ(corners(loadGltf(fan.write(dir, "fan"))),
              (std::vector<std::uint32_t>{0, 1, 4, 1, 3, 4, 3, 2, 4, 2, 0, 4}));
    // Not indexed: (1 2 0), (2 3 0), (3 4 0).
    GltfBuilder plainFan;
    plainFan.mesh(
        Json::array({{{"attributes", {{"POSITION", plainFan.accessor(square, "VEC3")}}}, {"mode", 6}}}));
    EXPECT_EQ(corners(loadGltf(plainFan.write(dir, "plain_fan"))),
              (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
    // Points and lines beside triangles: skipped, counted in a warning the scene carries.
    GltfBuilder mixed;
    const int p = mixed.accessor(square, "VEC3");
    mixed.mesh(Json::array({{{"attributes", {{"POSITION", p}}}, {"mode", 0}},
                            {{"attributes", {{"POSITION", p}}},
                             {"mode", 1},
                             {"indices", mixed.accessor({0, 1}, "SCALAR", true)}},
                            {{"attributes", {{"POSITION", p}}},
                             {"mode", 4},
                             {"indices", mixed.accessor({0, 1, 2}, "SCALAR", true)}}}));
    const std::string path = mixed.write(dir, "mixed");
    const MeshData mesh = loadGltf(path);
    EXPECT_EQ(mesh.triangles.size(), 1u);
    const Scene scene = loadScene(path);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("2 glTF primitives of points or lines"), std::string::npos)
        << scene.warnings[0];
    // A strip of two indices is no triangle.
    GltfBuilder shortStrip;
    shortStrip.mesh(Json::array({{{"attributes", {{"POSITION", shortStrip.accessor(square, "VEC3")}}},
                                  {"indices", shortStrip.accessor({0, 1}, "SCALAR", true)},
                                  {"mode", 5}}}));
    expectError<InputError>([&] { loadGltf(shortStrip.write(dir, "short")); },
                            {"mesh 0 primitive 0 has 2 indices, fewer than the 3 of a strip"});
}

TEST(Gltf, MorphTargetsAndSkinsPoseTheMeshAsTheNodesGiveIt) {
    const TempDir dir;
    // A triangle with one morph target that lifts its vertices by (0, 1, 0), (0, 2, 0), (0, 4, 0).
    GltfBuilder b;
    const int positions = b.accessor({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
    const int lift = b.accessor({0, 1, 0, 0, 2, 0, 0, 4, 0}, "VEC3");
    b.mesh(Json::array({{{"attributes", {{"POSITION", positions}}}, {"targets", {{{"POSITION", lift}}}}}}));
    b.j["meshes"][0]["weights"] = {0.5};
    const MeshData half = loadGltf(b.write(dir, "morph"));
    EXPECT_EQ(half.positions[0], vec3(0.0f, 0.5f, 0.0f));
    EXPECT_EQ(half.positions[2], vec3(0.0f, 3.0f, 0.0f));
    // The node's weights take the mesh's place.
    b.j["nodes"][0]["weights"] = {0.25};
    EXPECT_EQ(loadGltf(b.write(dir, "node_weights")).positions[1], vec3(1.0f, 0.5f, 0.0f));
    b.j["nodes"][0]["weights"] = {0.25, 1.0};
    expectError<InputError>([&] { loadGltf(b.write(dir, "two_weights")); },
                            {"mesh 0 primitive 0 has 1 morph targets and 2 weights"});
    // A malformed target is refused whatever its weight: at 0, and without weights (all 0).
    b.j["nodes"][0].erase("weights");
    b.j["meshes"][0]["weights"] = {0.0};
    b.j["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = 99;
    expectError<InputError>(
        [&] { loadGltf(b.write(dir, "target_99")); },
        {"target_99.gltf", "mesh 0 primitive 0 morph target 0 POSITION: accessor 99 does not exist"});
    b.j["meshes"][0].erase("weights");
    expectError<InputError>([&] { loadGltf(b.write(dir, "target_99_unweighted")); },
                            {"target_99_unweighted.gltf", "accessor 99 does not exist"});
    b.j["meshes"][0]["weights"] = {0.0};
    b.j["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = b.accessor({0, 1, 0, 1}, "VEC2");
    expectError<InputError>([&] { loadGltf(b.write(dir, "target_vec2")); },
                            {"mesh 0 primitive 0 morph target 0 POSITION", "has the wrong type"});
    b.j["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = lift;
    // A skinned node without JOINTS_0 and WEIGHTS_0 cannot be posed.
    b.j["nodes"][0].erase("weights");
    b.j["nodes"][0]["skin"] = 0;
    b.j["skins"] = Json::array({{{"joints", {0}}}});
    expectError<InputError>(
        [&] { loadGltf(b.write(dir, "unweighted")); },
        {"mesh 0 primitive 0 has no JOINTS_0 and WEIGHTS_0, though node 0 gives it skin 0"});
}

TEST(Gltf, RequiredExtensionsAndOtherVersionsAreRefusedByName) {
    const TempDir dir;
    const auto with = [&](const std::string& name, const std::function<void(Json&)>& tweak) {
        return writeGltf(dir, name, Packing::External, {{"alphaMode", "MASK"}}, tweak);
    };
    expectError<InputError>(
        [&] {
            loadGltf(with("draco", [](Json& j) {
                j["extensionsUsed"] = {"KHR_draco_mesh_compression", "KHR_texture_transform"};
                j["extensionsRequired"] = {"KHR_draco_mesh_compression", "KHR_texture_transform"};
            }));
        },
        {"draco.gltf", "extensionsRequired names KHR_draco_mesh_compression,", "does not implement"});
    // Merely used, an extension is ignored; KHR_texture_transform may be required.
    EXPECT_EQ(loadGltf(with("used", [](Json& j) { j["extensionsUsed"] = {"KHR_materials_unlit"}; }))
                  .triangles.size(),
              4u);
    EXPECT_EQ(
        loadGltf(with("transform", [](Json& j) { j["extensionsRequired"] = {"KHR_texture_transform"}; }))
            .triangles.size(),
        4u);
    expectError<InputError>([&] { loadGltf(with("v3", [](Json& j) { j["asset"]["version"] = "3.0"; })); },
                            {"v3.gltf", "asset.version is 3.0", "glTF 2.x only"});
    expectError<InputError>([&] { loadGltf(with("v1", [](Json& j) { j["asset"]["version"] = "1.0"; })); },
                            {"asset.version is 1.0"});
    expectError<InputError>([&] { loadGltf(with("min", [](Json& j) { j["asset"]["minVersion"] = "2.1"; })); },
                            {"asset.minVersion is 2.1, above the glTF 2.0"});
    EXPECT_EQ(loadGltf(with("v21", [](Json& j) { j["asset"]["version"] = "2.1"; })).triangles.size(), 4u);
}

TEST(Gltf, UrisThatNameNoRegularFileAreRefusedByName) {
    const TempDir dir;
    // tinygltf's own reader takes a directory for a file of 2^63 bytes and ends in std::bad_alloc.
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "dot", Packing::External, {{"alphaMode", "MASK"}},
                               [](Json& j) { j["buffers"][0]["uri"] = "."; }));
        },
        {"dot.gltf", "buffer 0 uri \".\" is a directory, not a file"});
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "gone", Packing::External, {{"alphaMode", "MASK"}},
                               [](Json& j) { j["buffers"][0]["uri"] = "absent.bin"; }));
        },
        {"gone.gltf", "buffer 0 uri \"absent.bin\" does not exist"});
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "image_dot", Packing::External, {{"alphaMode", "MASK"}},
                               [](Json& j) { j["images"][0]["uri"] = "."; }));
        },
        {"image_dot.gltf", "image 0 '.'", "is a directory"});
    // An image's buffer view outside its buffer (tinygltf hands such bytes over unchecked).
    expectError<InputError>(
        [&] {
            loadGltf(writeGltf(dir, "view", Packing::Binary, {{"alphaMode", "MASK"}},
                               [](Json& j) { j["bufferViews"][3]["byteLength"] = 1 << 20; }));
        },
        {"view.glb", "image 0", "buffer view 3 reaches outside its buffer"});
    // An empty uri: tinygltf's own message names neither the buffer nor the image.
    for (const char* list : {"buffers", "images"})
        expectError<InputError>(
            [&] {
                loadGltf(writeGltf(dir, std::string("empty_") + list, Packing::External,
                                   {{"alphaMode", "MASK"}}, [&](Json& j) { j[list][0]["uri"] = ""; }));
            },
            {std::string("empty_") + list + ".gltf", std::string("glTF: ") + list + "[0].uri is empty"});
}

/// `glb` with the little-endian 32-bit word at byte `offset` set to `value`.
std::string patched(std::string glb, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) glb[offset + std::size_t(i)] = char(value >> (8 * i) & 0xff);
    return glb;
}

TEST(Gltf, GlbContainersAreRefusedBySayingWhatIsWrong) {
    const TempDir dir;
    // A valid .glb: the 12-byte header (magic, version, length), the JSON chunk (length, "JSON",
    // text), the BIN chunk (length, "BIN\0", bytes).
    const std::string path = writeGltf(dir, "good", Packing::Binary, {{"alphaMode", "MASK"}});
    ASSERT_EQ(loadGltf(path).triangles.size(), 4u);
    std::string good;
    for (std::uint8_t byte : readBytes(path)) good += char(byte);
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, good.data() + 12, 4);
    const std::size_t bin = 20 + jsonLength; ///< where the BIN chunk's header begins
    const auto size = [](std::size_t n) { return std::uint32_t(n); };
    const std::pair<std::string, std::vector<std::string>> cases[] = {
        {"", {"is 0 bytes long, too short for the 12-byte header of a binary glTF"}},
        {good.substr(0, 8), {"is 8 bytes long, too short for the 12-byte header"}},
        {good.substr(0, 12),
         {"the header gives the file a length of " + std::to_string(good.size()) +
          " bytes, but it has 12 (a truncated file?)"}},
        {patched(good.substr(0, 12), 8, 12), {"has no JSON chunk: the file ends after its 12-byte header"}},
        {patched(good.substr(0, 16), 8, 16), {"ends 4 bytes into the 8-byte header of chunk 0"}},
        {patched(good.substr(0, 60), 8, 60),
         {"chunk 0 (type \"JSON\") has a length of " + std::to_string(jsonLength) +
          " bytes, beyond the file's end (40 bytes follow its header)"}},
        {patched(good, 12, 0x7ffffff0), {"chunk 0 (type \"JSON\") has a length of 2147483632 bytes, beyond"}},
        {patched(good, 16, 0x58585858), {"its first chunk is of type \"XXXX\", not \"JSON\""}},
        {patched(good, 12, 0), {"its JSON chunk is empty"}},
        {patched(good, bin, 0xfffffff0), {"chunk 1 (type \"BIN\") has a length of 4294967280 bytes, beyond"}},
        {patched(good, bin + 4, 0x41544144),
         {"its second chunk is of type \"DATA\", where only a BIN chunk"}},
        {patched(good.substr(0, good.size() - 4), 8, size(good.size() - 4)),
         {"chunk 1", "beyond the file's end"}},
        {patched(patched(good, bin, 2), 8, size(bin + 10)).substr(0, bin + 10),
         {"its BIN chunk's length, 2 bytes, is not a multiple of 4"}},
        {patched(good, 8, size(good.size() + 1)), {"a length of " + std::to_string(good.size() + 1)}},
        {patched(good, 0, 0x46544c67), {"does not begin with \"glTF\", the magic of a binary glTF"}},
        // Without the BIN chunk, the buffer without a uri has no data.
        {patched(good.substr(0, bin), 8, size(bin)),
         {"buffers[0] has no uri, and the .glb has no BIN chunk"}},
    };
    int n = 0;
    for (const auto& [bytes, parts] : cases) {
        const std::string name = "case" + std::to_string(n++) + ".glb";
        SCOPED_TRACE(name);
        std::vector<std::string> all = parts;
        all.push_back(name);
        expectError<InputError>([&, &glb = bytes] { loadGltf(dir.write(name, glb)); }, all);
    }
    // A buffer longer than the BIN chunk, and a second buffer without a uri.
    const auto withBuffers = [&](const std::string& name, const Json& buffers) {
        return writeGltf(dir, name, Packing::Binary, {{"alphaMode", "MASK"}},
                         [&](Json& j) { j["buffers"] = buffers; });
    };
    expectError<InputError>(
        [&] {
            loadGltf(withBuffers("long", {{{"byteLength", 1 << 20}}}));
        },
        {"long.glb", "buffers[0].byteLength: 1048576 bytes, beyond the BIN chunk's"});
    expectError<InputError>(
        [&] {
            loadGltf(withBuffers("second", {{{"byteLength", 4}}, {{"byteLength", 4}}}));
        },
        {"second.glb", "buffers[1] has no uri: in a .glb only the first buffer takes the BIN chunk"});
    // A glTF in JSON named .glb, and a binary glTF named .gltf.
    expectError<InputError>([&] { loadGltf(dir.write("json.glb", good.substr(20, jsonLength))); },
                            {"json.glb", "a glTF in JSON is named .gltf"});
    expectError<InputError>([&] { loadGltf(dir.write("binary.gltf", good)); },
                            {"binary.gltf", "is a binary glTF; name it .glb"});
    // The JSON chunk's syntax errors, without the JSON library's own tag.
    try {
        loadGltf(dir.write("syntax.glb", patched(good, 20, 0x7b7b7b7b)));
        ADD_FAILURE() << "syntax.glb loaded";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("glTF: invalid JSON in the JSON chunk: parse error at line 1, column 2"),
                  std::string::npos)
            << what;
        EXPECT_EQ(what.find("json.exception"), std::string::npos) << what;
    }
}

TEST(Gltf, FieldsStsvReadsAreRefusedByJsonPathWhenMalformed) {
    const TempDir dir;
    // Each of these tinygltf drops, reads as "none" or wraps without a word, and the file loaded
    // with the value missing (a node untransformed, a Draco file read as plain, a texture unused).
    const std::string tex = "materials[1].pbrMetallicRoughness.baseColorTexture";
    const std::string index = ": expected an index (an integer from 0 to 2147483647), got ";
    const std::vector<std::pair<std::function<void(Json&)>, std::string>> cases = {
        {[](Json& j) { j["nodes"][0]["matrix"] = std::vector<double>(15, 0.0); },
         "nodes[0].matrix: expected 16 numbers, got 15"},
        {[](Json& j) { j["nodes"][1]["translation"] = "x"; },
         "nodes[1].translation: expected 3 numbers, got the string \"x\""},
        {[](Json& j) {
             j["nodes"][1]["rotation"] = {0, 0, 1};
         },
         "nodes[1].rotation: expected 4 numbers, got 3"},
        {[](Json& j) {
             j["nodes"][1]["rotation"] = {0, 0, 0, 5};
         },
         "nodes[1].rotation: [0,0,0,5] has length 5: a rotation is a unit quaternion"},
        {[](Json& j) {
             j["nodes"][1]["rotation"] = {0, 0, 0, 1.002};
         },
         "has length 1.002"},
        {[](Json& j) {
             j["nodes"][1]["scale"] = {1, "2", 1};
         },
         "nodes[1].scale[1]: expected a number, got the string \"2\""},
        {[](Json& j) { j["nodes"][1]["children"] = {2.0}; }, "nodes[1].children[0]" + index + "2.0"},
        {[](Json& j) { j["nodes"][0]["mesh"] = "0"; }, "nodes[0].mesh" + index + "the string \"0\""},
        {[](Json& j) { j["nodes"][0]["mesh"] = 4294967295u; }, "nodes[0].mesh" + index + "4294967295"},
        {[](Json& j) { j["nodes"][0]["skin"] = -1; }, "nodes[0].skin" + index + "-1"},
        {[](Json& j) {
             j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
             j["extensionsRequired"] = "KHR_draco_mesh_compression";
         },
         "extensionsRequired: expected an array of extension names, got the string "
         "\"KHR_draco_mesh_compression\""},
        {[](Json& j) { j["extensionsUsed"] = {5}; }, "extensionsUsed[0]: expected an extension name, got 5"},
        {[](Json& j) { j["scene"] = -1; }, "glTF: scene" + index + "-1"},
        {[](Json& j) { j["scenes"] = Json::object(); },
         "scenes: expected an array of objects, got an object"},
        {[](Json& j) {
             j["scenes"][0]["nodes"] = {0, "1"};
         },
         "scenes[0].nodes[1]" + index + "the string \"1\""},
        {[](Json& j) { j["meshes"][0]["primitives"][0]["mode"] = -1; },
         "meshes[0].primitives[0].mode: expected a primitive mode, an integer from 0 to 6, got -1"},
        {[](Json& j) { j["meshes"][0]["primitives"][0]["mode"] = "4"; },
         "meshes[0].primitives[0].mode: expected a primitive mode, an integer from 0 to 6, got the string "
         "\"4\""},
        {[](Json& j) { j["meshes"][0]["primitives"][0]["indices"] = "3"; },
         "meshes[0].primitives[0].indices" + index + "the string \"3\""},
        {[](Json& j) { j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 0.5; },
         "meshes[0].primitives[0].attributes.POSITION" + index + "0.5"},
        {[](Json& j) { j["meshes"][0]["primitives"][0].erase("attributes"); },
         "meshes[0].primitives[0].attributes is missing"},
        {[](Json& j) {
             j["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1};
         },
         "materials[1].pbrMetallicRoughness.baseColorFactor: expected 4 numbers, got 2"},
        {[](Json& j) {
             j["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 2};
         },
         "materials[1].pbrMetallicRoughness.baseColorFactor[3]: 2 is outside [0, 1]"},
        {[](Json& j) { j["materials"][1]["alphaMode"] = 5; },
         "materials[1].alphaMode: expected \"OPAQUE\", \"MASK\" or \"BLEND\", got 5"},
        {[](Json& j) { j["materials"][1]["alphaCutoff"] = -1; },
         "materials[1].alphaCutoff: expected a number ≥ 0, got -1"},
        {[](Json& j) { j["materials"][1]["alphaCutoff"] = "0.5"; },
         "materials[1].alphaCutoff: expected a number ≥ 0, got the string \"0.5\""},
        {[](Json& j) { j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = -1; },
         tex + ".index" + index + "-1"},
        {[](Json& j) { j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = -1; },
         tex + ".texCoord" + index + "-1"},
        {[](Json& j) { j["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"].erase("index"); },
         tex + ".index is missing"},
        {[](Json& j) { j["materials"][1]["pbrMetallicRoughness"] = Json::array(); },
         "materials[1].pbrMetallicRoughness: expected an object, got an array"},
        {[](Json& j) { j["textures"][0]["source"] = "0"; },
         "textures[0].source" + index + "the string \"0\""},
        {[](Json& j) { j["samplers"][0]["wrapS"] = "33071"; },
         "samplers[0].wrapS: expected an integer (a wrap mode), got the string \"33071\""},
        {[](Json& j) { j["accessors"][1]["byteOffset"] = "48"; },
         "accessors[1].byteOffset: expected an integer ≥ 0, got the string \"48\""},
        {[](Json& j) { j["bufferViews"][0]["byteOffset"] = -4; },
         "bufferViews[0].byteOffset: expected an integer ≥ 0, got -4"},
        {[](Json& j) { j["buffers"][0]["byteLength"] = 0; },
         "buffers[0].byteLength: expected an integer ≥ 1, got 0"},
        {[](Json& j) { j["images"][0]["uri"] = 5; }, "images[0].uri: expected a string, got 5"},
    };
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const std::string name = "field" + std::to_string(i);
        SCOPED_TRACE(cases[i].second);
        expectError<InputError>(
            [&] {
                loadGltf(writeGltf(dir, name, Packing::External, {{"alphaMode", "MASK"}}, cases[i].first));
            },
            {name + ".gltf", cases[i].second});
    }
    // A rotation a rounded digit away from unit length loads, as glTF exporters write them.
    const MeshData turned =
        loadGltf(writeGltf(dir, "rounded", Packing::External, {{"alphaMode", "MASK"}}, [](Json& j) {
            j["nodes"][1]["rotation"] = {0, 0, 0, 1.0004};
        }));
    EXPECT_EQ(turned.triangles.size(), 4u);
}

TEST(Gltf, DeeplyNestedJsonIsRefusedBeforeTinygltfRecursesIntoIt) {
    const TempDir dir;
    const std::string plain = writeGltf(dir, "plain", Packing::Embedded, {{"alphaMode", "MASK"}},
                                        [](Json& j) { j["nodes"][0]["extras"] = "EXTRAS"; });
    std::string text;
    for (std::uint8_t byte : readBytes(plain)) text += char(byte);
    // The file with node 0's extras nested `levels` deep.
    const auto nested = [&](const std::string& name, int levels) {
        std::string extras;
        for (int i = 0; i < levels; ++i) extras += "{\"a\":";
        extras += "1" + std::string(std::size_t(levels), '}');
        std::string gltf = text;
        gltf.replace(gltf.find("\"EXTRAS\""), 8, extras);
        return dir.write(name, gltf);
    };
    // An application's data a hundred levels deep loads; 100000 levels overflowed tinygltf's
    // stack, which copies extras recursively.
    EXPECT_EQ(loadGltf(nested("hundred.gltf", 100)).triangles.size(), 4u);
    expectError<InputError>([&] { loadGltf(nested("deep.gltf", 100000)); },
                            {"deep.gltf", "glTF: JSON nested deeper than 128 levels"});
}

/// Khronos's glTF sample and generator models as Debian's assimp-testmodels ships them (one of
/// the test packages `make test` installs); a failure names the package when it is missing.
std::string khronosModel(const std::string& name) {
    std::string path = "/usr/share/assimp/models/" + name;
    if (!std::filesystem::exists(path))
        ADD_FAILURE() << path << " is missing: it comes with Debian's assimp-testmodels package "
                      << "(`make test-deps` installs it, or apt-get install assimp-testmodels)";
    return path;
}

TEST(Gltf, KhronosModelsFromDebian) {
    // BoxTextured in its three packings: 36 indices over 24 vertices of a cube with POSITION
    // min/max ±0.5 (the file's accessor bounds), under a node matrix that turns z-up into y-up, so
    // the bounds stay ±0.5; the same triangles from each. Its material has the default OPAQUE
    // mode, so its texture (with a MIRRORED_REPEAT sampler stsv refuses) is never read.
    std::vector<vec3> first;
    for (const char* file :
         {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf",
          "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"}) {
        SCOPED_TRACE(file);
        const MeshData m = loadGltf(khronosModel(file));
        ASSERT_EQ(m.triangles.size(), 12u);
        ASSERT_EQ(m.positions.size(), 24u);
        Bounds b;
        for (const vec3& p : m.positions) b.extend(p);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(b.lo[k], -0.5f, 1e-6f);
            EXPECT_NEAR(b.hi[k], 0.5f, 1e-6f);
        }
        EXPECT_EQ(m.materials[0].alphaMode, AlphaMode::Opaque);
        EXPECT_EQ(m.materials[0].alphaTexture, -1);
        if (first.empty()) first = m.positions;
        EXPECT_EQ(m.positions, first);
    }
    // The asset generator's quads of modes 4, 5 and 6 (plain and indexed): every triangle wound
    // counter-clockwise seen from +z, as the generator's reference images show them (a strip's
    // second triangle turned back).
    for (int i : {4, 5, 6, 11, 12, 13, 14, 15}) {
        char name[96];
        std::snprintf(name, sizeof name,
                      "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf", i);
        const MeshData m = loadGltf(khronosModel(name));
        ASSERT_EQ(m.triangles.size(), 2u) << name;
        for (const uvec3& t : m.triangles) {
            const vec3 n = cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
            EXPECT_GT(n.z, 0.0f) << name;
        }
    }
    // simple_skin: skinned by joints at (0, 1, 0) whose inverse bind matrices translate by
    // (−0.5, −1, 0): its vertices, x in [0, 1] in the mesh, land at x in [−0.5, 0.5].
    {
        const MeshData m = loadGltf(khronosModel("glTF2/simple_skin/simple_skin.gltf"));
        Bounds b;
        for (const vec3& p : m.positions) b.extend(p);
        EXPECT_EQ(b.lo, vec3(-0.5f, 0.0f, 0.0f));
        EXPECT_EQ(b.hi, vec3(0.5f, 2.0f, 0.0f));
    }
    // Every .gltf and .glb the package ships (`dpkg -L assimp-testmodels`), each loaded with the
    // triangle count a separate reading of its accessors gives (every instance of the default
    // scene, degenerate triangles apart), or refused with the reason.
    struct Outcome {
        const char* file;
        std::size_t triangles; ///< 0: refused
        const char* reason;    ///< part of the refusal
    };
    const char* const pointsOrLines = "has no triangles (1 primitives of points or lines skipped)";
    const char* const glTF1 = "stsv reads glTF 2.x only";
    const Outcome outcomes[] = {
        {"glTF/BoxTextured-glTF/BoxTextured.gltf", 0, "asset.version is 1.0"},
        {"glTF/BoxTextured-glTF-Binary/BoxTextured.glb", 0, "a binary glTF of container version 1"},
        {"glTF/BoxTextured-glTF-Embedded/BoxTextured.gltf", 0, glTF1},
        {"glTF/BoxTextured-glTF-MaterialsCommon/BoxTextured.gltf", 0, glTF1},
        {"glTF/CesiumMilkTruck/CesiumMilkTruck.gltf", 0, "asset.version is 1, not a string"},
        {"glTF/IncorrectVertexArrays/Cube_v1.gltf", 0, glTF1},
        {"glTF/TwoBoxes/TwoBoxes.gltf", 0, glTF1},
        {"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", 110342, nullptr},
        {"glTF2/BoxBadNormals-glTF-Binary/BoxBadNormals.glb", 12, nullptr},
        {"glTF2/BoxTexcoords-glTF/boxTexcoords.gltf", 12, nullptr},
        {"glTF2/BoxTextured-glTF/BoxTextured.gltf", 12, nullptr},
        {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 12, nullptr},
        {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", 12, nullptr},
        {"glTF2/BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", 12, nullptr},
        {"glTF2/BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", 0,
         "extensionsRequired names KHR_technique_webgl"},
        {"glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", 0,
         "mesh 0 primitive 0 vertex 0 of node 1 is non-finite"},
        {"glTF2/ClearCoat-glTF/ClearCoatTest.gltf", 37116, nullptr},
        {"glTF2/IncorrectVertexArrays/Cube.gltf", 0,
         "mesh 1 primitive 0 has 35 indices, not a multiple of 3"},
        {"glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf", 0, "index 65535 is beyond its 24 vertices"},
        {"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", 0, "index 255 is beyond its 24 vertices"},
        {"glTF2/MissingBin/BoxTextured.gltf", 0, "buffer 0 uri \"BoxTextured0.bin\" does not exist"},
        {"glTF2/RecursiveNodes/RecursiveNodes.gltf", 0, "node 0 is a root of scene 0 and a child of node 1"},
        {"glTF2/SchemaFailures/sceneWrongType.gltf", 0, "scene: expected an index"},
        {"glTF2/TestNoRootNode/NoScene.gltf", 0, "has no scene"},
        {"glTF2/TestNoRootNode/SceneWithoutNodes.gltf", 0, "scene 0 has no triangles"},
        {"glTF2/cameras/Cameras.gltf", 2, nullptr},
        {"glTF2/draco/2CylinderEngine.gltf", 0, "extensionsRequired names KHR_draco_mesh_compression"},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_02.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_03.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_07.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_09.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_10.gltf", 0, pointsOrLines},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf", 2, nullptr},
        {"glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf", 2, nullptr},
        {"glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", 12, nullptr},
        {"glTF2/issue_3269/texcoord_crash.gltf", 10, nullptr},
        {"glTF2/simple_skin/simple_skin.gltf", 8, nullptr},
        {"glTF2/textureTransform/TextureTransformTest.gltf", 24, nullptr},
        // Values of the wrong type where stsv reads them are refused; badNumber's and badString's
        // are in fields it does not read (normalTexture.scale, a scene's name).
        {"glTF2/wrongTypes/badArray.gltf", 0,
         "meshes[0].primitives: expected an array of objects, got an object"},
        {"glTF2/wrongTypes/badExtension.gltf", 0,
         "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform: expected an "
         "object, got the string \"Not an object\""},
        {"glTF2/wrongTypes/badNumber.gltf", 12, nullptr},
        {"glTF2/wrongTypes/badObject.gltf", 0,
         "materials[0].pbrMetallicRoughness: expected an object, got an array"},
        {"glTF2/wrongTypes/badString.gltf", 12, nullptr},
        {"glTF2/wrongTypes/badUint.gltf", 0,
         "materials[0].pbrMetallicRoughness.baseColorTexture.index: expected an index (an integer from 0 to "
         "2147483647), got -1"},
    };
    std::size_t listed = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(khronosModel(""))) {
        const std::string ext = entry.path().extension().string();
        listed += ext == ".gltf" || ext == ".glb";
    }
    EXPECT_EQ(listed, std::size(outcomes)) << "a model the table does not list";
    for (const Outcome& o : outcomes) {
        SCOPED_TRACE(o.file);
        const std::string path = khronosModel(o.file);
        if (o.triangles > 0) {
            EXPECT_EQ(loadGltf(path).triangles.size(), o.triangles);
        } else {
            expectError<InputError>([&] { loadGltf(path); }, {path, o.reason});
        }
    }
}

} // namespace
} // namespace stsv
