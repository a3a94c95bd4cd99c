// D(r), the layer count at the light centre (DESIGN §4.5), as the count of the opaque triangles
// the segment p → r crosses, through a bounding volume hierarchy over them (wedges/layer_bvh.h
// builds it): one reference ray per receiver point, as Laine et al. (2005) and Hierarchical
// Penumbra Casting (Lehtinen, Laine and Aila 2008) make the relative depth complexities of the
// other light samples absolute. Its cost grows with the pixels and the logarithm of the
// triangle count, where a counting shadow volume rasterises two caps per triangle.
// Compiles as C++ and GLSL 4.50 (core/dh.h).
//
// The tables, as 16-byte texels (uvec4, floats by their bits):
//   node n, LAYER_BVH_NODE_TEXELS from 4n: the boxes of its two children, (lo0.xyz, hi0.x),
//     (hi0.yz, lo1.xy), (lo1.z, hi1.xyz), then (child0, child1, 0, 0). A child is a node index,
//     or LAYER_BVH_LEAF | first triangle << 3 | (count − 1) for a leaf of 1 to LAYER_BVH_LEAF_MAX
//     triangles, or LAYER_BVH_EMPTY (its box empty: lo > hi). Node 0 is the root.
//   triangle i, LAYER_BVH_TRIANGLE_TEXELS from 3i: (v0, scene triangle), (v1, 0), (v2, 0).
//
// The CPU mirror counts D(r) with this function, Vulkan's dcs_center.comp with the same; the
// Embree reference is the independent oracle. The crossing test takes the Plücker edge products
// of Embree's robust test (each edge's product from its two vertices alone, `precise`): two
// triangles sharing an edge compute the same product with opposite signs, and a product of
// exactly 0 takes a sign that flips with the edge, so a segment through the edge crosses exactly
// one of them.
#ifndef STSV_WEDGES_LAYER_BVH_DH_H
#define STSV_WEDGES_LAYER_BVH_DH_H

#include "core/dh.h"
#include "scene/occlusion_rules_dh.h"

DH_BEGIN

DH_CONST uint LAYER_BVH_NODE_TEXELS = 4u;
DH_CONST uint LAYER_BVH_TRIANGLE_TEXELS = 3u;
DH_CONST uint LAYER_BVH_LEAF = 0x80000000u;
DH_CONST uint LAYER_BVH_EMPTY = 0xffffffffu;
DH_CONST uint LAYER_BVH_LEAF_MAX = 4u; ///< layerLeaf tests up to four, unrolled
/// The deepest a tree may be: the traversal's stack holds one entry a level.
DH_CONST uint LAYER_BVH_STACK = 40u;
/// Node visits a segment may take on the GPU (lavapipe ends an invocation's loops after 65 535
/// iterations): past them the count is cut short and the caller reports it.
DH_CONST uint LAYER_BVH_MAX_VISITS = 60000u;

/// What the counts cost: node visits, triangle tests, segments cut short.
struct LayerCountWork {
    uint visits;
    uint tests;
    uint cutShort;
    uint pad;
};

/// The direction's reciprocal for the box tests, finite everywhere: a zero component becomes
/// ±1e-30 (then 0 · its reciprocal is 0, never a NaN).
DH_FUNC vec3 layerInverseDirection(vec3 d) {
    vec3 safe = vec3(abs(d.x) > 1e-30f ? d.x : (d.x < 0.0f ? -1e-30f : 1e-30f),
                     abs(d.y) > 1e-30f ? d.y : (d.y < 0.0f ? -1e-30f : 1e-30f),
                     abs(d.z) > 1e-30f ? d.z : (d.z < 0.0f ? -1e-30f : 1e-30f));
    return vec3(1.0f) / safe;
}

/// Whether o + t·d meets the box [lo, hi] for some t in [0, 1], conservatively: each slab
/// parameter is within 4 ulp of its value (a rounded difference times a reciprocal GLSL rounds
/// to 2.5 ulp), so an overlap of [0, 1] that exists survives a slack of 1e-6.
DH_FUNC bool layerSegmentMeetsBox(vec3 o, vec3 inverse, vec3 lo, vec3 hi) {
    vec3 a = (lo - o) * inverse;
    vec3 b = (hi - o) * inverse;
    vec3 near = min(a, b);
    vec3 far = max(a, b);
    float t0 = max(max(near.x, near.y), max(near.z, 0.0f));
    float t1 = min(min(far.x, far.y), min(far.z, 1.0f));
    return t0 <= t1 + 1e-6f && lo.x <= hi.x;
}

/// The sign an edge product takes when it is exactly 0 (the segment through the edge's line): the
/// sign it would take with the segment's start moved by (ε, ε², ε³), ε → 0+. The product of
/// edge vector e, from layerSegmentCrosses, grows by −2·δ·(d × e) when the start moves by δ, so
/// the sign is minus that of the first non-zero component of d × e. It flips with e exactly,
/// so of two triangles sharing the edge (which run it in opposite directions) exactly one takes
/// the segment. Through a vertex shared by several triangles only products that are exactly 0
/// follow the one moved segment; products that round to either side of 0 there may let the fan
/// take the segment more or less than once (as Embree's test may), where a rasteriser's
/// fixed-point edge functions would not.
DH_FUNC bool layerTiePositive(vec3 e, vec3 d) {
    vec3 c = cross(d, e);
    float first = c.x != 0.0f ? c.x : (c.y != 0.0f ? c.y : c.z);
    return first < 0.0f;
}

/// Whether o + t·d crosses triangle (a, b, c) at t in [tMin, shadowTMax(tMin)]: the Plücker products of the
/// segment with the three edges (Embree's robust form, each from its edge's two vertices alone)
/// of one sign, a product of exactly 0 taking the sign of layerTiePositive, then the plane's
/// parameter. A segment through a shared edge or vertex crosses one triangle there, not two
/// (Embree's test accepts products within an ulp of 0 on both sides, and may count two).
DH_FUNC bool layerSegmentCrosses(vec3 o, vec3 d, float tMin, vec3 a, vec3 b, vec3 c) {
    vec3 v0 = a - o;
    vec3 v1 = b - o;
    vec3 v2 = c - o;
    vec3 e0 = v2 - v0;
    vec3 e1 = v0 - v1;
    vec3 e2 = v1 - v2;
    DH_PRECISE float u = dot(cross(e0, v2 + v0), d);
    DH_PRECISE float v = dot(cross(e1, v0 + v1), d);
    DH_PRECISE float w = dot(cross(e2, v1 + v2), d);
    bool pu = u != 0.0f ? u > 0.0f : layerTiePositive(e0, d);
    bool pv = v != 0.0f ? v > 0.0f : layerTiePositive(e1, d);
    bool pw = w != 0.0f ? w > 0.0f : layerTiePositive(e2, d);
    if (pu != pv || pv != pw) return false;
    vec3 n = cross(e1, e0);
    float den = dot(n, d);
    if (den == 0.0f) return false;
    float t = dot(v0, n) / den;
    return t >= tMin && t <= shadowTMax(tMin);
}

/// Whether triangle (a, b, c) crosses the plane w = w0 of a pixel's projection (dcs_dh.h: H(q) =
/// (dot(row0, q − p), dot(row1, q − p), dot(row2, q − p)), w the parameter along every segment
/// p → s) where the segments pass: its clip line there, at frame coordinates H.xy / w0, meets
/// the square [−1, 1]² that holds every light sample (a disk's too). The planes of the segments'
/// gaps, w0 = tMin and shadowTMax(tMin), are where a triangle enters or leaves the counted set as
/// the sample moves without an edge of it being crossed: there the crossings of DCS's identity
/// miss a change of D. Conservative: the clip points' rounding, divided by w0, widens the square
/// (a triangle lying in the plane meets it), so a true meeting is never missed.
DH_FUNC bool layerTriangleMeetsGap(vec3 a, vec3 b, vec3 c, vec3 p, vec3 row0, vec3 row1, vec3 row2,
                                   float w0) {
    vec3 h[3];
    h[0] = vec3(dot(row0, a - p), dot(row1, a - p), dot(row2, a - p));
    h[1] = vec3(dot(row0, b - p), dot(row1, b - p), dot(row2, b - p));
    h[2] = vec3(dot(row0, c - p), dot(row1, c - p), dot(row2, c - p));
    // The clip points (H.xy at w = w0: the frame point times w0), their box, and whether an edge
    // lies in the plane (then the triangle's part there is not a segment: the box alone decides).
    vec2 lo = vec2(3.0e38f);
    vec2 hi = vec2(-3.0e38f);
    vec2 q0 = vec2(0.0f);
    vec2 q1 = vec2(0.0f);
    uint found = 0u;
    bool inPlane = false;
    float magnitude = 0.0f;
    for (uint i = 0u; i < 3u; ++i) {
        vec3 u = h[i];
        vec3 v = h[(i + 1u) % 3u];
        magnitude = max(magnitude, max(abs(u.x), abs(u.y)));
        if ((u.z < w0 && v.z < w0) || (u.z > w0 && v.z > w0)) continue;
        if (u.z == v.z) {
            inPlane = true;
            lo = min(lo, min(vec2(u), vec2(v)));
            hi = max(hi, max(vec2(u), vec2(v)));
            continue;
        }
        vec2 q = vec2(u + (v - u) * ((w0 - u.z) / (v.z - u.z)));
        lo = min(lo, q);
        hi = max(hi, q);
        if (found == 0u)
            q0 = q;
        else
            q1 = q;
        ++found;
    }
    if (found == 0u && !inPlane) return false;
    // The square [−1, 1]² times w0, widened by its thousandth and the points' rounding (a few
    // units of round-off of the vertices' coordinates, 10⁻⁶ of them).
    float reach = w0 * (1.0f + 1e-3f) + 1e-6f * magnitude;
    if (!(lo.x <= reach && lo.y <= reach && hi.x >= -reach && hi.y >= -reach)) return false;
    if (inPlane || found < 2u) return true;
    // The segment q0 q1 misses the square when its line has every corner strictly on one side.
    vec2 d = q1 - q0;
    float s0 = d.x * (reach - q0.y) - d.y * (reach - q0.x);
    float s1 = d.x * (reach - q0.y) - d.y * (-reach - q0.x);
    float s2 = d.x * (-reach - q0.y) - d.y * (reach - q0.x);
    float s3 = d.x * (-reach - q0.y) - d.y * (-reach - q0.x);
    bool above = s0 > 0.0f && s1 > 0.0f && s2 > 0.0f && s3 > 0.0f;
    bool below = s0 < 0.0f && s1 < 0.0f && s2 < 0.0f && s3 < 0.0f;
    return !above && !below;
}

/// What a layer count also asks (layerCountGaps): whether a triangle meets a gap of the pixel's
/// segments — the planes w = tMin and w = shadowTMax(tMin) of its projection (row0, row1, row2)
/// where the segments pass (layerTriangleMeetsGap) — through the boxes of those planes' parts
/// inside the cone to the light frame (c, T, B): centre p + w0·(c − p), half extents
/// w0·(|T| + |B|), widened as the triangle test's square. `asked` 0: nothing asked.
struct LayerGaps {
    vec3 row0;
    float tMin;
    vec3 row1;
    uint asked;
    vec3 row2;
    float pad;
    vec3 startLo;
    vec3 startHi;
    vec3 endLo;
    vec3 endHi;
};

/// The box of the plane w = w0's part inside the cone from p to the light frame (c, T, B).
DH_FUNC void layerGapBox(vec3 p, vec3 c, vec3 T, vec3 B, float w0, DH_OUT(vec3) lo, DH_OUT(vec3) hi) {
    vec3 centre = p + w0 * (c - p);
    vec3 extent = w0 * (1.0f + 2e-3f) * (abs(T) + abs(B)) + 1e-6f * (abs(centre) + abs(p) + abs(c));
    lo = centre - extent;
    hi = centre + extent;
}

DH_FUNC LayerGaps layerGapsOf(vec3 p, vec3 c, vec3 T, vec3 B, vec3 row0, vec3 row1, vec3 row2, float tMin) {
    LayerGaps g;
    g.row0 = row0;
    g.row1 = row1;
    g.row2 = row2;
    g.tMin = tMin;
    g.asked = 1u;
    g.pad = 0.0f;
    layerGapBox(p, c, T, B, tMin, g.startLo, g.startHi);
    layerGapBox(p, c, T, B, shadowTMax(tMin), g.endLo, g.endHi);
    return g;
}

DH_FUNC LayerGaps layerNoGaps() {
    LayerGaps g;
    g.row0 = vec3(0.0f);
    g.row1 = vec3(0.0f);
    g.row2 = vec3(0.0f);
    g.tMin = 0.0f;
    g.asked = 0u;
    g.pad = 0.0f;
    g.startLo = vec3(0.0f);
    g.startHi = vec3(-1.0f);
    g.endLo = vec3(0.0f);
    g.endHi = vec3(-1.0f);
    return g;
}

DH_FUNC bool layerBoxesOverlap(vec3 lo, vec3 hi, vec3 qlo, vec3 qhi) {
    return lo.x <= qhi.x && lo.y <= qhi.y && lo.z <= qhi.z && hi.x >= qlo.x && hi.y >= qlo.y && hi.z >= qlo.z;
}

/// Whether a child box [lo, hi] may hold a triangle that meets a gap still unanswered.
DH_FUNC bool layerGapsMayMeet(LayerGaps gaps, bool met, vec3 lo, vec3 hi) {
    return gaps.asked != 0u && !met &&
           (layerBoxesOverlap(lo, hi, gaps.startLo, gaps.startHi) ||
            layerBoxesOverlap(lo, hi, gaps.endLo, gaps.endHi));
}

DH_END

#endif // STSV_WEDGES_LAYER_BVH_DH_H

#if defined(LAYER_BVH) && !defined(STSV_WEDGES_LAYER_BVH_TRAVERSAL)
#define STSV_WEDGES_LAYER_BVH_TRAVERSAL
// The includer defines, before it includes this file (a value passed in, as WEDGE_FACES):
//   struct LayerBvh { ... };                          the tables
//   uvec4 layerBvhNode(LayerBvh bvh, uint texel)      texel of the nodes
//   uvec4 layerBvhTriangle(LayerBvh bvh, uint texel)  texel of the triangles
// and the macro LAYER_BVH.

DH_BEGIN

/// Leaf triangle i: 1 when o + t·d crosses it at t in [tMin, 1] and it is not `ignore`.
DH_FUNC uint layerLeafTriangle(LayerBvh bvh, uint i, vec3 o, vec3 d, float tMin, uint ignore) {
    uvec4 t0 = layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i);
    if (t0.w == ignore) return 0u;
    uvec4 t1 = layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i + 1u);
    uvec4 t2 = layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i + 2u);
    return layerSegmentCrosses(o, d, tMin, uintBitsToFloat(uvec3(t0)), uintBitsToFloat(uvec3(t1)),
                               uintBitsToFloat(uvec3(t2)))
               ? 1u
               : 0u;
}

/// The triangles of leaf `child` o + t·d crosses at t in [tMin, 1], but `ignore` (unrolled:
/// no loop iterations on lavapipe's budget).
#ifdef __cplusplus
DH_STATIC_ASSERT(LAYER_BVH_LEAF_MAX <= 4u);
#endif
DH_FUNC uint layerLeaf(LayerBvh bvh, uint child, vec3 o, vec3 d, float tMin, uint ignore,
                       DH_INOUT(LayerCountWork) work) {
    uint first = (child & ~LAYER_BVH_LEAF) >> 3u;
    uint count = (child & 7u) + 1u;
    work.tests += count;
    uint crossed = layerLeafTriangle(bvh, first, o, d, tMin, ignore);
    if (count > 1u) crossed += layerLeafTriangle(bvh, first + 1u, o, d, tMin, ignore);
    if (count > 2u) crossed += layerLeafTriangle(bvh, first + 2u, o, d, tMin, ignore);
    if (count > 3u) crossed += layerLeafTriangle(bvh, first + 3u, o, d, tMin, ignore);
    return crossed;
}

/// Whether a triangle of leaf `child` other than `ignore` meets either gap plane.
DH_FUNC bool layerLeafMeetsGaps(LayerBvh bvh, uint child, vec3 p, LayerGaps gaps, uint ignore,
                                DH_INOUT(LayerCountWork) work) {
    uint first = (child & ~LAYER_BVH_LEAF) >> 3u;
    uint count = (child & 7u) + 1u;
    work.tests += count;
    bool met = false;
    for (uint i = first; i < first + count; ++i) {
        uvec4 t0 = layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i);
        if (t0.w == ignore) continue;
        vec3 a = uintBitsToFloat(uvec3(t0));
        vec3 b = uintBitsToFloat(uvec3(layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i + 1u)));
        vec3 c = uintBitsToFloat(uvec3(layerBvhTriangle(bvh, LAYER_BVH_TRIANGLE_TEXELS * i + 2u)));
        met = met || layerTriangleMeetsGap(a, b, c, p, gaps.row0, gaps.row1, gaps.row2, gaps.tMin) ||
              layerTriangleMeetsGap(a, b, c, p, gaps.row0, gaps.row1, gaps.row2, shadowTMax(gaps.tMin));
    }
    return met;
}

/// The number of triangles of the tree the segment p → r crosses at t in [tMin, 1] of r − p,
/// `ignore` (the receiver's scene triangle: the self-shadowing rule) left out — Embree's
/// countLayers on the same triangles — and, in the same traversal, whether a triangle but
/// `ignore` meets a gap of `gaps` (gapMet; false when gaps.asked is 0): the boxes near p and
/// near the light lie along the segment, so asking costs few more node visits. There DCS's
/// crossings do not carry D(r) to every sample, and the pixel counts its samples' segments
/// instead (dcs_dh.h dcsBlockCastsRays). `nodes`: the tree's node count (0: empty);
/// `maxVisits`: the node visits it may take before it stops (work.cutShort; a gap then counts
/// as met).
DH_FUNC uint layerCountGaps(LayerBvh bvh, uint nodes, vec3 p, vec3 r, float tMin, uint ignore, uint maxVisits,
                            LayerGaps gaps, DH_INOUT(LayerCountWork) work, DH_OUT(bool) gapMet) {
    vec3 d = r - p;
    vec3 inverse = layerInverseDirection(d);
    uint crossed = 0u;
    uint stack[LAYER_BVH_STACK];
    uint top = 0u;
    uint node = 0u;
    bool more = nodes > 0u;
    bool met = false;
    uint visits = 0u;
    for (; more && visits < maxVisits; ++visits) {
        uint base = LAYER_BVH_NODE_TEXELS * node;
        vec4 a = uintBitsToFloat(layerBvhNode(bvh, base));
        vec4 b = uintBitsToFloat(layerBvhNode(bvh, base + 1u));
        vec4 c = uintBitsToFloat(layerBvhNode(bvh, base + 2u));
        uvec4 children = layerBvhNode(bvh, base + 3u);
        uint next = LAYER_BVH_EMPTY;
        // The two children written out (a loop over them runs slower on lavapipe).
        vec3 lo0 = vec3(a);
        vec3 hi0 = vec3(a.w, b.x, b.y);
        bool segment0 = layerSegmentMeetsBox(p, inverse, lo0, hi0);
        bool gap0 = layerGapsMayMeet(gaps, met, lo0, hi0);
        if (segment0 || gap0) {
            if ((children.x & LAYER_BVH_LEAF) != 0u) {
                if (segment0) crossed += layerLeaf(bvh, children.x, p, d, tMin, ignore, work);
                if (gap0 && layerLeafMeetsGaps(bvh, children.x, p, gaps, ignore, work)) met = true;
            } else {
                next = children.x;
            }
        }
        vec3 lo1 = vec3(b.z, b.w, c.x);
        vec3 hi1 = vec3(c.y, c.z, c.w);
        bool segment1 = layerSegmentMeetsBox(p, inverse, lo1, hi1);
        bool gap1 = layerGapsMayMeet(gaps, met, lo1, hi1);
        if (segment1 || gap1) {
            if ((children.y & LAYER_BVH_LEAF) != 0u) {
                if (segment1) crossed += layerLeaf(bvh, children.y, p, d, tMin, ignore, work);
                if (gap1 && layerLeafMeetsGaps(bvh, children.y, p, gaps, ignore, work)) met = true;
            } else if (next == LAYER_BVH_EMPTY) {
                next = children.y;
            } else {
                stack[top] = children.y;
                ++top;
            }
        }
        if (next == LAYER_BVH_EMPTY) {
            if (top == 0u) {
                more = false;
            } else {
                --top;
                next = stack[top];
            }
        }
        node = next;
    }
    work.visits += visits;
    if (more) ++work.cutShort;
    gapMet = gaps.asked != 0u && (met || more);
    return crossed;
}

/// layerCountGaps without the gaps: the segment's count alone.
DH_FUNC uint layerCount(LayerBvh bvh, uint nodes, vec3 p, vec3 r, float tMin, uint ignore, uint maxVisits,
                        DH_INOUT(LayerCountWork) work) {
    bool unused;
    return layerCountGaps(bvh, nodes, p, r, tMin, ignore, maxVisits, layerNoGaps(), work, unused);
}

DH_END

#endif // the traversal
