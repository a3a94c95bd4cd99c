#version 450
// STSV through the tree of the S-triangles' balls (DESIGN §4.5; the CPU mirror's walk,
// render/cpu/cpu_stsv.cpp, with the same tests), over the lists of common/cluster_walk.glsl:
//   CLUSTER_STAGE 0, 1, 2: the blocks, the indirect dispatches, the walk of a level; a leaf's
//     triangle whose ball meets the segments from the block's points to the light keeps, as
//     (block, record) pairs, its volumes (the records stsv_hull.comp built with
//     STSV_HULL_RECORDS_ONLY) that do not leave the block's box outside one of their planes;
//   3 (pixels): an invocation a kept pair, for the block's 16 pixels: a visible point inside the
//     volume and its triangle's light planes, on another triangle (the self-shadowing rule), is
//     listed for stsv_samples.comp — the test of stsv.frag, for the pixels whose point the
//     volume holds, without a hull or a fragment.
// The culling tests are conservative, so the bits are the hull draw's; the pairs listed are the
// draw's less some whose triangle meets no segment from the block's points to the light (a
// volume is larger than what its triangle shadows), which set no bit.
#extension GL_GOOGLE_include_directive : require
#include "stsv/stsv_samples.glsl"
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };
#include "common/cluster_walk.glsl"

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_STSV_ITEM_RECORDS) readonly buffer ItemRecords { uint itemRecords[]; };

/// The planes of record `record`'s volume and its triangle's light planes.
void recordPlanes(uint record, uvec4 ids, out StsvVolume vol, out StsvLightPlanes lp) {
    vol.planeCount = (ids.w >> 8u) & 255u;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = stsvRecordVec4(record, GPU_STSV_RECORD_PLANES + i);
    lp.count = ids.w >> 16u;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = stsvRecordVec4(record, GPU_STSV_RECORD_LIGHT_PLANES + i);
}

/// A leaf's item is a triangle (data.x) with its ball: its volumes (a side each), unless the
/// block's box lies outside one of their planes.
void clusterKeep(uint block, uint item, vec4 region, LightHull hull, inout uint tests, inout uint rejected) {
    ++tests;
    if (!tableMayAdd(clusterItems, item, region, hull)) {
        ++rejected;
        return;
    }
    uint tri = clusterData(clusterItems, item).x;
    uint triangleCount = uint(triangles.length());
    for (uint side = 0u; side < 2u; ++side) {
        uint entry = itemRecords[side * triangleCount + tri];
        if (entry == 0u) continue;
        uint record = entry - 1u;
        uvec4 ids = stsvRecordTexel(record, GPU_STSV_RECORD_IDS);
        StsvVolume vol;
        StsvLightPlanes lp;
        recordPlanes(record, ids, vol, lp);
        if (stsvVolumeMissesBox(vol, blockLo(block), blockHi(block)) ||
            stsvLightPlanesMissBox(lp, blockLo(block), blockHi(block)))
            continue;
        appendPair(GPU_CLUSTER_KEPT, uvec2(block, record));
    }
}

void main() {
#if CLUSTER_STAGE == 0
    clusterBlocksStage();
#elif CLUSTER_STAGE == 1
    clusterArgsStage();
#elif CLUSTER_STAGE == 2
    clusterWalkStage();
#else
    uint entries = listEntries(GPU_CLUSTER_KEPT);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    uint tested = 0u;
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 pair = pairs[listBase(GPU_CLUSTER_KEPT) + e];
        // The volume once for the block's 16 pixels.
        uvec4 ids = stsvRecordTexel(pair.y, GPU_STSV_RECORD_IDS);
        StsvVolume vol;
        StsvLightPlanes lp;
        recordPlanes(pair.y, ids, vol, lp);
        for (uint lane = 0u; lane < 16u; ++lane) {
            ivec2 pixel = blockPixel(pair.x, lane);
            if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
            uint receiver = imageLoad(gTriangle, pixel).x;
            if (receiver == GPU_NO_TRIANGLE) continue;
            vec3 p = vec3(imageLoad(gPosition, pixel));
            ++tested;
            // stsv.frag's test; past the list's end the entry is dropped, the host sees the
            // count and renders again.
            if (stsvPointInVolume(vol, p) && stsvPointInLightPlanes(lp, p) && receiver != ids.z)
                deferredAppend(lsPixelIndex(uvec2(pixel), frame.width), pair.y);
        }
    }
    tested = subgroupAdd(tested);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, tested);
#endif
}
