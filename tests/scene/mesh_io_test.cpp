#include "core/error.h"
#include "core/image.h"
#include "scene/load.h"
#include "scene/mesh_io.h"

#include "scene_test_util.h"

#include <gtest/gtest.h>

#include <map>

namespace stsv {
namespace {

using test::expectError;
using test::TempDir;

/// uv of the mesh vertex at `position` (exact match; fixtures use exactly representable values).
std::vector<vec2> uvsAt(const MeshData& mesh, vec3 position) {
    std::vector<vec2> uvs;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (mesh.positions[i] == position) uvs.push_back(mesh.texcoords[i]);
    return uvs;
}

vec3 triangleNormal(const MeshData& mesh, std::size_t t) {
    const uvec3 tri = mesh.triangles[t];
    return normalize(
        cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]));
}

vec3 centroid(const MeshData& mesh, std::size_t t) {
    const uvec3 tri = mesh.triangles[t];
    return (mesh.positions[tri.x] + mesh.positions[tri.y] + mesh.positions[tri.z]) / 3.0f;
}

Image8 makeImage(int w, int h, const std::function<void(int, int, std::uint8_t*)>& texel) {
    Image8 image;
    image.width = w;
    image.height = h;
    image.channels = 4;
    image.pixels.resize(std::size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) texel(x, y, &image.pixels[(std::size_t(y) * w + x) * 4]);
    return image;
}

const char* const QUAD_OBJ = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                             "f 1/1 2/2 3/3 4/4\n";

TEST(Obj, QuadTexcoordsAreFlippedToRowZeroAtTop) {
    TempDir dir;
    const MeshData mesh = loadObj(dir.write("quad.obj", QUAD_OBJ));
    ASSERT_EQ(mesh.triangles.size(), 2u);
    // OBJ (u, v) → stsv (u, 1 − v): the OBJ's bottom-left vt (0, 0) is texture row H−1.
    const std::pair<vec3, vec2> expected[] = {
        {{0, 0, 0}, {0, 1}}, {{1, 0, 0}, {1, 1}}, {{1, 1, 0}, {1, 0}}, {{0, 1, 0}, {0, 0}}};
    for (const auto& [p, uv] : expected) {
        const auto uvs = uvsAt(mesh, p);
        ASSERT_EQ(uvs.size(), 1u) << "p=" << p.x << "," << p.y;
        EXPECT_EQ(uvs[0], uv) << "p=" << p.x << "," << p.y << " uv=" << uvs[0].x << "," << uvs[0].y;
    }
    for (std::size_t t = 0; t < 2; ++t)
        EXPECT_GT(triangleNormal(mesh, t).z, 0.99f) << "winding kept, t=" << t;
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_FALSE(mesh.materials[0].perforated());
}

TEST(Obj, PentagonTexcoordsFollowEveryFanTriangle) {
    // OpenMesh's TriMesh would keep the polygon's texcoords on one fan triangle only.
    TempDir dir;
    const MeshData mesh =
        loadObj(dir.write("penta.obj", "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\n"
                                       "vt 0 0\nvt 0.5 0\nvt 0.75 0.25\nvt 0.25 0.5\nvt 0 0.25\n"
                                       "f 1/1 2/2 3/3 4/4 5/5\n"));
    ASSERT_EQ(mesh.triangles.size(), 3u);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const vec3 p = mesh.positions[i];
        // The fixture's vt is (p.x/4, p.y/4) but for vertex 5, whose vt is (0, 0.25).
        const vec2 vt = p.x < 0.0f ? vec2(0.0f, 0.25f) : vec2(p.x / 4.0f, p.y / 4.0f);
        EXPECT_EQ(mesh.texcoords[i], vec2(vt.x, 1.0f - vt.y)) << "p=" << p.x << "," << p.y;
    }
}

TEST(Obj, UsemtlAssignsMaterialsPerFace) {
    TempDir dir;
    dir.write("m.mtl", "newmtl red\nKd 1 0 0\n\nnewmtl blue\nKd 0 0 1\n");
    const MeshData mesh =
        loadObj(dir.write("m.obj", "mtllib m.mtl\n"
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n"
                                   "f 1 2 3\n"              // before any usemtl: default
                                   "usemtl blue\nf 1 3 4\n" // x < 1
                                   "usemtl red\nf 5 6 7\n"));
    ASSERT_EQ(mesh.triangles.size(), 3u);
    std::vector<std::string> names;
    for (std::size_t t = 0; t < 3; ++t) names.push_back(mesh.materials[mesh.triangleMaterial[t]].name);
    EXPECT_EQ(names, (std::vector<std::string>{"default", "blue", "red"}));
    EXPECT_EQ(mesh.materials[mesh.triangleMaterial[1]].albedo, vec3(0, 0, 1));
    EXPECT_EQ(mesh.materials[mesh.triangleMaterial[2]].albedo, vec3(1, 0, 0));
    EXPECT_GT(centroid(mesh, 2).x, 4.0f);
}

TEST(Obj, MapDUsesLuminanceOfAnOpaqueImageAndHonoursClamp) {
    TempDir dir;
    // Grey ramp without alpha: map_d takes the grey value (red = luminance for grey).
    writePng(dir.path("ramp.png"), makeImage(4, 2, [](int x, int y, std::uint8_t* t) {
                 t[0] = t[1] = t[2] = std::uint8_t(x * 60 + y * 10);
                 t[3] = 255;
             }));
    dir.write("a.mtl", "newmtl leaf\nKd 0.2 0.6 0.1\nmap_d -clamp on ramp.png\n");
    const MeshData mesh = loadObj(dir.write("a.obj", std::string("mtllib a.mtl\nusemtl leaf\n") + QUAD_OBJ));
    ASSERT_EQ(mesh.materials.size(), 1u);
    const Material& m = mesh.materials[0];
    ASSERT_TRUE(m.perforated());
    EXPECT_EQ(m.wrap, WrapMode::Clamp);
    const Texture& t = mesh.textures[std::size_t(m.alphaTexture)];
    ASSERT_EQ(t.width, 4);
    ASSERT_EQ(t.height, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(t.alpha(x, y), x * 60 + y * 10) << "x=" << x << " y=" << y;
}

TEST(Obj, MapDUsesTheAlphaChannelWhenPresent) {
    TempDir dir;
    writePng(dir.path("mask.png"), makeImage(2, 2, [](int x, int y, std::uint8_t* t) {
                 t[0] = t[1] = t[2] = 200; // red is constant: must not be used
                 t[3] = std::uint8_t((x + 2 * y) * 80);
             }));
    dir.write("a.mtl", "newmtl grate\nmap_d mask.png\n");
    const MeshData mesh = loadObj(dir.write("a.obj", std::string("mtllib a.mtl\nusemtl grate\n") + QUAD_OBJ));
    const Material& m = mesh.materials[0];
    ASSERT_TRUE(m.perforated());
    EXPECT_EQ(m.wrap, WrapMode::Repeat);
    const Texture& t = mesh.textures[std::size_t(m.alphaTexture)];
    EXPECT_EQ(t.alpha(0, 0), 0);
    EXPECT_EQ(t.alpha(1, 0), 80);
    EXPECT_EQ(t.alpha(0, 1), 160);
    EXPECT_EQ(t.alpha(1, 1), 240);
}

TEST(Obj, MapKdIsAMaskOnlyWhenItHasTransparentTexels) {
    TempDir dir;
    writePng(dir.path("cutout.png"), makeImage(2, 1, [](int x, int, std::uint8_t* t) {
                 t[0] = 10;
                 t[1] = 20;
                 t[2] = 30;
                 t[3] = x == 0 ? 0 : 255;
             }));
    writePng(dir.path("solid.png"),
             makeImage(2, 1, [](int, int, std::uint8_t* t) { t[0] = t[1] = t[2] = t[3] = 255; }));
    dir.write("a.mtl", "newmtl cut\nmap_Kd cutout.png\nnewmtl solid\nKd 0.5 0.5 0.5\nmap_Kd solid.png\n");
    const MeshData mesh = loadObj(dir.write("a.obj", "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                     "usemtl cut\nf 1 2 3\nusemtl solid\nf 1 3 2\n"));
    ASSERT_EQ(mesh.materials.size(), 2u);
    ASSERT_TRUE(mesh.materials[0].perforated());
    EXPECT_EQ(mesh.textures[std::size_t(mesh.materials[0].alphaTexture)].alpha(0, 0), 0);
    EXPECT_EQ(mesh.textures[std::size_t(mesh.materials[0].alphaTexture)].alpha(1, 0), 255);
    EXPECT_FALSE(mesh.materials[1].perforated());
    EXPECT_EQ(mesh.materials[1].albedo, vec3(0.5f));
}

TEST(Obj, FacesWithRepeatedVerticesAreSkippedAndCounted) {
    TempDir dir;
    const MeshData mesh =
        loadObj(dir.write("d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 1 2\nf 2 4 3\n"));
    EXPECT_EQ(mesh.triangles.size(), 2u);
    EXPECT_EQ(mesh.skippedFaces, 1u);
}

TEST(Obj, NonManifoldFaceKeepsItsTexcoords) {
    // The third face repeats the directed edge 1→2 of the first: OpenMesh adds it on copied
    // vertices (and in 9.0 rotates its texcoords, which the loader repairs from the file).
    TempDir dir;
    const MeshData mesh =
        loadObj(dir.write("nm.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 1\n"
                                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 0.5\nvt 0.25 0.75\nvt 0.75 0.25\n"
                                    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 1/4 2/5 4/6\n"));
    ASSERT_EQ(mesh.triangles.size(), 3u);
    const uvec3 tri = mesh.triangles[2];
    const vec2 expected[3] = {{0.5f, 0.5f}, {0.25f, 0.25f}, {0.75f, 0.75f}}; // (u, 1 − v) of vt 4, 5, 6
    for (int k = 0; k < 3; ++k)
        EXPECT_EQ(mesh.texcoords[tri[k]], expected[k])
            << "corner " << k << " uv=" << mesh.texcoords[tri[k]].x << "," << mesh.texcoords[tri[k]].y;
    EXPECT_EQ(mesh.positions[tri[0]], vec3(0, 0, 0));
    EXPECT_EQ(mesh.positions[tri[1]], vec3(1, 0, 0));
    EXPECT_EQ(mesh.positions[tri[2]], vec3(0, 0, 1));
}

struct BadObj {
    const char* name;
    const char* text;
    int line; ///< 0: no line in the message
    const char* says;
};

class BadObjTest : public ::testing::TestWithParam<BadObj> {};

TEST_P(BadObjTest, NamesFileLineAndProblem) {
    const BadObj& c = GetParam();
    TempDir dir;
    const std::string path = dir.write("bad.obj", c.text);
    std::vector<std::string> parts{c.line > 0 ? path + ":" + std::to_string(c.line) + ":" : path + ":",
                                   c.says};
    expectError<InputError>([&] { loadObj(path); }, parts);
}

INSTANTIATE_TEST_SUITE_P(
    Obj, BadObjTest,
    ::testing::Values(
        BadObj{"TooFewCoordinates", "v 0 0 0\nv 1 0\n", 2, "vertex needs 3 coordinates"},
        BadObj{"MalformedNumber", "v 0 0 0\nv 1 0 0\nv 1 x2 0\nf 1 2 3\n", 3, "malformed number 'x2'"},
        BadObj{"NaN", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 2, "non-finite"},
        BadObj{"Infinity", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", 3, "non-finite"},
        BadObj{"NaNTexcoord", "v 0 0 0\nvt 0.5 nan\n", 2, "non-finite"},
        // Finite as a double, infinite as the float the scene holds (OpenMesh's stream failed on
        // it and dropped the vertex, found by fuzzing).
        BadObj{"BeyondFloatRange", "v 0 0 0\nv 1 0 0\nv 0 1 4e38\nf 1 2 3\n", 3,
               "beyond the range of a float"},
        BadObj{"TexcoordBeyondFloatRange", "v 0 0 0\nvt -1e39 0\n", 2, "beyond the range of a float"},
        BadObj{"IndexOutOfRange", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "index 4 is out of range"},
        BadObj{"ForwardReference", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", 3, "out of range"},
        BadObj{"NegativeOutOfRange", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "out of range"},
        BadObj{"ZeroIndex", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0"},
        BadObj{"TexcoordOutOfRange", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", 5,
               "texture coordinate index 2"},
        BadObj{"TruncatedFace", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", 4, "face needs at least 3 vertices"},
        BadObj{"TruncatedCorner", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/", 4, "malformed face corner '3/'"},
        BadObj{"MalformedIndex", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 three\n", 4,
               "malformed vertex index 'three'"},
        BadObj{"UnknownStatement", "v 0 0 0\nvx 1 0 0\n", 2, "unknown OBJ statement 'vx'"},
        BadObj{"MissingMtllib", "mtllib nowhere.mtl\nv 0 0 0\n", 1, "nowhere.mtl' does not exist"},
        BadObj{"Empty", "# nothing here\n\n", 0, "no vertices"},
        BadObj{"NoFaces", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", 0, "no faces"},
        BadObj{"OnlyDegenerateFaces", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n", 4,
               "face names vertex 2 (counting from 1) twice, a degenerate face, and so do all 1 faces of the "
               "file: it has no valid face"}),
    [](const ::testing::TestParamInfo<BadObj>& p) { return std::string(p.param.name); });

TEST(Obj, UndefinedMaterialNamesObjLine) {
    TempDir dir;
    dir.write("a.mtl", "newmtl known\nKd 1 1 1\n");
    const std::string obj =
        dir.write("a.obj", "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl unknown\nf 1 2 3\n");
    expectError<InputError>([&] { loadObj(obj); }, {obj + ":5:", "'unknown'"});
}

TEST(Obj, MissingTextureNamesMtlLine) {
    TempDir dir;
    const std::string mtl = dir.write("a.mtl", "newmtl m\nKd 1 1 1\nmap_d holes.png\n");
    const std::string obj = dir.write("a.obj", std::string("mtllib a.mtl\nusemtl m\n") + QUAD_OBJ);
    expectError<InputError>([&] { loadObj(obj); }, {mtl + ":3:", "holes.png", "does not exist"});
}

TEST(Obj, UnreadableTextureNamesMtlLine) {
    TempDir dir;
    dir.write("fake.png", "this is not a PNG");
    const std::string mtl = dir.write("a.mtl", "newmtl m\nmap_Kd fake.png\n");
    const std::string obj = dir.write("a.obj", std::string("mtllib a.mtl\nusemtl m\n") + QUAD_OBJ);
    expectError<InputError>([&] { loadObj(obj); }, {mtl + ":2:", "fake.png"});
}

TEST(Obj, MalformedKdNamesMtlLine) {
    TempDir dir;
    const std::string mtl = dir.write("a.mtl", "newmtl m\nKd 1 nan 1\n");
    const std::string obj = dir.write("a.obj", std::string("mtllib a.mtl\nusemtl m\n") + QUAD_OBJ);
    expectError<InputError>([&] { loadObj(obj); }, {mtl + ":2:", "non-finite"});
}

TEST(Obj, MissingFileIsAnInputError) {
    expectError<InputError>([] { loadObj("/nonexistent/dir/mesh.obj"); },
                            {"/nonexistent/dir/mesh.obj", "does not exist"});
}

// ---------------------------------------------------------------- OFF

TEST(Off, CubeWithCommentsAndQuads) {
    TempDir dir;
    const MeshData mesh =
        loadOff(dir.write("cube.off", "OFF\n# a unit cube\n8 6 12\n"
                                      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                                      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n"));
    EXPECT_EQ(mesh.triangles.size(), 12u);
    EXPECT_EQ(mesh.positions.size(), 8u) << "vertices shared (no texcoords to split them)";
    ASSERT_EQ(mesh.materials.size(), 1u);
    EXPECT_FALSE(mesh.materials[0].perforated());
    // Outward winding kept: every normal points away from the cube centre.
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        EXPECT_GT(dot(triangleNormal(mesh, t), centroid(mesh, t) - vec3(0.5f)), 0.0f) << "t=" << t;
}

TEST(Obj, AFaceOfManyRepeatedVerticesIsSkippedAndNamed) {
    // A face of 300 000 corners naming three vertices over and over: OpenMesh kept it as the
    // triangle 1 2 3 while the loader counted it as degenerate ("OpenMesh read 1 faces where the
    // file has 0 valid faces").
    std::string face = "f";
    for (int i = 0; i < 300000; ++i) face += " " + std::to_string(1 + i % 3);
    TempDir dir;
    const std::string only = dir.write("only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + face + "\n");
    expectError<InputError>(
        [&] { loadObj(only); },
        {only + ":4:", "face names vertex 1 (counting from 1) twice", "it has no valid face"});
    // Beside a valid face it is skipped and counted like any face with a repeated vertex.
    const MeshData mesh =
        loadObj(dir.write("beside.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" + face + "\n"));
    EXPECT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.skippedFaces, 1u);
}

TEST(Off, FacesWithRepeatedVerticesAreSkippedOrNamed) {
    TempDir dir;
    const std::string only = dir.write("only.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n6 0 1 2 0 1 2\n");
    expectError<InputError>(
        [&] { loadOff(only); },
        {only + ":6:", "face names vertex 0 (counting from 0) twice", "it has no valid face"});
    const MeshData mesh =
        loadOff(dir.write("beside.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n6 0 1 2 0 1 2\n3 0 1 2\n"));
    EXPECT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.skippedFaces, 1u);
}

TEST(Obj, TexcoordsBeyondTheTexelRangeAreRefused) {
    // vt 1e38 is finite, but u·width names no texel: Scene::validate refuses it by triangle.
    TempDir dir;
    writePng(dir.path("mask.png"), makeImage(8, 8, [](int x, int, std::uint8_t* t) {
                 t[0] = t[1] = t[2] = 200;
                 t[3] = x % 2 ? 255 : 0;
             }));
    dir.write("a.mtl", "newmtl holes\nmap_d mask.png\n");
    const std::string obj = dir.write("a.obj", "mtllib a.mtl\nusemtl holes\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                               "vt 0 0\nvt 1e38 0\nvt 1 1\nf 1/1 2/2 3/3\n");
    expectError<InputError>(
        [&] { loadScene(obj); },
        {obj + ":", "triangle 0 vertex 1 texture coordinate: u = 1e+38 is 8e+38 texels", "2^24"});
    // Without a texture the same coordinates are accepted.
    EXPECT_NO_THROW(loadScene(dir.write("plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1e38 0\nvt 1 1\n"
                                                     "f 1/1 2/2 3/3\n")));
}

TEST(Off, CountsOnTheHeaderLine) {
    TempDir dir;
    const MeshData mesh = loadOff(dir.write("t.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    EXPECT_EQ(mesh.triangles.size(), 1u);
}

struct BadOff {
    const char* name;
    const char* text;
    int line;
    const char* says;
};

class BadOffTest : public ::testing::TestWithParam<BadOff> {};

TEST_P(BadOffTest, NamesFileLineAndProblem) {
    const BadOff& c = GetParam();
    TempDir dir;
    const std::string path = dir.write("bad.off", c.text);
    std::vector<std::string> parts{c.line > 0 ? path + ":" + std::to_string(c.line) + ":" : path + ":",
                                   c.says};
    expectError<InputError>([&] { loadOff(path); }, parts);
}

INSTANTIATE_TEST_SUITE_P(
    Off, BadOffTest,
    ::testing::Values(
        BadOff{"WrongHeader", "PLY\n3 1 0\n", 1, "not an OFF file"}, BadOff{"Empty", "", 0, "empty file"},
        BadOff{"MalformedCount", "OFF\n3 x 0\n", 2, "malformed count 'x'"},
        BadOff{"Binary", "OFF BINARY\n", 1, "binary OFF"},
        BadOff{"TruncatedVertices", "OFF\n4 1 0\n0 0 0\n1 0 0\n", 4, "file ends after 2 of 4 vertices"},
        BadOff{"TruncatedFaces", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6,
               "file ends after 1 of 2 faces"},
        BadOff{"ShortVertex", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", 4, "vertex needs 3 numbers"},
        BadOff{"NaN", "OFF\n3 1 0\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n", 4, "non-finite"},
        BadOff{"IndexOutOfRange", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", 6,
               "vertex index 3 is out of range"},
        BadOff{"NegativeIndex", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", 6, "out of range"},
        BadOff{"TruncatedFace", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", 6, "face lists 2 of its 3"},
        BadOff{"TwoGonFace", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 6, "vertex count"},
        BadOff{"NoFaces", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", 2, "no faces"}),
    [](const ::testing::TestParamInfo<BadOff>& p) { return std::string(p.param.name); });

TEST(MeshFile, UnknownExtensionIsAUsageError) {
    expectError<UsageError>([] { loadMeshFile("model.ply"); }, {"model.ply", ".ply"});
}

} // namespace
} // namespace stsv

namespace stsv {
namespace {

TEST(Obj, AcceptsCommonSyntaxVariants) {
    // CRLF, tabs, groups, smoothing groups, vertex colours, normals, v//vn and v/vt/vn corners,
    // negative (relative) indices, a polyline, 3-component vt: all must read like plain faces.
    TempDir dir;
    const MeshData mesh =
        loadObj(dir.write("v.obj", "# exported\r\no thing\r\ng part\r\ns 1\r\n"
                                   "v 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\r\nv\t1 1 0\t0 0 1\r\nv 0 1 0 1 1 1\r\n"
                                   "vn 0 0 1\r\nvt 0 0 0\r\nvt 1 0 0\r\nvt 1 1 0\r\nvt 0 1 0\r\n"
                                   "f 1/1/1 2/2/1 3/3/1\r\n"
                                   "f -4//-1 -2//-1 -1//-1\r\n"
                                   "l 1 2 3\r\n"));
    ASSERT_EQ(mesh.triangles.size(), 2u);
    EXPECT_EQ(mesh.skippedFaces, 0u);
    // Triangle 0 carries texcoords (flipped), triangle 1 has none (all corners 0).
    const uvec3 t0 = mesh.triangles[0];
    EXPECT_EQ(mesh.positions[t0.z], vec3(1, 1, 0));
    EXPECT_EQ(mesh.texcoords[t0.z], vec2(1, 0));
    const uvec3 t1 = mesh.triangles[1];
    EXPECT_EQ(mesh.positions[t1.x], vec3(0, 0, 0));
    EXPECT_EQ(mesh.positions[t1.y], vec3(1, 1, 0));
    EXPECT_EQ(mesh.positions[t1.z], vec3(0, 1, 0));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.texcoords[t1[k]], vec2(0, 0));
}

TEST(Obj, UsemtlWithoutLibraryGroupsFaces) {
    TempDir dir;
    const MeshData mesh = loadObj(dir.write(
        "g.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 2\nusemtl a\nf 2 1 3\n"));
    ASSERT_EQ(mesh.triangles.size(), 3u);
    EXPECT_EQ(mesh.materials.size(), 2u);
    EXPECT_EQ(mesh.triangleMaterial, (std::vector<std::uint32_t>{0, 1, 0}));
}

} // namespace
} // namespace stsv
