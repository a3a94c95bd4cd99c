// A clipped hull (volumes/clip_box_dh.h) as the volume passes draw it, for the compute hull pass
// (hull_append.glsl) and the mesh shaders (hull_mesh.glsl) alike: which of its faces the
// rasteriser keeps, and where its corners lie in world space and in clip space.
#ifndef STSV_SHADERS_HULL_FACES_GLSL
#define STSV_SHADERS_HULL_FACES_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "volumes/extrusion_dh.h"

/// A hull corner in world space (x_world = origin + scale·x): `precise`, so that the corner two
/// faces share gets the same bits in both (no contraction at one of them).
vec3 hullWorldCorner(vec3 corner, vec3 origin, float scale) {
    precise vec3 p = origin + scale * corner;
    return p;
}

/// A world point in clip space, `precise` in hull.vert and the mesh shaders alike, so that both
/// paths put a corner on the same bits.
vec4 hullClipPosition(vec3 world) {
    precise vec4 clip = frame.clipFromWorld * vec4(world, 1.0);
    return clip;
}

/// The faces of `hull` (set up by `h`) that the rasteriser keeps, bit f for face f: those not
/// turned towards the eye (the volume passes draw back faces). A face is left out only when the
/// eye lies clearly on its outer side, 1e-4 of the eye's distance beyond its plane, far beyond
/// the rounding of the rasteriser's own decision. `triangles` gets their fans' triangles,
/// `corners` their corners counted per face.
uint hullDrawnFaces(ClippedBox hull, StsvHullSetup h, out uint triangles, out uint corners) {
    triangles = 0u;
    corners = 0u;
    vec3 eye = (vec3(frame.eye) - h.origin) / h.scale;
    uint drawn = 0u;
    for (uint f = 0u; f < hull.faceCount; ++f) {
        uint o = f * CLIP_MAX_FACE_VERTICES;
        vec3 normal = vec3(0.0); // Newell: twice the area, outward
        for (uint i = 0u; i < hull.count[f]; ++i) {
            vec3 a = CLIP_CORNER(hull, o + i);
            vec3 b = CLIP_CORNER(hull, o + (i + 1u) % hull.count[f]);
            normal += vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        }
        vec3 toEye = eye - CLIP_CORNER(hull, o);
        if (dot(normal, toEye) > 1e-4 * length(normal) * length(toEye)) continue;
        drawn |= 1u << f;
        triangles += hull.count[f] - 2u;
        corners += hull.count[f];
    }
    return drawn;
}

#endif
