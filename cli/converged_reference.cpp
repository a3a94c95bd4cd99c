#include "cli/converged_reference.h"

#include "core/error.h"
#include "core/files.h"
#include "core/progress.h"
#include "core/version.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace stsv {

namespace fs = std::filesystem;

namespace {

/// FNV-1a, 64 bits: a cache key, not a defence against crafted collisions.
class Fnv1a {
  public:
    void bytes(const void* data, std::size_t count) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < count; ++i) {
            m_hash ^= p[i];
            m_hash *= 0x100000001b3ull;
        }
    }
    void u64(std::uint64_t v) { bytes(&v, sizeof v); }
    void f32(float v) { bytes(&v, sizeof v); }
    void vec(vec3 v) {
        f32(v.x);
        f32(v.y);
        f32(v.z);
    }
    void text(const std::string& s) {
        u64(s.size());
        bytes(s.data(), s.size());
    }
    std::uint64_t value() const { return m_hash; }

  private:
    std::uint64_t m_hash = 0xcbf29ce484222325ull;
};

std::string hex(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

std::string envOr(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

/// The running executable's size and modification time (Unix seconds and nanoseconds), or null
/// where /proc/self/exe cannot be read.
nlohmann::json executableStamp() {
    struct stat st {};
    if (::stat("/proc/self/exe", &st) != 0) return nullptr;
    return {{"size", std::int64_t(st.st_size)},
            {"mtime_s", std::int64_t(st.st_mtim.tv_sec)},
            {"mtime_ns", std::int64_t(st.st_mtim.tv_nsec)}};
}

/// The .npy at `path` as an image of exactly width × height × channels floats; InputError
/// naming the file and what is wrong otherwise.
ImageF readImageNpy(const std::string& path, int width, int height, int channels) {
    const NpyArray a = readNpy(path);
    std::vector<std::size_t> shape{std::size_t(height), std::size_t(width)};
    if (channels != 1) shape.push_back(std::size_t(channels));
    if (a.dtype != "<f4") throw InputError(path, "dtype " + a.dtype + ", expected <f4");
    if (a.shape != shape) throw InputError(path, "shape does not match the frame size");
    ImageF image(width, height, channels);
    if (a.bytes.size() != image.pixels.size() * sizeof(float))
        throw InputError(path, "holds " + std::to_string(a.bytes.size()) + " bytes of pixels, expected " +
                                   std::to_string(image.pixels.size() * sizeof(float)));
    std::memcpy(image.pixels.data(), a.bytes.data(), a.bytes.size());
    for (float v : image.pixels)
        if (!std::isfinite(v)) throw InputError(path, "holds a value that is not finite");
    return image;
}

const char* const KEY_FILE = "key.json";
const char* const VISIBILITY_FILE = "visibility.npy";
const char* const LIT_FILE = "lit.npy";

/// The entry's images when `dir` holds `key` and well-formed images; otherwise a reason in
/// `why` (empty when the entry does not exist).
bool readEntry(const fs::path& dir, const nlohmann::json& key, const RenderOptions& o,
               ConvergedImages& images, std::string& why) {
    std::error_code ec;
    if (!fs::exists(dir / KEY_FILE, ec)) {
        if (fs::exists(dir, ec)) why = "it has no " + std::string(KEY_FILE);
        return false;
    }
    try {
        std::ifstream in(dir / KEY_FILE);
        const nlohmann::json stored = nlohmann::json::parse(in);
        if (!stored.is_object() || !stored.contains("key") || stored["key"] != key) {
            why = "its key differs from this compare's";
            return false;
        }
        images.visibility = readImageNpy((dir / VISIBILITY_FILE).string(), o.width, o.height, 1);
        images.color = readImageNpy((dir / LIT_FILE).string(), o.width, o.height, 3);
        return true;
    } catch (const nlohmann::json::exception& e) {
        why = std::string(KEY_FILE) + " is not valid JSON (" + e.what() + ")";
    } catch (const Error& e) {
        why = e.message();
    }
    return false;
}

/// Writes the entry into a fresh sibling directory and renames it over `dir`, so a reader never
/// sees half an entry. Error on failure (the caller reports it).
void writeEntry(const fs::path& dir, const nlohmann::json& description, const ConvergedImages& images) {
    fs::create_directories(dir.parent_path());
    const fs::path staging =
        dir.parent_path() / (dir.filename().string() + ".tmp" + std::to_string(::getpid()));
    fs::remove_all(staging);
    fs::create_directories(staging);
    try {
        writeNpy((staging / VISIBILITY_FILE).string(), images.visibility);
        writeNpy((staging / LIT_FILE).string(), images.color);
        const std::string key = description.dump(2) + "\n";
        writeFileBytes((staging / KEY_FILE).string(), key.data(), key.size());
    } catch (const Error&) {
        std::error_code ec; // a half-written entry is not left in the cache either
        fs::remove_all(staging, ec);
        throw;
    }
    fs::remove_all(dir);
    fs::rename(staging, dir);
}

} // namespace

ConvergedImages averageFrames(const std::vector<const Frame*>& frames) {
    if (frames.empty()) throw Error("averageFrames: no frames");
    const Frame& first = *frames.front();
    std::vector<double> visibility(first.visibility.pixels.size(), 0.0);
    std::vector<double> color(first.color.pixels.size(), 0.0);
    for (const Frame* f : frames) {
        if (f->visibility.pixels.size() != visibility.size() || f->color.pixels.size() != color.size() ||
            f->visibility.width != first.visibility.width || f->color.width != first.color.width)
            throw Error("averageFrames: frames of different sizes");
        for (std::size_t i = 0; i < visibility.size(); ++i) visibility[i] += double(f->visibility.pixels[i]);
        for (std::size_t i = 0; i < color.size(); ++i) color[i] += double(f->color.pixels[i]);
    }
    const double k = double(frames.size());
    ConvergedImages out;
    out.visibility = first.visibility;
    out.color = first.color;
    for (std::size_t i = 0; i < visibility.size(); ++i) out.visibility.pixels[i] = float(visibility[i] / k);
    for (std::size_t i = 0; i < color.size(); ++i) out.color.pixels[i] = float(color[i] / k);
    return out;
}

std::uint64_t sceneContentHash(const Scene& scene) {
    Fnv1a h;
    h.u64(scene.positions.size());
    for (vec3 p : scene.positions) h.vec(p);
    h.u64(scene.texcoords.size());
    for (vec2 t : scene.texcoords) {
        h.f32(t.x);
        h.f32(t.y);
    }
    h.u64(scene.triangles.size());
    for (uvec3 t : scene.triangles) {
        h.u64(t.x);
        h.u64(t.y);
        h.u64(t.z);
    }
    h.u64(scene.triangleMaterial.size());
    for (std::uint32_t m : scene.triangleMaterial) h.u64(m);
    h.u64(scene.materials.size());
    for (const Material& m : scene.materials) {
        h.vec(m.albedo);
        h.u64(std::uint64_t(std::int64_t(m.alphaTexture)));
        h.u64(std::uint64_t(m.wrap));
        h.u64(m.doubleSided ? 1 : 0);
        // A mask or opaque material is all in its binary mask; a translucent one adds its alpha
        // (hashed only then, so that the keys of scenes without one stay as they were).
        if (m.translucent()) {
            h.u64(std::uint64_t(AlphaMode::Blend));
            h.u64(std::uint64_t(std::int64_t(m.blendTexture)));
            h.f32(m.alphaFactor);
        }
    }
    h.u64(scene.textures.size());
    for (const Texture& t : scene.textures) {
        h.u64(std::uint64_t(t.width));
        h.u64(std::uint64_t(t.height));
        h.u64(t.rgba.size());
        h.bytes(t.rgba.data(), t.rgba.size());
    }
    h.vec(scene.camera.eye);
    h.vec(scene.camera.target);
    h.vec(scene.camera.up);
    h.f32(scene.camera.fovY);
    h.u64(scene.lights.size());
    for (const Light& l : scene.lights) {
        h.vec(l.position);
        h.u64(l.type);
        h.vec(l.normal);
        h.f32(l.radius);
        h.vec(l.axisU);
        h.f32(l.angularRadius);
        h.vec(l.axisV);
        h.vec(l.radiance);
    }
    return h.value();
}

std::string convergedCacheDirectory() {
    if (std::string dir = envOr("STSV_CACHE_DIR"); !dir.empty()) return dir;
    if (const std::string xdg = envOr("XDG_CACHE_HOME"); !xdg.empty())
        return (fs::path(xdg) / "stsv").string();
    if (const std::string home = envOr("HOME"); !home.empty())
        return (fs::path(home) / ".cache" / "stsv").string();
    return "";
}

nlohmann::json convergedCacheKey(const Scene& scene, const RenderOptions& options, int frames) {
    nlohmann::json o = toJson(frameOptions(options));
    o.erase("validation"); // checks the Vulkan calls, changes no pixel
    return {{"format", 1},
            {"stsv_version", version()},
            {"executable", executableStamp()},
            {"scene_content_fnv1a", hex(sceneContentHash(scene))},
            {"options", o},
            {"frames", frames}};
}

std::string toString(ConvergedReference::Cache cache) {
    switch (cache) {
    case ConvergedReference::Cache::Hit:
        return "hit";
    case ConvergedReference::Cache::Written:
        return "written";
    case ConvergedReference::Cache::Off:
        return "off";
    case ConvergedReference::Cache::Failed:
        return "failed";
    }
    return "?";
}

ConvergedReference convergedReference(const ConvergedRequest& request) {
    if (request.frames < 1) throw UsageError("--converged must be at least 1");
    if (!request.scene || !request.render) throw Error("convergedReference: no scene or renderer");
    const RenderOptions& o = request.options;
    ConvergedReference result;
    const nlohmann::json key = convergedCacheKey(*request.scene, o, request.frames);
    const bool cached = request.useCache && !request.cacheDir.empty();
    fs::path entry;
    if (cached) {
        std::uint64_t h = 0xcbf29ce484222325ull;
        for (unsigned char c : key.dump()) h = (h ^ c) * 0x100000001b3ull;
        entry = fs::path(request.cacheDir) / "converged" / hex(h);
        result.entry = entry.string();
        std::string why;
        if (readEntry(entry, key, o, result.images, why)) {
            result.cache = ConvergedReference::Cache::Hit;
            return result;
        }
        if (!why.empty()) result.messages.push_back("ignoring cache entry " + entry.string() + ": " + why);
    }

    std::vector<Frame> rendered;
    rendered.reserve(std::size_t(request.frames));
    std::vector<const Frame*> frames;
    {
        Progress progress("converged reference", std::size_t(request.frames));
        for (int k = 0; k < request.frames; ++k) {
            if (k == 0 && request.first) {
                frames.push_back(request.first);
            } else {
                RenderOptions frameOptions = o;
                frameOptions.seed = o.seed + std::uint32_t(k);
                rendered.push_back(request.render(frameOptions));
                ++result.framesRendered;
            }
            progress.advance();
        }
    }
    for (const Frame& f : rendered) frames.push_back(&f);
    result.images = averageFrames(frames);
    if (!cached) return result;

    nlohmann::json seeds = nlohmann::json::array();
    for (int k = 0; k < request.frames; ++k) seeds.push_back(o.seed + std::uint32_t(k));
    const nlohmann::json description = {{"key", key},
                                        {"about",
                                         {{"scene", request.spec},
                                          {"set", request.sceneSets.set},
                                          {"seeds", seeds},
                                          {"samples_per_pixel", request.frames * o.samples},
                                          {"files", {{"visibility", VISIBILITY_FILE}, {"lit", LIT_FILE}}}}}};
    try {
        writeEntry(entry, description, result.images);
        result.cache = ConvergedReference::Cache::Written;
    } catch (const std::exception& e) {
        result.cache = ConvergedReference::Cache::Failed;
        result.messages.push_back("cannot write cache entry " + entry.string() + ": " + e.what());
    }
    return result;
}

} // namespace stsv
