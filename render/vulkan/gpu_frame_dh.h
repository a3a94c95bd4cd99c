// Device/host layout of the Vulkan frame (DESIGN §3, §5): the scene tables, frame constants and
// binding indices shared by the Vulkan passes (render/vulkan/gpu_*_pass*.cpp, gpu_frame_resources.cpp)
// and the shaders, plus the small per-pixel helpers every pass uses (G-buffer point, shading
// normal, alpha texel).
#ifndef STSV_RENDER_GPU_FRAME_DH_H
#define STSV_RENDER_GPU_FRAME_DH_H

#include "core/dh.h"
#include "scene/light_dh.h"
#include "scene/surface_dh.h"
#include "shadowmaps/shadow_map_dh.h"
#include "volumes/extrusion_dh.h"
#include "volumes/stsv_dh.h"

DH_BEGIN

// Descriptor set 0 (one set per light: the light's sample buffers differ, the rest is shared).
DH_CONST uint GPU_BINDING_TRIANGLES = 0u;   ///< GpuTriangle[] (SSBO)
DH_CONST uint GPU_BINDING_ALPHA = 1u;       ///< alpha bytes of every texture, 4 per uint (SSBO)
DH_CONST uint GPU_BINDING_TEXTURES = 2u;    ///< GpuTexture[] (SSBO)
DH_CONST uint GPU_BINDING_PATTERN = 3u;     ///< vec2 pattern points, set-major (SamplePlan::points)
DH_CONST uint GPU_BINDING_FRAME = 4u;       ///< GpuFrame then GpuLight[] (SSBO)
DH_CONST uint GPU_BINDING_POSITION = 5u;    ///< G-buffer world position, rgba32f storage image
DH_CONST uint GPU_BINDING_TRIANGLE_ID = 6u; ///< G-buffer triangle id, r32ui storage image
DH_CONST uint GPU_BINDING_COUNTERS = 7u;    ///< packed 16-bit depth-complexity counters (SSBO)
DH_CONST uint GPU_BINDING_STATS = 8u;       ///< GpuStats per light (SSBO)
DH_CONST uint GPU_BINDING_MASKS = 9u;       ///< GPU_MAX_MASK_IMAGES rg32ui storage images (bitmask)
DH_CONST uint GPU_BINDING_COLOR = 10u;      ///< rgba32f storage image, linear RGB
DH_CONST uint GPU_BINDING_VISIBILITY = 11u; ///< r32f storage image, v_coef averaged over lights
DH_CONST uint GPU_BINDING_EDGES = 12u;      ///< GpuEdge[]: welded edges of the opaque triangles (SSBO)
DH_CONST uint GPU_BINDING_EDGE_FACES = 13u; ///< GpuEdgeFace[], grouped per edge (SSBO)
DH_CONST uint GPU_BINDING_CENTER = 14u;     ///< r32i storage image: z-fail layer count at the light centre
DH_CONST uint GPU_BINDING_VCOEF = 15u;      ///< r32f storage image: PW occlusion sum, then v_coef
DH_CONST uint GPU_BINDING_SHADOW_MAP = 16u; ///< the light's map: GpuShadowDepth words, faces × size² (SSBO)
DH_CONST uint GPU_BINDING_SHADOW_VIEWS = 17u;  ///< ShadowFilterParams then ShadowMapView per light (SSBO)
DH_CONST uint GPU_BINDING_SHADOW_TAPS = 18u;   ///< Poisson-disk taps: blocker set, then filter set (SSBO)
DH_CONST uint GPU_BINDING_HULL_DRAW = 19u;     ///< GpuHullDraw: draw arguments and counts (SSBO)
DH_CONST uint GPU_BINDING_HULL_RECORDS = 20u;  ///< the hulls' records, 18 uvec4 each (SSBO)
DH_CONST uint GPU_BINDING_HULL_VERTICES = 21u; ///< uvec4 per hull vertex: xyz bits, record (SSBO)
DH_CONST uint GPU_BINDING_HULL_RECORD_TEXELS = 22u; ///< the records as rgba32ui texels
DH_CONST uint GPU_BINDING_HULL_VERTEX_TEXELS = 23u; ///< the hull vertices as rgba32ui texels
DH_CONST uint GPU_BINDING_DEFERRED_COUNT = 24u;     ///< uvec4, x: fragments deferred (SSBO)
DH_CONST uint GPU_BINDING_DEFERRED = 25u;           ///< uvec2 per deferred fragment: pixel, item (SSBO)
DH_CONST uint GPU_BINDING_STSV_MASK_WORDS = 26u;    ///< their mask words, pixel-major (SSBO)
DH_CONST uint GPU_BINDING_CARRIER_TEXELS = 27u;   ///< rgba32ui per carrier face: triangle, its carried edges
DH_CONST uint GPU_BINDING_EDGE_TEXELS = 28u;      ///< GpuEdge[] as rgba32ui texels, GPU_EDGE_TEXELS each
DH_CONST uint GPU_BINDING_EDGE_FACE_TEXELS = 29u; ///< GpuEdgeFace[] as rgba32ui texels

DH_CONST uint GPU_NO_TRIANGLE = 0xffffffffu; ///< G-buffer triangle id of the background (core/gbuffer.h)
DH_CONST uint GPU_NO_EDGE = 0xffffffffu;     ///< an empty slot of a carrier's edges
DH_CONST uint GPU_MAX_MASK_IMAGES = 4u;      ///< RG32UI images for N = 256 (64 samples each)

/// GpuTriangle::flags: STSV_FLAG_CLAMP and STSV_FLAG_OPAQUE as in stsv_dh.h, plus:
DH_CONST uint GPU_TRIANGLE_DOUBLE_SIDED = 256u; ///< shading normal faces the viewer
DH_CONST uint GPU_STSV_FLAG_MASK = 3u;          ///< the bits stsvSetupTriangle takes

/// One scene triangle. std430: 6 × 16 bytes.
struct GpuTriangle {
    vec4 v0;      ///< world units, w = 1
    vec4 v1;      ///< world units, w = 1
    vec4 v2;      ///< world units, w = 1
    vec2 t0;      ///< texture coordinates of v0
    vec2 t1;      ///< of v1
    vec2 t2;      ///< of v2
    uint texture; ///< index into GpuTexture[] (0 for opaque triangles, as stsvTriangleFor)
    uint flags;   ///< STSV_FLAG_CLAMP | STSV_FLAG_OPAQUE | GPU_TRIANGLE_DOUBLE_SIDED
    vec4 albedo;  ///< linear RGB, w unused
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

/// Fragment statistics of one light's STSV and wedge passes (atomic counters in the fragment
/// shaders).
struct GpuStats {
    uint fragments;          ///< STSV fragments that passed the depth test (volume behind the visible point)
    uint inside;             ///< of those, p inside the volume and on its side: they run the sample loop
    uint wedgeFragments;     ///< wedge-pass fragments that passed the depth test
    uint wedgeInside;        ///< of those, p inside the bound with the edge a silhouette seen from p
    uint centerFragments;    ///< counting-volume fragments that passed the (biased) depth test
    uint centerCounted;      ///< of those, faces behind the visible point: they add ±w to D(r)
    uint hullVolumes;        ///< STSV volumes the hull pass built (stsv_hull.comp)
    uint hullTriangles;      ///< triangles of their hulls drawn (those facing away from the eye)
    uint wedgeHulls;         ///< wedge bounds the wedge hull pass built (wedge_hull.comp)
    uint wedgeHullTriangles; ///< triangles of their hulls drawn
    uint deferred;           ///< STSV fragments whose samples stsv_samples.comp tested
    uint listed;             ///< STSV hull-draw fragments listed for stsv_samples.comp, past the end too
    uint wedgeListed;        ///< DCS wedge-draw fragments listed for wedge_samples.comp, past the end too
    uint kernelClamped; ///< PCSS: pixels whose filter radius pcss_max_kernel clamped (shadow_filter.comp)
};

/// A hull pass's record of one volume: GPU_HULL_RECORD_TEXELS 16-byte texels (GpuStsvRecord,
/// GpuWedgeRecord), read by the fragments of hull.vert through their flat record index.
DH_CONST uint GPU_HULL_RECORD_TEXELS = 18u;

/// Items (sides of a triangle or a carrier face) per thread of a hull pass, at most: a workgroup
/// first finds which of its threads × HULL_ITEMS_PER_THREAD items have a volume (a cheap test),
/// then its threads build and clip those, so that a SIMD batch clips as many volumes as it has
/// lanes (render/vulkan/gpu_hulls.cpp chooses HULL_ITEMS_PER_THREAD per device).
DH_CONST uint GPU_HULL_MAX_ITEMS_PER_THREAD = 16u;

/// What an STSV fragment needs about its volume (STSV paper §3): the triangle constants of
/// Eq. 2–5, the volume's planes and the triangle's light planes. Flat varyings of the geometry
/// and mesh shaders; a record of the hull pass, read by index. std430: 18 × 16 bytes.
struct GpuStsvRecord {
    vec4 m0;
    vec4 m1;
    vec4 m2;
    vec4 uv0E1; ///< uv0 (xy), uvE1 (zw)
    vec4 uvE2;  ///< uvE2 (xy), zw unused
    uvec4 ids;  ///< texture, flags, triangle, side | planeCount << 8 | light planes' count << 16
    vec4 planes[STSV_VOLUME_MAX_PLANES];
    vec4 lightPlanes[STSV_LIGHT_PLANES_MAX];
};

/// GpuStsvRecord as 16-byte texels: its ids, its first plane, its first light plane.
DH_CONST uint GPU_STSV_RECORD_IDS = 5u;
DH_CONST uint GPU_STSV_RECORD_PLANES = 6u;
DH_CONST uint GPU_STSV_RECORD_LIGHT_PLANES = 11u;

/// What a wedge fragment needs about its carrier's bound (wedge.geom's flat varyings, or a
/// record of the wedge hull pass): ids = (carrier, side | light planes' count << 8 | the
/// carried edges that are potential silhouettes << 16 (bit k: slot k), planeCount,
/// WEDGE_SIDE0_PRESENT | side 0's planeCount), the volume's planes, side 0's planes (side 1
/// leaves their points to side 0), the carrier's light planes. std430: 18 × 16 bytes.
struct GpuWedgeRecord {
    uvec4 ids;
    vec4 planes[STSV_VOLUME_MAX_PLANES];
    vec4 planesSide0[STSV_VOLUME_MAX_PLANES];
    vec4 lightPlanes[STSV_LIGHT_PLANES_MAX];
};

/// GpuWedgeRecord as 16-byte texels.
DH_CONST uint GPU_WEDGE_RECORD_PLANES = 1u;
DH_CONST uint GPU_WEDGE_RECORD_PLANES_SIDE0 = 6u;
DH_CONST uint GPU_WEDGE_RECORD_LIGHT_PLANES = 11u;

/// A hull pass's counts and the arguments of the indirect draw of its triangles (the first
/// four words are a VkDrawIndirectCommand). Zeroed before each hull pass.
struct GpuHullDraw {
    uint vertexCount;   ///< 3 × the triangles appended
    uint instanceCount; ///< 1, written by the hull pass
    uint firstVertex;
    uint firstInstance;
    uint records; ///< records appended
    uint pad0;
    uint pad1;
    uint pad2;
};

/// One welded edge of the opaque triangles (wedges/adjacency.h). std430: 2 × 16 bytes.
struct GpuEdge {
    vec3 v0;        ///< world units
    uint firstFace; ///< into GpuEdgeFace[]
    vec3 v1;        ///< world units
    uint faceCount; ///< 1 open, 2 manifold, > 2 non-manifold
};

/// GpuEdge as 16-byte texels: (v0, firstFace), (v1, faceCount).
DH_CONST uint GPU_EDGE_TEXELS = 2u;

/// One triangle incident to an edge. std430: 2 × 16 bytes.
struct GpuEdgeFace {
    vec3 opposite; ///< world units; the triangle's third vertex
    uint triangle; ///< scene triangle index
    uint forward;  ///< 1: the triangle's winding runs the edge v0 → v1, 0: v1 → v0
    uint pad0;
    uint pad1;
    uint pad2;
};

/// GpuEdgeFace as 16-byte texels: (opposite, triangle), (forward, pads).
DH_CONST uint GPU_EDGE_FACE_TEXELS = 2u;

/// A map texel as the rasteriser writes it with atomicMax: the bits of the depth (a positive
/// float, whose bits order as its value) inverted, so the nearest surface wins and a cleared
/// word (0) reads as no surface.
DH_FUNC uint gpuShadowDepthWord(float depth) {
    return ~floatBitsToUint(depth);
}
DH_FUNC float gpuShadowDepthOf(uint word) {
    return word == 0u ? SHADOW_MAP_EMPTY : uintBitsToFloat(~word);
}

/// Push constants of every pass.
struct GpuPush {
    uint light;      ///< index into GpuLight[]; ≥ lightCount: none (resolve only initialises)
    uint initialize; ///< resolve: 1 = write ambient/background first (the first light)
    uint flags;      ///< GPU_PUSH_* bits
    uint pad0;
};

/// GpuPush::flags: the STSV pass takes the perforated triangles only (pw+stsv, dcs+stsv).
DH_CONST uint GPU_PUSH_PERFORATED_ONLY = 1u;

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(GpuTriangle) == 96);
DH_STATIC_ASSERT(sizeof(GpuTexture) == 16);
DH_STATIC_ASSERT(sizeof(GpuFrame) == 176);
DH_STATIC_ASSERT(sizeof(GpuLight) == 96);
DH_STATIC_ASSERT(sizeof(GpuStats) == 56);
DH_STATIC_ASSERT(sizeof(GpuStsvRecord) == 16 * GPU_HULL_RECORD_TEXELS);
DH_STATIC_ASSERT(sizeof(GpuWedgeRecord) == 16 * GPU_HULL_RECORD_TEXELS);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, planes) == 16 * GPU_WEDGE_RECORD_PLANES);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, planesSide0) == 16 * GPU_WEDGE_RECORD_PLANES_SIDE0);
DH_STATIC_ASSERT(offsetof(GpuWedgeRecord, lightPlanes) == 16 * GPU_WEDGE_RECORD_LIGHT_PLANES);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, ids) == 16 * GPU_STSV_RECORD_IDS);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, planes) == 16 * GPU_STSV_RECORD_PLANES);
DH_STATIC_ASSERT(offsetof(GpuStsvRecord, lightPlanes) == 16 * GPU_STSV_RECORD_LIGHT_PLANES);
DH_STATIC_ASSERT(sizeof(GpuHullDraw) == 32);
DH_STATIC_ASSERT(sizeof(GpuPush) == 16);
DH_STATIC_ASSERT(sizeof(GpuEdge) == 32);
DH_STATIC_ASSERT(sizeof(GpuEdgeFace) == 32);
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
