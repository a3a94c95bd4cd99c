// The geometry an STSV volume pass rasterises: the region a fragment accepts (the volume's planes
// and the triangle's light planes) inside the scene box, as the half-spaces of a closed
// polyhedron that volumes/clip_box_dh.h clips. Compiles as C++ and as GLSL 4.50 (core/dh.h).
#ifndef STSV_VOLUMES_HULL_SETUP_DH_H
#define STSV_VOLUMES_HULL_SETUP_DH_H

#include "core/dh.h"
#include "volumes/clip_box_dh.h"
#include "volumes/light_planes_dh.h"
#include "volumes/volume_dh.h"

DH_BEGIN

/// The half-spaces and the box whose intersection (clipBox) is a volume's hull, in the volume's
/// StsvVolumeFrame: x_world = origin + scale·x.
struct StsvHullSetup {
    vec4 planes[CLIP_MAX_PLANES];
    vec3 lo;
    uint count;
    vec3 hi;
    float scale;
    vec3 origin;
    uint empty;   ///< 1: the volume is empty, so is its hull
    float minCut; ///< clipBox's: STSV_STRIP_EXPANSION
    uint pad0;
    uint pad1;
    uint pad2;
};

#ifdef __cplusplus
// The light planes and the triangle's plane, or the volume's planes, fit the clipper.
DH_STATIC_ASSERT(STSV_LIGHT_PLANES_MAX + 1u <= CLIP_MAX_PLANES && STSV_VOLUME_MAX_PLANES <= CLIP_MAX_PLANES);
#endif

/// What the fragment accepts — the volume's planes, the triangle's light planes — inside the
/// scene box, as the half-spaces of a closed polyhedron (clip_box_dh.h): every plane moved
/// outwards by the slack and STSV_STRIP_EXPANSION, the box by STSV_STRIP_MARGIN (box diagonals),
/// far beyond the rounding of the clipping, so that the polyhedron encloses every point the
/// tests accept; cuts shallower than STSV_STRIP_EXPANSION are left out (clipBox's minCut). It is the smallest
/// geometry whose back faces behind the visible point give a fragment for every point inside (DESIGN §4.2),
/// where the strip of stsvBuildVolume, a prism closed by three side planes, can be many times larger.
DH_FUNC StsvHullSetup stsvVolumeHullSetup(StsvVolume vol, StsvLightPlanes lp, vec3 v0, vec3 v1, vec3 v2,
                                          vec3 boundsLo, vec3 boundsHi) {
    StsvVolumeFrame frame = stsvVolumeFrame(v0, v1, v2, boundsLo, boundsHi);
    float expansion = frame.slack + STSV_STRIP_EXPANSION;
    StsvHullSetup h;
    h.lo = frame.boxLo - vec3(STSV_STRIP_MARGIN);
    h.hi = frame.boxHi + vec3(STSV_STRIP_MARGIN);
    h.origin = frame.origin;
    h.scale = frame.scale;
    h.empty = (vol.flags & STSV_VOLUME_EMPTY) != 0u ? 1u : 0u;
    h.minCut = STSV_STRIP_EXPANSION;
    h.pad0 = 0u;
    h.pad1 = 0u;
    h.pad2 = 0u;
    uint count = 0u;
    // The light planes first: the tightest, they leave the later planes little to cut.
    for (uint i = 0u; i < min(lp.count, STSV_LIGHT_PLANES_MAX); ++i) {
        h.planes[count] = stsvPlaneToFrame(frame, lp.planes[i]) + vec4(0.0f, 0.0f, 0.0f, expansion);
        count += 1u;
    }
    // With light planes, the volume's own planes add slivers, not tightness: its triangle plane
    // only (the rest still bound the region the fragment accepts, inside this larger one).
    uint volumePlanes = lp.count > 0u ? min(vol.planeCount, 1u) : min(vol.planeCount, STSV_VOLUME_MAX_PLANES);
    for (uint i = 0u; i < volumePlanes; ++i) {
        h.planes[count] = stsvPlaneToFrame(frame, vol.planes[i]) + vec4(0.0f, 0.0f, 0.0f, expansion);
        count += 1u;
    }
    for (uint i = count; i < CLIP_MAX_PLANES; ++i) h.planes[i] = vec4(0.0f);
    h.count = count;
    return h;
}

DH_END

#endif // STSV_VOLUMES_HULL_SETUP_DH_H
