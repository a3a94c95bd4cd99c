#version 450
// Counting shadow volume at the light centre r (DESIGN §4.5; z-fail, capped): the layer count
// D(r) of every visible point p, the number of opaque triangles crossed by the segment p → r.
// Each opaque triangle t has the closed volume of the points it hides from r: t itself (near
// cap), its projection from r at farDistance (far cap) and one quad per edge. Caps are emitted
// per triangle; the quads of triangles sharing an edge are summed into one quad per welded edge
// with weight w_e (0 for an edge that is not a silhouette from r: its quads cancel). Every face
// is emitted with its outward normal counter-clockwise, so dcs_center.frag adds ±w by facing.
//
// Primitive ids (a point list, no vertex inputs): [0, T) scene triangles (caps; non-opaque ones
// emit nothing), [T, T + E) the welded edges whose quads may have a weight (centerEdges: the
// host's list of the silhouettes seen from r and near-ties; any other edge's quads cancel).
#extension GL_GOOGLE_include_directive : require
#include "wedges/wedge_bindings.glsl"

layout(points) in;
layout(triangle_strip, max_vertices = 6) out;

layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CENTER_EDGES) uniform usamplerBuffer centerEdges;

layout(location = 0) flat out int outWeight;       ///< added as +w on back faces, −w on front faces
layout(location = 1) flat out uint outSkipTriangle; ///< near cap of this triangle: not for its own points
/// World plane of the face, xyz its unit outward normal: the fragment decides "behind the
/// visible point" with it (dcs_center.frag).
layout(location = 2) flat out vec4 outPlane;

// Shared corners must land on identical clip coordinates in every face that uses them (the
// rasteriser is watertight only then): every position below is `precise`.
void emitTriangle(vec3 a, vec3 b, vec3 c, int weight, uint skip) {
    vec3 corners[3] = vec3[3](a, b, c);
    vec3 normal = cross(b - a, c - a);
    float area = length(normal);
    if (!(area > 0.0)) return; // degenerate after rounding: covers no pixel centre
    normal /= area;
    vec4 plane = vec4(normal, -dot(normal, a));
    for (int i = 0; i < 3; ++i) {
        precise vec4 clip = frame.clipFromWorld * vec4(corners[i], 1.0);
        gl_Position = clip;
        outWeight = weight;
        outSkipTriangle = skip;
        outPlane = plane;
        EmitVertex();
    }
    EndPrimitive();
}

/// v extruded away from the light centre to farDistance.
vec3 extrude(Light light, vec3 v) {
    precise vec3 far = v + normalize(awayFromLightCenter(light, v)) * frame.farDistance;
    return far;
}

/// v moved away from the light centre by the segments' start gap: the CPU mirror counts a
/// triangle only where the segment p → r crosses it at t > shadowTMin(p, r, D) (volumes/
/// stsv_dh.h), i.e. more than SHADOW_T_MIN·min(|r − p|, D) from p. Starting the volume there
/// (caps and quads alike, so it stays closed) counts the same triangles; a point that lies on
/// an occluder — a crease, an intersection — is then decided as on the CPU, not by a depth tie.
vec3 nearCorner(Light light, vec3 v) {
    vec3 away = awayFromLightCenter(light, v);
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    float reach = light.type == LIGHT_DIRECTIONAL ? sceneDiameter : min(length(away), sceneDiameter);
    precise vec3 near = v + normalize(away) * (SHADOW_T_MIN * reach);
    return near;
}

void main() {
    Light light = lights[pc.light].light;
    uint id = uint(gl_PrimitiveIDIn);
    uint triangleCount = uint(triangles.length());
    if (id < triangleCount) {
        GpuTriangle g = triangles[id];
        if (!gpuOpaqueOccluder(g.flags)) return;
        vec3 v0 = nearCorner(light, vec3(g.v0));
        vec3 v1 = nearCorner(light, vec3(g.v1));
        vec3 v2 = nearCorner(light, vec3(g.v2));
        // The volume lies behind t seen from r: the near cap's outward normal points at r, the
        // far cap's away from it (central projection keeps the orientation seen from r).
        int facing = triangleFacingLight(light, id);
        if (facing == 0) return; // r in the plane of t: an empty volume
        vec3 f0 = extrude(light, v0);
        vec3 f1 = extrude(light, v1);
        vec3 f2 = extrude(light, v2);
        if (facing > 0) {
            emitTriangle(v0, v1, v2, 1, id);
            emitTriangle(f0, f2, f1, 1, GPU_NO_TRIANGLE);
        } else {
            emitTriangle(v0, v2, v1, 1, id);
            emitTriangle(f0, f1, f2, 1, GPU_NO_TRIANGLE);
        }
        return;
    }
    if (id - triangleCount >= uint(textureSize(centerEdges))) return;
    uint e = texelFetch(centerEdges, int(id - triangleCount)).x;
    if (e >= uint(edges.length())) return;
    GpuEdge edge = edges[e];
    // m = u × (v1 − v0), u the extrusion direction: the normal of the plane through r and the
    // edge. Face f's volume lies on the side of its third vertex o_f, so its quad's outward
    // normal is −sign(m·(o_f − v0))·m = ±facing_f·m, + when f runs the edge v0 → v1 (the two
    // signs are one determinant; the facing is taken from triangleFacingLight so that caps and
    // quads agree). Summed over the faces: w_e·m.
    int weight = 0;
    for (uint f = edge.firstFace; f < edge.firstFace + edge.faceCount; ++f) {
        int facing = triangleFacingLight(light, edgeFaces[f].triangle);
        weight += edgeFaces[f].forward != 0u ? facing : -facing;
    }
    if (weight == 0) return;
    vec3 n0 = nearCorner(light, edge.v0);
    vec3 n1 = nearCorner(light, edge.v1);
    vec3 f0 = extrude(light, n0);
    vec3 f1 = extrude(light, n1);
    // (v0, f1, v1) and (v0, f0, f1) have normals along +m.
    emitTriangle(n0, f1, n1, weight, GPU_NO_TRIANGLE);
    emitTriangle(n0, f0, f1, weight, GPU_NO_TRIANGLE);
}
