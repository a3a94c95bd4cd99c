// Descriptor declarations of the opaque-occluder passes (dcs_center.comp, wedge.*, wedge_fold.comp) in
// set GPU_SET_FAMILY (wedges/vulkan/gpu_wedges_dh.h): the welded edges of the opaque triangles and
// their faces (wedges/vulkan/gpu_wedge_passes.cpp uploads them).
#ifndef STSV_SHADERS_WEDGE_BINDINGS_GLSL
#define STSV_SHADERS_WEDGE_BINDINGS_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "wedges/vulkan/gpu_wedges_dh.h"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"
#include "wedges/wedge_bound_dh.h"

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_EDGES) readonly buffer Edges { GpuEdge edges[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_EDGE_FACES) readonly buffer EdgeFaces { GpuEdgeFace edgeFaces[]; };
// The same tables as texels, for reads at a per-lane index (a vector gather on lavapipe, where a
// storage-buffer load is a loop over the lanes); per carrier face its triangle, then the edges it
// carries (GPU_NO_EDGE in free slots).
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CARRIER_TEXELS) uniform usamplerBuffer carrierTexels;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_EDGE_TEXELS) uniform usamplerBuffer edgeTexels;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_EDGE_FACE_TEXELS) uniform usamplerBuffer edgeFaceTexels;

uvec4 carrierAt(uint c) { return texelFetch(carrierTexels, int(c)); }
uint carrierCount() { return uint(textureSize(carrierTexels)); }

/// What the edge term reads of an edge (GpuEdge texels 0 and 1).
struct WedgeEdge {
    vec3 v0;
    uint firstFace;
    vec3 v1;
    uint faceCount;
};
WedgeEdge wedgeEdgeAt(uint e) {
    uvec4 a = texelFetch(edgeTexels, int(e * GPU_EDGE_TEXELS));
    uvec4 b = texelFetch(edgeTexels, int(e * GPU_EDGE_TEXELS + 1u));
    WedgeEdge edge;
    edge.v0 = uintBitsToFloat(a.xyz);
    edge.firstFace = a.w;
    edge.v1 = uintBitsToFloat(b.xyz);
    edge.faceCount = b.w;
    return edge;
}

/// wedge.geom → wedge.frag: the fragment must leave the points of the side-0 volume to side 0.
const uint WEDGE_SIDE0_PRESENT = 256u;

/// dcsPotentialSilhouette (wedges/dcs_dh.h) of the edge, as wedges/adjacency.cpp
/// potentialSilhouetteEdges: open and non-manifold edges always.
bool potentialSilhouette(GpuEdge edge, vec4 sphere) {
    if (edge.faceCount != 2u) return true;
    return dcsPotentialSilhouette(edge.v0, edge.v1, edgeFaces[edge.firstFace].opposite,
                                  edgeFaces[edge.firstFace + 1u].opposite, sphere);
}

/// The bound of the wedges of a carrier face's potential silhouette edges, one side of the face
/// (wedgeSideBound, as the CPU mirror's SilhouetteEdges builds it; both sides when the light
/// straddles the face's plane). One bound serves all the edges the face carries. `record` is what
/// the wedge fragment reads (GpuWedgeRecord).
struct WedgeBound {
    vec3 v0; ///< the carrier's corners, world units
    vec3 v1;
    vec3 v2;
    StsvVolume vol;
    StsvLightPlanes lp;
    GpuWedgeRecord record;
};

/// The edges carrier c carries that are potential silhouettes of light `lightIndex`: bit k for
/// slot k of carriers[c].yzw.
uint carrierSilhouettes(uint c, uint lightIndex) {
    uvec4 carrier = carrierAt(c);
    vec4 sphere = lights[lightIndex].sphere;
    uint mask = 0u;
    for (uint k = 0u; k < 3u; ++k) {
        uint e = carrier[k + 1u];
        if (e != GPU_NO_EDGE && potentialSilhouette(edges[e], sphere)) mask |= 1u << k;
    }
    return mask;
}

/// Whether carrier c's side `side` may have a bound for light `lightIndex`: the tests of
/// wedgeSetupBound that build nothing (a potential silhouette among its edges, a lit side);
/// `silhouettes` gets carrierSilhouettes.
bool wedgeMayHaveBound(uint c, uint side, uint lightIndex, out uint silhouettes) {
    silhouettes = carrierSilhouettes(c, lightIndex);
    if (silhouettes == 0u) return false;
    GpuTriangle g = triangles[carrierAt(c).x];
    return side < stsvSideCount(vec3(g.v0), vec3(g.v1), vec3(g.v2), lights[lightIndex].sphere);
}

/// The bound of carrier c's side `side` for light `lightIndex`, with `strip` its volume's ten
/// vertices (the prisms of wedge.geom), else only its planes (the hulls); false when it has none (no
/// potential silhouette of the light among its edges, an empty or unlit side).
bool wedgeSetupBound(uint c, uint side, uint lightIndex, bool strip, out WedgeBound b) {
    b.vol.flags = STSV_VOLUME_EMPTY;
    b.lp.count = 0u;
    uint silhouettes;
    if (!wedgeMayHaveBound(c, side, lightIndex, silhouettes)) return false;
    vec4 sphere = lights[lightIndex].sphere;
    GpuTriangle g = triangles[carrierAt(c).x];
    b.v0 = vec3(g.v0);
    b.v1 = vec3(g.v1);
    b.v2 = vec3(g.v2);
    vec3 lo = vec3(frame.boxLo);
    vec3 hi = vec3(frame.boxHi);
    if (!wedgeSideBound(b.v0, b.v1, b.v2, lights[lightIndex].light, sphere, frame.farDistance, lo, hi, side, strip,
                        b.vol, b.lp))
        return false;
    // Side 1 hands the points of the side-0 volume to side 0, so that every point is visited
    // once (the CPU mirror tests "inside any of the face's volumes").
    StsvVolume vol0;
    vol0.planeCount = 0u;
    vol0.flags = STSV_VOLUME_EMPTY;
    for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) vol0.planes[k] = vec4(0.0);
    if (side == 1u) vol0 = stsvBuildVolumePlanes(b.v0, b.v1, b.v2, sphere, lo, hi, 0u);
    uint side0 = (vol0.flags & STSV_VOLUME_EMPTY) == 0u ? WEDGE_SIDE0_PRESENT | vol0.planeCount : 0u;
    b.record.ids = uvec4(c, side | (b.lp.count << 8u) | (silhouettes << 16u), b.vol.planeCount, side0);
    for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) {
        b.record.planes[k] = b.vol.planes[k];
        b.record.planesSide0[k] = vol0.planes[k];
    }
    for (uint k = 0u; k < STSV_LIGHT_PLANES_MAX; ++k) b.record.lightPlanes[k] = b.lp.planes[k];
    return true;
}

#endif
