#version 450
// STSV through the tree of the S-triangles' balls (DESIGN §4.5; the CPU mirror's walk,
// volumes/cpu/cpu_stsv.cpp, with the same tests), over the lists of render/shaders/cluster_walk.glsl:
//   CLUSTER_STAGE 0, 1, 2: the blocks, the indirect dispatches, the walk of a level; a leaf's
//     triangle whose ball meets the segments from the block's points to the light is kept as a
//     (block, triangle) pair;
//   3 (volumes): an invocation a kept pair: the triangle's volumes (a side each: the records
//     stsv_hull.comp built with STSV_HULL_RECORDS_ONLY) that do not leave the block's box outside
//     one of their planes become (block, record) candidates (a list of their own, so that the
//     box tests run in full SIMD batches, not in the lanes of the walk that kept the triangle);
//   4 (pixels): an invocation a candidate, for the block's 16 pixels: a visible point inside the
//     volume and its triangle's light planes, on another triangle (the self-shadowing rule), is
//     listed for stsv_samples.comp — the test of stsv.frag, for the pixels whose point the
//     volume holds, without a hull or a fragment.
// The culling tests are conservative, so the bits are the hull draw's; the pairs listed are the
// draw's less some whose triangle meets no segment from the block's points to the light (a
// volume is larger than what its triangle shadows), which set no bit.
#extension GL_GOOGLE_include_directive : require
#include "volumes/shaders/stsv_samples.glsl"
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };
#define CLUSTER_GROUP_SIZE GPU_STSV_CLUSTER_GROUP
#include "render/shaders/cluster_walk.glsl"

layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_STSV_ITEM_RECORDS) readonly buffer ItemRecords { uint itemRecords[]; };

/// The planes of record `record`'s volume and its triangle's light planes.
void recordPlanes(uint record, uvec4 ids, out StsvVolume vol, out StsvLightPlanes lp) {
    vol.planeCount = (ids.w >> 8u) & 255u;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = stsvRecordVec4(record, GPU_STSV_RECORD_PLANES + i);
    lp.count = ids.w >> 16u;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = stsvRecordVec4(record, GPU_STSV_RECORD_LIGHT_PLANES + i);
}

/// A leaf's items are triangles (data.x) with their balls: each kept as (block, triangle) for
/// stage 3 when its ball meets the segments from the block's points to the light. (Its volumes'
/// box tests run there, over a list of the survivors: in this loop most lanes would idle through
/// them.)
void clusterKeep(uint block, uint leaf, uvec4 range, vec4 region, LightHull hull, inout uint tests, inout uint rejected) {
    for (uint item = range.x; item < range.x + range.y; ++item) {
        ++tests;
        if (tableMayAdd(clusterItems, item, region, hull))
            groupAppend(GROUP_KEPT, uvec2(block, clusterData(clusterItems, item).x));
        else
            ++rejected;
    }
}

void main() {
#if CLUSTER_STAGE == 0
    clusterBlocksStage();
#elif CLUSTER_STAGE == 1
    clusterArgsStage();
#elif CLUSTER_STAGE == 2
    clusterWalkStage();
#elif CLUSTER_STAGE == 3
    // The kept triangles' volumes (a side each), unless the block's box lies outside one of their
    // planes: (block, record) candidates.
    uint entries = listEntries(GPU_CLUSTER_KEPT);
    uint triangleCount = uint(triangles.length());
    groupBegin();
    CLUSTER_FOR_EACH_STEP(first, entries) {
        uint e = first + gl_LocalInvocationID.x;
        if (e < entries) {
            uvec2 pair = pairs[listBase(GPU_CLUSTER_KEPT) + e];
            vec3 lo = blockLo(pair.x);
            vec3 hi = blockHi(pair.x);
            for (uint side = 0u; side < 2u; ++side) {
                uint entry = itemRecords[side * triangleCount + pair.y];
                if (entry == 0u) continue;
                uint record = entry - 1u;
                StsvVolume vol;
                StsvLightPlanes lp;
                recordPlanes(record, stsvRecordTexel(record, GPU_STSV_RECORD_IDS), vol, lp);
                if (!stsvVolumeMissesBox(vol, lo, hi) && !stsvLightPlanesMissBox(lp, lo, hi))
                    groupAppend(GROUP_CANDIDATES, uvec2(pair.x, record));
            }
        }
        groupFlush();
    }
#else
    uint entries = listEntries(GPU_CLUSTER_CANDIDATES);
    uint tested = 0u;
    groupBegin();
    CLUSTER_FOR_EACH_STEP(first, entries) {
        uint e = first + gl_LocalInvocationID.x;
        if (e < entries) {
            uvec2 pair = pairs[listBase(GPU_CLUSTER_CANDIDATES) + e];
            // The volume once for the block's 16 pixels.
            uvec4 ids = stsvRecordTexel(pair.y, GPU_STSV_RECORD_IDS);
            StsvVolume vol;
            StsvLightPlanes lp;
            recordPlanes(pair.y, ids, vol, lp);
            uint inside = 0u;
            for (uint lane = 0u; lane < 16u; ++lane) {
                ivec2 pixel = blockPixel(pair.x, lane);
                if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
                uint receiver = imageLoad(gTriangle, pixel).x;
                if (receiver == GPU_NO_TRIANGLE) continue;
                vec3 p = vec3(imageLoad(gPosition, pixel));
                ++tested;
                // stsv.frag's test.
                if (stsvPointInVolume(vol, p) && stsvPointInLightPlanes(lp, p) && receiver != ids.z)
                    inside |= 1u << lane;
            }
            // Listed for stsv_samples.comp; past the list's end an entry is dropped, the host
            // sees the count and renders again.
            groupAppendPixels(GROUP_DEFERRED, pair.x, inside, pair.y);
        }
        groupFlush();
    }
    tested = subgroupAdd(tested);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, tested);
#endif
}
