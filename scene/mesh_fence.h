// A perforated quad turned into its equivalent closed mesh (STSV paper Fig. 11): the
// opaque texels of its alpha texture, as repeated over the quad, merged into boxes of opaque texel
// runs, each a closed box of small thickness. The same fence renders as 2 perforated triangles
// (`fence`) or as a mesh of 10^5+ opaque triangles (`fence-mesh`).
#pragma once

#include "scene/geometry.h"
#include "scene/procedural.h"

namespace stsv {

/// The most texels (of the texture as repeated over the quad) makeTexelBoxMesh visits.
constexpr double MAX_TEXEL_BOX_TEXELS = double(1u << 28);

/// The fence-mesh scene's ranges (its `--set` knobs), each end at the other knobs' defaults: the
/// mesh grows as repeat² × texture size, 2.4 M triangles at the defaults (16, 256), 3.8 M at
/// repeat 20 and 3.7 M at texture size 384, about 10 GB in a frame. Each wire box casts a
/// penumbra as wide as the light, so its light stops at 2 m, not the fence's 10: a CPU frame of
/// 160 × 120 took 22 s at 1 m, 157 s at 3 m and over 5 minutes at 10 m (stsv and dcs alike).
constexpr ParamRange FENCE_MESH_LIGHT_SIZE{1e-4, 2.0};
constexpr ParamRange FENCE_MESH_REPEAT{1, 20};
constexpr ParamRange FENCE_MESH_TEXTURE_SIZE{8, 384};
/// Depth of the wire boxes, m: from 0.01 mm (at the fence, whose coordinates reach 2 m, floats
/// are 2.4e-7 m apart: the boxes stay 40 of them deep) to 10 cm.
constexpr ParamRange TEXEL_BOX_THICKNESS{1e-5, 0.1};

struct TexelBoxOptions {
    float thickness = 0.0005f; ///< world units; box depth along the quad's normal (z)
    bool mergeRows = true;     ///< merge identical runs of consecutive rows into one rectangle
    /// Gap left between vertically adjacent boxes, in texel heights: boxes never touch, so the
    /// mesh is a union of disjoint closed boxes (every welded edge has exactly two faces). The
    /// slit is 10^-3 texel high and `thickness` deep, so only rays within ~10^-3·texel/thickness
    /// radians of its plane could pass.
    float rowGap = 1e-3f;
};

/// Boxes over the opaque texels (alpha ≥ 128, the texel rule) of `texture` repeated over the
/// quad of makeQuad(size, uvRepeat) (xy plane, centred, u along +x from the left edge, v from the
/// top edge down) under `wrap`; z ∈ [−thickness/2, thickness/2]. One opaque material (index 0);
/// 12 triangles and 8 vertices per box. UsageError for an empty texture, non-positive sizes,
/// more than MAX_TEXEL_BOX_TEXELS texels, or a mesh above the memory limit.
MeshData makeTexelBoxMesh(const Texture& texture, WrapMode wrap, vec2 size, vec2 uvRepeat,
                          const TexelBoxOptions& options = {});

/// `fence` (makeFenceScene(params): same camera, light, ground and texture) with its perforated
/// quad replaced by makeTexelBoxMesh of the chain-link texture, as one opaque mesh "fence-mesh".
Scene makeFenceMeshScene(const FenceParams& params = {}, const TexelBoxOptions& options = {});

} // namespace stsv
