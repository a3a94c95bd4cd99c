// The main() of the hull passes (stsv_hull.comp, wedge_hull.comp), which define before including
// it `bool hullItem(uint item, out uint index, out uint side)`, the cheap test of whether item
// `item` (a side of a triangle or a carrier face: every side 0, then every side 1) may have a
// volume, and `void buildHull(uint index, uint side)`, which builds, clips and appends it.
//
// A workgroup's items are HULL_ITEMS_PER_THREAD per thread (render/vulkan/gpu_hulls.cpp). It queues
// those that pass the cheap test in shared memory, then its threads build and clip the queued
// ones: a SIMD batch then clips as many volumes as it has lanes, where most carrier faces have no
// potential silhouette and a batch of them would clip one or two.
#ifndef STSV_SHADERS_HULL_QUEUE_GLSL
#define STSV_SHADERS_HULL_QUEUE_GLSL

#include "render/shaders/hull_append.glsl"

#ifndef HULL_ITEMS_PER_THREAD
#define HULL_ITEMS_PER_THREAD 8
#endif
shared uint hullQueue[CLIP_SHARED_INVOCATIONS * HULL_ITEMS_PER_THREAD];
shared uint hullQueueCount;

/// The k-th of this invocation's items.
uint hullGroupItem(uint k) {
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    return (group * uint(HULL_ITEMS_PER_THREAD) + k) * uint(CLIP_SHARED_INVOCATIONS) + gl_LocalInvocationIndex;
}

void main() {
    if (gl_WorkGroupID.x + gl_WorkGroupID.y + gl_LocalInvocationIndex == 0u) draw.instanceCount = 1u;
    if (gl_LocalInvocationIndex == 0u) hullQueueCount = 0u;
    barrier();
    for (uint k = 0u; k < uint(HULL_ITEMS_PER_THREAD); ++k) {
        uint index;
        uint side;
        if (hullItem(hullGroupItem(k), index, side)) hullQueue[atomicAdd(hullQueueCount, 1u)] = hullGroupItem(k);
    }
    barrier();
    uint queued = hullQueueCount;
    for (uint q = gl_LocalInvocationIndex; q < queued; q += uint(CLIP_SHARED_INVOCATIONS)) {
        uint index;
        uint side;
        hullItem(hullQueue[q], index, side);
        buildHull(index, side);
    }
}

#endif
