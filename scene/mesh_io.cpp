#include "scene/mesh_io.h"

#include "core/error.h"
#include "core/files.h"
#include "core/memory_budget.h"
#include "core/progress.h"
#include "scene/gltf_scene.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace stsv {

namespace {

namespace fs = std::filesystem;

// PolyMesh, not TriMesh: OpenMesh's TriMesh triangulates polygons while importing and then
// writes the polygon's texcoords onto one fan triangle only (garbage on the others).
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

/// A text input whole; a file that would not fit the memory limit a few times over (the mesh it
/// describes takes several times its text) is refused before it is read.
std::string readText(const std::string& path, const char* what) {
    return readFileBytes(path, what, std::size_t(memoryLimitBytes() / 8));
}

/// Lines of a text file with 1-based numbers; comments (# …) and a trailing \r removed. A file
/// of more than a few MiB shows its reading's progress (`label`).
struct Lines {
    explicit Lines(const std::string& text, const char* label = "reading")
        : m_text(text),
          m_progress(text.size() > PROGRESS_BYTES ? std::make_unique<Progress>(label, text.size())
                                                  : nullptr) {}
    bool next(std::string_view& line, std::size_t& number) {
        if (m_pos > m_text.size() || (m_pos == m_text.size() && m_pos != 0)) return false;
        if (m_text.empty()) return false;
        if (m_progress && m_pos - m_reported > PROGRESS_BYTES / 16) {
            m_progress->advance(m_pos - m_reported);
            m_reported = m_pos;
        }
        std::size_t end = m_text.find('\n', m_pos);
        if (end == std::string::npos) end = m_text.size();
        line = std::string_view(m_text).substr(m_pos, end - m_pos);
        m_pos = end + 1;
        number = ++m_number;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos)
            line = line.substr(0, hash);
        return true;
    }
    std::size_t lastLine() const { return m_number; }

  private:
    static constexpr std::size_t PROGRESS_BYTES = std::size_t(8) << 20;
    const std::string& m_text;
    std::unique_ptr<Progress> m_progress;
    std::size_t m_pos = 0;
    std::size_t m_reported = 0;
    std::size_t m_number = 0;
};

std::vector<std::string_view> splitTokens(std::string_view line) {
    std::vector<std::string_view> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\v' || line[i] == '\f'))
            ++i;
        const std::size_t start = i;
        while (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\v' || line[i] == '\f'))
            ++i;
        if (i > start) tokens.push_back(line.substr(start, i - start));
    }
    return tokens;
}

bool parseDouble(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && ptr == token.data() + token.size();
}

bool parseLong(std::string_view token, long long& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && ptr == token.data() + token.size();
}

/// A finite number within a float's range (the scene holds floats) or an InputError naming
/// file:line and what the number was for.
double finiteNumber(std::string_view token, const std::string& file, std::size_t line, const char* what) {
    double value = 0.0;
    if (!parseDouble(token, value))
        throw InputError(file, line, "malformed number '" + std::string(token) + "' in " + what);
    if (!std::isfinite(value))
        throw InputError(file, line, "non-finite number '" + std::string(token) + "' in " + what);
    if (std::abs(value) > double(std::numeric_limits<float>::max()))
        throw InputError(
            file, line, "number '" + std::string(token) + "' in " + what + " is beyond the range of a float");
    return value;
}

/// A validated number (finiteNumber) as OpenMesh is given it: the float it rounds to, written in
/// the shortest form that reads back as that float, so that OpenMesh's stream never meets a
/// spelling it reads differently from ours (a sign, hundreds of digits).
std::string canonicalFloat(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    float value = 0.0f;
    std::from_chars(token.data(), token.data() + token.size(), value);
    char buffer[32];
    const char* end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    return std::string(static_cast<const char*>(buffer), end);
}

/// OpenMesh writes warnings ("Material not defined", "complex edge") to its own streams; our
/// validator reports problems itself, so they are muted while OpenMesh reads. The streams are
/// global, hence the mutex.
class OpenMeshQuiet {
  public:
    OpenMeshQuiet() : m_lock(mutex()) {
        m_log = omlog().is_enabled();
        m_out = omout().is_enabled();
        m_err = omerr().is_enabled();
        omlog().disable();
        omout().disable();
        omerr().disable();
    }
    ~OpenMeshQuiet() {
        if (m_log) omlog().enable();
        if (m_out) omout().enable();
        if (m_err) omerr().enable();
    }
    OpenMeshQuiet(const OpenMeshQuiet&) = delete;
    OpenMeshQuiet& operator=(const OpenMeshQuiet&) = delete;

  private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> m_lock;
    bool m_log = true, m_out = true, m_err = true;
};

/// Reads `path` through OpenMesh, or `text` in the format `extension` when given (then `path`
/// only names the file in errors).
void readThroughOpenMesh(const std::string& path, PolyMesh& mesh, bool wantTexcoords,
                         const std::string* text = nullptr, const char* extension = nullptr) {
    // DESIGN §8: request the properties *and* pass the options, or texcoords are garbage.
    OpenMesh::IO::Options options;
    if (wantTexcoords) {
        mesh.request_vertex_texcoords2D();
        mesh.request_halfedge_texcoords2D();
        options += OpenMesh::IO::Options::FaceTexCoord;
        options += OpenMesh::IO::Options::VertexTexCoord;
    }
    bool ok = false;
    {
        OpenMeshQuiet quiet;
        if (text) {
            std::istringstream stream(*text);
            ok = OpenMesh::IO::read_mesh(mesh, stream, extension, options);
        } else {
            ok = OpenMesh::IO::read_mesh(mesh, path, options);
        }
    }
    if (!ok) throw InputError(path, "OpenMesh could not read the file (after it passed validation)");
}

/// Deduplicates (mesh vertex, texcoord) pairs into MeshData vertices.
class VertexWelder {
  public:
    explicit VertexWelder(MeshData& out) : m_out(out) {}
    std::uint32_t get(std::uint32_t vertex, vec3 position, vec2 uv) {
        const Key key{vertex, std::bit_cast<std::uint32_t>(uv.x), std::bit_cast<std::uint32_t>(uv.y)};
        const auto [it, inserted] =
            m_map.try_emplace(key, static_cast<std::uint32_t>(m_out.positions.size()));
        if (inserted) {
            m_out.positions.push_back(position);
            m_out.texcoords.push_back(uv);
        }
        return it->second;
    }

  private:
    struct Key {
        std::uint32_t vertex, u, v;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = k.vertex * 0x9E3779B97F4A7C15ull;
            h ^= (std::uint64_t(k.u) << 32 | k.v) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2);
            return std::size_t(h ^ (h >> 29));
        }
    };
    MeshData& m_out;
    std::unordered_map<Key, std::uint32_t, Hash> m_map;
};

// ---------------------------------------------------------------- MTL

struct TextureCache {
    std::map<std::string, int> byKey; // resolved path + alpha source → index in MeshData::textures
};

int loadTextureFile(const std::string& referer, std::size_t line, const fs::path& file, AlphaSource source,
                    MeshData& into, TextureCache& cache) {
    const std::string key = file.lexically_normal().string() + "|" + std::to_string(int(source));
    if (const auto it = cache.byKey.find(key); it != cache.byKey.end()) return it->second;
    if (const std::string reason = notAFileReason(file.string()); !reason.empty())
        throw InputError(referer, line, "texture file '" + file.string() + "' " + reason);
    Image8 image;
    try {
        image = readPngRgba(file.string());
    } catch (const InputError& e) {
        throw InputError(referer, line, std::string("cannot read texture: ") + e.what());
    }
    if (image.width <= 0 || image.height <= 0)
        throw InputError(referer, line, "texture '" + file.string() + "' is empty");
    into.textures.push_back(textureFromImage(image, file.string(), source));
    const int index = static_cast<int>(into.textures.size() - 1);
    cache.byKey[key] = index;
    return index;
}

struct MapStatement {
    std::string file;
    bool clamp = false;
    AlphaSource channel = AlphaSource::Auto;
};

/// map_* [-options] filename: options are skipped (-clamp and -imfchan are honoured).
MapStatement parseMapStatement(const std::vector<std::string_view>& tokens, const std::string& mtl,
                               std::size_t line) {
    MapStatement map;
    std::size_t i = 1;
    while (i < tokens.size() && tokens[i].size() > 1 && tokens[i][0] == '-') {
        const std::string_view opt = tokens[i++];
        auto needArgument = [&]() -> std::string_view {
            if (i >= tokens.size())
                throw InputError(mtl, line, "option '" + std::string(opt) + "' is missing its value");
            return tokens[i++];
        };
        if (opt == "-clamp") {
            map.clamp = needArgument() == "on";
        } else if (opt == "-imfchan") {
            const std::string_view c = needArgument();
            map.channel = c == "r"   ? AlphaSource::Red
                          : c == "g" ? AlphaSource::Green
                          : c == "b" ? AlphaSource::Blue
                          : c == "m" ? AlphaSource::Alpha
                                     : AlphaSource::Luminance;
        } else if (opt == "-blendu" || opt == "-blendv" || opt == "-cc" || opt == "-bm" || opt == "-boost" ||
                   opt == "-texres" || opt == "-type") {
            needArgument();
        } else if (opt == "-mm") {
            needArgument();
            needArgument();
        } else if (opt == "-o" || opt == "-s" || opt == "-t") {
            needArgument(); // 1 to 3 numbers
            double dummy = 0.0;
            for (int k = 0; k < 2 && i + 1 < tokens.size() && parseDouble(tokens[i], dummy); ++k) ++i;
        } else {
            throw InputError(mtl, line, "unknown texture option '" + std::string(opt) + "'");
        }
    }
    if (i >= tokens.size())
        throw InputError(mtl, line, "'" + std::string(tokens[0]) + "' names no texture file");
    for (std::size_t k = i; k < tokens.size(); ++k) {
        if (k > i) map.file += ' ';
        map.file += tokens[k];
    }
    return map;
}

} // namespace

bool hasTransparency(const Image8& image) {
    for (std::size_t i = 3; i < image.pixels.size(); i += 4)
        if (image.pixels[i] < 255) return true;
    return false;
}

Texture textureFromImage(const Image8& image, const std::string& name, AlphaSource source) {
    Texture texture;
    texture.name = name;
    texture.width = image.width;
    texture.height = image.height;
    texture.rgba = image.pixels;
    if (source == AlphaSource::Auto)
        source = hasTransparency(image) ? AlphaSource::Alpha : AlphaSource::Luminance;
    if (source == AlphaSource::Alpha) return texture;
    for (std::size_t i = 0; i + 3 < texture.rgba.size(); i += 4) {
        const std::uint8_t r = texture.rgba[i], g = texture.rgba[i + 1], b = texture.rgba[i + 2];
        std::uint8_t a = r;
        if (source == AlphaSource::Green) a = g;
        if (source == AlphaSource::Blue) a = b;
        if (source == AlphaSource::Luminance)
            a = static_cast<std::uint8_t>(std::lround(0.2126 * r + 0.7152 * g + 0.0722 * b));
        texture.rgba[i + 3] = a;
    }
    return texture;
}

void loadMtl(const std::string& path, MeshData& into) {
    const std::string text = readText(path, "material library");
    const fs::path dir = fs::path(path).parent_path();
    TextureCache cache;
    Lines lines(text);
    std::string_view line;
    std::size_t number = 0;
    Material* current = nullptr;
    // Per material: the map_Kd and map_d statements, resolved at the end of the material.
    struct Pending {
        std::size_t materialIndex;
        std::size_t kdLine = 0, dLine = 0;
        MapStatement kd, d;
    };
    std::vector<Pending> pending;
    while (lines.next(line, number)) {
        const auto tokens = splitTokens(line);
        if (tokens.empty()) continue;
        const std::string_view key = tokens[0];
        if (key == "newmtl") {
            if (tokens.size() < 2) throw InputError(path, number, "'newmtl' needs a material name");
            Material m;
            m.name = std::string(line.substr(line.find("newmtl") + 6));
            m.name.erase(0, m.name.find_first_not_of(" \t"));
            m.name.erase(m.name.find_last_not_of(" \t") + 1);
            into.materials.push_back(m);
            current = &into.materials.back();
            pending.push_back({into.materials.size() - 1, 0, 0, {}, {}});
            continue;
        }
        if (key == "Kd" || key == "map_Kd" || key == "map_d") {
            if (!current) throw InputError(path, number, "'" + std::string(key) + "' before any 'newmtl'");
        }
        if (key == "Kd") {
            if (tokens.size() < 2) throw InputError(path, number, "'Kd' needs 1 or 3 numbers");
            if (tokens[1] == "spectral" || tokens[1] == "xyz")
                throw InputError(path, number, "only RGB 'Kd' is supported");
            vec3 kd(float(finiteNumber(tokens[1], path, number, "Kd")));
            if (tokens.size() >= 4) {
                kd.y = float(finiteNumber(tokens[2], path, number, "Kd"));
                kd.z = float(finiteNumber(tokens[3], path, number, "Kd"));
            } else if (tokens.size() == 3) {
                throw InputError(path, number, "'Kd' needs 1 or 3 numbers, got 2");
            }
            if (const std::string problem = albedoProblem(kd); !problem.empty())
                throw InputError(path, number, "'Kd' " + problem);
            current->albedo = kd;
        } else if (key == "map_Kd") {
            pending.back().kd = parseMapStatement(tokens, path, number);
            pending.back().kdLine = number;
        } else if (key == "map_d") {
            pending.back().d = parseMapStatement(tokens, path, number);
            pending.back().dLine = number;
        }
        // Every other statement (Ka, Ks, Ns, d, illum, map_bump, PBR extensions, ...) does not
        // affect shadows and is ignored.
    }
    for (const Pending& p : pending) {
        Material& m = into.materials[p.materialIndex];
        if (p.dLine) {
            // map_d is a scalar map: its alpha channel if it has one, else luminance (or -imfchan).
            m.alphaTexture = loadTextureFile(path, p.dLine, dir / p.d.file, p.d.channel, into, cache);
            m.wrap = p.d.clamp ? WrapMode::Clamp : WrapMode::Repeat;
        } else if (p.kdLine) {
            // map_Kd is a mask only where its alpha channel is not fully opaque.
            const int t = loadTextureFile(path, p.kdLine, dir / p.kd.file, AlphaSource::Alpha, into, cache);
            const Texture& tex = into.textures[t];
            bool transparent = false;
            for (std::size_t i = 3; i < tex.rgba.size() && !transparent; i += 4)
                transparent = tex.rgba[i] < 255;
            if (transparent) {
                m.alphaTexture = t;
                m.wrap = p.kd.clamp ? WrapMode::Clamp : WrapMode::Repeat;
            }
        }
    }
}

// ---------------------------------------------------------------- OBJ

namespace {

/// What our validator learned about the OBJ; OpenMesh's result is matched against it.
struct ObjScan {
    std::vector<vec2> texcoords; ///< vt, v not yet flipped
    std::size_t vertexCount = 0;
    std::vector<std::uint32_t> faceStart;     ///< into corners; size = faces + 1
    std::vector<std::int64_t> cornerVertex;   ///< 0-based
    std::vector<std::int64_t> cornerTexcoord; ///< 0-based, −1 = none
    std::vector<std::uint32_t> faceMaterial;  ///< into MeshData::materials
    /// The file as OpenMesh reads it: the validated v, vt and f statements only (the numbers as
    /// canonicalFloat writes them, indices absolute, a face's texcoords only where every corner has one), so
    /// that OpenMesh never meets what it mishandles (a comment after a face corner wrote one texcoord out of
    /// bounds, found by fuzzing).
    std::string canonical;
    std::vector<std::size_t> faceLine;
    /// Faces that name a vertex twice (degenerate): counted and skipped, never given to OpenMesh
    /// (its OBJ reader drops the repeats and keeps the rest of such a face as a smaller polygon).
    std::vector<bool> faceRepeats;
    std::size_t firstRepeatLine = 0;     ///< the first such face's line
    std::int64_t firstRepeatVertex = -1; ///< the vertex it repeats, 0-based
};

/// A vertex `corners` names twice (the smallest such), or −1; sorted, as a face may have any
/// number of corners.
std::int64_t repeatedVertex(std::vector<std::int64_t> corners) {
    std::sort(corners.begin(), corners.end());
    const auto it = std::adjacent_find(corners.begin(), corners.end());
    return it == corners.end() ? -1 : *it;
}

/// InputError for a file whose every face repeats a vertex: the first such face, and that no face is left.
[[noreturn]] void throwNoValidFace(const std::string& path, std::size_t line, std::int64_t vertex,
                                   std::size_t faces, const char* firstIndex) {
    throw InputError(path, line,
                     "face names vertex " + std::to_string(vertex) + " (counting from " + firstIndex +
                         ") twice, a degenerate face, and so do all " + std::to_string(faces) +
                         " faces of the file: it has no valid face");
}

const char* const IGNORED_OBJ_STATEMENTS[] = {
    "o",          "g",         "s",     "l",     "p",        "vp",       "cstype", "deg",    "bmat",
    "step",       "curv",      "curv2", "surf",  "parm",     "trim",     "hole",   "scrv",   "sp",
    "end",        "con",       "mg",    "bevel", "c_interp", "d_interp", "lod",    "usemap", "maplib",
    "shadow_obj", "trace_obj", "ctech", "stech", "call",     "csh"};

/// Pass 1 of scanObj: the materials of every `mtllib` into `out`, by name, so that `usemtl` can be
/// checked wherever `mtllib` appears.
struct ObjMaterials {
    std::map<std::string, std::uint32_t> byName;
    bool anyLibrary = false;
};

ObjMaterials loadObjMaterialLibraries(const std::string& path, const std::string& text, MeshData& out) {
    const fs::path dir = fs::path(path).parent_path();
    ObjMaterials materials;
    Lines lines(text, "OBJ: material libraries");
    std::string_view line;
    std::size_t number = 0;
    while (lines.next(line, number)) {
        const auto tokens = splitTokens(line);
        if (tokens.empty() || tokens[0] != "mtllib") continue;
        if (tokens.size() < 2) throw InputError(path, number, "'mtllib' names no file");
        materials.anyLibrary = true;
        for (std::size_t k = 1; k < tokens.size(); ++k) {
            const fs::path mtl = dir / std::string(tokens[k]);
            if (const std::string reason = notAFileReason(mtl.string()); !reason.empty())
                throw InputError(path, number, "material library '" + mtl.string() + "' " + reason);
            const std::size_t before = out.materials.size();
            loadMtl(mtl.string(), out);
            for (std::size_t m = before; m < out.materials.size(); ++m)
                materials.byName.try_emplace(out.materials[m].name, static_cast<std::uint32_t>(m));
        }
    }
    return materials;
}

/// One face corner ("v", "v/vt", "v//vn" or "v/vt/vn", indices from 1 or negative from the end):
/// its vertex and texture coordinate (−1: none), 0-based, appended to `scan`.
void scanObjCorner(std::string_view corner, const std::string& path, std::size_t number, ObjScan& scan) {
    std::string_view parts[3];
    int partCount = 0;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= corner.size(); ++i) {
        if (i == corner.size() || corner[i] == '/') {
            if (partCount == 3)
                throw InputError(path, number, "malformed face corner '" + std::string(corner) + "'");
            parts[partCount++] = corner.substr(start, i - start);
            start = i + 1;
        }
    }
    auto index = [&](std::string_view token, std::size_t count, const char* what) -> std::int64_t {
        long long value = 0;
        if (!parseLong(token, value))
            throw InputError(path, number,
                             "malformed " + std::string(what) + " index '" + std::string(token) +
                                 "' in face corner '" + std::string(corner) + "'");
        if (value == 0)
            throw InputError(path, number, std::string(what) + " index 0 (OBJ indices start at 1)");
        const long long resolved = value > 0 ? value - 1 : static_cast<long long>(count) + value;
        if (resolved < 0 || resolved >= static_cast<long long>(count))
            throw InputError(path, number,
                             std::string(what) + " index " + std::to_string(value) +
                                 " is out of range: " + std::to_string(count) + " defined before this line");
        return resolved;
    };
    scan.cornerVertex.push_back(index(parts[0], scan.vertexCount, "vertex"));
    if (partCount >= 2 && !parts[1].empty())
        scan.cornerTexcoord.push_back(index(parts[1], scan.texcoords.size(), "texture coordinate"));
    else if (partCount >= 2 && parts[1].empty() && partCount == 2)
        throw InputError(path, number, "malformed face corner '" + std::string(corner) + "'");
    else
        scan.cornerTexcoord.push_back(-1);
    if (partCount == 3) {
        long long dummy = 0;
        if (!parseLong(parts[2], dummy) || dummy == 0)
            throw InputError(path, number,
                             "malformed normal index in face corner '" + std::string(corner) + "'");
    }
}

/// An `f` statement: its corners appended to `scan`, whether it repeats a vertex, and its line of
/// the canonical file (none for a face that repeats a vertex; texture coordinates only where every
/// corner has one). The caller adds its material and line.
void scanObjFace(const std::vector<std::string_view>& tokens, const std::string& path, std::size_t number,
                 ObjScan& scan) {
    if (tokens.size() < 4)
        throw InputError(path, number,
                         "face needs at least 3 vertices, got " + std::to_string(tokens.size() - 1));
    for (std::size_t k = 1; k < tokens.size(); ++k) scanObjCorner(tokens[k], path, number, scan);
    const std::size_t first = scan.faceStart.back();
    scan.faceStart.push_back(static_cast<std::uint32_t>(scan.cornerVertex.size()));
    const std::int64_t repeated =
        repeatedVertex({scan.cornerVertex.begin() + std::ptrdiff_t(first), scan.cornerVertex.end()});
    scan.faceRepeats.push_back(repeated >= 0);
    if (repeated >= 0 && scan.firstRepeatLine == 0) {
        scan.firstRepeatLine = number;
        scan.firstRepeatVertex = repeated;
    }
    bool allTexcoords = true;
    for (std::size_t c = first; c < scan.cornerVertex.size(); ++c)
        allTexcoords &= scan.cornerTexcoord[c] >= 0;
    if (repeated >= 0) return;
    scan.canonical.push_back('f');
    for (std::size_t c = first; c < scan.cornerVertex.size(); ++c) {
        scan.canonical += " " + std::to_string(scan.cornerVertex[c] + 1);
        if (allTexcoords) scan.canonical += "/" + std::to_string(scan.cornerTexcoord[c] + 1);
    }
    scan.canonical.push_back('\n');
}

ObjScan scanObj(const std::string& path, const std::string& text, MeshData& out) {
    ObjScan scan;
    scan.faceStart.push_back(0);
    ObjMaterials materials = loadObjMaterialLibraries(path, text, out);

    int currentMaterial = -1; // −1: the default material, created on first use
    auto defaultMaterial = [&]() -> std::uint32_t {
        const auto it = materials.byName.find("");
        if (it != materials.byName.end()) return it->second;
        Material m;
        m.name = "default";
        out.materials.push_back(m);
        const auto index = static_cast<std::uint32_t>(out.materials.size() - 1);
        materials.byName[""] = index;
        return index;
    };

    Lines lines(text, "OBJ: reading");
    std::string_view line;
    std::size_t number = 0;
    while (lines.next(line, number)) {
        const auto tokens = splitTokens(line);
        if (tokens.empty()) continue;
        if (tokens.back() == "\\")
            throw InputError(path, number, "line continuation ('\\') is not supported");
        const std::string_view key = tokens[0];
        if (key == "v") {
            if (tokens.size() < 4)
                throw InputError(path, number,
                                 "vertex needs 3 coordinates, got " + std::to_string(tokens.size() - 1));
            for (std::size_t k = 1; k < tokens.size(); ++k) finiteNumber(tokens[k], path, number, "vertex");
            ++scan.vertexCount;
            scan.canonical.append("v ").append(canonicalFloat(tokens[1])).append(" ");
            scan.canonical.append(canonicalFloat(tokens[2])).append(" ").append(canonicalFloat(tokens[3]));
            scan.canonical.push_back('\n');
        } else if (key == "vt") {
            if (tokens.size() < 2) throw InputError(path, number, "texture coordinate needs at least u");
            vec2 uv(0.0f);
            for (std::size_t k = 1; k < tokens.size(); ++k) {
                const double value = finiteNumber(tokens[k], path, number, "texture coordinate");
                if (k <= 2) uv[int(k - 1)] = float(value);
            }
            scan.texcoords.push_back(uv);
            scan.canonical.append("vt ").append(canonicalFloat(tokens[1])).append(" ");
            scan.canonical.append(tokens.size() > 2 ? canonicalFloat(tokens[2]) : "0");
            scan.canonical.push_back('\n');
        } else if (key == "vn") {
            if (tokens.size() < 4) throw InputError(path, number, "normal needs 3 numbers");
            for (std::size_t k = 1; k < tokens.size(); ++k) finiteNumber(tokens[k], path, number, "normal");
        } else if (key == "f") {
            scanObjFace(tokens, path, number, scan);
            if (currentMaterial < 0) currentMaterial = static_cast<int>(defaultMaterial());
            scan.faceMaterial.push_back(static_cast<std::uint32_t>(currentMaterial));
            scan.faceLine.push_back(number);
        } else if (key == "usemtl") {
            if (tokens.size() < 2) throw InputError(path, number, "'usemtl' needs a material name");
            std::string name(line.substr(line.find("usemtl") + 6));
            name.erase(0, name.find_first_not_of(" \t"));
            name.erase(name.find_last_not_of(" \t") + 1);
            const auto it = materials.byName.find(name);
            if (it != materials.byName.end()) {
                currentMaterial = static_cast<int>(it->second);
            } else if (!materials.anyLibrary) {
                // No library to look in: usemtl only groups faces; each name gets a default material.
                Material m;
                m.name = name;
                out.materials.push_back(m);
                currentMaterial = static_cast<int>(out.materials.size() - 1);
                materials.byName[name] = static_cast<std::uint32_t>(currentMaterial);
            } else {
                throw InputError(path, number,
                                 "material '" + name + "' is not defined by any 'mtllib' of this file");
            }
        } else if (key == "mtllib") {
            // handled in pass 1
        } else if (std::find(std::begin(IGNORED_OBJ_STATEMENTS), std::end(IGNORED_OBJ_STATEMENTS), key) ==
                   std::end(IGNORED_OBJ_STATEMENTS)) {
            throw InputError(path, number, "unknown OBJ statement '" + std::string(key) + "'");
        }
    }
    if (scan.vertexCount == 0) throw InputError(path, "no vertices ('v' lines)");
    if (scan.faceMaterial.empty()) throw InputError(path, "no faces ('f' lines)");
    return scan;
}

} // namespace

MeshData loadObj(const std::string& path) {
    const std::string text = readText(path, "OBJ file");
    MeshData out;
    const ObjScan scan = scanObj(path, text, out);

    // OpenMesh is given the faces without a repeated vertex, in file order, and adds faces that
    // would break manifoldness on fresh copies of their vertices. Face i of OpenMesh is therefore
    // the i-th face of the scan without a repeated vertex; we check that rather than assume it.
    std::vector<std::size_t> scanFaceOf;
    scanFaceOf.reserve(scan.faceMaterial.size());
    for (std::size_t f = 0; f < scan.faceMaterial.size(); ++f) {
        if (scan.faceRepeats[f])
            ++out.skippedFaces;
        else
            scanFaceOf.push_back(f);
    }
    if (scanFaceOf.empty())
        throwNoValidFace(path, scan.firstRepeatLine, scan.firstRepeatVertex + 1, scan.faceMaterial.size(),
                         "1");

    PolyMesh mesh;
    readThroughOpenMesh(path, mesh, true, &scan.canonical, ".obj");
    if (mesh.n_faces() != scanFaceOf.size())
        throw InputError(path, "OpenMesh read " + std::to_string(mesh.n_faces()) +
                                   " faces where the file has " + std::to_string(scanFaceOf.size()) +
                                   " valid faces");
    if (mesh.n_vertices() < scan.vertexCount)
        throw InputError(path, "OpenMesh read fewer vertices than the file has");

    VertexWelder welder(out);
    std::vector<std::uint32_t> loop;
    for (const auto fh : mesh.faces()) {
        const std::size_t f = scanFaceOf[static_cast<std::size_t>(fh.idx())];
        const std::uint32_t first = scan.faceStart[f], count = scan.faceStart[f + 1] - first;
        // The face's halfedges in OpenMesh order, rotated so that corner 0 of the file comes first.
        std::vector<PolyMesh::HalfedgeHandle> halfedges;
        for (const auto heh : mesh.fh_range(fh)) halfedges.push_back(heh);
        if (halfedges.size() != count)
            throw InputError(path, scan.faceLine[f], "OpenMesh read this face with a different vertex count");
        bool copied = false; // the face lives on duplicated vertices (non-manifold input)
        std::size_t rotation = count;
        for (std::size_t k = 0; k < count; ++k) {
            const auto v = static_cast<std::size_t>(mesh.to_vertex_handle(halfedges[k]).idx());
            if (v >= scan.vertexCount) copied = true;
            if (v == static_cast<std::size_t>(scan.cornerVertex[first])) rotation = k;
        }
        bool allTexcoords = true;
        for (std::uint32_t c = 0; c < count; ++c)
            allTexcoords = allTexcoords && scan.cornerTexcoord[first + c] >= 0;

        loop.clear();
        for (std::uint32_t c = 0; c < count; ++c) {
            vec3 position;
            std::uint32_t vertexId = 0;
            vec2 uv(0.0f);
            if (copied) {
                // OpenMesh 9.0 copies the vertices in corner order but then writes the face's
                // texcoords rotated; use the file's texcoords and the copied vertex of corner c.
                const auto v = static_cast<std::uint32_t>(scan.cornerVertex[first + c]);
                const auto p = mesh.point(OpenMesh::VertexHandle(static_cast<int>(v)));
                position = vec3(p[0], p[1], p[2]);
                vertexId = v;
                if (allTexcoords)
                    uv = scan.texcoords[static_cast<std::size_t>(scan.cornerTexcoord[first + c])];
            } else {
                if (rotation == count)
                    throw InputError(path, scan.faceLine[f],
                                     "OpenMesh read this face with different vertices");
                const auto heh = halfedges[(rotation + c) % count];
                const auto vh = mesh.to_vertex_handle(heh);
                if (static_cast<std::int64_t>(vh.idx()) != scan.cornerVertex[first + c])
                    throw InputError(path, scan.faceLine[f],
                                     "OpenMesh read this face with different vertices");
                const auto p = mesh.point(vh);
                position = vec3(p[0], p[1], p[2]);
                vertexId = static_cast<std::uint32_t>(vh.idx());
                if (allTexcoords) {
                    const auto t = mesh.texcoord2D(heh);
                    uv = vec2(t[0], t[1]);
                }
            }
            if (allTexcoords)
                uv.y = 1.0f - uv.y; // OBJ v = 0 is the image's bottom; stsv v = 0 is row 0 (top)
            loop.push_back(welder.get(vertexId, position, uv));
        }
        for (std::uint32_t c = 1; c + 1 < count; ++c) { // fan triangulation, file winding kept
            out.triangles.emplace_back(loop[0], loop[c], loop[c + 1]);
            out.triangleMaterial.push_back(scan.faceMaterial[f]);
        }
    }
    if (out.triangles.empty()) throw InputError(path, "no usable faces (all have repeated vertices)");
    return out;
}

// ---------------------------------------------------------------- OFF

namespace {

/// An OFF file's non-blank lines, as tokens (comments cut).
class OffTokens {
  public:
    explicit OffTokens(const std::string& text) : m_lines(text, "OFF: reading") {}
    /// The next line with a token; false at the end of the file.
    bool next() {
        std::string_view line;
        while (m_lines.next(line, m_number)) {
            m_tokens = splitTokens(line);
            if (!m_tokens.empty()) return true;
        }
        return false;
    }
    const std::vector<std::string_view>& tokens() const { return m_tokens; }
    std::size_t line() const { return m_number; }
    std::size_t lastLine() const { return m_lines.lastLine(); }

  private:
    Lines m_lines;
    std::size_t m_number = 0;
    std::vector<std::string_view> m_tokens;
};

/// The header ([ST][C][N]OFF) and the counts line of an OFF file.
struct OffHeader {
    std::string header;
    bool texcoords = false, colors = false, normals = false;
    long long vertexCount = 0, faceCount = 0;
};

OffHeader readOffHeader(OffTokens& in, const std::string& path) {
    if (!in.next()) throw InputError(path, "empty file (expected an 'OFF' header)");
    OffHeader h;
    h.header = std::string(in.tokens()[0]);
    const std::size_t offAt = h.header.rfind("OFF");
    if (offAt == std::string::npos || offAt + 3 != h.header.size())
        throw InputError(path, in.line(),
                         "not an OFF file: header is '" + h.header + "', expected [ST][C][N]OFF");
    std::string prefix = h.header.substr(0, offAt);
    if (prefix.rfind("ST", 0) == 0) h.texcoords = true, prefix.erase(0, 2);
    if (!prefix.empty() && prefix[0] == 'C') h.colors = true, prefix.erase(0, 1);
    if (!prefix.empty() && prefix[0] == 'N') h.normals = true, prefix.erase(0, 1);
    if (!prefix.empty())
        throw InputError(path, in.line(), "unsupported OFF header '" + h.header + "' (4D or nD OFF)");
    std::size_t t = 1;
    if (t < in.tokens().size() && in.tokens()[t] == "BINARY")
        throw InputError(path, in.line(), "binary OFF is not supported");
    if (t >= in.tokens().size()) {
        if (!in.next()) throw InputError(path, in.line(), "file ends before the vertex/face counts");
        t = 0;
    }
    long long counts[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        if (t + std::size_t(k) >= in.tokens().size())
            throw InputError(path, in.line(), "expected 'vertexCount faceCount edgeCount'");
        if (!parseLong(in.tokens()[t + std::size_t(k)], counts[k]) || counts[k] < 0)
            throw InputError(path, in.line(),
                             "malformed count '" + std::string(in.tokens()[t + std::size_t(k)]) + "'");
    }
    h.vertexCount = counts[0];
    h.faceCount = counts[1];
    if (h.vertexCount < 3) throw InputError(path, in.line(), "fewer than 3 vertices");
    if (h.faceCount < 1) throw InputError(path, in.line(), "no faces");
    return h;
}

/// The validated vertices and faces of an OFF file as OpenMesh reads them. OpenMesh 9.0's OFF
/// reader silently reads nothing when the counts share the header line and misreads comment or
/// blank lines, so it is fed a canonical copy of the validated tokens: header line, counts line,
/// one vertex or face per line, and only the faces without a repeated vertex.
struct OffScan {
    std::string canonical;
    std::size_t repeated = 0;        ///< faces that name a vertex twice, skipped
    std::size_t firstRepeatLine = 0; ///< the first such face's line
    std::int64_t firstRepeatVertex = -1;
};

/// Appends `items` to `text` as one line.
void appendLine(std::string& text, const std::vector<std::string_view>& items) {
    for (std::size_t k = 0; k < items.size(); ++k) {
        if (k) text += ' ';
        text += items[k];
    }
    text += '\n';
}

OffScan scanOffBody(OffTokens& in, const OffHeader& h, const std::string& path) {
    OffScan scan;
    std::string body;
    const std::size_t minVertexNumbers = 3 + (h.normals ? 3 : 0) + (h.colors ? 3 : 0) + (h.texcoords ? 2 : 0);
    for (long long v = 0; v < h.vertexCount; ++v) {
        if (!in.next())
            throw InputError(path, in.lastLine(),
                             "file ends after " + std::to_string(v) + " of " + std::to_string(h.vertexCount) +
                                 " vertices");
        if (in.tokens().size() < minVertexNumbers)
            throw InputError(path, in.line(),
                             "vertex needs " + std::to_string(minVertexNumbers) + " numbers, got " +
                                 std::to_string(in.tokens().size()));
        std::vector<std::string> numbers;
        for (const auto token : in.tokens()) {
            finiteNumber(token, path, in.line(), "vertex");
            numbers.push_back(canonicalFloat(token));
        }
        appendLine(body, std::vector<std::string_view>(numbers.begin(), numbers.end()));
    }
    std::vector<std::int64_t> corners;
    for (long long f = 0; f < h.faceCount; ++f) {
        if (!in.next())
            throw InputError(path, in.lastLine(),
                             "file ends after " + std::to_string(f) + " of " + std::to_string(h.faceCount) +
                                 " faces");
        const std::vector<std::string_view>& tokens = in.tokens();
        long long n = 0;
        if (!parseLong(tokens[0], n) || n < 3)
            throw InputError(path, in.line(),
                             "face must start with its vertex count (≥ 3), got '" + std::string(tokens[0]) +
                                 "'");
        if (tokens.size() < std::size_t(n) + 1)
            throw InputError(path, in.line(),
                             "face lists " + std::to_string(tokens.size() - 1) + " of its " +
                                 std::to_string(n) + " vertex indices");
        corners.clear();
        for (long long k = 1; k <= n; ++k) {
            long long index = 0;
            if (!parseLong(tokens[std::size_t(k)], index))
                throw InputError(path, in.line(),
                                 "malformed vertex index '" + std::string(tokens[std::size_t(k)]) + "'");
            if (index < 0 || index >= h.vertexCount)
                throw InputError(path, in.line(),
                                 "vertex index " + std::to_string(index) + " is out of range [0, " +
                                     std::to_string(h.vertexCount - 1) + "]");
            corners.push_back(index);
        }
        for (std::size_t k = std::size_t(n) + 1; k < tokens.size(); ++k)
            finiteNumber(tokens[k], path, in.line(), "face colour");
        if (const std::int64_t twice = repeatedVertex(corners); twice >= 0) {
            if (scan.repeated++ == 0) scan.firstRepeatLine = in.line(), scan.firstRepeatVertex = twice;
            continue;
        }
        // Face colours are validated but not used: OpenMesh reads a huge one as a colour count
        // and allocates without bound (found by fuzzing), so it gets the indices only.
        appendLine(body, {tokens.begin(), tokens.begin() + std::ptrdiff_t(n + 1)});
    }
    if (scan.repeated == static_cast<std::size_t>(h.faceCount))
        throwNoValidFace(path, scan.firstRepeatLine, scan.firstRepeatVertex, scan.repeated, "0");
    // The counts line, written once the faces without a repeated vertex are known.
    scan.canonical = h.header + "\n" + std::to_string(h.vertexCount) + " " +
                     std::to_string(static_cast<std::size_t>(h.faceCount) - scan.repeated) + " 0\n" + body;
    return scan;
}

} // namespace

MeshData loadOff(const std::string& path) {
    const std::string text = readText(path, "OFF file");
    OffTokens in(text);
    const OffHeader h = readOffHeader(in, path);
    const OffScan scan = scanOffBody(in, h, path);

    PolyMesh mesh;
    readThroughOpenMesh(path, mesh, h.texcoords, &scan.canonical, ".off");
    const std::size_t expectedFaces = static_cast<std::size_t>(h.faceCount) - scan.repeated;
    if (mesh.n_faces() != expectedFaces)
        throw InputError(path, "OpenMesh read " + std::to_string(mesh.n_faces()) +
                                   " faces where the file has " + std::to_string(expectedFaces) +
                                   " valid faces");

    MeshData out;
    out.skippedFaces = scan.repeated;
    Material m;
    m.name = "default";
    out.materials.push_back(m);
    VertexWelder welder(out);
    std::vector<std::uint32_t> loop;
    for (const auto fh : mesh.faces()) {
        loop.clear();
        for (const auto vh : mesh.fv_range(fh)) {
            const auto p = mesh.point(vh);
            vec2 uv(0.0f);
            if (h.texcoords) {
                const auto tc = mesh.texcoord2D(vh);
                uv = vec2(tc[0], 1.0f - tc[1]); // same convention as OBJ: v = 0 at the bottom
            }
            loop.push_back(welder.get(static_cast<std::uint32_t>(vh.idx()), vec3(p[0], p[1], p[2]), uv));
        }
        for (std::size_t c = 1; c + 1 < loop.size(); ++c) {
            out.triangles.emplace_back(loop[0], loop[c], loop[c + 1]);
            out.triangleMaterial.push_back(0);
        }
    }
    if (out.triangles.empty()) throw InputError(path, "no usable faces (all have repeated vertices)");
    return out;
}

MeshData loadMeshFile(const std::string& path) {
    const std::string ext = lowerExtension(path);
    if (ext == ".obj") return loadObj(path);
    if (ext == ".off") return loadOff(path);
    if (ext == ".gltf" || ext == ".glb") return loadGltf(path);
    throw UsageError("'" + path + "': unsupported mesh format '" + ext +
                     "' (expected .obj, .off, .gltf or .glb)");
}

} // namespace stsv
