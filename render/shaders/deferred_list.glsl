// The list of deferred fragments (render/vulkan/gpu_deferred.h): a volume draw or a cluster walk
// appends (pixel index, item) for each fragment whose per-pixel set-up and sample loop a compute
// pass runs instead (DCS's walk with the pair's edge term: wedge_term.glsl wedgeTermStore),
// one thread a fragment (stsv_samples.comp, wedge_samples.comp). On lavapipe a fragment batch
// runs every instruction of the shader for its lanes, masked, and its loops as long as its
// slowest lane; the compute pass's batches hold only fragments that need the work.
#ifndef STSV_SHADERS_DEFERRED_LIST_GLSL
#define STSV_SHADERS_DEFERRED_LIST_GLSL

#include "render/shaders/frame_bindings.glsl"
#include "render/vulkan/gpu_volumes_dh.h"

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DEFERRED_COUNT) buffer DeferredCount { uvec4 deferredCount; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DEFERRED) buffer Deferred { uvec2 deferred[]; };
// Where the lister also computes what the sample loop needs: GPU_DEFERRED_TERM_TEXELS a fragment.
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DEFERRED_TERMS) buffer DeferredTerms { uvec4 deferredTerms[]; };

/// Appends (pixelIndex, item) at `slot`; false when the list is full (the count still grows past
/// its end, so the host knows how much room the frame needed).
bool deferredAppendAt(uint pixelIndex, uint item, out uint slot) {
    slot = atomicAdd(deferredCount.x, 1u);
    if (slot >= uint(deferred.length())) return false;
    deferred[slot] = uvec2(pixelIndex, item);
    return true;
}

/// Appends (pixelIndex, item); false when the list is full.
bool deferredAppend(uint pixelIndex, uint item) {
    uint slot;
    return deferredAppendAt(pixelIndex, item, slot);
}

/// The entries a compute pass reads: those appended, at most the list's length.
uint deferredEntries() {
    return min(deferredCount.x, uint(deferred.length()));
}

#endif
