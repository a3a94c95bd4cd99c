// Device/host layout of the Vulkan frame (DESIGN §3, §5): the scene tables, frame constants and
// the bindings of descriptor set 0, which every pass of every family shares (render/vulkan/
// gpu_*_pass*.cpp, gpu_frame_resources.cpp, and the shaders), the push constants, plus the small
// per-pixel helpers every pass uses (G-buffer point, shading normal, alpha texel). Each family's
// own set is declared in its header (gpu_stsv_dh.h, gpu_wedges_dh.h, gpu_shadowmaps_dh.h).
#ifndef STSV_RENDER_GPU_FRAME_DH_H
#define STSV_RENDER_GPU_FRAME_DH_H

#include "core/dh.h"
#include "scene/light_dh.h"
#include "scene/surface_dh.h"
#include "volumes/stsv_dh.h"

DH_BEGIN

// Descriptor sets. Set GPU_SET_FRAME holds what the passes share (the scene tables, the G-buffer,
// the light's sample buffers and the v_coef image the families write), one set per light (the
// light's sample buffers differ). Set GPU_SET_FAMILY holds what only one family's passes bind,
// its stats first (GPU_BINDING_FAMILY_STATS); each family declares the rest of its set in its own
// header (gpu_volumes_dh.h with gpu_stsv_dh.h and gpu_wedges_dh.h, gpu_shadowmaps_dh.h), so a
// frame allocates and binds nothing of a family it does not run. The resolve, which is no family,
// binds the images only it writes in a set of its own in that place.
DH_CONST uint GPU_SET_FRAME = 0u;
DH_CONST uint GPU_SET_FAMILY = 1u;

// Set GPU_SET_FRAME.
DH_CONST uint GPU_BINDING_TRIANGLES = 0u;   ///< GpuTriangle[] (SSBO)
DH_CONST uint GPU_BINDING_ALPHA = 1u;       ///< alpha bytes of every texture, 4 per uint (SSBO)
DH_CONST uint GPU_BINDING_TEXTURES = 2u;    ///< GpuTexture[] (SSBO)
DH_CONST uint GPU_BINDING_PATTERN = 3u;     ///< vec2 pattern points, set-major (SamplePlan::points)
DH_CONST uint GPU_BINDING_FRAME = 4u;       ///< GpuFrame then GpuLight[] (SSBO)
DH_CONST uint GPU_BINDING_POSITION = 5u;    ///< G-buffer world position, rgba32f storage image
DH_CONST uint GPU_BINDING_TRIANGLE_ID = 6u; ///< G-buffer triangle id, r32ui storage image
DH_CONST uint GPU_BINDING_COUNTERS = 7u;    ///< packed 16-bit depth-complexity counters (SSBO)
DH_CONST uint GPU_BINDING_MASKS = 8u;       ///< GPU_MAX_MASK_IMAGES rg32ui storage images (bitmask)
/// r32f storage image: v_coef per pixel of the methods that write one (PW's occlusion sum, then
/// v_coef; the image family's filters), which the resolve reads
DH_CONST uint GPU_BINDING_VCOEF = 9u;
/// Transmittance frames: the optical-depth table of every material, 256 uints each
/// (opticalDepthTable, scene/geometry.h), and the light's per-sample optical-depth sums, one
/// uint per (pixel, sample) at lsCounterSlot (SSBOs; scene/occlusion_rules_dh.h).
DH_CONST uint GPU_BINDING_DEPTH_TABLES = 10u;
DH_CONST uint GPU_BINDING_DEPTHS = 11u;

// Set GPU_SET_FAMILY: the family's stats, one struct per light (GpuStsvStats, GpuWedgeStats,
// GpuShadowMapStats), atomic counters of its shaders.
DH_CONST uint GPU_BINDING_FAMILY_STATS = 0u;
// Set GPU_SET_FAMILY of the resolve pass, which keeps no stats: the images only it writes.
DH_CONST uint GPU_BINDING_RESOLVE_COLOR = 1u;      ///< rgba32f storage image, linear RGB
DH_CONST uint GPU_BINDING_RESOLVE_VISIBILITY = 2u; ///< r32f storage image, v_coef averaged over lights

DH_CONST uint GPU_NO_TRIANGLE = 0xffffffffu; ///< G-buffer triangle id of the background (core/gbuffer.h)
DH_CONST uint GPU_MAX_MASK_IMAGES = 4u;      ///< RG32UI images for N = 256 (64 samples each)

/// GpuTriangle::flags: STSV_FLAG_CLAMP, STSV_FLAG_OPAQUE and STSV_FLAG_TRANSLUCENT as in
/// stsv_dh.h (stsvTextureFor, volumes/stsv.h), plus:
DH_CONST uint GPU_TRIANGLE_DOUBLE_SIDED = 256u; ///< shading normal faces the viewer
/// A Blend material: not a receiver (the G-buffer sees through) and no opaque occluder.
DH_CONST uint GPU_TRIANGLE_TRANSLUCENT = 512u;
/// The bits stsvSetupTriangle takes.
DH_CONST uint GPU_STSV_FLAG_MASK = STSV_FLAG_CLAMP | STSV_FLAG_OPAQUE | STSV_FLAG_TRANSLUCENT;

/// One scene triangle. std430: 6 × 16 bytes.
struct GpuTriangle {
    vec4 v0;       ///< world units, w = 1
    vec4 v1;       ///< world units, w = 1
    vec4 v2;       ///< world units, w = 1
    vec2 t0;       ///< texture coordinates of v0
    vec2 t1;       ///< of v1
    vec2 t2;       ///< of v2
    uint texture;  ///< index into GpuTexture[] (0 for opaque triangles, as stsvTextureFor)
    uint flags;    ///< STSV_FLAG_* of stsvTextureFor | GPU_TRIANGLE_*
    vec3 albedo;   ///< linear RGB
    uint material; ///< the triangle's material: its optical-depth table (GPU_BINDING_DEPTH_TABLES)
};

/// One alpha texture: its bytes start at `offset` (bytes) of the alpha buffer, row-major.
struct GpuTexture {
    uint offset; ///< bytes
    int width;   ///< texels
    int height;  ///< texels
    uint pad0;
};

/// Frame constants. std430: 11 × 16 bytes.
struct GpuFrame {
    mat4 clipFromWorld; ///< Vulkan clip space, reversed depth and no far plane (gpuClipFromWorld)
    vec4 eye;           ///< world units, w unused
    vec4 boxLo;         ///< scene box (world units), w unused
    vec4 boxHi;         ///< scene box (world units), w unused
    vec4 background;    ///< linear RGB of uncovered pixels
    uint width;         ///< pixels
    uint height;        ///< pixels
    uint sampleCount;   ///< N
    uint interleave;    ///< K of K×K interleaved sets
    uint seed;          ///< decorrelation seed
    uint decorrelate;   ///< 0 or 1
    uint lightCount;
    float lightWeight; ///< 1 / lightCount: weight of each light's v_coef in the visibility image
    float farDistance; ///< world units: distance of a directional light's samples (light_bounds.h)
    float ambient;     ///< ambient term, fraction of albedo
    uint supersample;  ///< K: sub-pixel (x, y) takes the light samples of pixel (x/K, y/K)
    uint pad1;
};

/// A scene light and the sphere its volumes are extruded against (light_bounds.h).
struct GpuLight {
    Light light;
    vec4 sphere; ///< world units: centre xyz, radius w
};

/// Push constants of every pass.
struct GpuPush {
    uint light;      ///< index into GpuLight[]; ≥ lightCount: none (resolve only initialises)
    uint initialize; ///< resolve: 1 = write ambient/background first (the first light); the
                     ///< cluster walk's boxes pass: the end of its part of the tiles
    uint flags;      ///< GPU_PUSH_* bits; the cluster walk: a tile's side in 4 × 4 blocks (4 or 1)
    uint step;       ///< the cluster walk: the level, the list an args pass sizes, or the part's first tile
};

/// GpuPush::flags: the STSV pass takes the perforated triangles only (pw+stsv, dcs+stsv).
DH_CONST uint GPU_PUSH_PERFORATED_ONLY = 1u;

/// Whether a triangle of these GpuTriangle::flags is an opaque occluder (the wedge families'),
/// as Scene::opaqueOccluder: no binary mask and not translucent.
DH_FUNC bool gpuOpaqueOccluder(uint flags) {
    return (flags & STSV_FLAG_OPAQUE) != 0u && (flags & GPU_TRIANGLE_TRANSLUCENT) == 0u;
}

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuTriangle) == 96);
DH_STATIC_ASSERT(offsetof(GpuTriangle, material) == 92); // std430: a vec3 then a uint in its last 4 bytes
DH_STATIC_ASSERT(sizeof(GpuTexture) == 16);
DH_STATIC_ASSERT(sizeof(GpuFrame) == 176);
DH_STATIC_ASSERT(sizeof(GpuLight) == 96);
DH_STATIC_ASSERT(sizeof(GpuPush) == 16);
#endif

/// The visible point at barycentrics (b1, b2) (scene/surface_dh.h, as the Embree G-buffer).
DH_FUNC vec3 gpuPointOnTriangle(GpuTriangle t, vec2 bary) {
    return trianglePoint(vec3(t.v0), vec3(t.v1), vec3(t.v2), bary);
}

/// The shading normal (scene/surface_dh.h, as the Embree G-buffer).
DH_FUNC vec3 gpuShadingNormal(GpuTriangle t, vec3 eye, vec3 p) {
    return triangleShadingNormal(vec3(t.v0), vec3(t.v1), vec3(t.v2),
                                 (t.flags & GPU_TRIANGLE_DOUBLE_SIDED) != 0u, eye, p);
}

/// Byte of a packed byte array held in 32-bit words (little endian).
DH_FUNC uint gpuByteOf(uint word, uint byteIndex) {
    return (word >> (8u * (byteIndex & 3u))) & 255u;
}

DH_END

#endif // STSV_RENDER_GPU_FRAME_DH_H
