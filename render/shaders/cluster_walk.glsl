// The cluster walk of a volume family (render/vulkan/gpu_cluster_walk.h; DESIGN §4.5): a tree
// over the family's occluders, walked per 16 × 16 tile of pixels (4 × 4 where a tile needs more
// pairs than a list holds) down to the leaves, then per 4 × 4 block of the tile, level by level over lists of pairs, so that no invocation loops
// without bound (lavapipe ends a shader's loops after 65 535 iterations in all). The family's shader (dcs_clusters.comp, stsv_clusters.comp) declares its
// stats buffer `stats` (GpuClusterCounts `walk` second), defines clusterKeep — what becomes of a
// leaf that may add to a block, with groupAppend — and its own pixel stages, which
// append with groupAppend/groupReserve between groupFlush calls too, or with appendPixels (one
// atomic an input), and calls these:
//   clusterBlocksStage (CLUSTER_STAGE 0): each tile of a part of them (all of them unless the
//     lists needed more than a buffer holds: the passes run once per part) and each of its
//     blocks get the box of their visible points, and the tile the pair (tile, root) for level 0;
//   clusterArgsStage (1): the indirect dispatch of the next pass, from the count of the list it
//     reads;
//   clusterWalkStage (2): each (region, node) pair of a level whose node may add to the region, a
//     tile or a block (edge_cluster_dh.h clusterMayAdd: the ball meets the segments from the
//     region's ball to the light, and for a node with a normal cone, an edge of it can be a
//     silhouette), gives its children to the next level; a leaf, for a tile, gives the pairs
//     (block, leaf) of the tile's covered blocks to the next level (or, with
//     CLUSTER_KEEP_TILE_BLOCKS, tests them there), and for a block hands the leaf to clusterKeep. A node a tile drops holds nothing that adds to
//     a point of the tile (each test is conservative), so neither to one of its blocks.
// A list too short drops what it has no room for and records what it needed; the host grows
// the lists and renders the frame again.
#ifndef STSV_SHADERS_CLUSTER_WALK_GLSL
#define STSV_SHADERS_CLUSTER_WALK_GLSL

#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "render/shaders/frame_bindings.glsl"
#include "render/vulkan/gpu_volumes_dh.h"
#include "wedges/edge_cluster_dh.h"
#include "render/shaders/deferred_list.glsl"

#ifndef CLUSTER_STAGE
#define CLUSTER_STAGE 2
#endif
/// Invocations of a workgroup (stage 1: one): the family's shader defines it
/// (GPU_STSV_CLUSTER_GROUP, GPU_DCS_CLUSTER_GROUP; see groupAppend).
#if CLUSTER_STAGE == 1
layout(local_size_x = 1) in;
#else
layout(local_size_x = CLUSTER_GROUP_SIZE) in;
#endif

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_NODES) uniform usamplerBuffer clusterNodes;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_ITEMS) uniform usamplerBuffer clusterItems;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_COUNTS) buffer Counts { uint counts[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_PAIRS) buffer Pairs { uvec2 pairs[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BLOCKS) buffer Blocks { vec4 blockBoxes[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_DISPATCH) buffer Dispatch { uint dispatchArgs[]; };

uint blocksAcross() { return clusterBlocksAlong(frame.width); }
uint blocksDown() { return clusterBlocksAlong(frame.height); }
/// A tile's side in blocks: 4 (16 × 16 pixels), or 1 where a 16 × 16 tile needs more pairs than a
/// list holds (GpuPush::flags).
uint tileBlocks() { return pc.flags; }
uint tilesAcross() { return (blocksAcross() + tileBlocks() - 1u) / tileBlocks(); }
/// A pair's region is a tile when this bit is set (the tile's index below it), else a block.
const uint CLUSTER_TILE = 0x80000000u;
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
        atomicMax(stats[pc.light].walk.pairsNeeded, at + 1u);
}
/// The pairs a pass reads from slot `slot`'s list: those appended, at most its capacity.
uint listEntries(uint slot) { return min(counts[slot], listCapacity()); }

// Appends gathered per workgroup. Lavapipe runs an atomic one lane at a time and its two cores
// contend for a list's counter, so the stages append to shared memory (groupAppend) and, at
// each step of their loops (groupFlush), a workgroup takes its places in each list with one
// atomic and copies its entries there. An invocation appends at most
// GPU_CLUSTER_GROUP_ENTRIES / CLUSTER_GROUP_SIZE entries between two flushes (a tile's 16
// blocks, a leaf's 16 triangles or one kept leaf, a block's 16 pixels: the host asserts the leaf sizes),
// so the shared list never overflows (12 KiB of the 16 KiB any device has). The lists' order varies from run to run as with one
// atomic an entry; no pass's result depends on it.
const uint GROUP_CAPACITY = GPU_CLUSTER_GROUP_ENTRIES;
const uint GROUP_TARGETS = 4u;
const uint GROUP_NEXT_LEVEL = 0u; ///< the list of the walk's next level (slot pc.step + 1)
const uint GROUP_KEPT = 1u;       ///< GPU_CLUSTER_KEPT
const uint GROUP_CANDIDATES = 2u; ///< GPU_CLUSTER_CANDIDATES
const uint GROUP_DEFERRED = 3u;   ///< the deferred fragments (deferred_list.glsl)
shared uint groupCount;
shared uint groupTargetCount[GROUP_TARGETS];
shared uint groupTargetBase[GROUP_TARGETS];
shared uvec2 groupEntries[GROUP_CAPACITY];
shared uint groupPlaces[GROUP_CAPACITY]; ///< target << 24 | index among the target's entries

/// Room for `n` appends to target list `target` at the workgroup's next groupFlush: x the first
/// entry, y the first index among the target's; groupPut fills them. (Lavapipe runs even a
/// shared-memory atomic lane by lane: an invocation with several entries reserves them at once.)
uvec2 groupReserve(uint target, uint n) {
    return uvec2(atomicAdd(groupCount, n), atomicAdd(groupTargetCount[target], n));
}
void groupPut(uint target, uvec2 room, uint i, uvec2 entry) {
    groupEntries[room.x + i] = entry;
    groupPlaces[room.x + i] = (target << 24u) | (room.y + i);
}
/// Appends `entry` to target list `target` at the workgroup's next groupFlush.
void groupAppend(uint target, uvec2 entry) {
    groupPut(target, groupReserve(target, 1u), 0u, entry);
}

void groupBegin() {
    if (gl_LocalInvocationIndex == 0u) {
        groupCount = 0u;
        for (uint t = 0u; t < GROUP_TARGETS; ++t) groupTargetCount[t] = 0u;
    }
    barrier();
}

uint groupSlot(uint target) {
    return target == GROUP_NEXT_LEVEL ? pc.step + 1u : (target == GROUP_KEPT ? GPU_CLUSTER_KEPT : GPU_CLUSTER_CANDIDATES);
}

/// Writes the workgroup's appends to their lists (in uniform control flow). A pair list drops
/// what is past its capacity and records what it needed (appendPair); the deferred list drops
/// it, and its count tells the host.
void groupFlush() {
    memoryBarrierShared();
    barrier();
    uint local = gl_LocalInvocationIndex;
    if (local < GROUP_TARGETS && groupTargetCount[local] > 0u) {
        uint n = groupTargetCount[local];
        uint base = local == GROUP_DEFERRED ? atomicAdd(deferredCount.x, n) : atomicAdd(counts[groupSlot(local)], n);
        if (local != GROUP_DEFERRED && base + n > listCapacity()) atomicMax(stats[pc.light].walk.pairsNeeded, base + n);
        groupTargetBase[local] = base;
    }
    memoryBarrierShared();
    barrier();
    uint total = groupCount;
    for (uint i = local; i < total; i += gl_WorkGroupSize.x) {
        uint target = groupPlaces[i] >> 24u;
        uint at = groupTargetBase[target] + (groupPlaces[i] & 0xffffffu);
        if (target == GROUP_DEFERRED) {
            if (at < uint(deferred.length())) deferred[at] = groupEntries[i];
        } else if (at < listCapacity()) {
            pairs[listBase(groupSlot(target)) + at] = groupEntries[i];
        }
    }
    barrier();
    if (local == 0u) {
        groupCount = 0u;
        for (uint t = 0u; t < GROUP_TARGETS; ++t) groupTargetCount[t] = 0u;
    }
    barrier();
}

/// The entries of a stage's list, a workgroup's step at a time: `first` is the same for the
/// whole workgroup, so the loop's barriers (groupFlush) are in uniform control flow; entry
/// first + gl_LocalInvocationID.x is this invocation's, if below `entries`.
#define CLUSTER_FOR_EACH_STEP(first, entries) \
    for (uint first = gl_WorkGroupID.x * gl_WorkGroupSize.x; first < (entries); \
         first += gl_NumWorkGroups.x * gl_WorkGroupSize.x)

/// Cluster `index` of a table (nodes or items, GPU_CLUSTER_TEXELS each): ball, cone, texel 2.
vec4 clusterBall(usamplerBuffer table, uint index) { return uintBitsToFloat(texelFetch(table, int(index * GPU_CLUSTER_TEXELS))); }
vec4 clusterCone(usamplerBuffer table, uint index) { return uintBitsToFloat(texelFetch(table, int(index * GPU_CLUSTER_TEXELS + 1u))); }
uvec4 clusterData(usamplerBuffer table, uint index) { return texelFetch(table, int(index * GPU_CLUSTER_TEXELS + 2u)); }
/// clusterMayAdd of cluster `index` of a table against a region (a cluster without a cone: the
/// light-hull test of its ball alone).
bool tableMayAdd(usamplerBuffer table, uint index, vec4 region, LightHull hull) {
    uvec4 data = clusterData(table, index);
    return clusterMayAdd(clusterBall(table, index), clusterCone(table, index), uintBitsToFloat(data.z), region, hull);
}

/// Pixel `lane` (0 … 15, row by row) of block `block`.
ivec2 blockPixel(uint block, uint lane) {
    uint across = blocksAcross();
    return ivec2(CLUSTER_BLOCK * (block % across) + lane % CLUSTER_BLOCK,
                 CLUSTER_BLOCK * (block / across) + lane / CLUSTER_BLOCK);
}
/// The light-sample buffer's index of pixel `lane` of block `block`.
uint blockPixelIndex(uint block, uint lane) { return lsPixelIndex(uvec2(blockPixel(block, lane)), frame.width); }
/// Appends (pixel index, item) to the list of count slot `slot` for each pixel of block `block`
/// whose bit is set in `lanes` (bit i: blockPixel(block, i)), with one atomic, as appendPair does
/// one: for a pass whose invocations append to one list and seldom (DCS's pixels), where the
/// barriers of groupFlush at every step cost more than the atomics.
void appendPixels(uint slot, uint block, uint lanes, uint item) {
    if (lanes == 0u) return;
    uint n = uint(bitCount(lanes));
    uint at = atomicAdd(counts[slot], n);
    if (at + n > listCapacity()) atomicMax(stats[pc.light].walk.pairsNeeded, at + n);
    for (uint i = 0u; lanes != 0u; ++i) {
        uint lane = uint(findLSB(lanes));
        lanes &= lanes - 1u;
        if (at + i < listCapacity())
            pairs[listBase(slot) + at + i] = uvec2(blockPixelIndex(block, lane), item);
    }
}
/// Appends (pixel index, item) to target list `target` for each pixel of block `block` whose bit
/// is set in `lanes` (bit i: blockPixel(block, i)), with one reservation.
void groupAppendPixels(uint target, uint block, uint lanes, uint item) {
    if (lanes == 0u) return;
    uvec2 room = groupReserve(target, uint(bitCount(lanes)));
    for (uint i = 0u; lanes != 0u; ++i) {
        uint lane = uint(findLSB(lanes));
        lanes &= lanes - 1u;
        groupPut(target, room, i, uvec2(blockPixelIndex(block, lane), item));
    }
}
/// The box of visible points (lo.x > hi.x: it sees none) of a block, or of a tile
/// (region = CLUSTER_TILE | tile): the tiles' boxes follow the blocks'.
uint regionBox(uint region) {
    return 2u * ((region & CLUSTER_TILE) != 0u ? blocksAcross() * blocksDown() + (region & ~CLUSTER_TILE) : region);
}
vec3 regionLo(uint region) { return vec3(blockBoxes[regionBox(region)]); }
vec3 regionHi(uint region) { return vec3(blockBoxes[regionBox(region) + 1u]); }
vec3 blockLo(uint block) { return regionLo(block); }
vec3 blockHi(uint block) { return regionHi(block); }
/// Block k (0 … tileBlocks()² − 1, row by row) of tile `tile`; false past the frame's edge.
bool tileBlock(uint tile, uint k, out uint block) {
    uint bx = tileBlocks() * (tile % tilesAcross()) + k % tileBlocks();
    uint by = tileBlocks() * (tile / tilesAcross()) + k / tileBlocks();
    block = by * blocksAcross() + bx;
    return bx < blocksAcross() && by < blocksDown();
}

/// A family whose clusterKeep appends one pair at most defines CLUSTER_KEEP_TILE_BLOCKS 1: the walk
/// then tests a tile's leaf with each of its blocks where it meets the pair (a tile's blocks' pairs
/// fit the workgroup's room), instead of listing the (block, leaf) pairs for the next level.
#ifndef CLUSTER_KEEP_TILE_BLOCKS
#define CLUSTER_KEEP_TILE_BLOCKS 0
#endif

/// What the family does with leaf `leaf` (its items range.x … range.x + range.y − 1) that may add
/// to block `block` (region: the block's ball, hull: its lightHull): appends (block, …) pairs to
/// GPU_CLUSTER_KEPT with groupAppend, counting its own tests.
void clusterKeep(uint block, uint leaf, uvec4 range, vec4 region, LightHull hull, inout uint tests, inout uint rejected);

void clusterTileBoxes(uint tile) {
    if (tile >= pc.initialize) return;
    vec3 tileLo = vec3(3.0e38);
    vec3 tileHi = vec3(-3.0e38);
    for (uint k = 0u; k < tileBlocks() * tileBlocks(); ++k) {
        uint block;
        if (!tileBlock(tile, k, block)) continue;
        vec3 lo = vec3(3.0e38);
        vec3 hi = vec3(-3.0e38);
        for (uint lane = 0u; lane < CLUSTER_BLOCK * CLUSTER_BLOCK; ++lane) {
            ivec2 pixel = blockPixel(block, lane);
            if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) continue;
            if (imageLoad(gTriangle, pixel).x == GPU_NO_TRIANGLE) continue;
            vec3 p = vec3(imageLoad(gPosition, pixel));
            lo = min(lo, p);
            hi = max(hi, p);
        }
        blockBoxes[regionBox(block)] = vec4(lo, 0.0);
        blockBoxes[regionBox(block) + 1u] = vec4(hi, 0.0);
        tileLo = min(tileLo, lo);
        tileHi = max(tileHi, hi);
    }
    uint region = CLUSTER_TILE | tile;
    blockBoxes[regionBox(region)] = vec4(tileLo, 0.0);
    blockBoxes[regionBox(region) + 1u] = vec4(tileHi, 0.0);
    if (tileLo.x <= tileHi.x && uint(textureSize(clusterNodes)) >= GPU_CLUSTER_TEXELS) appendPair(0u, uvec2(region, 0u));
}

void clusterBlocksStage() {
    // The part's tiles: pc.step to pc.initialize, 64 a workgroup.
    for (uint i = gl_LocalInvocationID.x; i < 64u; i += gl_WorkGroupSize.x) clusterTileBoxes(pc.step + 64u * gl_WorkGroupID.x + i);
}

/// Entries an invocation of the pass over the kept pairs takes: GPU_CLUSTER_ENTRIES_PER_INVOCATION,
/// or fewer where the family's shader loops longer an entry (lavapipe's loop limit).
#ifndef CLUSTER_KEPT_ENTRIES_PER_INVOCATION
#define CLUSTER_KEPT_ENTRIES_PER_INVOCATION GPU_CLUSTER_ENTRIES_PER_INVOCATION
#endif

void clusterArgsStage() {
    // pc.step: the count slot of the list the next pass reads.
    uint invocations = listEntries(pc.step);
    uint perInvocation = pc.step == GPU_CLUSTER_KEPT ? uint(CLUSTER_KEPT_ENTRIES_PER_INVOCATION) : GPU_CLUSTER_ENTRIES_PER_INVOCATION;
    uint perGroup = uint(CLUSTER_GROUP_SIZE) * perInvocation;
    dispatchArgs[0] = clamp((invocations + perGroup - 1u) / perGroup, 1u, 65535u);
    dispatchArgs[1] = 1u;
    dispatchArgs[2] = 1u;
}

void clusterWalkStage() {
    // pc.step: the level.
    uint entries = listEntries(pc.step);
    vec4 lightBall = lights[pc.light].sphere;
    uint tests = 0u;
    uint rejected = 0u;
    groupBegin();
    CLUSTER_FOR_EACH_STEP(first, entries) {
        uint e = first + gl_LocalInvocationID.x;
        if (e < entries) {
            uvec2 pair = pairs[listBase(pc.step) + e];
            vec4 region = boxBall(regionLo(pair.x), regionHi(pair.x));
            LightHull hull = lightHull(region, lightBall);
            ++tests;
            if (!tableMayAdd(clusterNodes, pair.y, region, hull)) {
                ++rejected;
            } else {
                uvec4 range = clusterData(clusterNodes, pair.y);
                if (range.y == 0u) {
                    groupAppend(GROUP_NEXT_LEVEL, uvec2(pair.x, range.x));
                    groupAppend(GROUP_NEXT_LEVEL, uvec2(pair.x, range.x + 1u));
                } else if ((pair.x & CLUSTER_TILE) != 0u) {
                    for (uint k = 0u; k < tileBlocks() * tileBlocks(); ++k) {
                        uint block;
                        if (!tileBlock(pair.x & ~CLUSTER_TILE, k, block) || blockLo(block).x > blockHi(block).x)
                            continue;
#if CLUSTER_KEEP_TILE_BLOCKS
                        // The leaf with each block here, as the next level would test the pair.
                        vec4 blockRegion = boxBall(blockLo(block), blockHi(block));
                        LightHull blockHull = lightHull(blockRegion, lightBall);
                        ++tests;
                        if (tableMayAdd(clusterNodes, pair.y, blockRegion, blockHull))
                            clusterKeep(block, pair.y, range, blockRegion, blockHull, tests, rejected);
                        else
                            ++rejected;
#else
                        groupAppend(GROUP_NEXT_LEVEL, uvec2(block, pair.y));
#endif
                    }
                } else {
                    clusterKeep(pair.x, pair.y, range, region, hull, tests, rejected);
                }
            }
        }
        groupFlush();
    }
    tests = subgroupAdd(tests);
    rejected = subgroupAdd(rejected);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].walk.tests, tests);
        atomicAdd(stats[pc.light].walk.rejected, rejected);
    }
}

#endif
