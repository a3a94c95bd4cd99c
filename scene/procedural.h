// Built-in procedural scenes and textures: `fence` (one chain-link quad) and `foliage` (crossed-quad
// plants). Everything is deterministic: same parameters, same scene, on every platform.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <string>

namespace stsv {

/// The accepted range of a built-in scene's parameter, which its `--set` knob (scene/load.cpp)
/// takes too: each end renders a sensible image with the other parameters at their defaults.
struct ParamRange {
    double lo;
    double hi;
    /// In float, as the parameters are held (1e-4f is a little below 1e-4).
    bool contains(double value) const { return float(value) >= float(lo) && float(value) <= float(hi); }
};

/// "[1, 4096]", "[0.0001, 10]": a range as messages and `stsv info` write it.
std::string rangeText(const ParamRange& range);
/// UsageError "<scene>: <name> must be in [lo, hi], got <value>" unless `range` holds `value`.
void checkParam(const std::string& scene, const std::string& name, const ParamRange& range, double value);

/// Texels per edge of a generated texture: 8 (fewer cannot hold a diamond or a leaf; at 8 the
/// chain-link's wires fill the tile) to 8192 (256 MiB of RGBA).
constexpr ParamRange GENERATED_TEXTURE_SIZE{8, 8192};
/// Bytes a generated size × size texture holds at its peak: its RGBA8 texels, allocated once and
/// moved into the scene (`stsv info fence --set texture_size=8192` peaks 256 MiB above
/// texture_size=8).
double generatedTextureBytes(int size);
/// UsageError (core/memory_budget.h) when a generated size × size texture would not fit the
/// memory limit beside `heldBytes` already held; `what` names it and where it was asked for.
void checkGeneratedTextureMemory(const std::string& what, int size, double heldBytes = 0.0);

/// Chain-link (diamond wire mesh) alpha texture, size × size texels, 4 × 4 diamonds per tile,
/// wires alpha 255, holes alpha 0. Tiles seamlessly under WrapMode::Repeat; open fraction ≈ 0.65.
Texture makeChainLinkTexture(int size);

/// Leafy sprig alpha texture (stem at the bottom centre, alternating leaves), for WrapMode::Clamp;
/// the border texels are transparent except the stem at the bottom edge.
Texture makeLeafTexture(int size);

/// Fraction of texels with alpha < 128 (the texel rule's transparent texels).
double openFraction(const Texture& texture);

/// Edge of the fence's light, m: from 0.1 mm (at the light, 6.4 m from the origin, floats are
/// 4.8e-7 m apart: the edge still spans 200 of them, and its radiance, about 2e10, stays far from
/// float's 3.4e38) to 10 m (its lowest corner still above the fence's top edge; a larger light
/// reaches down to the fence, from 17 m through the ground, and at 100 m the picture was dark and
/// noisy).
constexpr ParamRange FENCE_LIGHT_SIZE{1e-4, 10.0};
/// Chain-link tiles across the fence: 1 to 4096 (1 mm tiles, finer than any pixel of the view).
constexpr ParamRange FENCE_REPEAT{1, 4096};
/// Opacity of the fence's translucent fabric; 0 = none.
constexpr ParamRange FENCE_FABRIC{0.0, 1.0};

struct FenceParams {
    float lightSize = 1.0f; ///< world units; edge of the square light
    int repeat = 16;        ///< texture tiles across the 4 m fence (and repeat/2 over its 2 m height)
    int textureSize = 256;  ///< texels per edge of the chain-link texture
    float fabric = 0.0f;    ///< opacity α of a translucent fabric hung 0.3 m behind the fence; 0 = none
};

/// A 4 m × 2 m chain-link fence (one quad, 2 perforated double-sided triangles) standing on a
/// 30 m × 30 m opaque ground (2 triangles), under a square light above and behind it, so that its
/// soft shadow falls on the ground in front of the camera.
Scene makeFenceScene(const FenceParams& params = {});

/// Plants in the foliage patch: 1 to a million (4 M S-triangles).
constexpr ParamRange FOLIAGE_COUNT{1, 1000000};
/// Metres between plants: from 1 cm (their shadows fade out in the renderers' fixed offsets from
/// about 0.3 mm down; at 1e-7 m the camera comes within Vulkan's near plane) to 2 m (plants stop
/// growing with the spacing at 0.75 m, so they shrink to specks in a wider patch).
constexpr ParamRange FOLIAGE_SPACING{0.01, 2.0};
/// Edge of the foliage light, m; 0 = a quarter of the patch edge (at least 1 m). A light too
/// large for its place is moved back along its direction until it clears the plants.
constexpr ParamRange FOLIAGE_LIGHT_SIZE{0.0, 1000.0};

struct FoliageParams {
    int count = 64;         ///< plants; each is 2 crossed quads = 4 S-triangles
    std::uint64_t seed = 1; ///< placement, size and orientation
    float spacing = 0.75f;  ///< world units between plants (jittered grid); the patch grows with count
    float lightSize = 0.0f; ///< world units; 0 = a quarter of the patch edge (at least 1 m)
    int textureSize = 128;  ///< texels per edge of the leaf texture
};

/// A square patch of plants (crossed vertical quads with a leaf alpha texture, double-sided) on an
/// opaque ground (2 triangles) under a square light. S-triangles = 4 · count.
Scene makeFoliageScene(const FoliageParams& params = {});

/// Gaussian alpha of a soft particle, size × size texels: alpha byte round(255·exp(−r²/(2·0.4²)))
/// at distance r from the centre in units of the half-edge, 0 from r = 1 on (a round sprite).
Texture makeGaussianTexture(int size);

/// Billboards of the particle scene: 1 to 100 000 (the ball is then thousands of layers deep,
/// opaque to the eye, and a CPU frame of 160 × 120 pixels takes a minute and a half).
constexpr ParamRange PARTICLES_COUNT{1, 100000};
/// Peak opacity of a particle: from 0.001 (already below the 1/255 an 8-bit pixel shows, so a
/// smaller one would change nothing) to 1.
constexpr ParamRange PARTICLES_OPACITY{0.001, 1.0};
/// Height of the cloud's centre: from 0.5 m (the cloud's lower half pressed onto the ground) to
/// 4 m (its top, 5.45 m with a billboard's half-width, still under the light's lowest corner).
constexpr ParamRange PARTICLES_HEIGHT{0.5, 4.0};

struct ParticlesParams {
    int count = 1000;       ///< billboards, 2 translucent triangles each
    float opacity = 0.5f;   ///< peak α at a particle's centre, (0, 1]
    std::uint64_t seed = 1; ///< placement
    /// Height of the cloud's centre, m. At 2 the cloud floats over the ground and every receiver
    /// lies behind all of it (seen from the light); below 1.2 + 0.25 (its radius and a
    /// billboard's half-width) it sits on the ground, which then lies inside it: particles in
    /// front of a receiver and beside it, at every depth up to the receiver's own.
    float height = 2.0f;
};

/// Klein et al.'s particle scene: `count` light-facing square billboards (0.5 m, Gaussian α
/// of peak `opacity`, Blend) in a ball of radius 1.2 m centred `height` above a ground, beside an
/// opaque 1 m cube,
/// under a square light, so that the soft translucent shadow and the cube's shadow meet.
Scene makeParticlesScene(const ParticlesParams& params = {});

} // namespace stsv
