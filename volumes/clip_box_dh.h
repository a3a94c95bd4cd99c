// A box clipped by half-spaces, as a closed polyhedron of convex faces: the geometry the volume
// passes rasterise when the volume's own planes are not a ten-vertex prism. The STSV volume's
// planes and its light planes (extrusion_dh.h) cut out the region whose points the fragment
// accepts; a prism closed by three side planes (STSV paper §2.2, Fig. 6) is much larger than that
// region when the light is large or the leaf edge-on, and every fragment of the difference costs
// a fragment invocation that only rejects. Compiles as C++ and as GLSL (core/dh.h).
//
// Clipping (Sutherland–Hodgman, face by face): each face polygon keeps its part on the inner side
// of the plane; the point where a face's boundary leaves the half-space is its exit, and the
// exits, ordered by angle about the plane's normal, close the cut as a new face. A cut point is
// computed from the (inside, outside) end of its edge in that order, so the two faces that share
// the edge get the same bits: the faces meet without cracks, and rasterising them is watertight.
#ifndef STSV_VOLUMES_CLIP_BOX_DH_H
#define STSV_VOLUMES_CLIP_BOX_DH_H

#include "core/dh.h"

DH_BEGIN

DH_CONST uint CLIP_MAX_PLANES = 8u;                  ///< half-spaces besides the box
DH_CONST uint CLIP_MAX_FACES = 6u + CLIP_MAX_PLANES; ///< the box's faces and one per plane
/// Vertices per face: a box face gains at most one per cut (4 + 8), a cut face has at most
/// one per face cut before it (13).
DH_CONST uint CLIP_MAX_FACE_VERTICES = 13u;
/// Triangles of a fan triangulation of every face: at most 2·V − 4 with V ≤ 2·F − 4 vertices.
DH_CONST uint CLIP_MAX_TRIANGLES = 4u * CLIP_MAX_FACES - 12u;

/// Where the polyhedron's corners live. C++, and GLSL by default: a member array of ClippedBox.
/// A GLSL compute shader may define CLIP_SHARED_INVOCATIONS (its workgroup size) before
/// including this header to keep the corners, and the face being clipped, in shared memory
/// instead, a slice per invocation: lavapipe turns a large local array indexed per lane into
/// code that LLVM takes most of a minute to compile, and that runs slower than shared loads.
/// CLIP_CORNER(b, k) is corner k of polyhedron b, CLIP_SCRATCH(k) point k of the face being
/// clipped, CLIP_ENTRY(k) and CLIP_EXIT(k) where the boundary of the k-th face a plane cuts
/// enters and leaves its half-space; clipBox's locals are declared with CLIP_SCRATCH_DECLARE and
/// CLIP_CUTS_DECLARE.
#ifdef CLIP_SHARED_INVOCATIONS
shared vec3 clipSharedCorners[CLIP_SHARED_INVOCATIONS * CLIP_MAX_FACES * CLIP_MAX_FACE_VERTICES];
shared vec3 clipSharedScratch[CLIP_SHARED_INVOCATIONS * CLIP_MAX_FACE_VERTICES];
shared vec3 clipSharedEntries[CLIP_SHARED_INVOCATIONS * CLIP_MAX_FACES];
shared vec3 clipSharedExits[CLIP_SHARED_INVOCATIONS * CLIP_MAX_FACES];
#define CLIP_CORNER(b, k)                                                                                    \
    clipSharedCorners[gl_LocalInvocationIndex * (CLIP_MAX_FACES * CLIP_MAX_FACE_VERTICES) + (k)]
#define CLIP_SCRATCH(k) clipSharedScratch[gl_LocalInvocationIndex * CLIP_MAX_FACE_VERTICES + (k)]
#define CLIP_ENTRY(k) clipSharedEntries[gl_LocalInvocationIndex * CLIP_MAX_FACES + (k)]
#define CLIP_EXIT(k) clipSharedExits[gl_LocalInvocationIndex * CLIP_MAX_FACES + (k)]
#define CLIP_SCRATCH_DECLARE
#define CLIP_CUTS_DECLARE
#else
#define CLIP_CORNER(b, k) (b).corner[k]
#define CLIP_SCRATCH(k) clipped[k]
#define CLIP_ENTRY(k) entries[k]
#define CLIP_EXIT(k) exits[k]
#define CLIP_SCRATCH_DECLARE vec3 clipped[CLIP_MAX_FACE_VERTICES];
#define CLIP_CUTS_DECLARE                                                                                    \
    vec3 entries[CLIP_MAX_FACES];                                                                            \
    vec3 exits[CLIP_MAX_FACES];
#endif

/// The polyhedron: face f has count[f] vertices, CLIP_CORNER(b, f·CLIP_MAX_FACE_VERTICES + i),
/// counter-clockwise seen from outside. Faces with fewer than three vertices are gone.
struct ClippedBox {
#ifndef CLIP_SHARED_INVOCATIONS
    vec3 corner[CLIP_MAX_FACES * CLIP_MAX_FACE_VERTICES];
#endif
    uint count[CLIP_MAX_FACES];
    uint faceCount;
};

/// Corner of the box [lo, hi] with hi in the axes whose bits are set in `bits` (1: x, 2: y, 4: z).
/// Picked, not summed, so that every face that holds a corner has its exact bits.
DH_FUNC vec3 clipBoxCorner(vec3 lo, vec3 hi, uint bits) {
    return vec3((bits & 1u) != 0u ? hi.x : lo.x, (bits & 2u) != 0u ? hi.y : lo.y,
                (bits & 4u) != 0u ? hi.z : lo.z);
}

/// The point where edge (a inside, b outside) crosses the plane, from its inside end.
DH_FUNC vec3 clipCrossing(vec3 a, float da, vec3 b, float db) {
    return a + (da / (da - db)) * (b - a);
}

/// Pseudo-angle in [0, 4) of (r·u, r·w): monotone in its angle, no trigonometry.
DH_FUNC float clipPseudoAngle(vec3 r, vec3 u, vec3 w) {
    float x = dot(r, u);
    float y = dot(r, w);
    float t = (abs(x) + abs(y)) > 0.0f ? y / (abs(x) + abs(y)) : 0.0f;
    return x >= 0.0f ? (y >= 0.0f ? t : 4.0f + t) : 2.0f - t;
}

/// The box [lo, hi] clipped by the first `count` planes (each (n, d), unit n, keeping
/// n·x + d ≥ 0) that cut deeper than minCut (≥ 0), one plane after the other: each face polygon keeps its
/// part inside the plane, and the cut face closes the hole; faces left with fewer than three distinct corners
/// are dropped. An empty result has no faces. One function, no calls that take the polyhedron: GLSL copies a
/// struct passed inout, and this one is 2 KB.
DH_FUNC ClippedBox clipBox(vec3 lo, vec3 hi, vec4 planes[CLIP_MAX_PLANES], uint count, float minCut) {
    ClippedBox b;
    // The box's faces (−x, +x, −y, +y, −z, +z), counter-clockwise seen from outside: corners on
    // the axes (u, w), right-handed with the outward normal.
    for (uint i = 0u; i < 6u; ++i) {
        uint axis = i / 2u;
        bool upper = (i & 1u) != 0u;
        uint u = upper ? (axis + 1u) % 3u : (axis + 2u) % 3u;
        uint w = upper ? (axis + 2u) % 3u : (axis + 1u) % 3u;
        uint base = upper ? (1u << axis) : 0u;
        uint o = i * CLIP_MAX_FACE_VERTICES;
        CLIP_CORNER(b, o) = clipBoxCorner(lo, hi, base);
        CLIP_CORNER(b, o + 1u) = clipBoxCorner(lo, hi, base | (1u << u));
        CLIP_CORNER(b, o + 2u) = clipBoxCorner(lo, hi, base | (1u << u) | (1u << w));
        CLIP_CORNER(b, o + 3u) = clipBoxCorner(lo, hi, base | (1u << w));
        b.count[i] = 4u;
    }
    for (uint i = 6u; i < CLIP_MAX_FACES; ++i) b.count[i] = 0u;
    b.faceCount = 6u;
    for (uint j = 0u; j < count && j < CLIP_MAX_PLANES && b.faceCount > 0u; ++j) {
        vec4 plane = planes[j];
        vec3 n = vec3(plane);
        // A plane that would cut off no more than minCut deep is left out: the polyhedron stays
        // a little larger, without the sliver faces such a cut makes (a rasteriser that snaps
        // their corners to its grid can turn a sliver round, and count a pixel twice).
        float deepest = 0.0f;
        for (uint f = 0u; f < b.faceCount; ++f) {
            uint o = f * CLIP_MAX_FACE_VERTICES;
            for (uint i = 0u; i < b.count[f]; ++i)
                deepest = max(deepest, -(dot(n, CLIP_CORNER(b, o + i)) + plane.w));
        }
        if (!(deepest > minCut)) continue;
        // Per cut face, the points where its boundary enters and leaves the half-space: the face's
        // new edge runs exit → entry, so the cut face runs entry → exit, and one face's exit is the
        // next one's entry (the same bits: clipCrossing from the edge's inside end on both sides).
        CLIP_CUTS_DECLARE
        uint cuts = 0u;
        bool paired = true;
        uint kept = 0u;
        for (uint f = 0u; f < b.faceCount; ++f) {
            uint o = f * CLIP_MAX_FACE_VERTICES;
            uint m = b.count[f];
            CLIP_SCRATCH_DECLARE
            uint c = 0u;
            uint faceEntries = 0u;
            uint faceExits = 0u;
            vec3 entry = vec3(0.0f);
            vec3 exit = vec3(0.0f);
            for (uint i = 0u; i < m; ++i) {
                vec3 a = CLIP_CORNER(b, o + i);
                vec3 e = CLIP_CORNER(b, o + (i + 1u) % m);
                float da = dot(n, a) + plane.w;
                float de = dot(n, e) + plane.w;
                bool aIn = da >= 0.0f;
                bool eIn = de >= 0.0f;
                bool crosses = aIn != eIn;
                vec3 x = aIn ? clipCrossing(a, da, e, de) : clipCrossing(e, de, a, da);
                if (!aIn && eIn) {
                    entry = x;
                    faceEntries += 1u;
                }
                // Kept points, each once (a plane through a corner makes a crossing equal to it).
                if (aIn && (c == 0u || CLIP_SCRATCH(max(c, 1u) - 1u) != a) && c < CLIP_MAX_FACE_VERTICES) {
                    CLIP_SCRATCH(c) = a;
                    c += 1u;
                }
                if (crosses && (c == 0u || CLIP_SCRATCH(max(c, 1u) - 1u) != x) &&
                    c < CLIP_MAX_FACE_VERTICES) {
                    CLIP_SCRATCH(c) = x;
                    c += 1u;
                }
                if (aIn && !eIn) {
                    exit = x;
                    faceExits += 1u;
                }
            }
            if (faceEntries + faceExits > 0u) {
                paired = paired && faceEntries == 1u && faceExits == 1u && cuts < CLIP_MAX_FACES;
                if (cuts < CLIP_MAX_FACES) {
                    CLIP_ENTRY(cuts) = entry;
                    CLIP_EXIT(cuts) = exit;
                    cuts += 1u;
                }
            }
            if (c > 1u && CLIP_SCRATCH(max(c, 1u) - 1u) == CLIP_SCRATCH(0u)) c -= 1u;
            // Fewer than three distinct points: nothing left of this face (or a sliver of no area).
            if (c < 3u) continue;
            uint ko = kept * CLIP_MAX_FACE_VERTICES;
            for (uint i = 0u; i < c; ++i) CLIP_CORNER(b, ko + i) = CLIP_SCRATCH(i);
            b.count[kept] = c;
            kept += 1u;
        }
        b.faceCount = kept;
        if (cuts < 3u || kept >= CLIP_MAX_FACES) continue;
        // The cut face, written straight into its slot: from an exit, the face whose entry it is
        // leads to that face's exit.
        uint ko = kept * CLIP_MAX_FACE_VERTICES;
        vec3 current = CLIP_EXIT(0u);
        CLIP_CORNER(b, ko) = current;
        uint used = 1u; // bit k: cut k's exit is on the cap
        uint capCount = 1u;
        bool chained = paired;
        for (uint step = 1u; step < cuts && chained; ++step) {
            uint next = CLIP_MAX_FACES;
            for (uint k = 1u; k < cuts; ++k)
                if ((used & (1u << k)) == 0u && next == CLIP_MAX_FACES && CLIP_ENTRY(k) == current) next = k;
            chained = next < CLIP_MAX_FACES;
            if (chained) {
                used |= 1u << next;
                current = CLIP_EXIT(next);
                CLIP_CORNER(b, ko + capCount) = current;
                capCount += 1u;
            }
        }
        chained = chained && CLIP_ENTRY(0u) == current;
        if (!chained) {
            // A plane through a corner shared by several faces: order the exits by angle about the
            // cut face's outward normal −n instead, around their centroid, in a basis (u, w) with
            // u × w = −n (an insertion sort on the pseudo-angle, recomputed from each point).
            capCount = cuts;
            vec3 centre = vec3(0.0f);
            for (uint k = 0u; k < cuts; ++k) centre += CLIP_EXIT(k);
            centre /= float(cuts);
            vec3 u = abs(n.x) < 0.6f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
            u = normalize(u - dot(u, n) * n);
            vec3 w = cross(-n, u);
            for (uint k = 0u; k < cuts; ++k) {
                vec3 p = CLIP_EXIT(k);
                float pk = clipPseudoAngle(p - centre, u, w);
                uint slot = k;
                while (slot > 0u && clipPseudoAngle(CLIP_CORNER(b, ko + slot - 1u) - centre, u, w) > pk) {
                    CLIP_CORNER(b, ko + slot) = CLIP_CORNER(b, ko + slot - 1u);
                    slot -= 1u;
                }
                CLIP_CORNER(b, ko + slot) = p;
            }
        }
        // Repeated points (a plane through a corner) only once, in place.
        uint corners = 1u;
        for (uint i = 1u; i < capCount; ++i) {
            vec3 p = CLIP_CORNER(b, ko + i);
            if (CLIP_CORNER(b, ko + corners - 1u) == p) continue;
            CLIP_CORNER(b, ko + corners) = p;
            corners += 1u;
        }
        if (corners > 1u && CLIP_CORNER(b, ko + max(corners, 1u) - 1u) == CLIP_CORNER(b, ko)) corners -= 1u;
        if (corners < 3u) continue;
        b.count[kept] = corners;
        b.faceCount = kept + 1u;
    }
    return b;
}

/// Number of triangles of a fan triangulation of every face.
DH_FUNC uint clipBoxTriangleCount(ClippedBox b) {
    uint t = 0u;
    for (uint f = 0u; f < b.faceCount; ++f) t += b.count[f] - 2u;
    return t;
}

DH_END

#endif // STSV_VOLUMES_CLIP_BOX_DH_H
