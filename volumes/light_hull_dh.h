// Which balls the segments from a region of receiver points to the light can meet: the test the
// CPU passes cull their hierarchies with (render/cpu: the STSV pass's tree of triangles, the
// wedges' tree of edge clusters), and, for one receiver point, the cone both backends test a
// pixel's leaves and wedge edges with (wedges/cpu/cpu_wedges.cpp, wedges/shaders). Both are
// conservative: a ball they reject holds nothing that occludes a light sample of the region, so
// culling with them changes no result. Compiles as C++ and GLSL 4.50 (core/dh.h).
#ifndef STSV_VOLUMES_LIGHT_HULL_DH_H
#define STSV_VOLUMES_LIGHT_HULL_DH_H

#include "core/dh.h"

DH_BEGIN

/// The segments from a ball of receiver points `region` to the light's ball `light` (both
/// (centre, radius), world units): they fill the convex hull of the two balls, which is the union
/// of the balls (1 − t)·region + t·light, t ∈ [0, 1]. What ballMeetsLightHull needs of it,
/// computed once per region.
struct LightHull {
    vec3 origin;  ///< the region's centre
    float radius; ///< the region's radius
    vec3 axis;    ///< light centre − origin
    float along;  ///< |axis|; 0 when one ball holds the other (then origin, radius are the larger ball)
    float slope;  ///< light radius − region radius
    float lean;   ///< k / sqrt(1 − k²), k = slope / along: where the nearest ball of the family lies
    float margin; ///< the region's part of the test's margin (ballMeetsLightHull)
    float pad;
};

DH_FUNC LightHull lightHull(vec4 region, vec4 light) {
    LightHull h;
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

/// False when the ball `ball` (grown by the margin) meets no segment of the hull: then nothing
/// inside it occludes a light sample of any point of the region — no triangle (STSV), no edge
/// (an edge adds to a receiver point p only where it crosses a segment from p to a light sample,
/// wedges/dcs_dh.h, or, for PW, where its projection from p reaches the light). The ball meets the hull iff
/// it meets a ball of the family; the distance from its centre to the ball at t minus that ball's radius is
/// convex in t, so its minimum over [0, 1] is at the clamped stationary point.
///
/// The margin, 1e-4 of the magnitudes involved, is far beyond the rounding of the test, and it
/// grows with both radii so that the test is monotone: a ball inside a ball that fails, or a
/// point of a region that fails (its hull lies inside the region's), fails too — a region or a
/// node rejected on the way down holds nothing a smaller one would keep.
DH_FUNC bool ballMeetsLightHull(vec4 ball, LightHull h) {
    vec3 d = vec3(ball) - h.origin;
    float margin = h.margin + 1e-4f * (abs(d.x) + abs(d.y) + abs(d.z) + 2.0f * ball.w);
    if (h.along == 0.0f) return length(d) <= h.radius + ball.w + margin;
    float a = dot(d, h.axis) / h.along;
    float side = sqrt(max(dot(d, d) - a * a, 0.0f));
    float t = clamp((a + h.lean * side) / h.along, 0.0f, 1.0f);
    return length(d - h.axis * t) - (h.radius + t * h.slope) <= ball.w + margin;
}

/// The segments from one receiver point to the light's ball, bounded by the cone from the point
/// that touches the ball: what a pixel's tests need of them (ballMeetsLightCone), computed once
/// per point. The cone holds the hull of the point and the ball (LightHull with region radius 0),
/// and is cheaper to test against: no square root or division per ball.
struct LightCone {
    vec3 apex;    ///< the receiver point
    float margin; ///< the point's part of the test's margin, as lightHull's
    vec3 axis;    ///< unit vector from the apex to the light's centre
    float sine;   ///< of the half-angle: light radius / distance; 1 when the point lies in the light's ball
};

DH_FUNC LightCone lightCone(vec3 p, vec4 light) {
    LightCone c;
    c.apex = p;
    vec3 axis = vec3(light) - p;
    float along = length(axis);
    c.margin = 1e-4f * (along + light.w + abs(p.x) + abs(p.y) + abs(p.z));
    c.axis = vec3(0.0f);
    c.sine = 1.0f;
    if (along > light.w) {
        c.axis = axis / along;
        c.sine = light.w / along;
    }
    return c;
}

/// False when the ball `ball` (grown by the margin) misses the cone of `c`: then it misses the
/// segments from the point to the light too, and holds nothing that occludes a light sample of
/// the point (ballMeetsLightHull, of which this is the looser, cheaper form for one point; the
/// margin is the same and no smaller than it there). In the plane of the axis and the ball's
/// centre, at axial distance a and lateral distance ℓ from the apex, the distance to the cone is
/// ℓ·cos θ − a·sin θ where the nearest point lies on its side (a·cos θ + ℓ·sin θ ≥ 0), else the
/// distance to the apex; both are compared squared. ℓ² is the squared length of the lateral
/// vector itself, not |d|² − a², whose cancellation near the axis would exceed the margin.
/// A point inside the light's ball has the whole space as its cone.
DH_FUNC bool ballMeetsLightCone(vec4 ball, LightCone c) {
    if (c.sine >= 1.0f) return true;
    vec3 d = vec3(ball) - c.apex;
    float reach = ball.w + c.margin + 1e-4f * (abs(d.x) + abs(d.y) + abs(d.z) + 2.0f * ball.w);
    float a = dot(d, c.axis);
    vec3 lateral = d - c.axis * a;
    float l2 = dot(lateral, lateral);
    float sine2 = c.sine * c.sine;
    float cosine2 = 1.0f - sine2;
    if (a < 0.0f && a * a * cosine2 >= l2 * sine2) return dot(d, d) <= reach * reach;
    float x = a * c.sine + reach;
    return x >= 0.0f && l2 * cosine2 <= x * x;
}

/// The ball around the points [lo, hi] (the box's circumscribed ball), grown by 1e-5 of its radius
/// for rounding: the region ball of a box of receiver points, or a cluster's ball.
DH_FUNC vec4 boxBall(vec3 lo, vec3 hi) {
    return vec4(0.5f * (lo + hi), 0.5f * length(hi - lo) * (1.0f + 1e-5f));
}

/// The smallest ball around the balls a and b (grown by 1e-5 of its radius where it is neither):
/// a tree node's ball around its children's.
DH_FUNC vec4 ballAround(vec4 a, vec4 b) {
    float distance = length(vec3(b) - vec3(a));
    if (distance + b.w <= a.w) return a;
    if (distance + a.w <= b.w) return b;
    float radius = 0.5f * (distance + a.w + b.w);
    return vec4(vec3(a) + (vec3(b) - vec3(a)) * ((radius - a.w) / distance), radius * (1.0f + 1e-5f));
}

/// The ball of edge v0 v1 (its midpoint, half its length): what a cluster's ball holds of each
/// of its edges, and what one edge tests against the hull of its receiver point.
DH_FUNC vec4 edgeBall(vec3 v0, vec3 v1) {
    return vec4(0.5f * (v0 + v1), 0.5f * length(v1 - v0));
}

DH_END

#endif // STSV_VOLUMES_LIGHT_HULL_DH_H
