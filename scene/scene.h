// The scene model: triangles with per-triangle materials, textures, a pinhole camera, lights.
#pragma once

#include "core/dh.h"
#include "scene/light_dh.h"
#include "scene/occlusion_rules_dh.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

enum class WrapMode : std::uint32_t { Repeat = 0, Clamp = 1 };

/// How a material's alpha α (its texture's alpha byte / 255 times alphaFactor) occludes, in
/// glTF 2.0's vocabulary: Opaque blocks everywhere, Mask blocks where α ≥ alphaCutoff (a
/// perforated triangle), Blend transmits 1 − α (a translucent triangle).
enum class AlphaMode : std::uint32_t { Opaque = 0, Mask = 1, Blend = 2 };

/// RGBA8 texture; the alpha channel is the transmittance mask of perforated materials.
struct Texture {
    std::string name; ///< file path, or a generator name for procedural textures
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba; ///< width·height·4 bytes, row 0 = v = 0

    std::uint8_t alpha(int x, int y) const { return rgba[(std::size_t(y) * width + x) * 4 + 3]; }
};

struct Material {
    std::string name;
    vec3 albedo{0.8f}; ///< linear RGB diffuse reflectance
    /// The binary mask every binary test reads (occlusion_rules_dh.h alphaBlocks: alpha byte ≥
    /// 128 blocks), index into Scene::textures; -1 = opaque. A Mask material's cutoff and factor
    /// are baked into it (setMaterialAlpha); a Blend material's is its stand-in α ≥ 0.5.
    int alphaTexture = -1;
    WrapMode wrap = WrapMode::Repeat;
    bool doubleSided =
        false; ///< lit from both sides (the shading normal faces the viewer); shadows are two-sided always
    AlphaMode alphaMode = AlphaMode::Mask; ///< Mask without alphaTexture is opaque
    /// Blend only: the texture whose alpha byte a, times alphaFactor, is α = a/255·alphaFactor;
    /// -1 = α is alphaFactor everywhere.
    int blendTexture = -1;
    float alphaFactor = 1.0f; ///< Blend only, in [0, 1]

    /// An S-triangle with a binary mask (Mask with a texture, or a Blend material's stand-in).
    bool perforated() const { return alphaTexture >= 0; }
    /// Transmits 1 − α: through STSV and the reference with the transmittance buffer.
    bool translucent() const { return alphaMode == AlphaMode::Blend; }
};

/// The optical depth a Blend material's alpha byte a adds to a segment that crosses it, in the
/// fixed-point units of occlusion_rules_dh.h: −ln(1 − a/255·alphaFactor) · OPTICAL_DEPTH_SCALE
/// rounded, OPTICAL_DEPTH_OPAQUE where α = 1; 256 entries, one per alpha byte (a material without
/// a blend texture reads entry 255: α = alphaFactor).
using OpticalDepthTable = std::array<std::uint32_t, 256>;
OpticalDepthTable opticalDepthTable(const Material& material);
/// The same for one α in [0, 1] (opticalDepthTable's entries).
std::uint32_t opticalDepthUnits(double alpha);

struct Camera {
    vec3 eye{0.0f, 1.0f, 5.0f}; ///< world units
    vec3 target{0.0f};          ///< world units
    vec3 up{0.0f, 1.0f, 0.0f};
    float fovY = 45.0f; ///< degrees, vertical
};

/// A named range of consecutive triangles (one loaded or generated object).
struct Mesh {
    std::string name;
    std::uint32_t firstTriangle = 0;
    std::uint32_t triangleCount = 0;
};

struct Bounds {
    vec3 lo{1e30f};
    vec3 hi{-1e30f};
    void extend(vec3 p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    /// Grows to hold `other` too (nothing for an empty one).
    void extend(const Bounds& other) {
        if (other.empty()) return;
        extend(other.lo);
        extend(other.hi);
    }
    /// Corner i of 8: bit 0 picks hi.x, bit 1 hi.y, bit 2 hi.z.
    vec3 corner(int i) const { return vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z); }
    vec3 center() const { return 0.5f * (lo + hi); }
    vec3 extent() const { return hi - lo; }
    float diameter() const { return empty() ? 0.0f : length(hi - lo); } ///< world units
    bool empty() const { return lo.x > hi.x; }
};

/// Bytes a scene triangle costs from loading to a rendered frame on the host, all stages
/// together (positions, the loaders' meshes, adjacency, the ray tracer's BVH, GPU tables): 2 M
/// triangles held 5.3 GB in `stsv render` (2026-12), about 2.6 KB each.
constexpr double SCENE_BYTES_PER_TRIANGLE = 2600.0;
/// The most lights a scene may have: a frame runs its per-light passes once for each.
constexpr std::size_t MAX_SCENE_LIGHTS = 1024;

/// The largest coordinate a scene may hold, world units: float math squares distances, and a
/// square above 3e38 is infinite.
constexpr float MAX_SCENE_COORDINATE = 1e9f;
/// Whether every component of v is finite and within ±MAX_SCENE_COORDINATE.
bool withinSceneRange(vec3 v);
/// "1e+09": the range in messages.
std::string sceneRangeText();

/// Empty when `albedo` is a diffuse reflectance (each component finite and in [0, 1]); else
/// what is wrong with it. Every loader checks albedos (JSON albedo, MTL Kd) with it.
std::string albedoProblem(vec3 albedo);

/// The accepted sizes of an area light, world units: a rectangle's edges, a disk's or a sphere's
/// radius. The samplers take a light's area as |T × B| of its half-extents T and B
/// (light_sampling_dh.h sampleContribution), a square root of fourth powers of them; those must
/// be normal floats (1.2e-38 to 3.4e38), which holds for half-extents from 3.3e-10 to 4.3e9.
constexpr float MIN_LIGHT_SIZE = 1e-9f;
constexpr float MAX_LIGHT_SIZE = 1e9f;
/// "[1e-09, 1e+09]": the range in messages.
std::string lightSizeRangeText();

/// Empty when `light` is well-formed (known type, finite, within range, unit normal, radiance ≥ 0,
/// a size within [MIN_LIGHT_SIZE, MAX_LIGHT_SIZE]); else what is wrong with it. Scene::validate
/// and the JSON loader (with the light's JSON path) use it.
std::string lightProblem(const Light& light);

/// The largest texel coordinate, |u|·width or |v|·height, a textured triangle's vertex may have:
/// the texel rule's TEXEL_INDEX_LIMIT (scene/occlusion_rules_dh.h), 2^24. The rule takes
/// floor(u·width) of a float, and a float holds every integer only below 2^24; beyond it
/// consecutive floats are two or more texels apart, so the coordinate can no longer name a texel.
constexpr double MAX_TEXEL_COORDINATE = double(TEXEL_INDEX_LIMIT);
/// Empty when `uv` names texels of `texture` (|u|·width and |v|·height below
/// MAX_TEXEL_COORDINATE); else what is wrong, naming the component and its value. Scene::validate
/// checks every vertex of a textured triangle with it; loaders check earlier where they can name
/// the place in their file.
std::string texcoordProblem(vec2 uv, const Texture& texture);

/// How finely float coordinates must resolve a scene where it lies: the spacing of floats at
/// its largest |coordinate| at most this fraction of its bounding-box diagonal. Measured on an
/// 11.5 m fence-like scene moved along x, by Vulkan at 320 × 240 against the same scene at the
/// origin, the pixel channels that differ by more than 16 levels: under 0.005 % at 3000 m (floats
/// 2.4e-4 m apart, 2.1e-5 of the diagonal), 0.12 % at 5000 m (4.2e-5) and 1 % at 1e6 m (where a
/// 10 m scene's Vulkan image was found 31 % off the reference). Coarser than this, a warning;
/// where triangles have collapsed, an error.
constexpr double MIN_SCENE_PRECISION = 3e-5;

/// UsageError (core/memory_budget.h) when `triangles` scene triangles would not fit the memory
/// limit; `what` names the scene or file.
void checkSceneMemory(const std::string& what, double triangles);

struct Scene {
    std::string source;                          ///< file or built-in name it came from
    std::vector<vec3> positions;                 ///< world units
    std::vector<vec2> texcoords;                 ///< one per position
    std::vector<uvec3> triangles;                ///< indices into positions
    std::vector<std::uint32_t> triangleMaterial; ///< one per triangle, index into materials
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Mesh> meshes;
    Camera camera;
    std::vector<Light> lights;
    std::size_t skippedFaces = 0; ///< input faces the loaders dropped as degenerate (repeated vertex index)
    /// Triangles kept whose vertices, as floats, coincide or lie on one line (zero area): counted
    /// by validate; they neither show nor cast a shadow in any method.
    std::size_t zeroAreaTriangles = 0;
    /// What a user should know about how the scene was read, one line each, without the file's
    /// name (the CLI prints them after loading): primitives skipped, precision lost far from the
    /// origin. Loaders append; nothing here stops a render.
    std::vector<std::string> warnings;

    std::size_t triangleCount() const { return triangles.size(); }
    const Material& materialOf(std::size_t tri) const { return materials[triangleMaterial[tri]]; }
    bool perforated(std::size_t tri) const { return materialOf(tri).perforated(); }
    bool translucent(std::size_t tri) const { return materialOf(tri).translucent(); }
    /// Neither perforated nor translucent: what the wedge families (dcs, pw) take; the rest goes
    /// through STSV in pw+stsv and dcs+stsv.
    bool opaqueOccluder(std::size_t tri) const { return !perforated(tri) && !translucent(tri); }
    /// Whether any triangle has a Blend material.
    bool hasTranslucent() const;
    Bounds bounds() const;

    /// Appends a triangle (positions and texcoords copied, unindexed) with a material index.
    void addTriangle(vec3 a, vec3 b, vec3 c, vec2 ta, vec2 tb, vec2 tc, std::uint32_t material);

    /// Checks indices, finite coordinates, texture coordinates, materials, textures, lights,
    /// camera and the float precision left where the scene lies; throws InputError naming
    /// `source` on the first problem. Where floats resolve less than MIN_SCENE_PRECISION of the
    /// scene's diagonal it appends a warning to `warnings` (once, however often it is called), and
    /// refuses the scene when some triangle has collapsed to a line or a point there. Counts the
    /// triangles of zero area (zeroAreaTriangles) and refuses a scene whose every triangle has
    /// zero area. Loaders call it before returning.
    void validate();
};

/// The point on triangle `tri` at barycentrics (b1, b2), and the shading normal a viewer at
/// `eye` sees there (faces the viewer for double-sided materials, the winding normal otherwise):
/// scene/surface_dh.h's rules, which the Vulkan G-buffer and resolve use too.
vec3 pointOnTriangle(const Scene& scene, std::uint32_t tri, vec2 bary);
vec3 shadingNormal(const Scene& scene, std::uint32_t tri, vec3 eye, vec3 p);

} // namespace stsv
