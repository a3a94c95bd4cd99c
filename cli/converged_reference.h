// The converged reference of `stsv compare --converged K`: K frames of one method with seeds
// S … S+K−1 (everything else equal), their visibility and linear lit images averaged (K·N samples
// per pixel), and the on-disk cache that lets repeated compares reuse it.
//
// What makes a cached image stale, and so what its key holds:
//  * the scene as loaded: geometry, texture coordinates, materials, texture texels, camera and
//    lights, hashed (sceneContentHash). Edits of the scene file, of the meshes and textures it
//    names and `--set` values all change that content; a file's name, mtime or size would miss
//    edits of the files it references, and would re-render an unchanged scene under another path;
//  * every frame option that changes the image (toJson of the frame's options: method, backend,
//    size, samples, pattern, seed S, interleave, decorrelate, buffer, ambient, device, the
//    method's parameters) and K;
//  * the renderer: the stsv version and the size and mtime of the running executable, so a
//    rebuilt stsv renders afresh rather than trust images of other code.
// The scene's spec and `--set` items are stored beside the key (for people), not in it.
#pragma once

#include "core/image.h"
#include "render/frame.h"
#include "scene/load.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace stsv {

/// The averaged images.
struct ConvergedImages {
    ImageF visibility; ///< one channel, mean of the K frames' visibility
    ImageF color;      ///< linear RGB, mean of the K frames' lit images
};

/// Mean of `frames` (same sizes), accumulated in double: value k of the result is
/// float(Σ_f frames[f].value[k] / K). Error on an empty list or differing sizes.
ConvergedImages averageFrames(const std::vector<const Frame*>& frames);

/// FNV-1a 64 over the rendered content of `scene` (not its source name, not mesh names).
std::uint64_t sceneContentHash(const Scene& scene);

/// The cache directory: $STSV_CACHE_DIR, else $XDG_CACHE_HOME/stsv, else $HOME/.cache/stsv;
/// empty when none of them is set (or set empty).
std::string convergedCacheDirectory();

/// What the cached images depend on (see the top of this file); `options` are the reference
/// frame's (method, backend, params, seed S).
nlohmann::json convergedCacheKey(const Scene& scene, const RenderOptions& options, int frames);

struct ConvergedRequest {
    const Scene* scene = nullptr;
    std::string spec;             ///< the SCENE argument, recorded beside the key
    SceneOptions sceneSets;       ///< `--set` items, recorded beside the key
    RenderOptions options;        ///< the reference's options with seed S
    int frames = 1;               ///< K ≥ 1
    bool useCache = true;         ///< false: render, neither read nor write the cache (--no-cache)
    std::string cacheDir;         ///< empty: no cache (nothing to read or write)
    const Frame* first = nullptr; ///< the frame of seed S when already rendered (reused, not re-rendered)
    /// Renders one frame of the given options (compare's renderer; tests may count calls).
    std::function<Frame(const RenderOptions&)> render;
};

struct ConvergedReference {
    ConvergedImages images;
    enum class Cache { Hit, Written, Off, Failed } cache = Cache::Off;
    std::string entry;                 ///< the cache entry's directory (empty without a cache)
    int framesRendered = 0;            ///< frames rendered by this call (0 on a hit)
    std::vector<std::string> messages; ///< one line each: ignored cache entries, write failures
};

/// "hit", "written", "off", "failed".
std::string toString(ConvergedReference::Cache cache);

/// The converged images of `request`: read from the cache when its entry holds this key and
/// well-formed images of the right size, else rendered (with a progress bar) and written there.
/// A corrupt or mismatched entry is reported in `messages` and re-rendered; a cache that cannot
/// be written is reported, never fatal. Render errors propagate.
ConvergedReference convergedReference(const ConvergedRequest& request);

} // namespace stsv
