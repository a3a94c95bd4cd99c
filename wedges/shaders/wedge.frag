#version 450
// Per-pixel edge terms of the opaque occluders (DESIGN §4.5; wedges/shaders/wedge_term.glsl): the
// bound is a carrier face's, shared by the potential silhouette edges the face carries. A
// visible point p inside it gets, for each of those edges that is a silhouette seen from p (its
// weight k_e over its faces except the visible triangle, in world space, is not zero),
//   DCS (WEDGE_PW 0): listed for wedge_samples.comp, which projects the edge onto the pixel's
//     light frame and adds k_e·[r → x crosses the edge]·sign(ℓ·X) to each light sample x's 16-bit
//     counter (Forest, Barthe & Paulin 2008). The list grows and the frame is rendered again when
//     it was too short (render/vulkan/gpu_renderer.cpp).
//   PW (WEDGE_PW 1): sign(k_e)·(signed fraction of the light beyond the edge), summed by
//     additive blending (Assarsson & Akenine-Möller 2003).
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef WEDGE_PW
#define WEDGE_PW 0
#endif
// The edge's record from the wedge hull pass (wedge_hull.comp), by index, instead of flat varyings.
#ifndef WEDGE_HULL_PATH
#define WEDGE_HULL_PATH 0
#endif
// The bound's record as per-primitive inputs from wedge.mesh instead of wedge.geom's flat varyings.
#ifndef WEDGE_MESH_PATH
#define WEDGE_MESH_PATH 0
#endif
#if WEDGE_MESH_PATH
#extension GL_EXT_mesh_shader : require
#define WEDGE_FLAT perprimitiveEXT flat
#else
#define WEDGE_FLAT flat
#endif
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "wedges/shaders/wedge_term.glsl"
#include "volumes/extrusion_dh.h"
#include "wedges/pw_dh.h"
#if !WEDGE_PW
#include "render/shaders/deferred_list.glsl"
#endif

layout(early_fragment_tests) in;

// The bound's record (GpuWedgeRecord).
#if WEDGE_HULL_PATH
// Read as texels (GPU_WEDGE_RECORD_* offsets): a texel fetch at a per-lane index is a vector
// gather on lavapipe, a storage-buffer load a loop over the lanes.
layout(location = 0) flat in uint inRecord;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_RECORD_TEXELS) uniform usamplerBuffer recordTexels;
uvec4 recordTexel(uint i) { return texelFetch(recordTexels, int(inRecord * GPU_HULL_RECORD_TEXELS + i)); }
uvec4 boundIds() { return recordTexel(0u); }
vec4 boundPlane(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_PLANES + i)); }
vec4 boundPlaneSide0(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_PLANES_SIDE0 + i)); }
vec4 boundLightPlane(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_LIGHT_PLANES + i)); }
#else
layout(location = 0) WEDGE_FLAT in uvec4 inIds;
layout(location = 1) WEDGE_FLAT in vec4 inPlanes[STSV_VOLUME_MAX_PLANES];
layout(location = 6) WEDGE_FLAT in vec4 inPlanesSide0[STSV_VOLUME_MAX_PLANES];
layout(location = 11) WEDGE_FLAT in vec4 inLightPlanes[STSV_LIGHT_PLANES_MAX];
uvec4 boundIds() { return inIds; }
vec4 boundPlane(uint i) { return inPlanes[i]; }
vec4 boundPlaneSide0(uint i) { return inPlanesSide0[i]; }
vec4 boundLightPlane(uint i) { return inLightPlanes[i]; }
#endif

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
#if WEDGE_PW
layout(location = 0) out float outOcclusion;
#endif

/// Whether p lies inside the bound (its planes and light planes, not in side 0's volume when
/// this is side 1).
bool insideBound(uvec4 ids, vec3 p) {
#if WEDGE_HULL_PATH
    // A record past the buffer (an overflow the host reports): no term.
    if (inRecord >= uint(textureSize(recordTexels)) / GPU_HULL_RECORD_TEXELS) return false;
#endif
    StsvVolume vol;
    vol.planeCount = ids.z;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = boundPlane(i);
    if (!stsvPointInVolume(vol, p)) return false;
    StsvLightPlanes lp;
    lp.count = (ids.y >> 8u) & 255u;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = boundLightPlane(i);
    if (!stsvPointInLightPlanes(lp, p)) return false;
    if ((ids.w & WEDGE_SIDE0_PRESENT) != 0u) {
        StsvVolume vol0;
        vol0.planeCount = ids.w & 255u;
        for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol0.planes[i] = boundPlaneSide0(i);
        if (stsvPointInVolume(vol0, p)) return false;
    }
    return true;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 p = vec3(imageLoad(gPosition, pixel));
    uint receiver = imageLoad(gTriangle, pixel).x;
    uvec4 ids = boundIds();
    bool inBound = insideBound(ids, p);
    uvec4 carried = inBound ? carrierAt(ids.x) : uvec4(GPU_NO_EDGE);
    // Bit k: carried.yzw[k] is a potential silhouette. A loop over the set bits runs as many
    // times as the batch's lanes need (a fragment batch on lavapipe holds one record's fragments),
    // where a loop over the three slots would run all three, masked.
    uint silhouettes = inBound ? (ids.y >> 16u) & 7u : 0u;
    uint fragments = subgroupAdd(1u);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, fragments);
#if WEDGE_PW
    float occlusion = 0.0;
    uint inside = 0u;
#endif
    while (silhouettes != 0u) {
        uint k = uint(findLSB(silhouettes));
        silhouettes &= silhouettes - 1u;
        uint e = carried[k + 1u];
        // The edge is a silhouette seen from p (the receiver's own face left out).
        WedgeEdge edge = wedgeEdgeAt(e);
        if (wedgeWorldWeight(p, edge.v0, edge.v1, wedgeFacesOf(edge), receiver) == 0) continue;
#if WEDGE_PW
        vec3 l;
        vec3 h0;
        vec3 h1;
        int kE;
        LightFrame lf;
        if (!wedgePixelTerm(p, edge, receiver, l, h0, h1, kE, lf)) continue;
        inside += 1u;
        occlusion += pwWedgeTerm(kE, pwEdgeCoverage(l, h0, h1, lf.domain));
#else
        // Past the list's end the entry is dropped; the host sees the count and renders again.
        deferredAppend(lsPixelIndex(uvec2(pixel), frame.width), e);
#endif
    }
#if WEDGE_PW
    uint insideCount = subgroupAdd(inside);
    if (subgroupElect()) atomicAdd(stats[pc.light].inside, insideCount);
    // On lavapipe every wedge fragment pays for the analytic coverage (polygon clipping in
    // local arrays, about 0.5 µs), silhouette or not: PW runs about 10x slower than DCS there.
    if (inside == 0u) discard;
    outOcclusion = occlusion;
#endif
}
