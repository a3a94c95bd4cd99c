// Ground-truth light-sample visibility by Embree shadow rays (DESIGN §4.7).
#pragma once

#include "reference/embree_scene.h"
#include "sampling/ls_buffer.h"
#include "sampling/pattern.h"

namespace stsv {

/// Fills `out` for light `light`: for every covered pixel and sample, a shadow segment from the
/// visible point to the sample (self-shadowing rule: the visible triangle never blocks). A
/// bitmask buffer gets occlusion bits; a counter buffer gets the number of blocking layers
/// (every opaque hit along the segment counts once). Uses every core; shows progress.
void traceReferenceSamples(const EmbreeScene& scene, const GBuffer& gbuffer, const Light& light,
                           const SamplePlan& plan, float farDistance, LightSampleBuffer& out);

} // namespace stsv
