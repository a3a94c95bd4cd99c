#version 450
// DCS's blocks that cast rays (wedges/dcs_dh.h dcsBlockCastsRays; the CPU mirror's dcsCpuSamples),
// after the cluster walk (dcs_clusters.comp) has added up each block's kept edges:
//   DCS_RAYS_STAGE 0: an invocation a block of the frame; a block whose edges exceed
//     DCS_RAY_EDGES per sample, or with a pixel whose segments' gaps meet a triangle
//     (dcs_center.comp), is listed, and the listing sets the indirect dispatch of stage 1;
//   1: a workgroup a listed block and GPU_DCS_RAY_SAMPLES_PER_GROUP of its samples, an invocation
//     one (pixel, sample): the segment from the visible point p to the sample counted through the
//     tree of wedges/layer_bvh_dh.h (layerCount, as the CPU mirror and the reference count it),
//     one traversal an invocation (lavapipe's loop budget), for every pixel of a block of many
//     edges and for the pixels of the others whose gaps meet a triangle. The walk listed no pair
//     of those pixels, so their counters hold 0: the count minus D(r) is added, and
//     wedge_fold.comp adds D(r) back.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef DCS_RAY_EDGES
#define DCS_RAY_EDGES DCS_RAY_EDGES_PER_SAMPLE
#endif
#include "wedges/shaders/wedge_bindings.glsl"
#include "wedges/edge_cluster_dh.h"

layout(local_size_x = 16 * GPU_DCS_RAY_SAMPLES_PER_GROUP) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CENTER, r32i) readonly uniform iimage2D centerCount;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DCS_BLOCKS) buffer DcsBlocks { uint dcsBlocks[]; };
#include "wedges/shaders/layer_bvh.glsl"

uint blocksAcross() { return clusterBlocksAlong(frame.width); }
uint blockCount() { return blocksAcross() * clusterBlocksAlong(frame.height); }

void main() {
#if DCS_RAYS_STAGE == 0
    uint block = gl_GlobalInvocationID.x;
    if (block == 0u) {
        dcsBlocks[GPU_DCS_RAY_DISPATCH + 1u] = 1u;
        dcsBlocks[GPU_DCS_RAY_DISPATCH + 2u] = uint(SAMPLE_COUNT) / GPU_DCS_RAY_SAMPLES_PER_GROUP;
    }
    if (block >= blockCount()) return;
    uint word = dcsBlocks[GPU_DCS_BLOCK_EDGES + block];
    if (!dcsBlockWordCastsRays(word, uint(SAMPLE_COUNT), DCS_RAY_EDGES) && (word & GPU_DCS_BLOCK_GAP) == 0u) return;
    uint at = atomicAdd(dcsBlocks[GPU_DCS_RAY_BLOCK_COUNT], 1u);
    dcsBlocks[GPU_DCS_BLOCK_EDGES + blockCount() + at] = block;
    atomicMax(dcsBlocks[GPU_DCS_RAY_DISPATCH], min(at + 1u, GPU_DCS_RAY_GROUPS_MAX));
#else
    uint lane = gl_LocalInvocationID.x / GPU_DCS_RAY_SAMPLES_PER_GROUP;
    uint s = GPU_DCS_RAY_SAMPLES_PER_GROUP * gl_WorkGroupID.z + gl_LocalInvocationID.x % GPU_DCS_RAY_SAMPLES_PER_GROUP;
    uint listed = dcsBlocks[GPU_DCS_RAY_BLOCK_COUNT];
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    uint nodes = layerNodeCount();
    LayerCountWork work = LayerCountWork(0u, 0u, 0u, 0u);
    uint covered = 0u;
    for (uint r = gl_WorkGroupID.x; r < listed; r += gl_NumWorkGroups.x) {
        uint block = dcsBlocks[GPU_DCS_BLOCK_EDGES + blockCount() + r];
        ivec2 pixel = ivec2(CLUSTER_BLOCK * (block % blocksAcross()) + lane % CLUSTER_BLOCK,
                            CLUSTER_BLOCK * (block / blocksAcross()) + lane / CLUSTER_BLOCK);
        if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
        // Every pixel of a block whose edges outnumber its rays; else those whose gaps meet a triangle.
        uint index = uint(pixel.y) * frame.width + uint(pixel.x);
        if (!dcsBlockWordCastsRays(dcsBlocks[GPU_DCS_BLOCK_EDGES + block], uint(SAMPLE_COUNT), DCS_RAY_EDGES) &&
            (dcsBlocks[dcsPixelGapWord(blockCount(), index)] & (1u << (index % 32u))) == 0u)
            continue;
        uint receiver = imageLoad(gTriangle, pixel).x;
        if (receiver == GPU_NO_TRIANGLE) continue;
        vec3 p = vec3(imageLoad(gPosition, pixel));
        LightFrame lf = lightFrame(lights[pc.light].light, p, frame.farDistance);
        PixelSamples samples = pixelSamples(uvec2(pixel), uint(SAMPLE_COUNT));
        vec3 x = lightSamplePosition(lf, pixelSamplePoint(samples, s, lf.domain));
        int count = int(layerCount(LayerBvh(0u), nodes, p, x, shadowTMin(p, lf.center, sceneDiameter), receiver,
                                   LAYER_BVH_MAX_VISITS, work));
        int d = imageLoad(centerCount, pixel).x;
        // A negative addend wraps modulo 2^32 across the word's two 16-bit counters, which
        // wedge_fold.comp undoes (as wedge_samples.comp's crossings).
        uint slot = lsCounterSlot(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT), s);
        if (count != d) atomicAdd(counters[lsCounterWord(slot)], uint(count - d) << lsCounterShift(slot));
        if (s == 0u) ++covered;
    }
    covered = subgroupAdd(covered);
    uint cutShort = subgroupAdd(work.cutShort);
    if (subgroupElect()) {
        if (covered > 0u) atomicAdd(stats[pc.light].rayPixels, covered);
        if (cutShort > 0u) atomicAdd(stats[pc.light].centerCutShort, cutShort);
    }
#endif
}
