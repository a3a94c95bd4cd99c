// Sample regions in the light frame (DESIGN §4.3): the box of the frame points (a, b) of a
// rectangle that satisfy a few linear tests, so that a per-pixel loop tests only the samples in
// it. The STSV fragment (volumes/stsv_dh.h stsvSampleRegion) and the DCS edge term
// (wedges/dcs_dh.h dcsSampleRegion) each express their per-sample test as half-planes
// f(a, b) = c.x + c.y·a + c.z·b ≥ 0 and clip with sampleRegionOfHalfPlanes. Compiles as C++ and
// GLSL (core/dh.h).
#ifndef STSV_SAMPLING_SAMPLE_REGION_DH_H
#define STSV_SAMPLING_SAMPLE_REGION_DH_H

#include "core/dh.h"

DH_BEGIN

DH_CONST uint SAMPLE_REGION_MAX_PLANES = 5u;

/// The box of the points of [lo, hi] inside the first `count` half-planes c_j.x + c_j.y·a +
/// c_j.z·b ≥ 0, clipped to [lo, hi]. Every half-plane is widened by 1e-5 of the magnitudes of
/// its terms (mags_j: |terms| before they cancel, weighted like c_j), and the box by 1e-5 of the
/// rectangle, far beyond the float rounding of a per-sample test that evaluates the same terms
/// and of the clipping, so a point outside the box fails one of the tests. False when no point
/// of the rectangle passes them all.
DH_FUNC bool sampleRegionOfHalfPlanes(vec3 planes[SAMPLE_REGION_MAX_PLANES],
                                      vec3 mags[SAMPLE_REGION_MAX_PLANES], uint count, vec2 lo, vec2 hi,
                                      DH_OUT(vec2) regionLo, DH_OUT(vec2) regionHi) {
    regionLo = lo;
    regionHi = hi;
    vec2 reach = max(abs(lo), abs(hi));
    // The rectangle as a polygon (counter-clockwise), clipped by each half-plane in turn: each
    // clip adds at most one vertex.
    vec2 poly[9];
    poly[0] = lo;
    poly[1] = vec2(hi.x, lo.y);
    poly[2] = hi;
    poly[3] = vec2(lo.x, hi.y);
    uint corners = 4u;
    for (uint j = 0u; j < count && j < SAMPLE_REGION_MAX_PLANES; ++j) {
        vec3 c = planes[j];
        float slack = 1e-5f * (mags[j].x + mags[j].y * reach.x + mags[j].z * reach.y);
        vec2 clipped[9];
        uint kept = 0u;
        for (uint i = 0u; i < corners; ++i) {
            vec2 a = poly[i];
            vec2 b = poly[(i + 1u) % corners];
            float fa = c.x + c.y * a.x + c.z * a.y + slack;
            float fb = c.x + c.y * b.x + c.z * b.y + slack;
            if (fa >= 0.0f) clipped[kept++] = a;
            if ((fa >= 0.0f) != (fb >= 0.0f)) clipped[kept++] = a + (fa / (fa - fb)) * (b - a);
        }
        corners = kept;
        if (corners == 0u) return false;
        for (uint i = 0u; i < corners; ++i) poly[i] = clipped[i];
    }
    vec2 boxLo = poly[0];
    vec2 boxHi = poly[0];
    for (uint i = 1u; i < corners; ++i) {
        boxLo = min(boxLo, poly[i]);
        boxHi = max(boxHi, poly[i]);
    }
    vec2 pad = 1e-5f * (hi - lo);
    regionLo = max(boxLo - pad, lo);
    regionHi = min(boxHi + pad, hi);
    return true;
}

DH_END

#endif // STSV_SAMPLING_SAMPLE_REGION_DH_H
