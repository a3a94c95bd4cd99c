// Built-in procedural scenes and textures: `fence` (one chain-link quad) and `foliage` (crossed-quad
// plants). Everything is deterministic: same parameters, same scene, on every platform.
#pragma once

#include "scene/scene.h"

#include <cstdint>

namespace stsv {

/// Chain-link (diamond wire mesh) alpha texture, size × size texels, 4 × 4 diamonds per tile,
/// wires alpha 255, holes alpha 0. Tiles seamlessly under WrapMode::Repeat; open fraction ≈ 0.65.
Texture makeChainLinkTexture(int size);

/// Leafy sprig alpha texture (stem at the bottom centre, alternating leaves), for WrapMode::Clamp;
/// the border texels are transparent except the stem at the bottom edge.
Texture makeLeafTexture(int size);

/// Fraction of texels with alpha < 128 (the texel rule's transparent texels).
double openFraction(const Texture& texture);

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

struct ParticlesParams {
    int count = 1000;       ///< billboards, 2 translucent triangles each
    float opacity = 0.5f;   ///< peak α at a particle's centre, (0, 1]
    std::uint64_t seed = 1; ///< placement
};

/// Klein et al.'s particle scene: `count` light-facing square billboards (0.5 m, Gaussian α
/// of peak `opacity`, Blend) in a ball of radius 1.2 m, beside an opaque 1 m cube, over a ground
/// under a square light, so that the soft translucent shadow and the cube's shadow meet.
Scene makeParticlesScene(const ParticlesParams& params = {});

} // namespace stsv
