// The object-based combinations of Algorithm 2 (STSV paper) composed by hand for the tests that
// call the CPU families directly, with their inputs in hand: the renderer composes the same rows
// through its techniques (render/cpu/cpu_techniques.cpp).
#pragma once

#include "volumes/cpu/cpu_stsv.h"
#include "wedges/cpu/cpu_wedges.h"

namespace stsv {

/// DCS+STSV (Algorithm 2, lines 8–9): DCS for the opaque triangles, then the STSV increments of
/// the perforated ones added to the same counters.
inline WedgeCpuStats dcsStsvCpuSamples(const WedgeOccluders& occ, const GBuffer& gbuffer, const Light& light,
                                       const SamplePlan& plan, float farDistance, LightSampleBuffer& counters,
                                       StsvCpuStats* stsvStats = nullptr,
                                       float rayEdgesPerSample = DCS_RAY_EDGES_PER_SAMPLE) {
    const WedgeCpuStats stats =
        dcsCpuSamples(occ, gbuffer, light, plan, farDistance, counters, rayEdgesPerSample);
    const StsvCpuStats s = stsvCpuSamples(occ.scene(), gbuffer, light, plan, farDistance, counters,
                                          stsvFilter(occ.scene(), StsvTriangles::Perforated));
    if (stsvStats) *stsvStats = s;
    return stats;
}

/// PW+STSV (Algorithm 2, lines 12–14): v = clamp(v_pw − occluded fraction of the STSV bitmask of
/// the perforated triangles, 0, 1). `stsvBits` (BufferKind::Bitmask, cleared by the caller)
/// receives the STSV bits.
inline WedgeCpuStats pwStsvCpuVisibility(const WedgeOccluders& occ, const GBuffer& gbuffer,
                                         const Light& light, const SamplePlan& plan, float farDistance,
                                         ImageF& visibility, LightSampleBuffer& stsvBits,
                                         StsvCpuStats* stsvStats = nullptr) {
    const WedgeCpuStats stats = pwCpuVisibility(occ, gbuffer, light, farDistance, visibility);
    const StsvCpuStats s = stsvCpuSamples(occ.scene(), gbuffer, light, plan, farDistance, stsvBits,
                                          stsvFilter(occ.scene(), StsvTriangles::Perforated));
    if (stsvStats) *stsvStats = s;
    pwFoldStsv(gbuffer, stsvBits, visibility);
    return stats;
}

} // namespace stsv
