// STSV's light planes: the shadow of a triangle from a planar light, bounded with the light's
// own shape.
//
// The volume (volumes/volume_dh.h) bounds the light by its sphere and the triangle by t' (§2.2): a convex
// prism that a geometry shader can close with three side planes. Both are loose where foliage lives: a square
// light's sphere is √2 its half-diagonal wide in every direction, and a leaf seen edge-on from the light has
// t' edges up to the leaf's depth nearer the light than its own. The point test need not be a prism, so for a
// light whose samples lie in a fixed square c ± T ± B (a rectangle, or the square around a disk) the fragment
// also tests the planes of the shadow's convex hull ([AAM03]'s wedge planes with the light polygon for its
// sphere):
//  - through each edge of the triangle, with the light on the negative side and the triangle on
//    the positive side, touching a corner of the square;
//  - through each edge of the square, with the light on the negative side and the triangle on
//    the positive side, touching a vertex of the triangle.
// Any such plane is conservative: a shadowed p = x + λ(t − x) with x on the light, t on the
// triangle and λ ≥ 1 has value (1 − λ)·P(x) + λ·P(t) ≥ 0. In float, the touched corner or vertex
// is a ball of radius 3·slack (slack as in stsvBuildVolume), the others must clear the plane by
// 2.5·slack, and the triangle-edge planes move 2·slack outwards: every shadowed p keeps a value
// above the rounding of the plane and of the per-point test. A plane that does not exist (an edge
// whose line passes through the light's hull) is left out.
// Compiles as C++ and as GLSL 4.50 (core/dh.h).
#ifndef STSV_VOLUMES_LIGHT_PLANES_DH_H
#define STSV_VOLUMES_LIGHT_PLANES_DH_H

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"
#include "volumes/volume_dh.h"

DH_BEGIN

DH_CONST uint STSV_LIGHT_PLANES_MAX = 7u;

/// Light planes of one triangle (both of its volumes: a plane that holds every shadowed point of
/// one side holds those of the other). std430: 8 × 16 bytes.
struct StsvLightPlanes {
    vec4 planes[STSV_LIGHT_PLANES_MAX]; ///< world space (n, d), unit n: inside iff dot(n, p) + d ≥ 0
    uint count;                         ///< 0…STSV_LIGHT_PLANES_MAX
    uint pad0;
    uint pad1;
    uint pad2;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(StsvLightPlanes) == 128);
#endif

DH_FUNC StsvLightPlanes stsvNoLightPlanes() {
    StsvLightPlanes lp;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = vec4(0.0f);
    lp.count = 0u;
    lp.pad0 = 0u;
    lp.pad1 = 0u;
    lp.pad2 = 0u;
    return lp;
}

/// The light planes of triangle (v0, v1, v2) for a light whose samples lie in the square with
/// centre c and half-axes T, B (world units), in the scene box [boundsLo, boundsHi]. None for
/// degenerate or non-finite input.
DH_FUNC StsvLightPlanes stsvLightPlanes(vec3 v0, vec3 v1, vec3 v2, vec3 c, vec3 T, vec3 B, vec3 boundsLo,
                                        vec3 boundsHi) {
    StsvLightPlanes lp = stsvNoLightPlanes();
    bool finiteInput = stsvFiniteVec(c) && stsvFiniteVec(T) && stsvFiniteVec(B) && stsvFiniteVec(boundsLo) &&
                       stsvFiniteVec(boundsHi);
    if (!finiteInput || stsvTriangleIsDegenerate(v0, v1, v2)) return lp;
    // The frame of stsvBuildVolume, with its slack.
    StsvVolumeFrame frame = stsvVolumeFrame(v0, v1, v2, boundsLo, boundsHi);
    float invScale = frame.invScale;
    float slack = frame.slack;
    float touch = 3.0f * slack;
    float clear = 2.5f * slack;
    vec3 q[3];
    q[0] = vec3(0.0f);
    q[1] = (v1 - v0) * invScale;
    q[2] = (v2 - v0) * invScale;
    vec3 cc = (c - v0) * invScale;
    vec3 x[4];
    x[0] = cc - (T + B) * invScale;
    x[1] = cc + (T - B) * invScale;
    x[2] = cc + (T + B) * invScale;
    x[3] = cc - (T - B) * invScale;
    uint count = 0u;
    // Through the triangle's edges, touching a corner of the square.
    for (uint i = 0u; i < 3u; ++i) {
        bool found = false;
        for (uint k = 0u; k < 4u && !found; ++k) {
            vec4 pl;
            if (!stsvOuterPlane(q[i], q[(i + 1u) % 3u], q[(i + 2u) % 3u], x[k], touch, cc - q[i], pl))
                continue;
            float worst = -1e30f;
            for (uint j = 0u; j < 4u; ++j) worst = max(worst, dot(vec3(pl), x[j]) + pl.w);
            if (worst > -clear) continue;
            lp.planes[count] = pl + vec4(0.0f, 0.0f, 0.0f, 2.0f * slack);
            count += 1u;
            found = true;
        }
    }
    // Through the square's edges, touching a vertex of the triangle: stsvOuterPlane puts the
    // touched ball on the negative side and the light's centre on the positive one; turned round.
    for (uint i = 0u; i < 4u; ++i) {
        bool found = false;
        for (uint k = 0u; k < 3u && !found; ++k) {
            vec4 pl;
            if (!stsvOuterPlane(x[i], x[(i + 1u) % 4u], cc, q[k], touch, q[k] - cc, pl)) continue;
            pl = -pl;
            float worst = 1e30f;
            for (uint j = 0u; j < 3u; ++j) worst = min(worst, dot(vec3(pl), q[j]) + pl.w);
            if (worst < clear) continue;
            lp.planes[count] = pl;
            count += 1u;
            found = true;
        }
    }
    lp.count = count;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        lp.planes[i] = i < count ? stsvPlaneToWorld(frame, lp.planes[i]) : vec4(0.0f);
    return lp;
}

/// True iff p is on the inner side of every light plane.
DH_FUNC bool stsvPointInLightPlanes(StsvLightPlanes lp, vec3 p) {
    bool inside = true;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        inside = inside && (i >= lp.count || !(dot(vec3(lp.planes[i]), p) + lp.planes[i].w < 0.0f));
    return inside;
}

/// The light planes of triangle (v0, v1, v2) for `light`: those of its sample square
/// (lightSampleSquare, sampling/light_sampling_dh.h), or none for a light without one. The one
/// set-up of both backends' STSV volumes and wedge bounds.
DH_FUNC StsvLightPlanes stsvTriangleLightPlanes(vec3 v0, vec3 v1, vec3 v2, Light light, float farDistance,
                                                vec3 boundsLo, vec3 boundsHi) {
    LightFrame square;
    if (!lightSampleSquare(light, farDistance, square)) return stsvNoLightPlanes();
    return stsvLightPlanes(v0, v1, v2, square.center, square.T, square.B, boundsLo, boundsHi);
}

/// True when no point of the box passes stsvPointInLightPlanes (stsvPlaneMissesBox).
DH_FUNC bool stsvLightPlanesMissBox(StsvLightPlanes lp, vec3 lo, vec3 hi) {
    bool misses = false;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        misses = misses || (i < lp.count && stsvPlaneMissesBox(lp.planes[i], lo, hi));
    return misses;
}

DH_END

#endif // STSV_VOLUMES_LIGHT_PLANES_DH_H
