// The wedge fragment's edge term (DESIGN §4.5): what wedges/shaders/wedge.frag's main() runs for a
// visible point p inside the bound of a potential silhouette edge, and what the CPU mirror
// (wedges/cpu/cpu_wedges.cpp) runs for each (pixel, edge) pair. Compiles as C++ and GLSL (core/dh.h).
//
// Data access. The faces of an edge come from a storage buffer on the GPU and from the
// EdgeAdjacency on the CPU, so the includer defines, before including this header,
//   struct WedgeFaces { ...; uint first; uint count; }   the faces first … first + count − 1
//   uint wedgeFaceTriangle(WedgeFaces faces, uint f)     scene triangle of face f
//   vec3 wedgeFaceOpposite(WedgeFaces faces, uint f)     its vertex opposite the edge (world units)
// and the macro WEDGE_FACES — a value passed in rather than declared functions, so the C++ side
// needs no globals (as volumes/stsv_fragment_dh.h).
#ifndef STSV_WEDGES_WEDGE_FRAGMENT_DH_H
#define STSV_WEDGES_WEDGE_FRAGMENT_DH_H

#ifndef WEDGE_FACES
#error "define WedgeFaces, wedgeFaceTriangle and wedgeFaceOpposite, then WEDGE_FACES"
#endif

#include "core/dh.h"
#include "wedges/dcs_dh.h"

DH_BEGIN

/// The edge's weight k_e seen from p in world space (dcsWorldSide), the receiver's own face
/// excluded: zero for most points (not a silhouette from p), which are rejected before the
/// projection onto the light frame.
DH_FUNC int wedgeWorldWeight(vec3 p, vec3 v0, vec3 v1, WedgeFaces faces, uint receiver) {
    int k = 0;
    for (uint f = faces.first; f < faces.first + faces.count; ++f)
        if (wedgeFaceTriangle(faces, f) != receiver)
            k += dcsWorldSide(p, v0, v1, wedgeFaceOpposite(faces, f));
    return k;
}

/// The edge v0 v1 projected from p onto the pixel's light frame (h0, h1, the line l = h0 × h1),
/// its weight k (dcsFaceSide of the faces except the receiver's) and the part between p and the
/// light (dcsClipEdge). False when the edge adds nothing to this pixel: k = 0 or nothing left.
DH_FUNC bool wedgeEdgeTerm(DcsPixel px, vec3 v0, vec3 v1, WedgeFaces faces, uint receiver, DH_OUT(vec3) l,
                           DH_OUT(vec3) h0, DH_OUT(vec3) h1, DH_OUT(int) k) {
    h0 = dcsProject(px, v0);
    h1 = dcsProject(px, v1);
    l = cross(h0, h1);
    k = 0;
    for (uint f = faces.first; f < faces.first + faces.count; ++f)
        if (wedgeFaceTriangle(faces, f) != receiver)
            k += dcsFaceSide(l, dcsProject(px, wedgeFaceOpposite(faces, f)));
    return k != 0 && dcsClipEdge(px.tMin, h0, h1);
}

DH_END

#endif // STSV_WEDGES_WEDGE_FRAGMENT_DH_H
