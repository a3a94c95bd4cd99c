// The bound of a carrier face's wedges (DESIGN §4.5): where the wedge of any potential silhouette
// edge the face carries may add a term — the face's STSV volume of a side (a segment towards the
// light that touches an edge touches the closed face, which that volume bounds conservatively)
// within the face's light planes. The one assembly of the CPU mirror's bounds
// (wedges/silhouette_edges.cpp) and of the Vulkan wedge draws (wedges/shaders/wedge_bindings.glsl).
// Compiles as C++ and GLSL (core/dh.h).
#ifndef STSV_WEDGES_WEDGE_BOUND_DH_H
#define STSV_WEDGES_WEDGE_BOUND_DH_H

#include "core/dh.h"
#include "volumes/light_planes_dh.h"
#include "volumes/volume_dh.h"

DH_BEGIN

/// Side `side` of the bound of carrier face (v0, v1, v2) for a light (its bounding ball
/// lightSphere) within the scene box: its volume (stsvSideVolume; with `strip` its ten vertices
/// too) and the face's light planes, the same for both sides. False when the side has no volume;
/// `lp` is then left as it was (a face whose side 0 has a volume and side 1 none keeps side 0's).
DH_FUNC bool wedgeSideBound(vec3 v0, vec3 v1, vec3 v2, Light light, vec4 lightSphere, float farDistance,
                            vec3 boundsLo, vec3 boundsHi, uint side, bool strip, DH_OUT(StsvVolume) vol,
                            DH_INOUT(StsvLightPlanes) lp) {
    if (!stsvSideVolume(v0, v1, v2, lightSphere, boundsLo, boundsHi, side, strip, vol)) return false;
    lp = stsvTriangleLightPlanes(v0, v1, v2, light, farDistance, boundsLo, boundsHi);
    return true;
}

DH_END

#endif // STSV_WEDGES_WEDGE_BOUND_DH_H
