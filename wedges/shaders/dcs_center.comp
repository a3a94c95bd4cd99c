#version 450
// D(r), the layer count at the light centre r (DESIGN §4.5), per pixel: the opaque triangles the
// segment from the visible point p to r crosses beyond the segments' start gap (shadowTMin),
// the visible triangle itself left out (the self-shadowing rule), counted through the tree of
// wedges/layer_bvh_dh.h — one reference ray a pixel (Laine et al. 2005; Lehtinen, Laine and
// Aila 2008), as the CPU mirror counts it. A pixel without a surface gets 0.
// With DCS_GAP_BLOCKS (DCS; PW has no other way), the same traversal asks whether a triangle
// meets the pixel's segment gaps (layerCountGaps: there the crossings miss a change of D); such a
// pixel sets its bit and its block's GPU_DCS_BLOCK_GAP: it counts its samples' segments instead
// (dcs_rays.comp), as the mirror's does, and its pairs add nothing.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#ifndef DCS_GAP_BLOCKS
#define DCS_GAP_BLOCKS 0
#endif
#include "wedges/shaders/wedge_bindings.glsl"
#include "wedges/edge_cluster_dh.h"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CENTER, r32i) writeonly uniform iimage2D centerCount;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DCS_BLOCKS) buffer DcsBlocks { uint dcsBlocks[]; };
#include "wedges/shaders/layer_bvh.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    bool inside = pixel.x < int(frame.width) && pixel.y < int(frame.height);
    uint receiver = inside ? imageLoad(gTriangle, pixel).x : GPU_NO_TRIANGLE;
    LayerCountWork work = LayerCountWork(0u, 0u, 0u, 0u);
    uint count = 0u;
    if (receiver != GPU_NO_TRIANGLE) {
        vec3 p = vec3(imageLoad(gPosition, pixel));
        LightFrame lf = lightFrame(lights[pc.light].light, p, frame.farDistance);
        float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
        float tMin = shadowTMin(p, lf.center, sceneDiameter);
        LayerGaps gaps = layerNoGaps();
#if DCS_GAP_BLOCKS
        DcsPixel px = dcsSetupPixel(p, lf.center, lf.T, lf.B, tMin);
        if (px.valid != 0.0) gaps = layerGapsOf(p, lf.center, lf.T, lf.B, px.row0, px.row1, px.row2, tMin);
#endif
        bool gapMet;
        count = layerCountGaps(LayerBvh(0u), layerNodeCount(), p, lf.center, tMin, receiver, LAYER_BVH_MAX_VISITS, gaps,
                               work, gapMet);
        if (gapMet) {
            uint blocks = clusterBlocksAlong(frame.width) * clusterBlocksAlong(frame.height);
            uint block = clusterBlocksAlong(frame.width) * (uint(pixel.y) / CLUSTER_BLOCK) + uint(pixel.x) / CLUSTER_BLOCK;
            uint index = uint(pixel.y) * frame.width + uint(pixel.x);
            atomicOr(dcsBlocks[GPU_DCS_BLOCK_EDGES + block], GPU_DCS_BLOCK_GAP);
            atomicOr(dcsBlocks[dcsPixelGapWord(blocks, index)], 1u << (index % 32u));
        }
    }
    if (inside) imageStore(centerCount, pixel, ivec4(int(count)));
    uint visits = subgroupAdd(work.visits);
    uint tests = subgroupAdd(work.tests);
    uint cutShort = subgroupAdd(work.cutShort);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].centerVisits, visits);
        atomicAdd(stats[pc.light].centerTests, tests);
        if (cutShort > 0u) atomicAdd(stats[pc.light].centerCutShort, cutShort);
    }
}
