// glTF 2.0 loading (scene/gltf_scene.h): files built here, as .gltf with an external buffer and
// image, as .gltf with both embedded as data URIs, and as .glb, each against the same scene in
// the JSON format; the alpha modes; node transforms and the camera; malformed files.
#include "core/image.h"
#include "scene/geometry.h"
#include "scene/gltf_scene.h"
#include "scene/json_scene.h"
#include "scene/load.h"
#include "tests/scene/scene_test_util.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

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
    bad("lines", [](Json& j) { j["meshes"][0]["primitives"][0]["mode"] = 1; },
        {"mode 1", "only triangle lists"});
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
    bad("mode", [](Json& j) { j["materials"][1]["alphaMode"] = "GLASS"; }, {"alphaMode"});
    bad("beyond",
        [](Json& j) {
            j["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
            j["accessors"][0]["count"] = 2;
        },
        {"index 2 is beyond its 2 vertices"});
    bad("empty", [](Json& j) { j["scenes"][0]["nodes"] = Json::array(); }, {"has no triangles"});
    bad("image", [](Json& j) { j["images"][0]["uri"] = "missing.png"; }, {"missing.png"});
    bad("cycle", [](Json& j) { j["nodes"][2]["children"] = Json::array({1}); }, {"deeper than"});
    expectError<InputError>([&] { loadGltf(dir.write("garbage.gltf", "{ not json")); },
                            {"garbage.gltf", "glTF"});
    expectError<InputError>([&] { loadGltf(dir.write("garbage.glb", "glTF\x02")); }, {"garbage.glb", "glTF"});
    expectError<InputError>([&] { loadGltf(dir.path("absent.glb")); }, {"absent.glb"});
}

/// Khronos's glTF sample and generator models as Debian's assimp-testmodels ships them (one of
/// the test packages `make test` installs).
std::string khronosModel(const std::string& name) {
    return "/usr/share/assimp/models/glTF2/" + name;
}

TEST(Gltf, KhronosModelsFromDebian) {
    // BoxTextured in its three packings: 36 indices over 24 vertices of a cube with POSITION
    // min/max ±0.5 (the file's accessor bounds), under a node matrix that turns z-up into y-up, so
    // the bounds stay ±0.5; the same triangles from each. Its material has the default OPAQUE
    // mode, so its texture (with a MIRRORED_REPEAT sampler stsv refuses) is never read.
    std::vector<vec3> first;
    for (const char* file :
         {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Embedded/BoxTextured.gltf",
          "BoxTextured-glTF-Binary/BoxTextured.glb"}) {
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
    // The asset generator's primitive modes: 06 a non-indexed triangle list, 13–15 indexed with
    // uint32, uint8 and uint16 indices (6 corners, 2 triangles each); the others points, lines,
    // line loops, strips and fans, refused by name.
    for (int i : {6, 13, 14, 15}) {
        char name[96];
        std::snprintf(name, sizeof name,
                      "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf", i);
        EXPECT_EQ(loadGltf(khronosModel(name)).triangles.size(), 2u) << name;
    }
    for (int i : {0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12}) {
        char name[96];
        std::snprintf(name, sizeof name,
                      "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_%02d.gltf", i);
        expectError<InputError>([&] { loadGltf(khronosModel(name)); }, {name, "only triangle lists"});
    }
    // assimp's invalid files: each refused with the file and the problem.
    expectError<InputError>([] { loadGltf(khronosModel("IndexOutOfRange/IndexOutOfRange.gltf")); },
                            {"IndexOutOfRange.gltf", "index 255 is beyond its 24 vertices"});
    expectError<InputError>([] { loadGltf(khronosModel("RecursiveNodes/RecursiveNodes.gltf")); },
                            {"RecursiveNodes.gltf", "deeper than"});
    expectError<InputError>([] { loadGltf(khronosModel("TestNoRootNode/NoScene.gltf")); },
                            {"NoScene.gltf", "has no scene"});
    expectError<InputError>([] { loadGltf(khronosModel("MissingBin/BoxTextured.gltf")); },
                            {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"});
}

} // namespace
} // namespace stsv
