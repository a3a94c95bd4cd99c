// Descriptor declarations of the opaque-occluder passes (dcs_center.*, wedge.*, wedge_fold.comp):
// the welded edges of the opaque triangles and their faces (render/gpu_opaque_passes.cpp uploads them).
#ifndef STSV_SHADERS_WEDGE_BINDINGS_GLSL
#define STSV_SHADERS_WEDGE_BINDINGS_GLSL

#include "frame_bindings.glsl"

layout(std430, set = 0, binding = GPU_BINDING_EDGES) readonly buffer Edges { GpuEdge edges[]; };
layout(std430, set = 0, binding = GPU_BINDING_EDGE_FACES) readonly buffer EdgeFaces { GpuEdgeFace edgeFaces[]; };

/// wedge.geom → wedge.frag: the fragment must leave the points of the side-0 volume to side 0.
const uint WEDGE_SIDE0_PRESENT = 256u;

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
