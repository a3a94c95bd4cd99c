#version 450
// DCS's silhouette edges through the light's cluster tree (DESIGN §4.5; the CPU mirror's walk,
// render/cpu/cpu_wedges.cpp forEachPixel and forEachSilhouette, with the same dh tests), level by
// level over lists of pairs so that no invocation loops without bound (lavapipe ends a shader's
// loops after 65535 iterations in all):
//   DCS_CLUSTER_STAGE 0 (blocks): each 4 × 4 block of pixels of a part of them (all of them
//     unless the lists needed more than a buffer holds: the passes run once per part) gets the
//     ball of its visible points, and the pair (block, root) for level 0;
//   1 (args): the indirect dispatch of the next pass, from the count of the list it reads;
//   2 (walk): each (block, node) pair of a level whose node may add to the block (edge_cluster_dh.h
//     clusterMayAdd) gives its children to the next level, or, a leaf, those of its edges, each a
//     cluster of its own, that may add to it, as (block, item) pairs;
//   3 (pixels): 16 invocations a kept pair, one a pixel of the block: an edge that is a
//     silhouette seen from the pixel's p (most are not) makes a (pixel, item) candidate;
//   4 (candidates): a candidate whose edge's ball meets the segments from p to the light, whose
//     edge clipped between p and the light is not empty and whose carrier's bound holds p is
//     listed for wedge_samples.comp, which adds k_e·[r → x crosses the edge] to each light sample
//     x's counter. (Lavapipe runs a batch's instructions for all its lanes: the candidates'
//     tests run in full batches.)
// The pairs listed are those of the wedge draw's fragments that pass every test, without a volume
// or a fragment; the culling tests are conservative, so they change no counter. A list too short drops what it has no room
// for and records what it needed; the host grows the lists and renders the frame again.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef DCS_CLUSTER_STAGE
#define DCS_CLUSTER_STAGE 2
#endif
#include "wedges/wedge_term.glsl"
#include "wedges/edge_cluster_dh.h"
#include "common/deferred_list.glsl"

#if DCS_CLUSTER_STAGE == 1
layout(local_size_x = 1) in;
#else
layout(local_size_x = 64) in;
#endif

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_NODES) uniform usamplerBuffer clusterNodes;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_ITEMS) uniform usamplerBuffer clusterItems;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BOUNDS) uniform usamplerBuffer clusterBounds;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_COUNTS) buffer Counts { uint counts[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_PAIRS) buffer Pairs { uvec2 pairs[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BLOCKS) buffer Blocks { vec4 blockBalls[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_DISPATCH) buffer Dispatch { uint dispatchArgs[]; };

uint blocksAcross() { return (frame.width + 3u) / 4u; }
uint listCapacity() { return uint(pairs.length()) / GPU_CLUSTER_LISTS; }
/// The list whose count is slot `slot`: the levels alternate between lists 0 and 1, the kept
/// pairs are list 2, the candidates list 3.
uint listBase(uint slot) {
    uint list = slot == GPU_CLUSTER_KEPT ? 2u : (slot == GPU_CLUSTER_CANDIDATES ? 3u : slot % 2u);
    return list * listCapacity();
}

/// Appends `pair` to the list of count slot `slot`; past its end it is dropped, and the count
/// still grows, which the stats record for the host.
void appendPair(uint slot, uvec2 pair) {
    uint at = atomicAdd(counts[slot], 1u);
    if (at < listCapacity())
        pairs[listBase(slot) + at] = pair;
    else
        atomicMax(stats[pc.light].pairsNeeded, at + 1u);
}
/// The pairs a pass reads from slot `slot`'s list: those appended, at most its capacity.
uint listEntries(uint slot) { return min(counts[slot], listCapacity()); }

/// Cluster `index` of a table (nodes or items, GPU_CLUSTER_TEXELS each): ball, cone, texel 2.
vec4 clusterBall(usamplerBuffer table, uint index) { return uintBitsToFloat(texelFetch(table, int(index * GPU_CLUSTER_TEXELS))); }
vec4 clusterCone(usamplerBuffer table, uint index) { return uintBitsToFloat(texelFetch(table, int(index * GPU_CLUSTER_TEXELS + 1u))); }
uvec4 clusterData(usamplerBuffer table, uint index) { return texelFetch(table, int(index * GPU_CLUSTER_TEXELS + 2u)); }
/// clusterMayAdd of cluster `index` of a table against a region.
bool tableMayAdd(usamplerBuffer table, uint index, vec4 region, LightHull hull) {
    uvec4 data = clusterData(table, index);
    return clusterMayAdd(clusterBall(table, index), clusterCone(table, index), uintBitsToFloat(data.z),
                         uintBitsToFloat(data.w), region, hull);
}

/// Whether p lies in carrier c's bound: in one of its volumes and in its light planes
/// (wedges/silhouette_edges.h FaceBound::contains).
bool insideBound(uint c, vec3 p) {
    uint base = c * GPU_CLUSTER_BOUND_TEXELS;
    uvec4 sizes = texelFetch(clusterBounds, int(base));
    bool inside = false;
    for (uint v = 0u; v < 2u; ++v) {
        StsvVolume vol;
        vol.planeCount = v == 0u ? sizes.y : sizes.z;
        for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
            vol.planes[i] = uintBitsToFloat(texelFetch(clusterBounds, int(base + 1u + v * STSV_VOLUME_MAX_PLANES + i)));
        inside = inside || (v < sizes.x && stsvPointInVolume(vol, p));
    }
    if (!inside) return false;
    StsvLightPlanes lp;
    lp.count = sizes.w;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        lp.planes[i] = uintBitsToFloat(texelFetch(clusterBounds, int(base + 1u + 2u * STSV_VOLUME_MAX_PLANES + i)));
    return stsvPointInLightPlanes(lp, p);
}

/// Pixel `lane` (0 … 15, row by row) of block `block`.
ivec2 blockPixel(uint block, uint lane) {
    uint across = blocksAcross();
    return ivec2(4u * (block % across) + lane % 4u, 4u * (block / across) + lane / 4u);
}

void main() {
#if DCS_CLUSTER_STAGE == 0
    // The part's blocks: pc.step to pc.initialize.
    uint block = pc.step + gl_GlobalInvocationID.x;
    if (block >= pc.initialize) return;
    vec3 lo = vec3(3.0e38);
    vec3 hi = vec3(-3.0e38);
    for (uint lane = 0u; lane < 16u; ++lane) {
        ivec2 pixel = blockPixel(block, lane);
        if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
        if (imageLoad(gTriangle, pixel).x == GPU_NO_TRIANGLE) continue;
        vec3 p = vec3(imageLoad(gPosition, pixel));
        lo = min(lo, p);
        hi = max(hi, p);
    }
    bool covered = lo.x <= hi.x;
    blockBalls[block] = covered ? boxBall(lo, hi) : vec4(0.0, 0.0, 0.0, -1.0);
    if (covered && uint(textureSize(clusterNodes)) >= GPU_CLUSTER_TEXELS) appendPair(0u, uvec2(block, 0u));
#elif DCS_CLUSTER_STAGE == 1
    // pc.step: the count slot of the list the next pass reads; the pixel pass takes 16
    // invocations a pair.
    uint invocations = listEntries(pc.step) * (pc.step == GPU_CLUSTER_KEPT ? 16u : 1u);
    uint perGroup = 64u * GPU_CLUSTER_ENTRIES_PER_INVOCATION;
    dispatchArgs[0] = clamp((invocations + perGroup - 1u) / perGroup, 1u, 65535u);
    dispatchArgs[1] = 1u;
    dispatchArgs[2] = 1u;
#elif DCS_CLUSTER_STAGE == 2
    // pc.step: the level.
    uint entries = listEntries(pc.step);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    vec4 lightBall = lights[pc.light].sphere;
    uint tests = 0u;
    uint rejected = 0u;
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 pair = pairs[listBase(pc.step) + e];
        vec4 region = blockBalls[pair.x];
        LightHull hull = lightHull(region, lightBall);
        ++tests;
        if (!tableMayAdd(clusterNodes, pair.y, region, hull)) {
            ++rejected;
            continue;
        }
        uvec4 range = clusterData(clusterNodes, pair.y);
        if (range.y == 0u) {
            appendPair(pc.step + 1u, uvec2(pair.x, range.x));
            appendPair(pc.step + 1u, uvec2(pair.x, range.x + 1u));
            continue;
        }
        for (uint k = range.x; k < range.x + range.y; ++k) {
            ++tests;
            if (tableMayAdd(clusterItems, k, region, hull))
                appendPair(GPU_CLUSTER_KEPT, uvec2(pair.x, k));
            else
                ++rejected;
        }
    }
    tests = subgroupAdd(tests);
    rejected = subgroupAdd(rejected);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].clusterTests, tests);
        atomicAdd(stats[pc.light].clustersRejected, rejected);
    }
#elif DCS_CLUSTER_STAGE == 3
    uint entries = 16u * listEntries(GPU_CLUSTER_KEPT);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 pair = pairs[listBase(GPU_CLUSTER_KEPT) + e / 16u];
        ivec2 pixel = blockPixel(pair.x, e % 16u);
        if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
        uint receiver = imageLoad(gTriangle, pixel).x;
        if (receiver == GPU_NO_TRIANGLE) continue;
        vec3 p = vec3(imageLoad(gPosition, pixel));
        WedgeEdge edge = wedgeEdgeAt(clusterData(clusterItems, pair.y).x);
        // The mirror's first test (forEachSilhouette): the edge is a silhouette seen from p.
        if (wedgeWorldWeight(p, edge.v0, edge.v1, wedgeFacesOf(edge), receiver) != 0)
            appendPair(GPU_CLUSTER_CANDIDATES, uvec2(lsPixelIndex(uvec2(pixel), frame.width), pair.y));
    }
#else
    uint entries = listEntries(GPU_CLUSTER_CANDIDATES);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    vec4 lightBall = lights[pc.light].sphere;
    Light light = lights[pc.light].light;
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    uint boundTests = 0u;
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 candidate = pairs[listBase(GPU_CLUSTER_CANDIDATES) + e];
        ivec2 pixel = ivec2(candidate.x % frame.width, candidate.x / frame.width);
        uint receiver = imageLoad(gTriangle, pixel).x;
        vec3 p = vec3(imageLoad(gPosition, pixel));
        uvec4 item = clusterData(clusterItems, candidate.y);
        WedgeEdge edge = wedgeEdgeAt(item.x);
        // The mirror's order after the silhouette test: the edge's ball, the edge term, the bound
        // (its leaf test with p is implied by the edge's ball).
        if (!ballMeetsLightHull(edgeBall(edge.v0, edge.v1), lightHull(vec4(p, 0.0), lightBall))) continue;
        LightFrame lf = lightFrame(light, p, frame.farDistance);
        DcsPixel px = dcsSetupPixel(p, lf.center, lf.T, lf.B, shadowTMin(p, lf.center, sceneDiameter));
        if (px.valid == 0.0) continue;
        vec3 l;
        vec3 h0;
        vec3 h1;
        int kE;
        if (!wedgeEdgeTerm(px, edge.v0, edge.v1, wedgeFacesOf(edge), receiver, l, h0, h1, kE)) continue;
        ++boundTests;
        if (!insideBound(item.y, p)) continue;
        // Past the list's end the entry is dropped; the host sees the count and renders again.
        deferredAppend(candidate.x, item.x);
    }
    boundTests = subgroupAdd(boundTests);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, boundTests);
#endif
}
