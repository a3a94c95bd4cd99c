#include "scene/json_scene.h"

#include "core/error.h"
#include "core/files.h"
#include "core/image.h"
#include "core/memory_budget.h"
#include "scene/geometry.h"
#include "scene/mesh_io.h"
#include "scene/procedural.h"

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace stsv {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// The shortest text that reads back as `value` ("1e+20", "-1", "0.5").
std::string numberText(double value) {
    char buffer[32];
    const char* end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    return std::string(static_cast<const char*>(buffer), end);
}

/// Reads typed values out of the parsed document; every error names the file and the JSON path.
class Reader {
  public:
    explicit Reader(std::string file) : m_file(std::move(file)) {}

    [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
        throw InputError(m_file, where.empty() ? problem : where + ": " + problem);
    }

    void expectObject(const Json& j, const std::string& where,
                      std::initializer_list<const char*> allowed) const {
        if (!j.is_object()) fail(where, "expected an object, got " + describe(j));
        for (const auto& item : j.items()) {
            bool known = false;
            for (const char* key : allowed) known = known || item.key() == key;
            if (!known) {
                std::string list;
                for (const char* key : allowed) list += std::string(list.empty() ? "" : ", ") + key;
                fail(join(where, item.key()), "unknown key (accepted: " + list + ")");
            }
        }
    }

    const Json& require(const Json& object, const char* key, const std::string& where) const {
        const auto it = object.find(key);
        if (it == object.end()) fail(where, std::string("missing required field '") + key + "'");
        return *it;
    }

    double number(const Json& j, const std::string& where) const {
        if (!j.is_number()) fail(where, "expected a number, got " + describe(j));
        const double value = j.get<double>();
        if (!std::isfinite(value)) fail(where, "number is not finite");
        return value;
    }
    float positive(const Json& j, const std::string& where) const {
        const double value = number(j, where);
        if (!(value > 0.0)) fail(where, "must be > 0, got " + j.dump());
        return float(value);
    }
    /// A light's size (a rectangle's edge, a disk's or sphere's radius) within
    /// [MIN_LIGHT_SIZE, MAX_LIGHT_SIZE].
    float lightSize(const Json& j, const std::string& where) const {
        const double value = number(j, where);
        if (!(value >= double(MIN_LIGHT_SIZE) && value <= double(MAX_LIGHT_SIZE)))
            fail(where, numberText(value) + " is outside the accepted light size " + lightSizeRangeText() +
                            " world units (the samplers need the light's area as a normal float)");
        return float(value);
    }
    float nonNegative(const Json& j, const std::string& where) const {
        const double value = number(j, where);
        if (value < 0.0) fail(where, "must be ≥ 0, got " + j.dump());
        return float(value);
    }
    int integer(const Json& j, const std::string& where) const {
        if (!j.is_number_integer()) fail(where, "expected an integer, got " + describe(j));
        const auto value = j.get<long long>();
        if (value < -2147483647 || value > 2147483647) fail(where, "integer out of range");
        return int(value);
    }
    std::string string(const Json& j, const std::string& where) const {
        if (!j.is_string()) fail(where, "expected a string, got " + describe(j));
        return j.get<std::string>();
    }
    bool boolean(const Json& j, const std::string& where) const {
        if (!j.is_boolean()) fail(where, "expected true or false, got " + describe(j));
        return j.get<bool>();
    }
    template <int N> vec<N, float> vector(const Json& j, const std::string& where) const {
        if (!j.is_array() || j.size() != std::size_t(N))
            fail(where, "expected an array of " + std::to_string(N) + " numbers, got " + describe(j));
        vec<N, float> v(0.0f);
        for (int i = 0; i < N; ++i)
            v[i] = float(number(j[std::size_t(i)], where + "[" + std::to_string(i) + "]"));
        return v;
    }
    /// A vec3 or one number for all three components.
    vec3 color(const Json& j, const std::string& where) const {
        const vec3 c = j.is_number() ? vec3(float(number(j, where))) : vector<3>(j, where);
        if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) fail(where, "components must be ≥ 0");
        return c;
    }
    vec3 direction(const Json& j, const std::string& where) const {
        const vec3 v = vector<3>(j, where);
        if (!(length(v) > 1e-12f)) fail(where, "must not be the zero vector");
        return normalize(v);
    }

    static std::string join(const std::string& where, const std::string& key) {
        return where.empty() ? key : where + "." + key;
    }
    static std::string index(const std::string& where, std::size_t i) {
        return where + "[" + std::to_string(i) + "]";
    }
    /// A value in an error message: its type and, for a scalar, its text cut to 40 characters;
    /// an array or object by its size only (never dumped whole).
    static std::string describe(const Json& j) {
        if (j.is_array()) return "an array of " + std::to_string(j.size()) + " item(s)";
        if (j.is_object()) return "an object of " + std::to_string(j.size()) + " member(s)";
        std::string text = j.dump();
        if (text.size() > 40) text = text.substr(0, 37) + "...";
        return std::string(j.type_name()) + " " + text;
    }

    const std::string& file() const { return m_file; }

  private:
    std::string m_file;
};

mat4 readTransform(const Reader& r, const Json& j, const std::string& where) {
    r.expectObject(j, where, {"translate", "rotate", "euler", "scale"});
    mat4 worldFromObject(1.0f);
    if (j.contains("translate"))
        worldFromObject =
            glm::translate(worldFromObject, r.vector<3>(j["translate"], Reader::join(where, "translate")));
    if (j.contains("rotate") && j.contains("euler"))
        r.fail(where, "give either 'rotate' or 'euler', not both");
    if (j.contains("rotate")) {
        const Json& rot = j["rotate"];
        const std::string w = Reader::join(where, "rotate");
        auto one = [&](const Json& item, const std::string& at) {
            r.expectObject(item, at, {"axis", "degrees"});
            const vec3 axis = r.direction(r.require(item, "axis", at), Reader::join(at, "axis"));
            const float degrees =
                float(r.number(r.require(item, "degrees", at), Reader::join(at, "degrees")));
            return glm::rotate(mat4(1.0f), glm::radians(degrees), axis);
        };
        if (rot.is_array()) {
            // A list of rotations applied in order: the first is applied to the object first.
            mat4 combined(1.0f);
            for (std::size_t i = 0; i < rot.size(); ++i)
                combined = one(rot[i], Reader::index(w, i)) * combined;
            worldFromObject = worldFromObject * combined;
        } else {
            worldFromObject = worldFromObject * one(rot, w);
        }
    }
    if (j.contains("euler")) {
        // Degrees about x, then y, then z (R = Rz · Ry · Rx).
        const vec3 e = glm::radians(r.vector<3>(j["euler"], Reader::join(where, "euler")));
        worldFromObject = worldFromObject * glm::rotate(mat4(1.0f), e.z, vec3(0, 0, 1)) *
                          glm::rotate(mat4(1.0f), e.y, vec3(0, 1, 0)) *
                          glm::rotate(mat4(1.0f), e.x, vec3(1, 0, 0));
    }
    if (j.contains("scale")) {
        const Json& s = j["scale"];
        const std::string w = Reader::join(where, "scale");
        const vec3 scale = s.is_number() ? vec3(r.positive(s, w)) : r.vector<3>(s, w);
        if (!(scale.x > 0.0f && scale.y > 0.0f && scale.z > 0.0f)) r.fail(w, "scale factors must be > 0");
        worldFromObject = glm::scale(worldFromObject, scale);
    }
    return worldFromObject;
}

class SceneBuilder {
  public:
    SceneBuilder(const std::string& path) : m_r(path), m_dir(fs::path(path).parent_path()) {
        m_scene.source = path;
    }

    Scene build(const Json& root) {
        m_r.expectObject(root, "", {"description", "camera", "materials", "meshes", "lights"});
        if (root.contains("description")) m_r.string(root["description"], "description");
        if (root.contains("materials")) readMaterials(root["materials"]);
        const Json& meshes = m_r.require(root, "meshes", "");
        if (!meshes.is_array() || meshes.empty()) m_r.fail("meshes", "expected a non-empty array of meshes");
        for (std::size_t i = 0; i < meshes.size(); ++i) readMesh(meshes[i], Reader::index("meshes", i));
        if (m_scene.triangles.empty()) m_r.fail("meshes", "the scene has no triangles");
        const Json& lights = m_r.require(root, "lights", "");
        if (!lights.is_array() || lights.empty()) m_r.fail("lights", "expected a non-empty array of lights");
        if (lights.size() > MAX_SCENE_LIGHTS)
            m_r.fail("lights", std::to_string(lights.size()) + " lights, more than the " +
                                   std::to_string(MAX_SCENE_LIGHTS) + " a frame renders");
        for (std::size_t i = 0; i < lights.size(); ++i) readLight(lights[i], Reader::index("lights", i));
        if (root.contains("camera")) {
            readCamera(root["camera"]);
        } else {
            const Bounds b = m_scene.bounds();
            m_scene.camera = frameSphere(b.center(), 0.55f * length(b.extent()), vec3(0.45f, 0.5f, 1.0f));
        }
        m_scene.validate();
        return std::move(m_scene);
    }

    /// One light object of the format (the command line's --light); `w` its place in messages.
    Light lightFrom(const Json& j, const std::string& w) {
        readLight(j, w);
        return m_scene.lights.back();
    }
    /// A camera object of the format (the command line's --camera).
    Camera cameraFrom(const Json& j) {
        readCamera(j);
        return m_scene.camera;
    }

  private:
    void readMaterials(const Json& list) {
        if (!list.is_array()) m_r.fail("materials", "expected an array, got " + Reader::describe(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string w = Reader::index("materials", i);
            const Json& j = list[i];
            m_r.expectObject(j, w,
                             {"name", "albedo", "alphaTexture", "alphaChannel", "alphaMode", "alphaFactor",
                              "alphaCutoff", "wrap", "doubleSided"});
            Material m;
            m.name = m_r.string(m_r.require(j, "name", w), Reader::join(w, "name"));
            if (m_materialByName.count(m.name))
                m_r.fail(Reader::join(w, "name"), "duplicate material name '" + m.name + "'");
            if (j.contains("albedo")) {
                m.albedo = m_r.color(j["albedo"], Reader::join(w, "albedo"));
                if (const std::string problem = albedoProblem(m.albedo); !problem.empty())
                    m_r.fail(Reader::join(w, "albedo"), problem);
            }
            AlphaSource channel = AlphaSource::Auto;
            if (j.contains("alphaChannel")) {
                const std::string c = m_r.string(j["alphaChannel"], Reader::join(w, "alphaChannel"));
                if (c == "auto")
                    channel = AlphaSource::Auto;
                else if (c == "alpha")
                    channel = AlphaSource::Alpha;
                else if (c == "red")
                    channel = AlphaSource::Red;
                else if (c == "luminance")
                    channel = AlphaSource::Luminance;
                else
                    m_r.fail(Reader::join(w, "alphaChannel"),
                             "expected \"auto\", \"alpha\", \"red\" or \"luminance\", got \"" + c + "\"");
            }
            int texture = -1;
            if (j.contains("alphaTexture"))
                texture = readTexture(j["alphaTexture"], Reader::join(w, "alphaTexture"), channel);
            AlphaMode mode = AlphaMode::Mask;
            if (j.contains("alphaMode")) {
                const std::string text = m_r.string(j["alphaMode"], Reader::join(w, "alphaMode"));
                if (text == "opaque")
                    mode = AlphaMode::Opaque;
                else if (text == "mask")
                    mode = AlphaMode::Mask;
                else if (text == "blend")
                    mode = AlphaMode::Blend;
                else
                    m_r.fail(Reader::join(w, "alphaMode"),
                             "expected \"opaque\", \"mask\" or \"blend\", got \"" + text + "\"");
            }
            const auto unit = [&](const char* key, float fallback) {
                if (!j.contains(key)) return fallback;
                const double value = m_r.number(j[key], Reader::join(w, key));
                if (!(value >= 0.0 && value <= 1.0)) m_r.fail(Reader::join(w, key), "must be in [0, 1]");
                return float(value);
            };
            setMaterialAlpha(m, m_scene.textures, mode, texture, unit("alphaFactor", 1.0f),
                             unit("alphaCutoff", 0.5f));
            if (j.contains("wrap")) {
                const std::string wrap = m_r.string(j["wrap"], Reader::join(w, "wrap"));
                if (wrap == "repeat")
                    m.wrap = WrapMode::Repeat;
                else if (wrap == "clamp")
                    m.wrap = WrapMode::Clamp;
                else
                    m_r.fail(Reader::join(w, "wrap"),
                             "expected \"repeat\" or \"clamp\", got \"" + wrap + "\"");
            }
            if (j.contains("doubleSided"))
                m.doubleSided = m_r.boolean(j["doubleSided"], Reader::join(w, "doubleSided"));
            m_materialByName[m.name] = addMaterial(m_scene, m);
        }
    }

    int readTexture(const Json& j, const std::string& w, AlphaSource channel) {
        if (j.is_string()) {
            const fs::path file = m_dir / j.get<std::string>();
            const std::string key = file.lexically_normal().string() + "|" + std::to_string(int(channel));
            if (const auto it = m_textureByKey.find(key); it != m_textureByKey.end()) return it->second;
            if (const std::string reason = notAFileReason(file.string()); !reason.empty())
                m_r.fail(w, "texture file '" + file.string() + "' " + reason);
            Image8 image;
            try {
                image = readPngRgba(file.string());
            } catch (const InputError& e) {
                m_r.fail(w, std::string("cannot read texture: ") + e.what());
            }
            const int index = addTexture(m_scene, textureFromImage(image, file.string(), channel));
            m_textureByKey[key] = index;
            return index;
        }
        m_r.expectObject(j, w, {"generator", "size"});
        const std::string generator =
            m_r.string(m_r.require(j, "generator", w), Reader::join(w, "generator"));
        int size = generator == "leaf" ? 128 : 256;
        if (j.contains("size")) size = m_r.integer(j["size"], Reader::join(w, "size"));
        if (!GENERATED_TEXTURE_SIZE.contains(size))
            m_r.fail(Reader::join(w, "size"), "must be in " + rangeText(GENERATED_TEXTURE_SIZE));
        if (generator != "chainlink" && generator != "leaf")
            m_r.fail(Reader::join(w, "generator"),
                     "unknown generator \"" + generator + "\" (expected \"chainlink\" or \"leaf\")");
        // Counted before it is generated, beside the textures the scene holds already.
        double held = 0.0;
        for (const Texture& t : m_scene.textures) held += double(t.rgba.size());
        checkGeneratedTextureMemory(m_r.file() + ": " + w + ": " + generator + " texture", size, held);
        return addTexture(m_scene,
                          generator == "chainlink" ? makeChainLinkTexture(size) : makeLeafTexture(size));
    }

    int materialNamed(const Json& j, const std::string& w) {
        const std::string name = m_r.string(j, w);
        const auto it = m_materialByName.find(name);
        if (it == m_materialByName.end()) m_r.fail(w, "unknown material '" + name + "'");
        return int(it->second);
    }

    void readMesh(const Json& j, const std::string& w) {
        m_r.expectObject(
            j, w, {"name", "file", "quad", "vertices", "texcoords", "triangles", "material", "transform"});
        const int sources = int(j.contains("file")) + int(j.contains("quad")) + int(j.contains("vertices"));
        if (sources != 1) m_r.fail(w, "needs exactly one of 'file', 'quad' or 'vertices' + 'triangles'");
        std::string name = j.contains("name") ? m_r.string(j["name"], Reader::join(w, "name")) : w;
        const mat4 worldFromObject = j.contains("transform")
                                         ? readTransform(m_r, j["transform"], Reader::join(w, "transform"))
                                         : mat4(1.0f);
        int material = -1;
        if (j.contains("material")) material = materialNamed(j["material"], Reader::join(w, "material"));

        MeshData mesh;
        if (j.contains("file")) {
            const fs::path file = m_dir / m_r.string(j["file"], Reader::join(w, "file"));
            if (const std::string reason = notAFileReason(file.string()); !reason.empty())
                m_r.fail(Reader::join(w, "file"), "mesh file '" + file.string() + "' " + reason);
            try {
                mesh = loadMeshFile(file.string());
            } catch (const UsageError& e) {
                m_r.fail(Reader::join(w, "file"), e.what());
            }
            if (!j.contains("name")) name = file.stem().string();
        } else {
            if (material < 0) m_r.fail(w, "inline geometry needs a 'material'");
            if (j.contains("quad")) {
                const std::string q = Reader::join(w, "quad");
                m_r.expectObject(j["quad"], q, {"size", "uvRepeat"});
                const vec2 size = m_r.vector<2>(m_r.require(j["quad"], "size", q), Reader::join(q, "size"));
                if (!(size.x > 0.0f && size.y > 0.0f)) m_r.fail(Reader::join(q, "size"), "sizes must be > 0");
                vec2 repeat(1.0f);
                if (j["quad"].contains("uvRepeat")) {
                    repeat = m_r.vector<2>(j["quad"]["uvRepeat"], Reader::join(q, "uvRepeat"));
                    // The quad's far corner has texture coordinates `repeat` (MAX_TEXEL_COORDINATE).
                    const Material& m = m_scene.materials[std::size_t(material)];
                    for (const int texture : {m.alphaTexture, m.blendTexture})
                        if (texture >= 0)
                            if (const std::string problem =
                                    texcoordProblem(repeat, m_scene.textures[std::size_t(texture)]);
                                !problem.empty())
                                m_r.fail(Reader::join(q, "uvRepeat"), problem);
                }
                mesh = makeQuad(size, repeat);
            } else {
                readTriangles(j, w, mesh);
            }
        }
        if (mesh.triangles.empty()) m_r.fail(w, "mesh has no triangles");
        checkTexcoords(mesh, material, w,
                       j.contains("quad")   ? "quad"
                       : j.contains("file") ? "file"
                                            : "texcoords");
        appendMesh(m_scene, mesh, worldFromObject, name, material);
    }

    /// Texture coordinates of textured triangles that name no texel (texcoordProblem), with the
    /// JSON place of the value at fault: a quad's uvRepeat, an inline vertex's texcoords, or the
    /// mesh file and its vertex. Scene::validate checks them again for every loader, by triangle.
    void checkTexcoords(const MeshData& mesh, int material, const std::string& w, const char* source) {
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const bool own = material < 0;
            if (own && t >= mesh.triangleMaterial.size()) break; // appendMesh reports it
            const std::size_t m = own ? mesh.triangleMaterial[t] : std::size_t(material);
            const std::vector<Material>& materials = own ? mesh.materials : m_scene.materials;
            const std::vector<Texture>& textures = own ? mesh.textures : m_scene.textures;
            if (m >= materials.size()) continue; // appendMesh and validate report it
            for (const int texture : {materials[m].alphaTexture, materials[m].blendTexture}) {
                if (texture < 0 || std::size_t(texture) >= textures.size()) continue;
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t v = mesh.triangles[t][k];
                    if (v >= mesh.texcoords.size()) continue; // none: appendMesh gives (0, 0)
                    const std::string problem =
                        texcoordProblem(mesh.texcoords[v], textures[std::size_t(texture)]);
                    if (problem.empty()) continue;
                    const std::string place = Reader::join(w, source);
                    if (std::string(source) == "quad") m_r.fail(Reader::join(place, "uvRepeat"), problem);
                    if (std::string(source) == "texcoords") m_r.fail(Reader::index(place, v), problem);
                    m_r.fail(place, "vertex " + std::to_string(v) + " texture coordinate: " + problem);
                }
            }
        }
    }

    void readTriangles(const Json& j, const std::string& w, MeshData& mesh) {
        const Json& vertices = m_r.require(j, "vertices", w);
        const Json& triangles = m_r.require(j, "triangles", w);
        const std::string wv = Reader::join(w, "vertices"), wt = Reader::join(w, "triangles");
        if (!vertices.is_array() || vertices.size() < 3)
            m_r.fail(wv, "expected an array of at least 3 [x, y, z] points");
        if (!triangles.is_array() || triangles.empty())
            m_r.fail(wt, "expected a non-empty array of [i, j, k] index triples");
        for (std::size_t i = 0; i < vertices.size(); ++i)
            mesh.positions.push_back(m_r.vector<3>(vertices[i], Reader::index(wv, i)));
        if (j.contains("texcoords")) {
            const Json& tc = j["texcoords"];
            const std::string wc = Reader::join(w, "texcoords");
            if (!tc.is_array() || tc.size() != vertices.size())
                m_r.fail(wc, "expected one [u, v] per vertex (" + std::to_string(vertices.size()) + ")");
            for (std::size_t i = 0; i < tc.size(); ++i)
                mesh.texcoords.push_back(m_r.vector<2>(tc[i], Reader::index(wc, i)));
        } else {
            mesh.texcoords.assign(mesh.positions.size(), vec2(0.0f));
        }
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            const std::string wi = Reader::index(wt, t);
            const Json& tri = triangles[t];
            if (!tri.is_array() || tri.size() != 3)
                m_r.fail(wi, "expected 3 vertex indices, got " + Reader::describe(tri));
            uvec3 index;
            for (int k = 0; k < 3; ++k) {
                const int v = m_r.integer(tri[std::size_t(k)], Reader::index(wi, std::size_t(k)));
                if (v < 0 || std::size_t(v) >= mesh.positions.size())
                    m_r.fail(Reader::index(wi, std::size_t(k)),
                             "vertex index " + std::to_string(v) + " is out of range [0, " +
                                 std::to_string(mesh.positions.size() - 1) + "]");
                index[k] = std::uint32_t(v);
            }
            mesh.triangles.push_back(index);
            mesh.triangleMaterial.push_back(0);
        }
    }

    void readLight(const Json& j, const std::string& w) {
        if (!j.is_object()) m_r.fail(w, "expected an object, got " + Reader::describe(j));
        const std::string type = m_r.string(m_r.require(j, "type", w), Reader::join(w, "type"));
        auto at = [&](const char* key) { return Reader::join(w, key); };
        auto radiance = [&]() { return m_r.color(m_r.require(j, "radiance", w), at("radiance")); };
        if (type == "rectangle") {
            m_r.expectObject(j, w,
                             {"type", "position", "normal", "size", "tangent", "axisU", "axisV", "radiance"});
            const vec3 position = m_r.vector<3>(m_r.require(j, "position", w), at("position"));
            if (j.contains("axisU") || j.contains("axisV")) {
                if (j.contains("size") || j.contains("tangent"))
                    m_r.fail(w, "give either 'axisU'/'axisV' or 'size'/'tangent'");
                const vec3 u = m_r.vector<3>(m_r.require(j, "axisU", w), at("axisU"));
                const vec3 v = m_r.vector<3>(m_r.require(j, "axisV", w), at("axisV"));
                if (!(length(u) > 0.0f && length(v) > 0.0f)) m_r.fail(w, "axisU and axisV must be non-zero");
                for (const char* key : {"axisU", "axisV"}) {
                    // A half-extent: the edge is twice its length (in double: its square may overflow).
                    const double edge = 2.0 * glm::length(glm::dvec3(std::string(key) == "axisU" ? u : v));
                    if (!(edge >= double(MIN_LIGHT_SIZE) && edge <= double(MAX_LIGHT_SIZE)))
                        m_r.fail(at(key), "gives an edge of " + numberText(edge) +
                                              ", outside the accepted light size " + lightSizeRangeText() +
                                              " world units (the samplers need the light's area as a "
                                              "normal float)");
                }
                const vec3 n = cross(u, v);
                if (!(length(n) > 1e-6f * length(u) * length(v))) m_r.fail(w, "axisU and axisV are parallel");
                if (std::abs(dot(u, v)) > 1e-4f * length(u) * length(v))
                    m_r.fail(w, "axisU and axisV must be perpendicular");
                vec3 normal = normalize(n);
                if (j.contains("normal")) {
                    const vec3 given = m_r.direction(j["normal"], at("normal"));
                    if (std::abs(dot(given, normal)) < 0.999f)
                        m_r.fail(at("normal"), "must be perpendicular to axisU and axisV");
                    normal = given;
                }
                Light light = makeRectangleLight(position, normal, vec2(2.0f * length(u), 2.0f * length(v)),
                                                 radiance(), u);
                m_scene.lights.push_back(light);
            } else {
                const vec3 normal = m_r.direction(m_r.require(j, "normal", w), at("normal"));
                const Json& s = m_r.require(j, "size", w);
                vec2 size(0.0f);
                if (s.is_number()) {
                    size = vec2(m_r.lightSize(s, at("size")));
                } else {
                    if (!s.is_array() || s.size() != 2)
                        m_r.fail(at("size"),
                                 "expected a number or an array of 2 numbers, got " + Reader::describe(s));
                    for (std::size_t i = 0; i < 2; ++i)
                        size[int(i)] = m_r.lightSize(s[i], Reader::index(at("size"), i));
                }
                vec3 tangent(0.0f);
                if (j.contains("tangent")) tangent = m_r.direction(j["tangent"], at("tangent"));
                m_scene.lights.push_back(makeRectangleLight(position, normal, size, radiance(), tangent));
            }
        } else if (type == "disk") {
            m_r.expectObject(j, w, {"type", "position", "normal", "radius", "radiance"});
            m_scene.lights.push_back(
                makeDiskLight(m_r.vector<3>(m_r.require(j, "position", w), at("position")),
                              m_r.direction(m_r.require(j, "normal", w), at("normal")),
                              m_r.lightSize(m_r.require(j, "radius", w), at("radius")), radiance()));
        } else if (type == "sphere") {
            m_r.expectObject(j, w, {"type", "position", "radius", "radiance"});
            m_scene.lights.push_back(
                makeSphereLight(m_r.vector<3>(m_r.require(j, "position", w), at("position")),
                                m_r.lightSize(m_r.require(j, "radius", w), at("radius")), radiance()));
        } else if (type == "directional") {
            m_r.expectObject(j, w, {"type", "direction", "angularRadius", "radiance"});
            const float degrees = m_r.nonNegative(m_r.require(j, "angularRadius", w), at("angularRadius"));
            if (degrees >= 90.0f) m_r.fail(at("angularRadius"), "must be < 90 degrees");
            m_scene.lights.push_back(
                makeDirectionalLight(m_r.direction(m_r.require(j, "direction", w), at("direction")),
                                     glm::radians(degrees), radiance()));
        } else {
            m_r.fail(at("type"),
                     "unknown light type \"" + type + "\" (expected rectangle, disk, sphere or directional)");
        }
        if (const std::string problem = lightProblem(m_scene.lights.back()); !problem.empty())
            m_r.fail(w, problem);
    }

    void readCamera(const Json& j) {
        const std::string w = "camera";
        m_r.expectObject(j, w, {"eye", "target", "up", "fovY"});
        Camera& c = m_scene.camera;
        c.eye = m_r.vector<3>(m_r.require(j, "eye", w), "camera.eye");
        c.target = m_r.vector<3>(m_r.require(j, "target", w), "camera.target");
        c.up = j.contains("up") ? m_r.direction(j["up"], "camera.up") : vec3(0.0f, 1.0f, 0.0f);
        if (j.contains("fovY")) {
            c.fovY = float(m_r.number(j["fovY"], "camera.fovY"));
            if (!(c.fovY > 0.0f && c.fovY < 180.0f)) m_r.fail("camera.fovY", "must be in (0, 180) degrees");
        }
        for (const char* key : {"eye", "target"}) {
            const vec3 v = std::string(key) == "eye" ? c.eye : c.target;
            if (!withinSceneRange(v))
                m_r.fail(Reader::join(w, key),
                         "coordinates must lie within ±" + sceneRangeText() + " world units");
        }
        const vec3 forward = c.target - c.eye;
        if (!(length(forward) > 0.0f)) m_r.fail(w, "eye and target coincide");
        if (length(cross(normalize(forward), c.up)) < 1e-4f)
            m_r.fail("camera.up", "is parallel to the view direction");
    }

    Reader m_r;
    fs::path m_dir;
    Scene m_scene;
    std::map<std::string, std::uint32_t> m_materialByName;
    std::map<std::string, int> m_textureByKey;
};

/// The 1-based line of byte `offset` of `text`.
std::size_t lineOf(const std::string& text, std::size_t offset) {
    return 1 + std::size_t(std::count(text.begin(),
                                      text.begin() + std::ptrdiff_t(std::min(offset, text.size())), '\n'));
}

/// The characters of a text as nlohmann::json's parser reads them, noting in `*reached` how far
/// it has read: the parser callback is given a value but not its place in the text, and the
/// place of a key is where the parser has read to when the callback sees it (just past the
/// key's closing quote: a string token needs no look-ahead).
class TrackedChars {
  public:
    using iterator_category = std::input_iterator_tag;
    using value_type = char;
    using difference_type = std::ptrdiff_t;
    using pointer = const char*;
    using reference = const char&;

    TrackedChars(const char* at, const char** reached) : m_at(at), m_reached(reached) {}
    reference operator*() const { return *m_at; }
    TrackedChars& operator++() {
        *m_reached = ++m_at;
        return *this;
    }
    TrackedChars operator++(int) {
        TrackedChars before = *this;
        ++*this;
        return before;
    }
    bool operator==(const TrackedChars& other) const { return m_at == other.m_at; }
    bool operator!=(const TrackedChars& other) const { return m_at != other.m_at; }

  private:
    const char* m_at;
    const char** m_reached;
};

/// `text` parsed as JSON with comments, nesting limited and duplicate keys refused; InputError
/// naming `path` (and the line).
Json parseJsonText(const std::string& path, const std::string& text) {
    Json root;
    const char* reached = text.data();
    // The keys of each object being read, with the offset just past each (for its line).
    std::vector<std::map<std::string, std::size_t>> keys;
    try {
        const Json::parser_callback_t check = [&](int depth, Json::parse_event_t event, Json& parsed) {
            // Nesting is limited while parsing: a scene is a few levels deep, and a deep value
            // would exhaust the stack of whatever walks it afterwards.
            if (depth > MAX_JSON_DEPTH &&
                (event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start))
                throw InputError(path, "JSON nested deeper than " + std::to_string(MAX_JSON_DEPTH) +
                                           " levels; a scene needs a handful");
            // A repeated key would keep only its last value, silently: refused where it repeats.
            if (event == Json::parse_event_t::object_start) keys.emplace_back();
            if (event == Json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
            if (event == Json::parse_event_t::key && !keys.empty()) {
                const auto offset = std::size_t(reached - text.data());
                const auto [it, added] = keys.back().try_emplace(parsed.get<std::string>(), offset);
                if (!added)
                    throw InputError(path, lineOf(text, offset),
                                     "duplicate key " + parsed.dump() + " (first at line " +
                                         std::to_string(lineOf(text, it->second)) +
                                         "): JSON would keep only the last value; give each key once");
            }
            return true;
        };
        root = Json::parse(TrackedChars(text.data(), &reached),
                           TrackedChars(text.data() + text.size(), &reached), check, true,
                           /*ignore_comments=*/true);
    } catch (const Json::out_of_range& e) { // number overflow ("1e999")
        std::string message = e.what();
        if (const auto at = message.find("] "); at != std::string::npos) message = message.substr(at + 2);
        throw InputError(path, "invalid JSON: " + message);
    } catch (const Json::parse_error& e) {
        // e.what() reads "[json.exception.parse_error.101] parse error at line L, column C: ...".
        std::string message = e.what();
        if (const auto at = message.find("] "); at != std::string::npos) message = message.substr(at + 2);
        throw InputError(path, lineOf(text, e.byte), "invalid JSON: " + message);
    }
    return root;
}

} // namespace

Scene loadJsonScene(const std::string& path) {
    const std::string text = readFileBytes(path, "scene file", std::size_t(memoryLimitBytes() / 8));
    return SceneBuilder(path).build(parseJsonText(path, text));
}

Light parseLightJson(const std::string& what, const std::string& text) {
    return SceneBuilder(what).lightFrom(parseJsonText(what, text), "");
}

Camera parseCameraJson(const std::string& what, const std::string& text) {
    return SceneBuilder(what).cameraFrom(parseJsonText(what, text));
}

} // namespace stsv
