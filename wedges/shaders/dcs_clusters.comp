#version 450
// DCS's silhouette edges through the light's cluster tree (DESIGN §4.5; the CPU mirror's walk,
// wedges/cpu/cpu_wedges.cpp forEachPixel and forEachSilhouette, with the same dh tests), over
// the lists of render/shaders/cluster_walk.glsl:
//   CLUSTER_STAGE 0, 1, 2: the blocks, the indirect dispatches, the walk of a level; a leaf
//     that may add to a block is kept as a (block, leaf) pair;
//   3 (pixels): an invocation a kept pair: the leaf's ball is tested with each of the block's 16
//     pixels, the leaf's edges as clusters of their own with the block, and for each edge and
//     pixel left, an edge that is a silhouette seen from the pixel's p (most are not) and whose
//     ball meets the segments from p to the light makes a (pixel, item) candidate, appended with
//     one atomic an edge;
//   A block whose kept edges exceed DCS_RAY_EDGES per sample (dcsBlockCastsRays) lists nothing in
//     stage 3, nor stage 4 a pixel whose segments' gaps meet a triangle (dcs_center.comp):
//     dcs_rays.comp counts their samples through the layer tree instead.
//   4 (candidates): a candidate whose edge clipped between p and the light is not empty and
//     whose carrier's bound holds p is listed for wedge_samples.comp, which adds
//     k_e·[r → x crosses the edge] to each light sample x's counter. (Lavapipe runs a batch's
//     instructions for all its lanes: the candidates' tests run in full batches.)
// The pairs listed are those of the wedge draw's fragments that pass every test, without a volume
// or a fragment; the culling tests are conservative, so they change no counter.
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#include "wedges/shaders/wedge_term.glsl"
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
#define CLUSTER_GROUP_SIZE GPU_DCS_CLUSTER_GROUP
// A kept leaf is one (block, leaf) pair.
#define CLUSTER_KEEP_TILE_BLOCKS 1
// The kept pairs an invocation of stage 3 takes: the host's define bounds its loops for the
// scene's edges (wedges/vulkan/gpu_wedge_clusters.h dcsKeptPairsPerInvocation).
#ifndef CLUSTER_KEPT_ENTRIES_PER_INVOCATION
#define CLUSTER_KEPT_ENTRIES_PER_INVOCATION 1u
#endif
#include "render/shaders/cluster_walk.glsl"

layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BOUNDS) uniform usamplerBuffer clusterBounds;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_DCS_BLOCKS) buffer DcsBlocks { uint dcsBlocks[]; };
#ifndef DCS_RAY_EDGES
#define DCS_RAY_EDGES DCS_RAY_EDGES_PER_SAMPLE
#endif

/// A leaf that may add to a block is kept as (block, leaf): stage 3 tests its edges, each a
/// cluster of its own (ball and cone of its two faces), and the block's pixels. Its edges count
/// toward the block's choice between crossings and rays (the mirror's BlockEdges::edgeCount).
void clusterKeep(uint block, uint leaf, uvec4 range, vec4 region, LightHull hull, inout uint tests, inout uint rejected) {
    atomicAdd(dcsBlocks[GPU_DCS_BLOCK_EDGES + block], range.y);
    groupAppend(GROUP_KEPT, uvec2(block, leaf));
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

/// The visible point p and its triangle of pixel `lane` of block `block`; false where the pixel
/// lies outside the frame or sees no surface.
bool blockPoint(uint block, uint lane, out vec3 p, out uint receiver) {
    ivec2 pixel = blockPixel(block, lane);
    p = vec3(0.0);
    receiver = GPU_NO_TRIANGLE;
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) return false;
    receiver = imageLoad(gTriangle, pixel).x;
    if (receiver == GPU_NO_TRIANGLE) return false;
    p = vec3(imageLoad(gPosition, pixel));
    return true;
}

void main() {
#if CLUSTER_STAGE == 0
    clusterBlocksStage();
#elif CLUSTER_STAGE == 1
    clusterArgsStage();
#elif CLUSTER_STAGE == 2
    clusterWalkStage();
#elif CLUSTER_STAGE == 3
    uint entries = listEntries(GPU_CLUSTER_KEPT);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    vec4 lightBall = lights[pc.light].sphere;
    uint tests = 0u;
    uint rejected = 0u;
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 pair = pairs[listBase(GPU_CLUSTER_KEPT) + e];
        // The block's samples are counted by rays (dcs_rays.comp): no pair is listed.
        if (dcsBlockWordCastsRays(dcsBlocks[GPU_DCS_BLOCK_EDGES + pair.x], uint(SAMPLE_COUNT), DCS_RAY_EDGES)) continue;
        uvec4 range = clusterData(clusterNodes, pair.y);
        // The block's pixels whose cones to the light's ball meet the leaf's ball (the mirror's
        // per-point leaf test: the ball holds each edge's, and a ball inside one that fails fails),
        // their cones kept for the edges (two image loads a pixel cost more than the array).
        vec4 leafBall = clusterBall(clusterNodes, pair.y);
        vec3 p;
        uint receiver;
        uint lanes = 0u;
        LightCone cones[16];
        uint receivers[16];
        for (uint lane = 0u; lane < 16u; ++lane) {
            bool covered = blockPoint(pair.x, lane, p, receiver);
            cones[lane] = lightCone(p, lightBall);
            receivers[lane] = receiver;
            if (covered && ballMeetsLightCone(leafBall, cones[lane])) lanes |= 1u << lane;
        }
        if (lanes == 0u) continue;
        // The leaf's edges that may add to the block, each as a cluster of its own.
        vec4 region = boxBall(blockLo(pair.x), blockHi(pair.x));
        LightHull hull = lightHull(region, lightBall);
        uint kept = 0u;
        for (uint k = 0u; k < range.y; ++k) {
            ++tests;
            if (tableMayAdd(clusterItems, range.x + k, region, hull))
                kept |= 1u << k;
            else
                ++rejected;
        }
        for (; kept != 0u; kept &= kept - 1u) {
            uint item = range.x + uint(findLSB(kept));
            WedgeEdge edge = wedgeEdgeAt(clusterData(clusterItems, item).x);
            WedgeFaces faces = wedgeFacesOf(edge);
            // The mirror's first two tests (forEachSilhouette): the edge is a silhouette seen
            // from p, its ball meets p's cone to the light's ball.
            vec4 ball = edgeBall(edge.v0, edge.v1);
            // The faces' normals once for the block's pixels (dcsTwoFaceWeight).
            bool two = faces.count <= 2u;
            uint t0 = two ? wedgeFaceTriangle(faces, faces.first) : GPU_NO_TRIANGLE;
            vec3 n0 = two ? dcsFaceNormal(edge.v0, edge.v1, wedgeFaceOpposite(faces, faces.first)) : vec3(0.0);
            bool second = faces.count == 2u;
            uint t1 = second ? wedgeFaceTriangle(faces, faces.first + 1u) : GPU_NO_TRIANGLE;
            vec3 n1 = second ? dcsFaceNormal(edge.v0, edge.v1, wedgeFaceOpposite(faces, faces.first + 1u)) : vec3(0.0);
            uint silhouette = 0u;
            for (uint l = lanes; l != 0u; l &= l - 1u) {
                uint lane = uint(findLSB(l));
                p = cones[lane].apex;
                receiver = receivers[lane];
                int weight = two ? dcsTwoFaceWeight(p, edge.v0, n0, t0, n1, t1, receiver)
                                 : wedgeWorldWeight(p, edge.v0, edge.v1, faces, receiver);
                if (weight != 0 && ballMeetsLightCone(ball, cones[lane])) silhouette |= 1u << lane;
            }
            appendPixels(GPU_CLUSTER_CANDIDATES, pair.x, silhouette, item);
        }
    }
    tests = subgroupAdd(tests);
    rejected = subgroupAdd(rejected);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].walk.tests, tests);
        atomicAdd(stats[pc.light].walk.rejected, rejected);
    }
#else
    uint entries = listEntries(GPU_CLUSTER_CANDIDATES);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    Light light = lights[pc.light].light;
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    uint boundTests = 0u;
    uint blocks = clusterBlocksAlong(frame.width) * clusterBlocksAlong(frame.height);
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 candidate = pairs[listBase(GPU_CLUSTER_CANDIDATES) + e];
        // A pixel whose segments' gaps meet a triangle counts its samples' segments (dcs_rays.comp).
        if ((dcsBlocks[dcsPixelGapWord(blocks, candidate.x)] & (1u << (candidate.x % 32u))) != 0u) continue;
        ivec2 pixel = ivec2(candidate.x % frame.width, candidate.x / frame.width);
        uint receiver = imageLoad(gTriangle, pixel).x;
        vec3 p = vec3(imageLoad(gPosition, pixel));
        uvec4 item = clusterData(clusterItems, candidate.y);
        WedgeEdge edge = wedgeEdgeAt(item.x);
        // The mirror's order after the silhouette test and the edge's ball (stage 3): the edge
        // term, the bound (its leaf test with p is implied by the edge's ball).
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
        // (Few candidates are listed: one atomic each costs less than the barriers of groupFlush.)
        // The edge term goes with it, so that wedge_samples.comp does not compute it again.
        uint slot;
        if (deferredAppendAt(candidate.x, item.x, slot)) wedgeTermStore(slot, l, h0, h1, kE);
    }
    boundTests = subgroupAdd(boundTests);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, boundTests);
#endif
}
