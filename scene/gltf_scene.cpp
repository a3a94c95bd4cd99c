#include "scene/gltf_scene.h"

#include "core/error.h"
#include "core/files.h"
#include "core/image.h"
#include "core/memory_budget.h"

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <string_view>

namespace stsv {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// glTF's component types, primitive modes and sampler wrap modes (glTF 2.0 §3.6.2.2, §3.7.2.1,
/// §5.26).
constexpr int GLTF_UNSIGNED_BYTE = 5121;
constexpr int GLTF_UNSIGNED_SHORT = 5123;
constexpr int GLTF_UNSIGNED_INT = 5125;
constexpr int GLTF_FLOAT = 5126;
constexpr int GLTF_LINE_STRIP = 3; ///< modes 0 to 3: points, lines, line loops, line strips
constexpr int GLTF_TRIANGLES = 4;
constexpr int GLTF_TRIANGLE_STRIP = 5;
constexpr int GLTF_TRIANGLE_FAN = 6;
constexpr int GLTF_REPEAT = 10497;
constexpr int GLTF_CLAMP_TO_EDGE = 33071;
/// Node trees deeper than this are refused: the walk recurses once a level.
constexpr int MAX_NODE_DEPTH = 256;
/// How far a node's rotation may be from a unit quaternion (glTF 2.0 §5.25 requires unit):
/// exporters write unit quaternions in float precision, and a few rounded digits stay well
/// inside this, while a rotation written as something else (a scale in w) does not.
constexpr double ROTATION_UNIT_TOLERANCE = 1e-3;
/// Bytes a glTF vertex costs while loading: its position and texture coordinate (20 bytes) in
/// the MeshData, and again in the Scene it is appended to. A mesh's vertices are copied once for
/// each node that draws it, so the count is taken over the scene's instances.
constexpr double GLTF_VERTEX_BYTES = 40.0;

/// The extensions stsv implements, which a file may list in extensionsRequired. Those a file
/// merely uses (extensionsUsed) are ignored, as glTF allows: the file is to load without them.
const char* const SUPPORTED_EXTENSIONS[] = {"KHR_texture_transform"};

/// Input quoted in a message, cut to `max` characters.
std::string clipped(const std::string& text, std::size_t max) {
    return text.size() <= max ? text : text.substr(0, max) + "...";
}

/// "major.minor" of asset.version and asset.minVersion; false when the text is not of that form.
bool parseVersion(const std::string& text, int& major, int& minor) {
    const auto dot = text.find('.');
    if (dot == std::string::npos || dot == 0 || dot > 4 || dot + 1 == text.size() || text.size() - dot > 5)
        return false;
    for (std::size_t i = 0; i < text.size(); ++i)
        if (i != dot && !(text[i] >= '0' && text[i] <= '9')) return false;
    major = std::stoi(text.substr(0, dot));
    minor = std::stoi(text.substr(dot + 1));
    return true;
}

/// Empty when stsv reads a file of this asset version and minimum version; else why not.
std::string versionProblem(const std::string& version, const std::string& minVersion) {
    int major = 0, minor = 0;
    if (version.empty()) return "asset.version is missing (glTF 2.0 files have \"2.0\")";
    if (!parseVersion(version, major, minor))
        return "asset.version \"" + clipped(version, 40) + "\" is not of the form major.minor";
    if (major != 2) return "asset.version is " + version + ": stsv reads glTF 2.x only";
    if (!minVersion.empty()) {
        if (!parseVersion(minVersion, major, minor))
            return "asset.minVersion \"" + clipped(minVersion, 40) + "\" is not of the form major.minor";
        if (major != 2 || minor > 0)
            return "asset.minVersion is " + minVersion + ", above the glTF 2.0 stsv reads";
    }
    return {};
}

/// Empty when stsv implements every extension of extensionsRequired; else which it does not.
std::string requiredExtensionsProblem(const std::vector<std::string>& required) {
    std::string unsupported;
    for (const std::string& name : required)
        if (std::find(std::begin(SUPPORTED_EXTENSIONS), std::end(SUPPORTED_EXTENSIONS), name) ==
            std::end(SUPPORTED_EXTENSIONS))
            unsupported += (unsupported.empty() ? "" : ", ") + clipped(name, 80);
    if (unsupported.empty()) return {};
    std::string supported;
    for (const char* name : SUPPORTED_EXTENSIONS)
        supported += (supported.empty() ? "" : ", ") + std::string(name);
    return "extensionsRequired names " + unsupported + ", which stsv does not implement (it implements " +
           supported + ")";
}

/// A URI as tinygltf turns it into a file name (its dlib urldecode: %XX escapes, '+' as a space).
std::string decodeUri(const std::string& uri) {
    const auto hex = [](char c) {
        return c >= '0' && c <= '9'   ? c - '0'
               : c >= 'a' && c <= 'f' ? c - 'a' + 10
               : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                      : 0;
    };
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && i + 2 < uri.size()) {
            out += char(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

/// The folder tinygltf resolves a file's URIs against (its GetBaseDir): the path up to the last
/// slash, empty when there is none.
std::string baseDirOf(const std::string& path) {
    const auto slash = path.find_last_of("/\\");
    return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

/// A URI resolved as tinygltf resolves it (its JoinPath).
std::string resolveUri(const std::string& baseDir, const std::string& uri) {
    if (baseDir.empty()) return decodeUri(uri);
    return baseDir + (baseDir.back() == '/' ? "" : "/") + decodeUri(uri);
}

bool isDataUri(const std::string& uri) {
    return uri.rfind("data:", 0) == 0;
}

/// What tinygltf reads through stsv's callbacks, and what they refused.
struct LoadContext {
    std::string path;           ///< the glTF file
    std::string baseDir;        ///< baseDirOf(path)
    double externalBytes = 0.0; ///< bytes of the buffer and image files read so far
    std::string refusedPath;    ///< the last file refused, and why
    std::string refusedReason;
    std::exception_ptr error; ///< an error thrown inside a callback, thrown again after tinygltf returns
};

/// tinygltf looks for a URI's file beside the glTF file, then in the working directory; only the
/// first is the file the glTF names (a missing texture must not be taken from wherever stsv
/// runs). It counts as existing whatever it is, so that readWholeFile says why it cannot be read.
bool fileExists(const std::string& absolute, void* user) {
    const auto& context = *static_cast<const LoadContext*>(user);
    return context.baseDir.empty() || absolute.rfind(context.baseDir, 0) == 0;
}

std::string expandFilePath(const std::string& path, void*) {
    return path;
}

/// tinygltf's own reader opens a directory as an empty stream of "size" 2^63 − 1 and asks for
/// that much memory (a buffer whose uri is "." ends in std::bad_alloc). This one refuses what is
/// not a regular file, saying why (refusalCause, GltfReader::encodedImage), and holds the files'
/// bytes to the memory limit.
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    auto& context = *static_cast<LoadContext*>(user);
    const auto refuse = [&](const std::string& reason) {
        context.refusedPath = path;
        context.refusedReason = reason;
        if (err) *err += reason;
        return false;
    };
    try {
        if (const std::string reason = notAFileReason(path); !reason.empty()) return refuse(reason);
        std::ifstream in(path, std::ios::binary | std::ios::ate);
        const std::streamoff size = in.tellg();
        if (!in || size < 0) return refuse("cannot be read");
        // Each file is held twice for a moment (tinygltf's read, then the buffer or image).
        context.externalBytes += double(size);
        checkMemory(context.path + ": the buffer and image files it names (" + path + " the last)",
                    2.0 * context.externalBytes, "use smaller files");
        out->resize(std::size_t(size));
        in.seekg(0);
        if (!in.read(reinterpret_cast<char*>(out->data()), size)) return refuse("cannot be read");
        return true;
    } catch (...) {
        if (!context.error) context.error = std::current_exception();
        if (err) *err += "refused";
        return false;
    }
}

/// The image callback keeps each image's encoded bytes (tinygltf's `as_is`): images are decoded
/// only where a material's alpha reads them, each after its header's size is held to the memory
/// limit (GltfReader::textureOf). An image in a buffer view is left where it is: tinygltf hands
/// over its bytes without checking that the view lies inside its buffer, so they are taken from
/// the view later, checked.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView >= 0) return true;
    image->image.assign(bytes, bytes + std::max(size, 0));
    image->as_is = true;
    return true;
}

// ---------------------------------------------------------------------- the GLB container

/// GLB (glTF 2.0 §4.4): a 12-byte header (magic "glTF", container version, the file's length),
/// then chunks, each its length, its type and that many bytes: JSON first, then BIN, which may be
/// left out. tinygltf reads the container without saying which of these is wrong ("Invalid glTF
/// binary."), lets a BIN chunk reach 8 bytes past the file's end, and on an empty file throws
/// std::out_of_range from its vector's at(0); the container is read here first, so that a
/// refusal says what is wrong with it.
constexpr std::size_t GLB_HEADER_BYTES = 12;
constexpr std::size_t GLB_CHUNK_HEADER_BYTES = 8;

/// What a GLB holds once its container is checked.
struct GlbChunks {
    std::string_view json;               ///< the JSON chunk's text
    std::optional<std::size_t> binBytes; ///< the BIN chunk's length, when there is one
};

std::uint32_t littleEndianU32(const std::string& bytes, std::size_t offset) {
    std::uint32_t value = 0;
    for (int i = 3; i >= 0; --i) value = value << 8 | std::uint8_t(bytes[offset + std::size_t(i)]);
    return value;
}

/// A GLB's chunks; InputError saying what is wrong with the container.
GlbChunks glbChunks(const std::string& path, const std::string& bytes) {
    const auto refuse = [&](const std::string& problem) { throw InputError(path, "glTF: " + problem); };
    const std::string size = std::to_string(bytes.size());
    if (bytes.size() < GLB_HEADER_BYTES)
        refuse("is " + size + " bytes long, too short for the 12-byte header of a binary glTF (.glb)");
    if (bytes.compare(0, 4, "glTF") != 0)
        refuse(
            "does not begin with \"glTF\", the magic of a binary glTF (.glb); a glTF in JSON is named .gltf");
    if (const std::uint32_t version = littleEndianU32(bytes, 4); version != 2)
        refuse("a binary glTF of container version " + std::to_string(version) +
               " (glTF 1.0 wrote 1): stsv reads glTF 2.x only");
    if (const std::uint32_t length = littleEndianU32(bytes, 8); length != bytes.size())
        refuse("the header gives the file a length of " + std::to_string(length) + " bytes, but it has " +
               size + (length > bytes.size() ? " (a truncated file?)" : ""));
    GlbChunks chunks;
    std::size_t at = GLB_HEADER_BYTES;
    for (int index = 0; index == 0 || at < bytes.size(); ++index) {
        const std::string chunk = "chunk " + std::to_string(index);
        if (index == 0 && at == bytes.size())
            refuse("has no JSON chunk: the file ends after its 12-byte header");
        if (bytes.size() - at < GLB_CHUNK_HEADER_BYTES)
            refuse("ends " + std::to_string(bytes.size() - at) + " bytes into the 8-byte header of " + chunk +
                   " (at byte " + std::to_string(at) + ")");
        const std::size_t length = littleEndianU32(bytes, at);
        // The type as text: four ASCII letters, "BIN" padded with a NUL.
        std::string type = bytes.substr(at + 4, 4);
        while (!type.empty() && type.back() == '\0') type.pop_back();
        const std::size_t start = at + GLB_CHUNK_HEADER_BYTES;
        if (length > bytes.size() - start)
            refuse(chunk + " (type \"" + type + "\") has a length of " + std::to_string(length) +
                   " bytes, beyond the file's end (" + std::to_string(bytes.size() - start) +
                   " bytes follow its header)");
        if (index == 0) {
            if (type != "JSON")
                refuse("its first chunk is of type \"" + type +
                       "\", not \"JSON\" (a binary glTF begins with its JSON)");
            if (length == 0) refuse("its JSON chunk is empty");
            chunks.json = std::string_view(bytes).substr(start, length);
        } else if (index == 1) {
            // tinygltf reads the second chunk as BIN whatever its type; the specification lets
            // only chunks after BIN have other types.
            if (type != "BIN")
                refuse("its second chunk is of type \"" + type + "\", where only a BIN chunk may be");
            if (length == 0) refuse("its BIN chunk is empty (a binary glTF leaves an empty BIN chunk out)");
            if (length % 4 != 0)
                refuse("its BIN chunk's length, " + std::to_string(length) +
                       " bytes, is not a multiple of 4 (chunks are padded to 4 bytes)");
            chunks.binBytes = length;
        }
        at = start + length;
    }
    return chunks;
}

// ---------------------------------------------------------------------- the JSON

/// JSON nesting read in a glTF. glTF's own objects lie under ten levels deep; extras and
/// extensions hold other applications' data and get more room. tinygltf copies extras and
/// extensions recursively, so a file nested 100000 levels deep would overflow its stack.
constexpr int MAX_GLTF_JSON_DEPTH = 128;

/// The glTF's JSON (`text`, a .glb's JSON chunk when `binary`); InputError naming the file and
/// where the text stops being JSON.
Json parseGltfJson(const std::string& path, std::string_view text, bool binary) {
    if (text.empty()) throw InputError(path, "glTF: is empty (0 bytes)");
    if (!binary && text.substr(0, 4) == "glTF")
        throw InputError(path, "glTF: is a binary glTF; name it .glb");
    try {
        const Json::parser_callback_t limitDepth = [&](int depth, Json::parse_event_t event, Json&) {
            if (depth > MAX_GLTF_JSON_DEPTH &&
                (event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start))
                throw InputError(path, "glTF: JSON nested deeper than " +
                                           std::to_string(MAX_GLTF_JSON_DEPTH) + " levels");
            return true;
        };
        return Json::parse(text.begin(), text.end(), limitDepth);
    } catch (const Json::exception& e) {
        // A syntax error or a number too large for a double ("1e400"); e.what() reads
        // "[json.exception.parse_error.101] parse error at line L, column C: ...".
        std::string message = e.what();
        if (const auto at = message.find("] "); at != std::string::npos) message = message.substr(at + 2);
        throw InputError(path, std::string("glTF: invalid JSON") + (binary ? " in the JSON chunk" : "") +
                                   ": " + message);
    }
}

std::string jsonString(const Json& j, const char* key) {
    const auto it = j.is_object() ? j.find(key) : j.end();
    return j.is_object() && it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

/// The glTF's JSON checked where tinygltf is lenient, for the fields stsv reads: tinygltf drops
/// a value of the wrong type or length without a word (a node matrix of 15 numbers, a
/// translation that is a string, extensionsRequired that is not an array), reads −1 as "none"
/// (a scene of −1, a primitive mode of −1) and drops a primitive without attributes, so the file
/// would load with the value missing. A refusal names the JSON path:
/// "nodes[3].matrix: expected 16 numbers, got 15". This is no schema validator: fields stsv
/// does not read are left to tinygltf.
class GltfJsonCheck {
  public:
    GltfJsonCheck(const std::string& path, const std::optional<GlbChunks>& glb) : m_path(path), m_glb(glb) {}

    void check(const Json& root) {
        if (!root.is_object()) fail("", "its JSON is " + describe(root) + ", not an object");
        checkAsset(root);
        index(root, "scene", "");
        forEach(root, "scenes", "scenes",
                [&](const Json& scene, const std::string& w) { indices(scene, "nodes", w); });
        forEach(root, "nodes", "nodes", [&](const Json& node, const std::string& w) { checkNode(node, w); });
        forEach(root, "meshes", "meshes",
                [&](const Json& mesh, const std::string& w) { checkMesh(mesh, w); });
        forEach(root, "materials", "materials",
                [&](const Json& material, const std::string& w) { checkMaterial(material, w); });
        forEach(root, "textures", "textures", [&](const Json& texture, const std::string& w) {
            index(texture, "source", w);
            index(texture, "sampler", w);
        });
        forEach(root, "samplers", "samplers", [&](const Json& sampler, const std::string& w) {
            for (const char* key : {"wrapS", "wrapT"})
                if (const Json* v = find(sampler, key); v && !v->is_number_integer())
                    fail(join(w, key), "expected an integer (a wrap mode), got " + describe(*v));
        });
        std::size_t images = 0, buffers = 0;
        forEach(root, "images", "images", [&](const Json& image, const std::string& w) {
            uri(image, w, "image " + std::to_string(images++), true);
            index(image, "bufferView", w);
        });
        forEach(root, "buffers", "buffers",
                [&](const Json& buffer, const std::string& w) { checkBuffer(buffer, w, buffers++); });
        forEach(root, "bufferViews", "bufferViews", [&](const Json& view, const std::string& w) {
            index(view, "buffer", w);
            unsignedInteger(view, "byteOffset", w);
            unsignedInteger(view, "byteStride", w);
        });
        forEach(root, "accessors", "accessors", [&](const Json& accessor, const std::string& w) {
            index(accessor, "bufferView", w);
            unsignedInteger(accessor, "byteOffset", w);
            boolean(accessor, "normalized", w);
        });
        forEach(root, "skins", "skins", [&](const Json& skin, const std::string& w) {
            indices(skin, "joints", w);
            index(skin, "inverseBindMatrices", w);
        });
    }

  private:
    [[noreturn]] void fail(const std::string& where, const std::string& problem) const {
        throw InputError(m_path, "glTF: " + (where.empty() ? problem : where + ": " + problem));
    }

    static std::string join(const std::string& where, const char* key) {
        return where.empty() ? std::string(key) : where + "." + key;
    }

    static std::string item(const std::string& where, std::size_t i) {
        return where + "[" + std::to_string(i) + "]";
    }

    /// A JSON value as a message shows it: numbers, booleans and null as written, a string
    /// quoted, arrays and objects by kind.
    static std::string describe(const Json& v) {
        if (v.is_string())
            return "the string " + clipped(v.dump(-1, ' ', false, Json::error_handler_t::replace), 60);
        if (v.is_array()) return "an array";
        if (v.is_object()) return "an object";
        return v.dump();
    }

    static const Json* find(const Json& object, const char* key) {
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }

    /// `f(element, path)` for each element of the array object[key], each an object; nothing
    /// when the key is absent.
    template <class F>
    void forEach(const Json& object, const char* key, const std::string& where, F f) const {
        const Json* list = find(object, key);
        if (!list) return;
        if (!list->is_array()) fail(where, "expected an array of objects, got " + describe(*list));
        for (std::size_t i = 0; i < list->size(); ++i) {
            const Json& element = (*list)[i];
            if (!element.is_object()) fail(item(where, i), "expected an object, got " + describe(element));
            f(element, item(where, i));
        }
    }

    /// The object object[key], or null when it is absent.
    const Json* child(const Json& object, const char* key, const std::string& where) const {
        const Json* v = find(object, key);
        if (v && !v->is_object()) fail(join(where, key), "expected an object, got " + describe(*v));
        return v;
    }

    /// An index into one of the glTF's arrays: an integer in [0, 2^31 − 1] (tinygltf keeps an
    /// index as an int, −1 for none).
    void indexValue(const Json& v, const std::string& where) const {
        if (!v.is_number_integer() ||
            (v.is_number_unsigned() ? v.get<std::uint64_t>() > INT32_MAX : v.get<std::int64_t>() < 0))
            fail(where, "expected an index (an integer from 0 to 2147483647), got " + describe(v));
    }

    void index(const Json& object, const char* key, const std::string& where) const {
        if (const Json* v = find(object, key)) indexValue(*v, join(where, key));
    }

    void indices(const Json& object, const char* key, const std::string& where) const {
        const Json* v = find(object, key);
        if (!v) return;
        if (!v->is_array()) fail(join(where, key), "expected an array of indices, got " + describe(*v));
        for (std::size_t i = 0; i < v->size(); ++i) indexValue((*v)[i], item(join(where, key), i));
    }

    void unsignedInteger(const Json& object, const char* key, const std::string& where) const {
        if (const Json* v = find(object, key); v && !v->is_number_unsigned())
            fail(join(where, key), "expected an integer ≥ 0, got " + describe(*v));
    }

    void boolean(const Json& object, const char* key, const std::string& where) const {
        if (const Json* v = find(object, key); v && !v->is_boolean())
            fail(join(where, key), "expected true or false, got " + describe(*v));
    }

    /// object[key] as `count` numbers (any count when 0), each in [0, 1] when `unit`; nullptr when
    /// the key is absent.
    const Json* numbers(const Json& object, const char* key, const std::string& where, std::size_t count,
                        bool unit = false) const {
        const Json* v = find(object, key);
        if (!v) return nullptr;
        const std::string w = join(where, key);
        const std::string expected =
            count ? std::to_string(count) + " numbers" : std::string("an array of numbers");
        if (!v->is_array()) fail(w, "expected " + expected + ", got " + describe(*v));
        if (count && v->size() != count)
            fail(w, "expected " + expected + ", got " + std::to_string(v->size()));
        for (std::size_t i = 0; i < v->size(); ++i) {
            const Json& x = (*v)[i];
            if (!x.is_number()) fail(item(w, i), "expected a number, got " + describe(x));
            if (unit && !(x.get<double>() >= 0.0 && x.get<double>() <= 1.0))
                fail(item(w, i), x.dump() + " is outside [0, 1]");
        }
        return v;
    }

    /// asset.version and asset.minVersion, then extensionsUsed and extensionsRequired: a glTF 1.0
    /// file is named as one before anything else of it is read as glTF 2.0.
    void checkAsset(const Json& root) const {
        const Json* asset = find(root, "asset");
        if (asset && asset->is_object() && asset->contains("version") && !(*asset)["version"].is_string())
            fail("", "asset.version is " + clipped((*asset)["version"].dump(), 40) +
                         ", not a string (glTF 1.0 files wrote a number): stsv reads glTF 2.x only");
        if (!asset || !asset->is_object() || !asset->contains("version"))
            fail(
                "",
                "has no asset.version (glTF 2.0 files say \"asset\": {\"version\": \"2.0\"}; a glTF 1.0 file "
                "need not)");
        if (const Json* min = find(*asset, "minVersion"); min && !min->is_string())
            fail("asset.minVersion", "expected a string, got " + describe(*min));
        if (const std::string problem =
                versionProblem(jsonString(*asset, "version"), jsonString(*asset, "minVersion"));
            !problem.empty())
            fail("", problem);
        std::vector<std::string> required;
        for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
            const Json* v = find(root, key);
            if (!v) continue;
            if (!v->is_array()) fail(key, "expected an array of extension names, got " + describe(*v));
            for (std::size_t i = 0; i < v->size(); ++i) {
                if (!(*v)[i].is_string())
                    fail(item(key, i), "expected an extension name, got " + describe((*v)[i]));
                if (std::string(key) == "extensionsRequired") required.push_back((*v)[i].get<std::string>());
            }
        }
        if (const std::string problem = requiredExtensionsProblem(required); !problem.empty())
            fail("", problem);
    }

    /// A node's transform (glTF 2.0 §3.5.2): a matrix of 16 numbers, or a translation, a unit
    /// quaternion rotation and a scale; what it draws and its children.
    void checkNode(const Json& node, const std::string& w) const {
        numbers(node, "matrix", w, 16);
        numbers(node, "translation", w, 3);
        numbers(node, "scale", w, 3);
        if (const Json* r = numbers(node, "rotation", w, 4)) {
            double squared = 0.0;
            for (const Json& x : *r) squared += x.get<double>() * x.get<double>();
            if (!(std::abs(std::sqrt(squared) - 1.0) <= ROTATION_UNIT_TOLERANCE)) {
                char length[32];
                std::snprintf(length, sizeof length, "%.6g", std::sqrt(squared));
                fail(join(w, "rotation"), clipped(r->dump(), 80) + " has length " + length +
                                              ": a rotation is a unit quaternion (x, y, z, w)");
            }
        }
        indices(node, "children", w);
        for (const char* key : {"mesh", "skin", "camera"}) index(node, key, w);
        numbers(node, "weights", w, 0);
    }

    void checkMesh(const Json& mesh, const std::string& w) const {
        numbers(mesh, "weights", w, 0);
        forEach(mesh, "primitives", join(w, "primitives"), [&](const Json& prim, const std::string& p) {
            const Json* attributes = child(prim, "attributes", p);
            if (!attributes)
                fail("", join(p, "attributes") + " is missing (a primitive's vertices are its attributes)");
            for (const auto& [name, accessor] : attributes->items())
                indexValue(accessor, join(join(p, "attributes"), name.c_str()));
            index(prim, "indices", p);
            index(prim, "material", p);
            if (const Json* mode = find(prim, "mode");
                mode && !(mode->is_number_integer() && mode->get<std::int64_t>() >= 0 &&
                          mode->get<std::int64_t>() <= GLTF_TRIANGLE_FAN))
                fail(join(p, "mode"),
                     "expected a primitive mode, an integer from 0 to 6, got " + describe(*mode));
            forEach(prim, "targets", join(p, "targets"), [&](const Json& target, const std::string& t) {
                for (const auto& [name, accessor] : target.items())
                    indexValue(accessor, join(t, name.c_str()));
            });
        });
    }

    /// A texture reference (textureInfo): its texture and texture coordinate set, and
    /// KHR_texture_transform, which GltfReader::textureTransform reads field by field.
    void checkTextureInfo(const Json& info, const std::string& w) const {
        if (!find(info, "index"))
            fail("", join(w, "index") + " is missing (a texture reference names its texture)");
        index(info, "index", w);
        index(info, "texCoord", w);
        if (const Json* extensions = child(info, "extensions", w))
            child(*extensions, "KHR_texture_transform", join(w, "extensions"));
    }

    void checkMaterial(const Json& material, const std::string& w) const {
        if (const Json* pbr = child(material, "pbrMetallicRoughness", w)) {
            const std::string p = join(w, "pbrMetallicRoughness");
            numbers(*pbr, "baseColorFactor", p, 4, true);
            if (const Json* info = child(*pbr, "baseColorTexture", p))
                checkTextureInfo(*info, join(p, "baseColorTexture"));
        }
        if (const Json* mode = find(material, "alphaMode");
            mode && !(mode->is_string() && (*mode == "OPAQUE" || *mode == "MASK" || *mode == "BLEND")))
            fail(join(w, "alphaMode"), "expected \"OPAQUE\", \"MASK\" or \"BLEND\", got " + describe(*mode));
        if (const Json* cutoff = find(material, "alphaCutoff");
            cutoff && !(cutoff->is_number() && cutoff->get<double>() >= 0.0))
            fail(join(w, "alphaCutoff"), "expected a number ≥ 0, got " + describe(*cutoff));
        boolean(material, "doubleSided", w);
    }

    /// The uri of `what` ("buffer 0", "image 2") at `w`: a string, not empty, there unless
    /// `optional` (an image may be in a buffer view instead).
    void uri(const Json& object, const std::string& w, const std::string& what, bool optional) const {
        const Json* v = find(object, "uri");
        if (!v) {
            if (!optional)
                fail("",
                     join(w, "uri") + " is missing (a buffer of a .gltf names a file or holds a data URI)");
            return;
        }
        if (!v->is_string()) fail(join(w, "uri"), "expected a string, got " + describe(*v));
        if (v->get_ref<const std::string&>().empty())
            fail("", join(w, "uri") + " is empty: " + what + " names neither a file nor a data URI");
    }

    /// A buffer's length and uri. A .glb's BIN chunk is the data of its first buffer, the one
    /// without a uri (glTF 2.0 §4.4.3.3).
    void checkBuffer(const Json& buffer, const std::string& w, std::size_t index) const {
        const Json* length = find(buffer, "byteLength");
        if (!length) fail("", join(w, "byteLength") + " is missing");
        if (!length->is_number_unsigned() || length->get<std::uint64_t>() == 0)
            fail(join(w, "byteLength"), "expected an integer ≥ 1, got " + describe(*length));
        if (!m_glb || find(buffer, "uri")) {
            uri(buffer, w, "buffer " + std::to_string(index), false);
            return;
        }
        if (index > 0) fail("", w + " has no uri: in a .glb only the first buffer takes the BIN chunk");
        if (!m_glb->binBytes) fail("", w + " has no uri, and the .glb has no BIN chunk to be its data");
        if (length->get<std::uint64_t>() > *m_glb->binBytes)
            fail(join(w, "byteLength"),
                 length->dump() + " bytes, beyond the BIN chunk's " + std::to_string(*m_glb->binBytes));
    }

    std::string m_path;
    const std::optional<GlbChunks>& m_glb;
};

/// Why tinygltf refused the file, where its own message does not say: a buffer whose uri names
/// no regular file (tinygltf stops at the first buffer it cannot read, before it reads any
/// image). Empty when that is not the cause. `bufferUris`: each buffer's uri, empty for none.
std::string refusalCause(const LoadContext& context, const std::vector<std::string>& bufferUris) {
    if (context.refusedPath.empty()) return {};
    for (std::size_t i = 0; i < bufferUris.size(); ++i) {
        const std::string& uri = bufferUris[i];
        if (!uri.empty() && !isDataUri(uri) && resolveUri(context.baseDir, uri) == context.refusedPath)
            return "buffer " + std::to_string(i) + " uri \"" + clipped(uri, 200) + "\" " +
                   context.refusedReason + " (" + context.refusedPath + ")";
    }
    return {};
}

/// KHR_texture_transform of a texture reference: uv' = T·R·S·uv, and the texture coordinate set
/// it reads instead of the textureInfo's, −1 for that one.
struct UvTransform {
    double m[2][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}}; ///< rows of the affine map
    int texCoord = -1;

    vec2 apply(vec2 uv) const {
        return vec2(float(m[0][0] * uv.x + m[0][1] * uv.y + m[0][2]),
                    float(m[1][0] * uv.x + m[1][1] * uv.y + m[1][2]));
    }
};

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
        // The nodes form trees (checked first), walked once to place them, their instances
        // counted against the memory limit before any vertex is read.
        checkNodeTrees(sceneIndex);
        m_world.assign(m_model.nodes.size(), std::nullopt);
        for (int node : m_model.scenes[std::size_t(sceneIndex)].nodes) place(node, mat4(1.0f), 0);
        checkSceneSize(sceneIndex);
        for (int node : m_order) {
            const tinygltf::Node& n = m_model.nodes[std::size_t(node)];
            if (n.mesh >= 0) addMesh(node, n.mesh);
        }
        // The scene the MeshData is appended to gets a copy of its textures (appendMesh): both are
        // held for a moment, the decoded images and the masks baked from them (16 bytes a texel
        // for a MASK with a cutoff other than 0.5, measured with /usr/bin/time -v).
        checkMemory(m_path + ": its textures, held twice while the scene is assembled", 2.0 * textureBytes(),
                    "use smaller textures");
        if (m_skippedPrimitives > 0)
            m_mesh.warnings.push_back(
                std::to_string(m_skippedPrimitives) +
                " glTF primitives of points or lines (modes 0 to 3) skipped: they cast no "
                "shadow");
        if (m_mesh.triangles.empty())
            fail("scene " + std::to_string(sceneIndex) + " has no triangles" +
                 (m_skippedPrimitives > 0
                      ? " (" + std::to_string(m_skippedPrimitives) + " primitives of points or lines skipped)"
                      : ""));
        return std::move(m_mesh);
    }

  private:
    [[noreturn]] void fail(const std::string& problem) const { throw InputError(m_path, "glTF: " + problem); }

    template <class T> const T& at(const std::vector<T>& list, int index, const char* what) const {
        if (index < 0 || std::size_t(index) >= list.size())
            fail(std::string(what) + " " + std::to_string(index) + " does not exist");
        return list[std::size_t(index)];
    }

    // ------------------------------------------------------------------ nodes

    /// glTF 2.0 §3.5.3: the nodes form disjoint strict trees, each node the child of at most one
    /// other, a scene's nodes roots. A node reached twice (two parents, listed twice by one, in a
    /// cycle) is refused by name: flattening a graph that shares nodes instances them once per
    /// path, 2^40 instances from 40 nodes that each list the next twice.
    void checkNodeTrees(int sceneIndex) const {
        std::vector<int> parent(m_model.nodes.size(), -1);
        for (std::size_t p = 0; p < m_model.nodes.size(); ++p)
            for (int child : m_model.nodes[p].children) {
                at(m_model.nodes, child, "node");
                const std::string node = "node " + std::to_string(child);
                int& known = parent[std::size_t(child)];
                if (known == int(p))
                    fail(node + " is listed twice among node " + std::to_string(p) +
                         "'s children: glTF nodes form trees, each node with at most one parent");
                if (known >= 0)
                    fail(node + " has two parents, nodes " + std::to_string(known) + " and " +
                         std::to_string(p) + ": glTF nodes form trees, each node with at most one parent");
                known = int(p);
            }
        const std::vector<int>& roots = m_model.scenes[std::size_t(sceneIndex)].nodes;
        for (std::size_t i = 0; i < roots.size(); ++i) {
            at(m_model.nodes, roots[i], "node");
            const std::string node = "node " + std::to_string(roots[i]);
            if (std::find(roots.begin(), roots.begin() + std::ptrdiff_t(i), roots[i]) !=
                roots.begin() + std::ptrdiff_t(i))
                fail(node + " is listed twice among scene " + std::to_string(sceneIndex) + "'s nodes");
            // A root with a parent is in a cycle or below another root: reached twice either way.
            if (const int p = parent[std::size_t(roots[i])]; p >= 0)
                fail(node + " is a root of scene " + std::to_string(sceneIndex) + " and a child of node " +
                     std::to_string(p) + " (a cycle, or a node reached twice)");
        }
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

    /// Depth first: each node's world matrix and its place in m_order, the first perspective
    /// camera met.
    void place(int index, const mat4& parent, int depth) {
        if (depth > MAX_NODE_DEPTH) fail("node hierarchy deeper than " + std::to_string(MAX_NODE_DEPTH));
        const tinygltf::Node& node = at(m_model.nodes, index, "node");
        const std::string where = "node " + std::to_string(index);
        for (double v : node.matrix)
            if (!std::isfinite(v)) fail(where + " has a non-finite matrix");
        for (const auto* list : {&node.translation, &node.rotation, &node.scale})
            for (double v : *list)
                if (!std::isfinite(v)) fail(where + " has a non-finite transform");
        const mat4 world = parent * localMatrix(node);
        m_world[std::size_t(index)] = world;
        m_order.push_back(index);
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
        for (int child : node.children) place(child, world, depth + 1);
    }

    static bool isTriangleMode(int mode) {
        return mode == GLTF_TRIANGLES || mode == GLTF_TRIANGLE_STRIP || mode == GLTF_TRIANGLE_FAN;
    }

    /// The triangles and vertices every instance in the scene will add, from the accessors'
    /// counts alone, against the memory limit: the refusal comes before flattening.
    void checkSceneSize(int sceneIndex) const {
        double triangles = 0.0, vertices = 0.0, instances = 0.0;
        for (int node : m_order) {
            const int meshIndex = m_model.nodes[std::size_t(node)].mesh;
            if (meshIndex < 0) continue;
            instances += 1.0;
            for (const tinygltf::Primitive& prim : at(m_model.meshes, meshIndex, "mesh").primitives) {
                if (!isTriangleMode(prim.mode)) continue;
                const auto pos = prim.attributes.find("POSITION");
                const double count = pos == prim.attributes.end()
                                         ? 0.0
                                         : double(at(m_model.accessors, pos->second, "accessor").count);
                const double corners =
                    prim.indices >= 0 ? double(at(m_model.accessors, prim.indices, "accessor").count) : count;
                triangles += prim.mode == GLTF_TRIANGLE_STRIP || prim.mode == GLTF_TRIANGLE_FAN
                                 ? std::max(corners - 2.0, 0.0)
                                 : std::floor(corners / 3.0);
                vertices += count;
            }
        }
        checkMemory(m_path + ": glTF scene " + std::to_string(sceneIndex) + " of " +
                        std::to_string(std::llround(instances)) + " mesh instances, " +
                        std::to_string(std::llround(triangles)) + " triangles and " +
                        std::to_string(std::llround(vertices)) + " vertices",
                    triangles * SCENE_BYTES_PER_TRIANGLE + vertices * GLTF_VERTEX_BYTES,
                    "use a coarser mesh");
    }

    // ------------------------------------------------------------------ accessors

    /// The accessor's elements as bytes: each element's address, checked against its buffer.
    struct View {
        const unsigned char* data = nullptr;
        std::size_t stride = 0;
        std::size_t count = 0;
        int componentType = 0;
        bool normalized = false;
    };

    static std::size_t componentsOf(int type) {
        switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
        }
    }

    View view(int accessorIndex, int type, const std::string& what) const {
        if (accessorIndex < 0 || std::size_t(accessorIndex) >= m_model.accessors.size())
            fail(what + ": accessor " + std::to_string(accessorIndex) + " does not exist");
        const tinygltf::Accessor& a = m_model.accessors[std::size_t(accessorIndex)];
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
        const std::size_t element = component * componentsOf(type);
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

    /// Component c of element i as a float: floats as they are, unsigned bytes and shorts
    /// normalized to [0, 1].
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

    /// Component c of element i of an unsigned integer accessor.
    static std::uint32_t integer(const View& v, std::size_t i, int c = 0) {
        const unsigned char* p = v.data + i * v.stride;
        if (v.componentType == GLTF_UNSIGNED_BYTE) return p[c];
        if (v.componentType == GLTF_UNSIGNED_SHORT) {
            std::uint16_t s;
            std::memcpy(&s, p + 2 * c, 2);
            return s;
        }
        std::uint32_t u;
        std::memcpy(&u, p + 4 * c, 4);
        return u;
    }

    // ------------------------------------------------------------------ meshes

    /// A skinned node's joint matrices (glTF 2.0 §3.7.3): each joint's world matrix times its
    /// inverse bind matrix; the skinned node's own transform does not apply.
    std::vector<mat4> jointMatrices(int nodeIndex, int skinIndex) const {
        const tinygltf::Skin& skin = at(m_model.skins, skinIndex, "skin");
        const std::string where =
            "skin " + std::to_string(skinIndex) + " of node " + std::to_string(nodeIndex);
        std::vector<mat4> joints;
        std::optional<View> inverse;
        if (skin.inverseBindMatrices >= 0) {
            inverse = view(skin.inverseBindMatrices, TINYGLTF_TYPE_MAT4, where + " inverseBindMatrices");
            if (inverse->componentType != GLTF_FLOAT || inverse->count < skin.joints.size())
                fail(where + " inverseBindMatrices must be float, one for each joint");
        }
        for (std::size_t j = 0; j < skin.joints.size(); ++j) {
            const int joint = skin.joints[j];
            at(m_model.nodes, joint, "node");
            if (!m_world[std::size_t(joint)])
                fail(where + ": joint node " + std::to_string(joint) + " is not in the scene");
            mat4 bind(1.0f);
            if (inverse)
                for (int k = 0; k < 16; ++k) {
                    bind[k / 4][k % 4] = component(*inverse, j, k);
                    if (!std::isfinite(bind[k / 4][k % 4]))
                        fail(where + " has a non-finite inverse bind matrix");
                }
            joints.push_back(*m_world[std::size_t(joint)] * bind);
        }
        return joints;
    }

    /// The positions of a primitive in world space: morph targets at the node's (else the mesh's)
    /// weights, then the skin or the node's transform.
    std::vector<vec3> worldPositions(const tinygltf::Primitive& prim, const View& positions, int nodeIndex,
                                     int meshIndex, const std::string& where) const {
        const tinygltf::Node& node = m_model.nodes[std::size_t(nodeIndex)];
        const tinygltf::Mesh& mesh = m_model.meshes[std::size_t(meshIndex)];
        std::vector<vec3> p(positions.count);
        for (std::size_t i = 0; i < positions.count; ++i)
            p[i] = vec3(component(positions, i, 0), component(positions, i, 1), component(positions, i, 2));
        // Morph targets (glTF 2.0 §3.7.2.2): p + Σ weight_t · target_t.
        const std::vector<double>& weights = node.weights.empty() ? mesh.weights : node.weights;
        if (!weights.empty() && weights.size() != prim.targets.size())
            fail(where + " has " + std::to_string(prim.targets.size()) + " morph targets and " +
                 std::to_string(weights.size()) + " weights");
        for (std::size_t t = 0; t < weights.size(); ++t)
            if (!std::isfinite(weights[t]))
                fail(where + " morph weight " + std::to_string(t) + " is not finite");
        for (std::size_t t = 0; t < prim.targets.size(); ++t) {
            const auto target = prim.targets[t].find("POSITION");
            if (target == prim.targets[t].end()) continue;
            // A malformed target is refused at any weight, none (0) included: the file is broken.
            const std::string what = where + " morph target " + std::to_string(t) + " POSITION";
            const View d = view(target->second, TINYGLTF_TYPE_VEC3, what);
            if (d.componentType != GLTF_FLOAT || d.count != positions.count)
                fail(what + " must be float, one for each vertex");
            const float weight = t < weights.size() ? float(weights[t]) : 0.0f;
            if (weight == 0.0f) continue;
            for (std::size_t i = 0; i < p.size(); ++i)
                p[i] += weight * vec3(component(d, i, 0), component(d, i, 1), component(d, i, 2));
        }
        if (node.skin < 0) {
            const mat4& world = *m_world[std::size_t(nodeIndex)];
            for (vec3& q : p) q = vec3(world * vec4(q, 1.0f));
            return p;
        }
        // Skinning (glTF 2.0 §3.7.3.3): Σ weight · jointMatrix over the JOINTS_n / WEIGHTS_n sets,
        // in the pose the nodes give (no animation is played).
        const std::vector<mat4> joints = jointMatrices(nodeIndex, node.skin);
        std::vector<mat4> skin(p.size(), mat4(0.0f));
        std::vector<float> total(p.size(), 0.0f);
        for (int set = 0;; ++set) {
            const auto j = prim.attributes.find("JOINTS_" + std::to_string(set));
            const auto w = prim.attributes.find("WEIGHTS_" + std::to_string(set));
            if (j == prim.attributes.end() && w == prim.attributes.end()) {
                if (set == 0)
                    fail(where + " has no JOINTS_0 and WEIGHTS_0, though node " + std::to_string(nodeIndex) +
                         " gives it skin " + std::to_string(node.skin));
                break;
            }
            const std::string js = where + " JOINTS_" + std::to_string(set),
                              ws = where + " WEIGHTS_" + std::to_string(set);
            if (j == prim.attributes.end() || w == prim.attributes.end())
                fail(where + " has only one of JOINTS_" + std::to_string(set) + " and WEIGHTS_" +
                     std::to_string(set));
            const View jv = view(j->second, TINYGLTF_TYPE_VEC4, js);
            const View wv = view(w->second, TINYGLTF_TYPE_VEC4, ws);
            if (jv.componentType != GLTF_UNSIGNED_BYTE && jv.componentType != GLTF_UNSIGNED_SHORT)
                fail(js + " must be unsigned byte or short");
            if (wv.componentType == GLTF_UNSIGNED_INT || (wv.componentType != GLTF_FLOAT && !wv.normalized))
                fail(ws + " must be float or normalized unsigned byte or short");
            if (jv.count != p.size() || wv.count != p.size())
                fail(where + " has a different count of joints and vertices");
            for (std::size_t i = 0; i < p.size(); ++i)
                for (int c = 0; c < 4; ++c) {
                    const float weight = component(wv, i, c);
                    if (!std::isfinite(weight) || weight < 0.0f)
                        fail(ws + " holds a negative or non-finite weight");
                    if (weight == 0.0f) continue;
                    const std::uint32_t joint = integer(jv, i, c);
                    if (joint >= joints.size())
                        fail(js + " names joint " + std::to_string(joint) + " of a skin of " +
                             std::to_string(joints.size()));
                    skin[i] += weight * joints[joint];
                    total[i] += weight;
                }
        }
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (!(total[i] > 0.0f))
                fail(where + " vertex " + std::to_string(i) + " of skinned node " +
                     std::to_string(nodeIndex) + " has no joint weight");
            // Weights are to sum to 1; exporters round them, so they are normalized here.
            p[i] = vec3((skin[i] / total[i]) * vec4(p[i], 1.0f));
        }
        return p;
    }

    /// The corner indices of a triangle list, strip or fan as a list of triangles (glTF 2.0
    /// §3.7.2.1): a strip's triangle i is (v_i, v_{i+1+i%2}, v_{i+2−i%2}), which keeps every
    /// second one wound as the first; a fan's is (v_{i+1}, v_{i+2}, v_0).
    std::vector<std::uint32_t> triangleCorners(int mode, const std::vector<std::uint32_t>& corners,
                                               const std::string& where) const {
        if (mode == GLTF_TRIANGLES) {
            if (corners.size() % 3 != 0)
                fail(where + " has " + std::to_string(corners.size()) + " indices, not a multiple of 3");
            return corners;
        }
        if (corners.size() == 1 || corners.size() == 2)
            fail(where + " has " + std::to_string(corners.size()) + " indices, fewer than the 3 of a " +
                 (mode == GLTF_TRIANGLE_STRIP ? "strip" : "fan"));
        std::vector<std::uint32_t> list;
        for (std::size_t i = 0; i + 2 < corners.size(); ++i) {
            if (mode == GLTF_TRIANGLE_STRIP)
                list.insert(list.end(), {corners[i], corners[i + 1 + i % 2], corners[i + 2 - i % 2]});
            else
                list.insert(list.end(), {corners[i + 1], corners[i + 2], corners[0]});
        }
        return list;
    }

    void addMesh(int nodeIndex, int meshIndex) {
        const tinygltf::Mesh& mesh = at(m_model.meshes, meshIndex, "mesh");
        if (mesh.primitives.empty()) fail("mesh " + std::to_string(meshIndex) + " has no primitives");
        for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const tinygltf::Primitive& prim = mesh.primitives[pi];
            const std::string where =
                "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(pi);
            if (prim.mode >= 0 && prim.mode <= GLTF_LINE_STRIP) {
                ++m_skippedPrimitives;
                continue;
            }
            if (!isTriangleMode(prim.mode))
                fail(where + " has mode " + std::to_string(prim.mode) +
                     ", which is no glTF primitive mode (0 to 6)");
            const auto pos = prim.attributes.find("POSITION");
            if (pos == prim.attributes.end()) fail(where + " has no POSITION");
            const View positions = view(pos->second, TINYGLTF_TYPE_VEC3, where + " POSITION");
            if (positions.componentType != GLTF_FLOAT) fail(where + " POSITION must be float");
            // The material first: it says which texture coordinate set the alpha reads.
            const MaterialUse& material = materialOf(prim.material);
            const std::string uvName = "TEXCOORD_" + std::to_string(material.texCoord);
            std::optional<View> uvs;
            if (const auto uv = prim.attributes.find(uvName); uv != prim.attributes.end()) {
                uvs = view(uv->second, TINYGLTF_TYPE_VEC2, where + " " + uvName);
                if (uvs->componentType == GLTF_UNSIGNED_INT ||
                    (uvs->componentType != GLTF_FLOAT && !uvs->normalized))
                    fail(where + " " + uvName + " must be float or normalized unsigned byte or short");
                if (uvs->count != positions.count)
                    fail(where + " has a different count of " + uvName + " and POSITION");
            } else if (material.readsTexture) {
                fail(material.name + " reads its baseColorTexture's alpha through " + uvName + ", which " +
                     where + " lacks");
            }
            const std::vector<vec3> world = worldPositions(prim, positions, nodeIndex, meshIndex, where);
            const auto base = static_cast<std::uint32_t>(m_mesh.positions.size());
            for (std::size_t i = 0; i < world.size(); ++i) {
                if (!withinSceneRange(world[i]))
                    fail(where + " vertex " + std::to_string(i) + " of node " + std::to_string(nodeIndex) +
                         " is non-finite or beyond ±" + sceneRangeText() + " in world space");
                m_mesh.positions.push_back(world[i]);
                vec2 uv(0.0f);
                if (uvs) {
                    uv = material.transform.apply(vec2(component(*uvs, i, 0), component(*uvs, i, 1)));
                    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                        fail(where + " " + uvName + " " + std::to_string(i) + " is not finite");
                }
                m_mesh.texcoords.push_back(uv);
            }
            std::vector<std::uint32_t> corners;
            if (prim.indices >= 0) {
                const View indices = view(prim.indices, TINYGLTF_TYPE_SCALAR, where + " indices");
                if (indices.componentType == GLTF_FLOAT) fail(where + " indices must be unsigned integers");
                for (std::size_t i = 0; i < indices.count; ++i) corners.push_back(integer(indices, i));
            } else {
                for (std::size_t i = 0; i < positions.count; ++i) corners.push_back(std::uint32_t(i));
            }
            corners = triangleCorners(prim.mode, corners, where);
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
                m_mesh.triangleMaterial.push_back(material.index);
            }
        }
    }

    // ------------------------------------------------------------------ materials

    /// A glTF material as the primitives that use it read it.
    struct MaterialUse {
        std::uint32_t index = 0;   ///< into MeshData::materials
        std::string name;          ///< "material 1 'veil'", for messages
        int texCoord = 0;          ///< the TEXCOORD_n its baseColorTexture reads
        bool readsTexture = false; ///< its alpha reads the texture (MASK or BLEND with a texture)
        UvTransform transform;     ///< KHR_texture_transform of its baseColorTexture
    };

    /// KHR_texture_transform on a texture reference (its README): offset, rotation, scale and a
    /// texCoord that overrides the reference's. uv' = T·R·S·uv, with R turning the UVs by
    /// `rotation` counter-clockwise as glTF's UV space shows them (u right, v down):
    /// u' = cos·u + sin·v, v' = −sin·u + cos·v. This is the README's worked example (offset
    /// [0, 1], rotation π/2 and scale 0.5 read the lower left quadrant) and what Babylon.js,
    /// three.js and Blender do; the README's GLSL listing writes the rotation of a v-up space
    /// instead, an error Khronos's glTF repository records and keeps for the example's sake.
    UvTransform textureTransform(const tinygltf::TextureInfo& info, const std::string& where) const {
        UvTransform result;
        const auto it = info.extensions.find("KHR_texture_transform");
        if (it == info.extensions.end()) return result;
        const tinygltf::Value& ext = it->second;
        const std::string w = where + " baseColorTexture KHR_texture_transform";
        if (!ext.IsObject()) fail(w + " is not an object");
        const auto number = [&](const tinygltf::Value& v, const std::string& what) {
            if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble()))
                fail(w + " " + what + " must be a finite number");
            return v.GetNumberAsDouble();
        };
        const auto pair = [&](const char* key, double fallback) -> std::array<double, 2> {
            if (!ext.Has(key)) return {fallback, fallback};
            const tinygltf::Value& v = ext.Get(key);
            if (!v.IsArray() || v.ArrayLen() != 2) fail(w + " " + key + " must be an array of 2 numbers");
            return {number(v.Get(0), key), number(v.Get(1), key)};
        };
        const std::array<double, 2> offset = pair("offset", 0.0), scale = pair("scale", 1.0);
        const double rotation = ext.Has("rotation") ? number(ext.Get("rotation"), "rotation") : 0.0;
        const double c = std::cos(rotation), s = std::sin(rotation);
        result.m[0][0] = c * scale[0];
        result.m[0][1] = s * scale[1];
        result.m[0][2] = offset[0];
        result.m[1][0] = -s * scale[0];
        result.m[1][1] = c * scale[1];
        result.m[1][2] = offset[1];
        if (ext.Has("texCoord")) {
            const tinygltf::Value& t = ext.Get("texCoord");
            if (!t.IsInt() || t.GetNumberAsInt() < 0) fail(w + " texCoord must be an integer ≥ 0");
            result.texCoord = t.GetNumberAsInt();
        }
        return result;
    }

    /// The use of glTF material `index` (−1: glTF's default material, opaque white).
    const MaterialUse& materialOf(int index) {
        if (const auto it = m_materials.find(index); it != m_materials.end()) return it->second;
        MaterialUse use;
        Material m;
        m.name = "gltf default";
        use.name = "the default material";
        AlphaMode mode = AlphaMode::Opaque;
        float factor = 1.0f, cutoff = 0.5f;
        int texture = -1;
        if (index >= 0) {
            const tinygltf::Material& g = at(m_model.materials, index, "material");
            const std::string where = "material " + std::to_string(index);
            m.name = g.name.empty() ? where : g.name;
            use.name = g.name.empty() ? where : where + " '" + clipped(g.name, 80) + "'";
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
                fail(where + " alphaMode \"" + clipped(g.alphaMode, 40) +
                     "\" (expected OPAQUE, MASK or BLEND)");
            m.doubleSided = g.doubleSided;
            const tinygltf::TextureInfo& info = g.pbrMetallicRoughness.baseColorTexture;
            if (info.index >= 0) {
                // The texture coordinates stored are the ones the base colour texture reads,
                // transformed, whether or not its alpha is used.
                if (info.texCoord < 0) fail(where + " baseColorTexture texCoord must be ≥ 0");
                use.transform = textureTransform(info, use.name);
                use.texCoord = use.transform.texCoord >= 0 ? use.transform.texCoord : info.texCoord;
                if (mode != AlphaMode::Opaque) {
                    use.readsTexture = true;
                    texture = textureOf(info.index, m.wrap);
                }
            }
        }
        setMaterialAlpha(m, m_mesh.textures, mode, texture, factor, cutoff);
        m_mesh.materials.push_back(m);
        use.index = static_cast<std::uint32_t>(m_mesh.materials.size() - 1);
        return m_materials.emplace(index, use).first->second;
    }

    /// The encoded bytes of image `index`: from its buffer view (checked to lie in its buffer),
    /// or as the image callback kept them; InputError saying why when there are none.
    std::pair<const std::uint8_t*, std::size_t> encodedImage(int index, const std::string& label) const {
        const tinygltf::Image& image = m_model.images[std::size_t(index)];
        if (image.bufferView >= 0) {
            const tinygltf::BufferView& bv = at(m_model.bufferViews, image.bufferView, "buffer view");
            const tinygltf::Buffer& buffer = at(m_model.buffers, bv.buffer, "buffer");
            if (bv.byteOffset > buffer.data.size() || bv.byteLength > buffer.data.size() - bv.byteOffset)
                fail(label + ": buffer view " + std::to_string(image.bufferView) +
                     " reaches outside its buffer");
            return {buffer.data.data() + bv.byteOffset, bv.byteLength};
        }
        if (image.as_is && !image.image.empty()) return {image.image.data(), image.image.size()};
        if (image.uri.empty()) fail(label + " has no data (a data URI that does not decode?)");
        const std::string file = resolveUri(baseDirOf(m_path), image.uri);
        const std::string reason = notAFileReason(file);
        fail(label + ": '" + file + "' " + (reason.empty() ? std::string("cannot be read") : reason));
    }

    /// The MeshData texture of glTF texture `index` (its image decoded to RGBA8: the alpha, 255
    /// without one), and its sampler's wrap mode.
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
        if (t.source < 0) fail(where + " has no source image (only an extension's, such as KTX2 or WebP)");
        if (const auto it = m_textures.find(t.source); it != m_textures.end()) return it->second;
        const tinygltf::Image& image = at(m_model.images, t.source, "image");
        const std::string name = !image.uri.empty()    ? clipped(image.uri, 200)
                                 : !image.name.empty() ? clipped(image.name, 80)
                                                       : std::string("embedded");
        const std::string label = "image " + std::to_string(t.source) + " '" + name + "'";
        const auto [data, size] = encodedImage(t.source, label);
        // The header's size is held to the memory limit before decoding (decodeImageRgba), with
        // the textures read before it.
        Image8 decoded;
        try {
            decoded = decodeImageRgba(label, data, size, true, textureBytes());
        } catch (const InputError& e) {
            fail(e.what());
        } catch (const UsageError& e) {
            throw UsageError(m_path + ": " + e.what());
        }
        Texture texture;
        texture.name = image.uri.empty() ? m_path + " " + label : image.uri;
        texture.width = decoded.width;
        texture.height = decoded.height;
        texture.rgba = std::move(decoded.pixels);
        m_mesh.textures.push_back(std::move(texture));
        const int result = int(m_mesh.textures.size() - 1);
        m_textures[t.source] = result;
        return result;
    }

    /// Bytes of the textures read so far, the masks baked from them included.
    double textureBytes() const {
        double bytes = 0.0;
        for (const Texture& t : m_mesh.textures) bytes += double(t.rgba.size());
        return bytes;
    }

    std::string m_path;
    const tinygltf::Model& m_model;
    MeshData m_mesh;
    std::optional<Camera>* m_camera = nullptr;
    std::vector<std::optional<mat4>> m_world; ///< per node: its world matrix, for the scene's nodes
    std::vector<int> m_order;                 ///< the scene's nodes, depth first
    std::size_t m_skippedPrimitives = 0;      ///< points and lines
    std::map<int, MaterialUse> m_materials;   ///< glTF material → its use
    std::map<int, int> m_textures;            ///< glTF image → ours
};

/// The file read by tinygltf, after its container and JSON are checked here.
tinygltf::Model readModel(const std::string& path) {
    const bool binary = lowerExtension(path) == ".glb";
    // tinygltf takes a file's length as a 32-bit unsigned int, as GLB's header does.
    const std::string bytes = readFileBytes(path, "glTF file", std::numeric_limits<std::uint32_t>::max());
    std::optional<GlbChunks> glb;
    if (binary) glb = glbChunks(path, bytes);
    // The JSON is checked before tinygltf reads it; only the buffers' uris are kept from it, to
    // name a buffer whose file tinygltf cannot read.
    std::vector<std::string> bufferUris;
    {
        const Json document = parseGltfJson(path, binary ? glb->json : std::string_view(bytes), binary);
        GltfJsonCheck(path, glb).check(document);
        if (const auto buffers = document.find("buffers"); buffers != document.end())
            for (const Json& buffer : *buffers) bufferUris.push_back(jsonString(buffer, "uri"));
    }
    LoadContext context;
    context.path = path;
    context.baseDir = baseDirOf(path);
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, nullptr, &context});
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    tinygltf::Model model;
    std::string error, warning;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto size = static_cast<unsigned int>(bytes.size());
        ok = binary
                 ? loader.LoadBinaryFromMemory(&model, &error, &warning, data, size, context.baseDir)
                 : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), size, context.baseDir);
    } catch (const std::bad_alloc&) {
        if (context.error) std::rethrow_exception(context.error);
        throw UsageError(path + ": glTF: out of memory while tinygltf read it; use a smaller file");
    } catch (const std::exception&) {
        // The checks above leave tinygltf nothing known to throw on; its exception's own text
        // ("vector::_M_range_check: ...") would tell a user nothing.
        if (context.error) std::rethrow_exception(context.error);
        throw InputError(path, "glTF: tinygltf stopped on a malformed part it does not name");
    }
    if (context.error) std::rethrow_exception(context.error);
    if (!ok) {
        if (const std::string cause = refusalCause(context, bufferUris); !cause.empty())
            throw InputError(path, "glTF: " + cause);
        // tinygltf ends each of its messages with a newline: one line, the messages apart by "; ".
        while (!error.empty() && (error.back() == '\n' || error.back() == ' ')) error.pop_back();
        for (std::size_t at = error.find('\n'); at != std::string::npos; at = error.find('\n', at))
            error.replace(at, 1, "; ");
        throw InputError(path,
                         "glTF: " + (error.empty() ? std::string("cannot be read") : clipped(error, 400)));
    }
    return model;
}

} // namespace

MeshData loadGltf(const std::string& path, std::optional<Camera>* camera) {
    if (const std::string reason = notAFileReason(path); !reason.empty())
        throw InputError(path, "glTF file " + reason);
    checkMemory(path, double(fs::file_size(path)) * 8.0, "use a smaller file");
    const tinygltf::Model model = readModel(path);
    return GltfReader(path, model).read(camera);
}

} // namespace stsv
