// Descriptor declarations of the opaque-occluder passes (dcs_center.*, wedge.*, wedge_fold.comp):
// the welded edges of the opaque triangles and their faces (render/gpu_opaque_passes.cpp uploads them).
#ifndef STSV_SHADERS_WEDGE_BINDINGS_GLSL
#define STSV_SHADERS_WEDGE_BINDINGS_GLSL

#include "frame_bindings.glsl"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"

layout(std430, set = 0, binding = GPU_BINDING_EDGES) readonly buffer Edges { GpuEdge edges[]; };
layout(std430, set = 0, binding = GPU_BINDING_EDGE_FACES) readonly buffer EdgeFaces { GpuEdgeFace edgeFaces[]; };

/// wedge.geom → wedge.frag: the fragment must leave the points of the side-0 volume to side 0.
const uint WEDGE_SIDE0_PRESENT = 256u;

/// dcsPotentialSilhouette (wedges/dcs_dh.h) of the edge, as wedges/adjacency.cpp
/// potentialSilhouetteEdges: open and non-manifold edges always.
bool potentialSilhouette(GpuEdge edge, vec4 sphere) {
    if (edge.faceCount != 2u) return true;
    return dcsPotentialSilhouette(edge.v0, edge.v1, edgeFaces[edge.firstFace].opposite,
                                  edgeFaces[edge.firstFace + 1u].opposite, sphere);
}

/// The bound of one potential silhouette edge's wedge (DESIGN §4.5; as render/cpu_wedges.cpp):
/// the STSV volume of the edge's carrier face (a segment towards the light that touches the edge
/// touches the closed face, which its STSV volume bounds conservatively), both sides when the
/// light straddles the face's plane, and the carrier's light planes. `record` is what the wedge
/// fragment reads (GpuWedgeRecord).
struct WedgeBound {
    vec3 v0; ///< the carrier's corners, world units
    vec3 v1;
    vec3 v2;
    StsvVolume vol;
    StsvLightPlanes lp;
    GpuWedgeRecord record;
};

/// Whether edge e's side `side` may have a bound for light `lightIndex`: the tests of
/// wedgeSetupBound that build nothing (a carrier, a potential silhouette, a lit side).
bool wedgeMayHaveBound(uint e, uint side, uint lightIndex) {
    GpuEdge edge = edges[e];
    if (edge.carrier == GPU_NO_TRIANGLE) return false;
    vec4 sphere = lights[lightIndex].sphere;
    if (!potentialSilhouette(edge, sphere)) return false;
    GpuTriangle g = triangles[edge.carrier];
    return side < stsvSideCount(vec3(g.v0), vec3(g.v1), vec3(g.v2), sphere);
}

/// The bound of edge e's side `side` for light `lightIndex`; false when it has none (not a
/// potential silhouette of the light, no carrier, an empty or unlit side).
bool wedgeSetupBound(uint e, uint side, uint lightIndex, out WedgeBound b) {
    b.vol.flags = STSV_VOLUME_EMPTY;
    if (!wedgeMayHaveBound(e, side, lightIndex)) return false;
    vec4 sphere = lights[lightIndex].sphere;
    GpuTriangle g = triangles[edges[e].carrier];
    b.v0 = vec3(g.v0);
    b.v1 = vec3(g.v1);
    b.v2 = vec3(g.v2);
    vec3 lo = vec3(frame.boxLo);
    vec3 hi = vec3(frame.boxHi);
    b.vol = stsvBuildVolume(b.v0, b.v1, b.v2, sphere, lo, hi, side);
    if ((b.vol.flags & STSV_VOLUME_EMPTY) != 0u) return false;
    // Side 1 hands the points of the side-0 volume to side 0, so that every point is visited
    // once (the CPU mirror tests "inside any of the face's volumes").
    StsvVolume vol0;
    vol0.planeCount = 0u;
    vol0.flags = STSV_VOLUME_EMPTY;
    for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) vol0.planes[k] = vec4(0.0);
    if (side == 1u) vol0 = stsvBuildVolume(b.v0, b.v1, b.v2, sphere, lo, hi, 0u);
    uint side0 = (vol0.flags & STSV_VOLUME_EMPTY) == 0u ? WEDGE_SIDE0_PRESENT | vol0.planeCount : 0u;
    b.lp = stsvNoLightPlanes();
    LightFrame square;
    if (lightSampleSquare(lights[lightIndex].light, frame.farDistance, square))
        b.lp = stsvLightPlanes(b.v0, b.v1, b.v2, square.center, square.T, square.B, lo, hi);
    b.record.ids = uvec4(e, side | (b.lp.count << 8u), b.vol.planeCount, side0);
    for (uint k = 0u; k < STSV_VOLUME_MAX_PLANES; ++k) {
        b.record.planes[k] = b.vol.planes[k];
        b.record.planesSide0[k] = vol0.planes[k];
    }
    for (uint k = 0u; k < STSV_LIGHT_PLANES_MAX; ++k) b.record.lightPlanes[k] = b.lp.planes[k];
    return true;
}

/// Direction from world point v away from the light centre r of lightFrame (sampling/
/// light_sampling_dh.h): v − position for the area lights, −normal for a directional light
/// (its centre p + normal·farDistance lies at infinity). Not normalised.
vec3 awayFromLightCenter(Light light, vec3 v) {
    return light.type == LIGHT_DIRECTIONAL ? -light.normal : v - light.position;
}

/// +1 when scene triangle `tri` faces the light centre r with its winding normal, −1 when it
/// faces away, 0 when r lies in its plane. The one orientation test of the counting volumes:
/// caps, edge quads (dcs_center.geom) and the self-shadowing correction (wedge_fold.comp) must
/// agree on it bit for bit, or a thin volume (r almost in the plane) is left open and miscounts
/// every pixel behind it; `precise` forbids contractions that could differ between the stages.
int triangleFacingLight(Light light, uint tri) {
    GpuTriangle g = triangles[tri];
    precise vec3 v0 = vec3(g.v0);
    precise vec3 n = cross(vec3(g.v1) - v0, vec3(g.v2) - v0);
    precise float facing = -dot(n, awayFromLightCenter(light, v0));
    return facing > 0.0 ? 1 : (facing < 0.0 ? -1 : 0);
}

#endif
