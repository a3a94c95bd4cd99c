// Conservative tests of a cluster of potential silhouette edges (wedges/edge_clusters.h) against
// a region of receiver points: the CPU mirror culls its clusters per screen tile, block and
// pixel with them (render/cpu/cpu_wedges.cpp). Both are conservative in the sense that a cluster
// they reject holds no edge that adds anything to any receiver point of the region, so culling
// with them changes no light sample. Compiles as C++ and GLSL 4.50 (core/dh.h).
//
// A cluster is a ball around its edges, (centre, radius), and a cone of the normals that decide
// whether each edge is a silhouette (unit axis, cosine of the half-angle; w < 0: no cone). A region is a ball
// around its receiver points; the light, the ball of sampling/light_bounds.h.
#ifndef STSV_WEDGES_EDGE_CLUSTER_DH_H
#define STSV_WEDGES_EDGE_CLUSTER_DH_H

#include "core/dh.h"

DH_BEGIN

/// The segments from a ball of receiver points `region` to the light's ball `light` (both
/// (centre, radius), world units): they fill the convex hull of the two balls, which is the union
/// of the balls (1 − t)·region + t·light, t ∈ [0, 1]. What clusterMeetsLightHull needs of it,
/// computed once per region.
struct ClusterLightHull {
    vec3 origin;  ///< the region's centre
    float radius; ///< the region's radius
    vec3 axis;    ///< light centre − origin
    float along;  ///< |axis|; 0 when one ball holds the other (then origin, radius are the larger ball)
    float slope;  ///< light radius − region radius
    float lean;   ///< k / sqrt(1 − k²), k = slope / along: where the nearest ball of the family lies
    float margin; ///< the region's part of the test's margin (clusterMeetsLightHull)
    float pad;
};

DH_FUNC ClusterLightHull clusterLightHull(vec4 region, vec4 light) {
    ClusterLightHull h;
    h.origin = vec3(region);
    h.radius = region.w;
    h.axis = vec3(light) - vec3(region);
    h.along = length(h.axis);
    h.slope = light.w - region.w;
    h.margin = 1e-4f * (h.along + 8.0f * region.w + light.w + abs(region.x) + abs(region.y) + abs(region.z));
    h.lean = 0.0f;
    h.pad = 0.0f;
    if (!(h.along > abs(h.slope))) {
        // One ball inside the other: the hull is the larger one.
        if (light.w > region.w) {
            h.origin = vec3(light);
            h.radius = light.w;
        }
        h.along = 0.0f;
        return h;
    }
    float k = h.slope / h.along;
    h.lean = k / sqrt(1.0f - k * k);
    return h;
}

/// False when the ball `cluster` (grown by the margin) meets no segment of the hull: then no edge
/// inside it adds to any point of the region, for an edge adds to a receiver point p only where
/// it crosses a segment from p to a light sample (wedges/dcs_dh.h), or, for PW, where its
/// projection from p reaches the light. The ball meets the hull iff it meets a ball of the
/// family; the distance from its centre to the ball at t minus that ball's radius is convex in
/// t, so its minimum over [0, 1] is at the clamped stationary point.
///
/// The margin, 1e-4 of the magnitudes involved, is far beyond the rounding of the test, and it
/// grows with both radii so that the test is monotone: a ball inside a ball that fails, or a
/// point of a region that fails (its hull lies inside the region's), fails too — a region or a
/// node rejected on the way down holds nothing a smaller one would keep.
DH_FUNC bool clusterMeetsLightHull(vec4 cluster, ClusterLightHull h) {
    vec3 d = vec3(cluster) - h.origin;
    float margin = h.margin + 1e-4f * (abs(d.x) + abs(d.y) + abs(d.z) + 2.0f * cluster.w);
    if (h.along == 0.0f) return length(d) <= h.radius + cluster.w + margin;
    float a = dot(d, h.axis) / h.along;
    float side = sqrt(max(dot(d, d) - a * a, 0.0f));
    float t = clamp((a + h.lean * side) / h.along, 0.0f, 1.0f);
    return length(d - h.axis * t) - (h.radius + t * h.slope) <= cluster.w + margin;
}

/// The ball of edge v0 v1 (its midpoint, half its length): what a cluster's ball holds of each
/// of its edges, and what one edge tests against the hull of its receiver point.
DH_FUNC vec4 edgeBall(vec3 v0, vec3 v1) {
    return vec4(0.5f * (v0 + v1), 0.5f * length(v1 - v0));
}

/// False when no edge of the cluster can be a silhouette from any point of the ball `region`:
/// every normal of the cone `cone` (unit axis, cos θ of its half-angle θ; w < 0: no cone) faces
/// the whole region, or turns away from all of it. With d = region centre − cluster centre, φ the
/// angle between the axis and d and reach = both radii: for a normal n within θ of the axis and
/// a plane point q in the cluster's ball, n·(x − q) ≥ |d|·cos(φ + θ) − reach for every x in the
/// region, and n·(x − q) ≤ |d|·cos(max(φ − θ, 0)) + reach. The margin is 1e-4 of the distances
/// involved plus `rounding`, the caller's allowance for the rounding of its per-point test
/// (distance units).
DH_FUNC bool clusterMayHaveSilhouette(vec4 cluster, vec4 cone, vec4 region, float rounding) {
    if (cone.w < 0.0f) return true;
    vec3 t = vec3(region);
    vec3 d = t - vec3(cluster);
    float distance = length(d);
    float reach = region.w + cluster.w;
    if (!(distance > reach)) return true;
    float cosPhi = clamp(dot(vec3(cone), d) / distance, -1.0f, 1.0f);
    float sinPhi = sqrt(max(1.0f - cosPhi * cosPhi, 0.0f));
    float sinTheta = sqrt(max(1.0f - cone.w * cone.w, 0.0f));
    float margin = 1e-4f * (distance + reach + abs(t.x) + abs(t.y) + abs(t.z)) + rounding;
    // φ + θ < π/2 exactly when cos(φ + θ) > 0, and φ − θ > π/2 when cos(φ − θ) < 0 (φ ∈ [0, π],
    // θ < π/2).
    float cosSum = cosPhi * cone.w - sinPhi * sinTheta;
    float cosDifference = cosPhi * cone.w + sinPhi * sinTheta;
    if (cosSum > 0.0f && distance * cosSum - reach > margin) return false;
    if (cosDifference < 0.0f && distance * cosDifference + reach < -margin) return false;
    return true;
}

DH_END

#endif // STSV_WEDGES_EDGE_CLUSTER_DH_H
