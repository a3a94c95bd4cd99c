// Depth complexity sampling (Forest, Barthe & Paulin 2008; STSV paper §3.2; DESIGN §4.5):
// per receiver point p, the edge crossings that carry the depth complexity from the light centre
// r to every light sample x. Compiles as C++ and as GLSL 4.50 (core/dh.h).
//
// Projection. The pixel's light frame is s = c + a·T + b·B (sampling/light_sampling_dh.h). A
// point q projects from p onto the frame's plane at homogeneous frame coordinates
//   H(q) = (a·w, b·w, w),  w = n·(q − p) / n·(c − p)          (n ⟂ the plane, towards it from p)
// which is linear in q − p (a 3×3 matrix per pixel). w is exactly the parameter t of the point
// along segments p → s, so "the part of an edge between p and the light" is the part with
// w ∈ [tMin, tMax] (the gaps at both ends, scene/occlusion_rules_dh.h): clipping there keeps every
// projected point finite and in front of p.
//
// Identity (DESIGN §4.5). Let D(x) = number of triangles crossed by segment p → x. Sweeping x
// from r along the segment r → x, D changes only when p → x passes an edge. For an edge with
// line ℓ = H(q0) × H(q1) and faces with third vertices o_f, face f is entered when x crosses
// to the side of ℓ where H(o_f) lies, so
//   D(x) = D(r) + Σ_edges [r → x crosses the projected, clipped edge] · sign(ℓ·X) · k_e,
//   k_e  = Σ_faces sign(ℓ·H(o_f))            (X = (a, b, 1), homogeneous)
// k_e = 0 for a manifold edge that is not a silhouette seen from p (the faces on opposite
// sides); ±2 for a silhouette of a closed mesh; ±1 for an open edge. (The papers count objects,
// ±1 per silhouette; counting triangles, as the Embree reference does, doubles closed meshes.)
// Signs are computed on homogeneous coordinates without division: det[H(u), H(v), H(w)] =
// det(H)·det[u, v, w], and every product of two such signs is independent of det(H).
#ifndef STSV_WEDGES_DCS_DH_H
#define STSV_WEDGES_DCS_DH_H

#include "core/dh.h"
#include "sampling/sample_region_dh.h"
#include "scene/occlusion_rules_dh.h"

DH_BEGIN

/// Per-pixel projection onto the light frame's plane. std430: 4 × 16 bytes.
struct DcsPixel {
    vec3 row0;  ///< H(q) = (dot(row0, q − p), dot(row1, q − p), dot(row2, q − p))
    float tMin; ///< segments p → s start at this parameter (shadowTMin, scene/occlusion_rules_dh.h)
    vec3 row1;
    float valid; ///< 1 if p lies strictly in front of the light plane, else 0 (no crossings)
    vec3 row2;   ///< n / n·(c − p)
    float pad0;
    vec3 p; ///< world units; the receiver point
    float pad1;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(DcsPixel) == 64);
#endif

/// Builds H for receiver p and the pixel's light frame (c, T, B).
DH_FUNC DcsPixel dcsSetupPixel(vec3 p, vec3 c, vec3 T, vec3 B, float tMin) {
    DcsPixel px;
    px.p = p;
    px.tMin = tMin;
    px.pad0 = 0.0f;
    px.pad1 = 0.0f;
    vec3 cp = c - p;
    vec3 n = cross(T, B);
    if (dot(n, cp) < 0.0f) n = -n;
    float dc = dot(n, cp);
    // Dual basis of (T, B) in the plane: dot(tDual, T) = 1, dot(tDual, B) = 0, dot(tDual, n) = 0.
    vec3 bn = cross(B, n);
    vec3 nt = cross(n, T);
    float dt = dot(T, bn);
    float db = dot(B, nt);
    px.valid = (dc > 0.0f && abs(dt) > 0.0f && abs(db) > 0.0f) ? 1.0f : 0.0f;
    if (px.valid == 0.0f) {
        px.row0 = vec3(0.0f);
        px.row1 = vec3(0.0f);
        px.row2 = vec3(0.0f);
        return px;
    }
    vec3 tDual = bn / dt;
    vec3 bDual = nt / db;
    px.row2 = n / dc;
    // a·w = dot(q − p, tDual) − w·dot(c − p, tDual), and likewise for b.
    px.row0 = tDual - dot(cp, tDual) * px.row2;
    px.row1 = bDual - dot(cp, bDual) * px.row2;
    return px;
}

/// Homogeneous frame coordinates H(q) of world point q.
DH_FUNC vec3 dcsProject(DcsPixel px, vec3 q) {
    vec3 d = q - px.p;
    return vec3(dot(px.row0, d), dot(px.row1, d), dot(px.row2, d));
}

/// Side of a face's third vertex (homogeneous ho) relative to edge line l: +1, −1, 0 in the plane.
DH_FUNC int dcsFaceSide(vec3 l, vec3 ho) {
    float s = dot(l, ho);
    return s > 0.0f ? 1 : (s < 0.0f ? -1 : 0);
}

/// The normal n = (v1 − v0) × (o − v0) of the face with edge v0 → v1 and third vertex o, from the
/// face's own short differences (dcsWorldSide's plane).
DH_FUNC vec3 dcsFaceNormal(vec3 v0, vec3 v1, vec3 o) {
    return cross(v1 - v0, o - v0);
}

/// sign(n·(v0 − p)): dcsWorldSide with its face normal n (dcsFaceNormal) computed once for many p.
DH_FUNC int dcsPlaneSide(vec3 n, vec3 v0, vec3 p) {
    float s = dot(n, v0 - p);
    return s > 0.0f ? 1 : (s < 0.0f ? -1 : 0);
}

/// Side of a face's third vertex o relative to the plane through p and the edge (v0, v1), in world
/// space: sign(det[v0 − p, v1 − p, o − p]). H is linear in q − p, so this is dcsFaceSide's sign
/// times sign(det H), the same for every face of the pixel: the world-space sum is zero exactly
/// when the projected one is. A cheap test of "is the edge a silhouette seen from p" before the
/// per-pixel projection is built.
///
/// Subtracting the first column from the others, det = n·(v0 − p) with n = dcsFaceNormal: the
/// face's plane evaluated at p. Computed so, the rounding scales with the face's size and p's
/// distance, not with the cube of the distance (the triple product of differences from p): the
/// sign is exact unless p lies within dcsSideRounding of the plane, which on a finely tessellated
/// mesh is what lets whole blocks of pixels be proven off every silhouette (edge_cluster_dh.h).
DH_FUNC int dcsWorldSide(vec3 p, vec3 v0, vec3 v1, vec3 o) {
    return dcsPlaneSide(dcsFaceNormal(v0, v1, o), v0, p);
}

/// The world weight of an edge of one or two faces (wedge_fragment_dh.h wedgeWorldWeight, term
/// for term) from their normals n0, n1 (dcsFaceNormal, computed once for many p; a missing second
/// face has normal 0) and scene triangles t0, t1, the receiver's own face left out.
DH_FUNC int dcsTwoFaceWeight(vec3 p, vec3 v0, vec3 n0, uint t0, vec3 n1, uint t1, uint receiver) {
    return (t0 != receiver ? dcsPlaneSide(n0, v0, p) : 0) + (t1 != receiver ? dcsPlaneSide(n1, v0, p) : 0);
}

/// How far from a face's plane (world units) dcsWorldSide's computed sign may differ from the
/// exact one, for a point up to `distance` from v0 and the face's conditioning
/// κ = |v1 − v0|·|o − v0| / |n| (≥ 1; large for a sliver). With unit roundoff u = 2⁻²⁴ and
/// γ₄ = 4u/(1 − 4u), the rounded differences and cross product put n off by at most
/// γ₄·√3·|v1 − v0|·|o − v0|, and the rounded difference and dot product the result by at most
/// γ₄·|n|·|v0 − p| more: γ₄·(√3·κ + 1)·|v0 − p| in distance from the plane. Twice that — a
/// normal rounded elsewhere (a cluster's cone, another compiler's contraction) is off by as much
/// again — is below 10⁻⁶·(κ + 1)·distance.
DH_FUNC float dcsSideRounding(float distance, float conditioning) {
    return 1e-6f * (conditioning + 1.0f) * distance;
}

/// Light-side culling of a manifold edge q0 q1 whose faces have third vertices o0 and o1: false
/// iff the edge is a silhouette for no light point in `sphere` (centre xyz, radius w, world
/// units). With face normals oriented by the edge, n_f = (q1 − q0) × (o_f − q0), the edge is a
/// silhouette seen from x iff n_0·(x − q0) and n_1·(x − q0) have the same sign (both third
/// vertices on one side of the plane through x and the edge); it never is when the whole sphere
/// lies strictly on the positive side of one face's plane and the negative side of the other's.
/// The margin (2·10⁻⁵ of the sphere's radius plus its distance, beyond float rounding) only
/// keeps extra edges, which add k_e = 0: at a crossing the plane through p and the edge holds a
/// light point, where the edge is no silhouette.
DH_FUNC bool dcsPotentialSilhouette(vec3 q0, vec3 q1, vec3 o0, vec3 o1, vec4 sphere) {
    vec3 c = vec3(sphere);
    vec3 n0 = cross(q1 - q0, o0 - q0);
    vec3 n1 = cross(q1 - q0, o1 - q0);
    float len0 = length(n0);
    float len1 = length(n1);
    if (!(len0 > 0.0f) || !(len1 > 0.0f)) return true;
    float s0 = dot(n0, c - q0) / len0;
    float s1 = dot(n1, c - q0) / len1;
    float margin = sphere.w + 2e-5f * (sphere.w + length(c - q0));
    return !((s0 > margin && s1 < -margin) || (s0 < -margin && s1 > margin));
}

/// Clips the projected edge h0 → h1 to w ∈ [tMin, shadowTMax(tMin)] (the part between p and the
/// light, past the segments' gaps). False when nothing is left.
DH_FUNC bool dcsClipEdge(float tMin, DH_INOUT(vec3) h0, DH_INOUT(vec3) h1) {
    float lo = tMin;
    float hi = shadowTMax(tMin);
    if (h0.z < lo && h1.z < lo) return false;
    if (h0.z > hi && h1.z > hi) return false;
    vec3 a = h0;
    vec3 b = h1;
    if (a.z < lo) a = h0 + (h1 - h0) * ((lo - h0.z) / (h1.z - h0.z));
    if (b.z < lo) b = h1 + (h0 - h1) * ((lo - h1.z) / (h0.z - h1.z));
    if (a.z > hi) a = h0 + (h1 - h0) * ((hi - h0.z) / (h1.z - h0.z));
    if (b.z > hi) b = h1 + (h0 - h1) * ((hi - h1.z) / (h0.z - h1.z));
    h0 = a;
    h1 = b;
    return true;
}

/// Signed crossing of segment r → x (r = frame centre (0, 0), x = frame point ab) with the
/// clipped projected edge a → b (homogeneous, w > 0) whose unclipped line is l: 0 if they do
/// not cross, else sign(l·X) (the side x ends on). Ties go half-open (a zero counts as
/// negative) so that two edges meeting at a projected vertex are crossed exactly once.
DH_FUNC int dcsSampleCrossing(vec3 l, vec3 a, vec3 b, vec2 ab) {
    float dX = l.x * ab.x + l.y * ab.y + l.z;
    bool sideR = l.z > 0.0f;
    bool sideX = dX > 0.0f;
    if (sideR == sideX) return 0;
    // a and b on opposite sides of the line through r and x (orient(r, x, ·) = x × ·, w > 0).
    bool sideA = ab.x * a.y - ab.y * a.x > 0.0f;
    bool sideB = ab.x * b.y - ab.y * b.x > 0.0f;
    if (sideA == sideB) return 0;
    return sideX ? 1 : -1;
}

/// Per block of CLUSTER_BLOCK × CLUSTER_BLOCK pixels, the cheaper of two exact ways to count its samples
/// (Lehtinen, Laine & Aila 2008, hierarchical penumbra casting, choose per region of receivers
/// the cheaper exact method): D(r) plus the silhouette crossings, whose cost grows with the edges
/// the block's pixels test, or each sample's segment counted through the layer tree
/// (layer_bvh_dh.h layerCount, the reference's robust crossing test), whose cost is the N rays.
/// True, rays, when the edges the walk kept for the block exceed `edgesPerSample` per sample. (A
/// pixel also casts rays where its segments' gaps meet a triangle: layer_bvh_dh.h layerCountGaps.)
/// The default, 1e9, never casts them: measured on the 2CylinderEngine, armadillo and fandisk
/// meshes, a segment counted through the layer tree (every layer, a binary tree read as texels)
/// costs more than the crossings it saves at every threshold, on the CPU and on lavapipe
/// (docs/methods.md).
DH_CONST float DCS_RAY_EDGES_PER_SAMPLE = 1e9f; ///< the default of the dcs rows' knob ray_edges
DH_FUNC bool dcsBlockCastsRays(uint blockEdges, uint samples, float edgesPerSample) {
    return float(blockEdges) > edgesPerSample * float(samples);
}

/// The frame points (a, b) of [lo, hi] that dcsSampleCrossing can count for the clipped edge
/// a → b on the line l, bounded (sampleRegionOfHalfPlanes): x must end on the far side of l
/// from r, l·X having the other sign than l.z, and lie in the cone from r between the directions
/// of a and b. (The opposite cone, where a and b also lie on opposite sides of the line r x, is
/// on r's side of l: there l·X = l.z·(1 + α + β) for x = −(αA + βB).) When r is within 1e-4 of
/// the edge's line (a and b nearly collinear with r, the cone nearly a half-plane) the whole
/// rectangle is returned. Testing only the samples in the box changes no result.
DH_FUNC bool dcsSampleRegion(vec3 l, vec3 a, vec3 b, vec2 lo, vec2 hi, DH_OUT(vec2) regionLo,
                             DH_OUT(vec2) regionHi) {
    regionLo = lo;
    regionHi = hi;
    float d = a.x * b.y - a.y * b.x;
    if (!(abs(d) > 1e-4f * length(vec2(a.x, a.y)) * length(vec2(b.x, b.y)))) return true;
    vec3 planes[SAMPLE_REGION_MAX_PLANES];
    vec3 mags[SAMPLE_REGION_MAX_PLANES];
    float far = l.z > 0.0f ? -1.0f : 1.0f;
    planes[0] = far * vec3(l.z, l.x, l.y);
    mags[0] = abs(vec3(l.z, l.x, l.y));
    // With d > 0 the cone is orient(a, x) ≥ 0 and orient(x, b) ≥ 0 (orient(u, v) = u.x v.y − u.y v.x).
    float turn = d > 0.0f ? 1.0f : -1.0f;
    planes[1] = turn * vec3(0.0f, -a.y, a.x);
    planes[2] = turn * vec3(0.0f, b.y, -b.x);
    mags[1] = vec3(0.0f, abs(a.y), abs(a.x));
    mags[2] = vec3(0.0f, abs(b.y), abs(b.x));
    for (uint j = 3u; j < SAMPLE_REGION_MAX_PLANES; ++j) {
        planes[j] = vec3(0.0f);
        mags[j] = vec3(0.0f);
    }
    return sampleRegionOfHalfPlanes(planes, mags, 3u, lo, hi, regionLo, regionHi);
}

DH_END

#endif // STSV_WEDGES_DCS_DH_H
