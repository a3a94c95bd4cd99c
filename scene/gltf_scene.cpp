#include "scene/gltf_scene.h"

#include "core/error.h"
#include "core/files.h"
#include "core/memory_budget.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

namespace stsv {

namespace {

namespace fs = std::filesystem;

/// glTF's component types and sampler wrap modes (glTF 2.0 §5.1.2, §5.26).
constexpr int GLTF_UNSIGNED_BYTE = 5121;
constexpr int GLTF_UNSIGNED_SHORT = 5123;
constexpr int GLTF_UNSIGNED_INT = 5125;
constexpr int GLTF_FLOAT = 5126;
constexpr int GLTF_TRIANGLES = 4;
constexpr int GLTF_REPEAT = 10497;
constexpr int GLTF_CLAMP_TO_EDGE = 33071;
/// Node hierarchies deeper than this are refused (glTF forbids cycles; this catches them).
constexpr int MAX_NODE_DEPTH = 256;

class GltfReader {
  public:
    GltfReader(const std::string& path, const tinygltf::Model& model) : m_path(path), m_model(model) {}

    MeshData read(std::optional<Camera>* camera) {
        if (m_model.scenes.empty()) fail("has no scene");
        const int sceneIndex = m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
        if (sceneIndex >= int(m_model.scenes.size()))
            fail("default scene " + std::to_string(sceneIndex) + " does not exist");
        m_camera = camera;
        if (camera) camera->reset();
        for (int node : m_model.scenes[std::size_t(sceneIndex)].nodes) walk(node, mat4(1.0f), 0);
        if (m_mesh.triangles.empty()) fail("scene " + std::to_string(sceneIndex) + " has no triangles");
        return std::move(m_mesh);
    }

  private:
    [[noreturn]] void fail(const std::string& problem) const { throw InputError(m_path, "glTF: " + problem); }

    template <class T> const T& at(const std::vector<T>& list, int index, const char* what) const {
        if (index < 0 || std::size_t(index) >= list.size())
            fail(std::string(what) + " " + std::to_string(index) + " does not exist");
        return list[std::size_t(index)];
    }

    static mat4 localMatrix(const tinygltf::Node& node) {
        if (node.matrix.size() == 16) {
            mat4 m;
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) m[c][r] = float(node.matrix[std::size_t(4 * c + r)]);
            return m;
        }
        mat4 m(1.0f);
        if (node.translation.size() == 3)
            m = glm::translate(
                m, vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2])));
        if (node.rotation.size() == 4) {
            // glTF stores (x, y, z, w); glm's quat constructor takes w first.
            const glm::quat q(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                              float(node.rotation[2]));
            m = m * glm::mat4_cast(glm::normalize(q));
        }
        if (node.scale.size() == 3)
            m = glm::scale(m, vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
        return m;
    }

    void walk(int index, const mat4& parent, int depth) {
        if (depth > MAX_NODE_DEPTH)
            fail("node hierarchy deeper than " + std::to_string(MAX_NODE_DEPTH) + " (a cycle?)");
        const tinygltf::Node& node = at(m_model.nodes, index, "node");
        const std::string where = "node " + std::to_string(index);
        for (double v : node.matrix)
            if (!std::isfinite(v)) fail(where + " has a non-finite matrix");
        for (const auto* list : {&node.translation, &node.rotation, &node.scale})
            for (double v : *list)
                if (!std::isfinite(v)) fail(where + " has a non-finite transform");
        const mat4 world = parent * localMatrix(node);
        if (node.mesh >= 0) addMesh(at(m_model.meshes, node.mesh, "mesh"), node.mesh, world);
        if (node.camera >= 0 && m_camera && !m_camera->has_value()) {
            const tinygltf::Camera& c = at(m_model.cameras, node.camera, "camera");
            if (c.type == "perspective") {
                // The camera looks down its node's −z with +y up (glTF 2.0 §3.10.1).
                Camera camera;
                camera.eye = vec3(world * vec4(0.0f, 0.0f, 0.0f, 1.0f));
                camera.target = camera.eye + normalize(vec3(world * vec4(0.0f, 0.0f, -1.0f, 0.0f)));
                camera.up = normalize(vec3(world * vec4(0.0f, 1.0f, 0.0f, 0.0f)));
                camera.fovY = float(glm::degrees(c.perspective.yfov));
                if (!(camera.fovY > 0.0f && camera.fovY < 180.0f))
                    fail("camera " + std::to_string(node.camera) + " has yfov outside (0, π)");
                *m_camera = camera;
            }
        }
        for (int child : node.children) walk(child, world, depth + 1);
    }

    /// The accessor's elements as bytes: each element's address, checked against its buffer.
    struct View {
        const unsigned char* data = nullptr;
        std::size_t stride = 0;
        std::size_t count = 0;
        int componentType = 0;
        bool normalized = false;
    };

    View view(int accessorIndex, int type, const std::string& what) const {
        const tinygltf::Accessor& a = at(m_model.accessors, accessorIndex, "accessor");
        const std::string where = what + " (accessor " + std::to_string(accessorIndex) + ")";
        if (a.sparse.isSparse) fail(where + " is sparse, which is not supported");
        if (a.type != type) fail(where + " has the wrong type");
        if (a.bufferView < 0) fail(where + " has no buffer view");
        const tinygltf::BufferView& bv = at(m_model.bufferViews, a.bufferView, "buffer view");
        const tinygltf::Buffer& buffer = at(m_model.buffers, bv.buffer, "buffer");
        std::size_t component = 0;
        switch (a.componentType) {
        case GLTF_UNSIGNED_BYTE:
            component = 1;
            break;
        case GLTF_UNSIGNED_SHORT:
            component = 2;
            break;
        case GLTF_UNSIGNED_INT:
        case GLTF_FLOAT:
            component = 4;
            break;
        default:
            fail(where + " has an unsupported component type " + std::to_string(a.componentType));
        }
        const std::size_t components = type == TINYGLTF_TYPE_SCALAR ? 1 : type == TINYGLTF_TYPE_VEC2 ? 2 : 3;
        const std::size_t element = component * components;
        const std::size_t stride = bv.byteStride ? bv.byteStride : element;
        if (stride < element)
            fail(where + ": byte stride " + std::to_string(stride) + " is below the element size");
        const std::size_t start = bv.byteOffset + a.byteOffset;
        // Overflow-safe: the last element must end inside the view and the view inside the buffer.
        if (bv.byteOffset > buffer.data.size() || bv.byteLength > buffer.data.size() - bv.byteOffset ||
            a.byteOffset > bv.byteLength ||
            (a.count > 0 && (a.count - 1 > (bv.byteLength - a.byteOffset) / stride ||
                             (a.count - 1) * stride + element > bv.byteLength - a.byteOffset)))
            fail(where + " reaches outside its buffer");
        return {buffer.data.data() + start, stride, a.count, a.componentType, a.normalized};
    }

    static float component(const View& v, std::size_t i, int c) {
        const unsigned char* p = v.data + i * v.stride;
        switch (v.componentType) {
        case GLTF_FLOAT: {
            float f;
            std::memcpy(&f, p + 4 * c, 4);
            return f;
        }
        case GLTF_UNSIGNED_BYTE:
            return float(p[c]) / 255.0f;
        case GLTF_UNSIGNED_SHORT: {
            std::uint16_t s;
            std::memcpy(&s, p + 2 * c, 2);
            return float(s) / 65535.0f;
        }
        default:
            return 0.0f;
        }
    }

    static std::uint32_t index(const View& v, std::size_t i) {
        const unsigned char* p = v.data + i * v.stride;
        if (v.componentType == GLTF_UNSIGNED_BYTE) return p[0];
        if (v.componentType == GLTF_UNSIGNED_SHORT) {
            std::uint16_t s;
            std::memcpy(&s, p, 2);
            return s;
        }
        std::uint32_t u;
        std::memcpy(&u, p, 4);
        return u;
    }

    void addMesh(const tinygltf::Mesh& mesh, int meshIndex, const mat4& world) {
        for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const tinygltf::Primitive& prim = mesh.primitives[pi];
            const std::string where =
                "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(pi);
            if (prim.mode != GLTF_TRIANGLES && prim.mode != -1)
                fail(where + " has mode " + std::to_string(prim.mode) +
                     " (points, lines, strips or fans): only triangle lists (mode 4) are supported");
            const auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) fail(where + " has no POSITION");
            const View positions = view(pos->second, TINYGLTF_TYPE_VEC3, where + " POSITION");
            if (positions.componentType != GLTF_FLOAT) fail(where + " POSITION must be float");
            // The material first: it says which texture coordinate set the alpha reads.
            int texCoord = 0;
            const std::uint32_t material = materialOf(prim.material, texCoord);
            std::optional<View> uvs;
            if (const auto uv = prim.attributes.find("TEXCOORD_" + std::to_string(texCoord));
                uv != prim.attributes.end()) {
                uvs = view(uv->second, TINYGLTF_TYPE_VEC2, where + " TEXCOORD_" + std::to_string(texCoord));
                if (uvs->componentType == GLTF_UNSIGNED_INT ||
                    (uvs->componentType != GLTF_FLOAT && !uvs->normalized))
                    fail(where + " TEXCOORD must be float or normalized unsigned byte or short");
                if (uvs->count != positions.count)
                    fail(where + " has a different count of TEXCOORD and POSITION");
            }
            checkMemory(m_path + ": " + where, double(positions.count) * 2600.0, "use a coarser mesh");
            const auto base = static_cast<std::uint32_t>(m_mesh.positions.size());
            for (std::size_t i = 0; i < positions.count; ++i) {
                const vec3 p(component(positions, i, 0), component(positions, i, 1),
                             component(positions, i, 2));
                m_mesh.positions.push_back(vec3(world * vec4(p, 1.0f)));
                m_mesh.texcoords.push_back(uvs ? vec2(component(*uvs, i, 0), component(*uvs, i, 1))
                                               : vec2(0.0f));
            }
            std::vector<std::uint32_t> corners;
            if (prim.indices >= 0) {
                const View indices = view(prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices");
                if (indices.componentType == GLTF_FLOAT) fail(where + " indices must be unsigned integers");
                for (std::size_t i = 0; i < indices.count; ++i) corners.push_back(index(indices, i));
            } else {
                for (std::size_t i = 0; i < positions.count; ++i) corners.push_back(std::uint32_t(i));
            }
            if (corners.size() % 3 != 0)
                fail(where + " has " + std::to_string(corners.size()) + " indices, not a multiple of 3");
            for (std::size_t c = 0; c < corners.size(); c += 3) {
                const uvec3 t(corners[c], corners[c + 1], corners[c + 2]);
                for (int k = 0; k < 3; ++k)
                    if (t[k] >= positions.count)
                        fail(where + " index " + std::to_string(t[k]) + " is beyond its " +
                             std::to_string(positions.count) + " vertices");
                if (t.x == t.y || t.y == t.z || t.x == t.z) {
                    ++m_mesh.skippedFaces;
                    continue;
                }
                m_mesh.triangles.push_back(uvec3(base) + t);
                m_mesh.triangleMaterial.push_back(material);
            }
        }
    }

    /// The MeshData material of glTF material `index` (−1: glTF's default material, opaque white),
    /// and the texture coordinate set its baseColorTexture reads.
    std::uint32_t materialOf(int index, int& texCoord) {
        if (const auto it = m_materials.find(index); it != m_materials.end()) {
            texCoord = it->second.second;
            return it->second.first;
        }
        Material m;
        m.name = "gltf default";
        AlphaMode mode = AlphaMode::Opaque;
        float factor = 1.0f, cutoff = 0.5f;
        int texture = -1;
        texCoord = 0;
        if (index >= 0) {
            const tinygltf::Material& g = at(m_model.materials, index, "material");
            const std::string where = "material " + std::to_string(index);
            m.name = g.name.empty() ? where : g.name;
            const std::vector<double>& f = g.pbrMetallicRoughness.baseColorFactor;
            if (f.size() != 4) fail(where + " baseColorFactor must have 4 components");
            m.albedo = vec3(float(f[0]), float(f[1]), float(f[2]));
            if (const std::string problem = albedoProblem(m.albedo); !problem.empty())
                fail(where + " baseColorFactor: " + problem);
            if (!(f[3] >= 0.0 && f[3] <= 1.0)) fail(where + " baseColorFactor alpha must be in [0, 1]");
            factor = float(f[3]);
            if (!(g.alphaCutoff >= 0.0 && g.alphaCutoff <= 1.0))
                fail(where + " alphaCutoff must be in [0, 1]");
            cutoff = float(g.alphaCutoff);
            if (g.alphaMode == "MASK")
                mode = AlphaMode::Mask;
            else if (g.alphaMode == "BLEND")
                mode = AlphaMode::Blend;
            else if (g.alphaMode != "OPAQUE")
                fail(where + " alphaMode \"" + g.alphaMode + "\" (expected OPAQUE, MASK or BLEND)");
            m.doubleSided = g.doubleSided;
            const tinygltf::TextureInfo& info = g.pbrMetallicRoughness.baseColorTexture;
            if (info.index >= 0 && mode != AlphaMode::Opaque) {
                if (info.texCoord < 0 || info.texCoord > 7) fail(where + " texCoord must be in [0, 7]");
                texCoord = info.texCoord;
                texture = textureOf(info.index, m.wrap);
            }
        }
        setMaterialAlpha(m, m_mesh.textures, mode, texture, factor, cutoff);
        m_mesh.materials.push_back(m);
        const auto result = static_cast<std::uint32_t>(m_mesh.materials.size() - 1);
        m_materials[index] = {result, texCoord};
        return result;
    }

    /// The MeshData texture of glTF texture `index` (its image's alpha, 255 without one), and
    /// its sampler's wrap mode.
    int textureOf(int index, WrapMode& wrap) {
        const tinygltf::Texture& t = at(m_model.textures, index, "texture");
        const std::string where = "texture " + std::to_string(index);
        wrap = WrapMode::Repeat;
        if (t.sampler >= 0) {
            const tinygltf::Sampler& s = at(m_model.samplers, t.sampler, "sampler");
            if (s.wrapS != s.wrapT)
                fail(where + " sampler has different wrap modes in u and v (" + std::to_string(s.wrapS) +
                     ", " + std::to_string(s.wrapT) + "): stsv wraps both alike");
            if (s.wrapS != GLTF_REPEAT && s.wrapS != GLTF_CLAMP_TO_EDGE)
                fail(where + " sampler wrap mode " + std::to_string(s.wrapS) +
                     " is not supported (REPEAT 10497 and CLAMP_TO_EDGE 33071 are)");
            wrap = s.wrapS == GLTF_CLAMP_TO_EDGE ? WrapMode::Clamp : WrapMode::Repeat;
        }
        if (const auto it = m_textures.find(t.source); it != m_textures.end()) return it->second;
        const tinygltf::Image& image = at(m_model.images, t.source, "image");
        const std::string name = image.uri.empty() ? where + " image " + std::to_string(t.source) : image.uri;
        const std::size_t pixels =
            std::size_t(std::max(image.width, 0)) * std::size_t(std::max(image.height, 0));
        const std::size_t bytesPerChannel = image.bits == 16 ? 2 : 1;
        if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.component > 4 ||
            (image.bits != 8 && image.bits != 16) ||
            image.image.size() != pixels * std::size_t(image.component) * bytesPerChannel)
            fail("image '" + name + "' was not decoded (missing, or not PNG or JPEG)");
        Texture texture;
        texture.name = name;
        texture.width = image.width;
        texture.height = image.height;
        texture.rgba.assign(pixels * 4, 255);
        for (std::size_t p = 0; p < pixels; ++p)
            for (int c = 0; c < image.component; ++c) {
                // 16-bit channels are little-endian in tinygltf's decoded image: the high byte.
                const std::size_t at = (p * std::size_t(image.component) + std::size_t(c)) * bytesPerChannel;
                const std::uint8_t value = image.image[at + bytesPerChannel - 1];
                // Grey (+ alpha) images: channel 0 is grey, channel 1 (of 2) is alpha.
                const int target = image.component == 2 && c == 1 ? 3 : image.component <= 2 ? -1 : c;
                if (target < 0) {
                    texture.rgba[4 * p] = texture.rgba[4 * p + 1] = texture.rgba[4 * p + 2] = value;
                } else {
                    texture.rgba[4 * p + std::size_t(target)] = value;
                }
            }
        m_mesh.textures.push_back(std::move(texture));
        const int result = int(m_mesh.textures.size() - 1);
        m_textures[t.source] = result;
        return result;
    }

    std::string m_path;
    const tinygltf::Model& m_model;
    MeshData m_mesh;
    std::optional<Camera>* m_camera = nullptr;
    std::map<int, std::pair<std::uint32_t, int>> m_materials; ///< glTF material → (ours, texCoord)
    std::map<int, int> m_textures;                            ///< glTF image → ours
};

} // namespace

MeshData loadGltf(const std::string& path, std::optional<Camera>* camera) {
    if (const std::string reason = notAFileReason(path); !reason.empty())
        throw InputError(path, "glTF file " + reason);
    checkMemory(path, double(fs::file_size(path)) * 8.0, "use a smaller file");
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    bool ok = false;
    try {
        ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &error, &warning, path)
                           : loader.LoadASCIIFromFile(&model, &error, &warning, path);
    } catch (const std::exception& e) {
        throw InputError(path, std::string("glTF: ") + e.what());
    }
    if (!ok) {
        while (!error.empty() && (error.back() == '\n' || error.back() == ' ')) error.pop_back();
        throw InputError(path, "glTF: " + (error.empty() ? std::string("cannot be read") : error));
    }
    return GltfReader(path, model).read(camera);
}

} // namespace stsv
