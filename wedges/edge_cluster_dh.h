// The silhouette test of a cluster of potential silhouette edges (wedges/edge_clusters.h) against
// a region of receiver points, beside the light-hull test of its ball (volumes/light_hull_dh.h):
// the CPU mirror culls its clusters per screen tile, block and pixel with them
// (wedges/cpu/cpu_wedges.cpp). A cluster either rejects holds no edge that adds anything to any
// receiver point of the region, so culling with them changes no light sample. Compiles as C++
// and GLSL 4.50 (core/dh.h).
//
// A cluster is a ball around its edges, (centre, radius), and a cone of the normals that decide
// whether each edge is a silhouette (unit axis, cosine of the half-angle; w < 0: no cone). A region is a ball
// around its receiver points; the light, the ball of sampling/light_bounds.h.
#ifndef STSV_WEDGES_EDGE_CLUSTER_DH_H
#define STSV_WEDGES_EDGE_CLUSTER_DH_H

#include "core/dh.h"
#include "volumes/light_hull_dh.h"
#include "wedges/dcs_dh.h"

DH_BEGIN

/// Pixels per side of the square blocks whose visible points the cluster walks bound together:
/// the CPU passes' blocks within a tile (render/cpu/cpu_binning.h) and the Vulkan walk's
/// (render/shaders/cluster_walk.glsl), 4 × 4 so a block's pixels fit a 16-bit lane mask.
DH_CONST uint CLUSTER_BLOCK = 4u;

/// Blocks along an image side of `pixels` pixels (the last one clipped).
DH_FUNC uint clusterBlocksAlong(uint pixels) {
    return (pixels + CLUSTER_BLOCK - 1u) / CLUSTER_BLOCK;
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

/// A cluster (ball, cone, and the conditioning of its faces, wedges/edge_clusters.h
/// EdgeClusterNode) against a region of receiver points (its ball, and `hull`, the lightHull of
/// it): false when no edge of the cluster can add to any point of the region — no segment from it
/// to the light meets the ball, or no edge can be a silhouette from it. The cone test's margin
/// grows by the rounding of the per-point orientation test (dcs_dh.h dcsSideRounding) for points
/// as far from an edge's first vertex as the region reaches.
DH_FUNC bool clusterMayAdd(vec4 ball, vec4 cone, float conditioning, vec4 region, LightHull hull) {
    if (!ballMeetsLightHull(ball, hull)) return false;
    if (cone.w < 0.0f) return true;
    float reach = length(vec3(region) - vec3(ball)) + region.w + ball.w;
    return clusterMayHaveSilhouette(ball, cone, region, dcsSideRounding(reach, conditioning));
}

DH_END

#endif // STSV_WEDGES_EDGE_CLUSTER_DH_H
