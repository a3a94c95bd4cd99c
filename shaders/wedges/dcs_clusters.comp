#version 450
// DCS's silhouette edges through the light's cluster tree (DESIGN §4.5; the CPU mirror's walk,
// render/cpu/cpu_wedges.cpp forEachPixel and forEachSilhouette, with the same dh tests), over
// the lists of common/cluster_walk.glsl:
//   CLUSTER_STAGE 0, 1, 2: the blocks, the indirect dispatches, the walk of a level; a leaf's
//     edges are tested as clusters of their own, and those that may add to the block are kept
//     as (block, item) pairs;
//   3 (pixels): an invocation a kept pair, for the block's 16 pixels: an edge that is a
//     silhouette seen from the pixel's p (most are not) and whose ball meets the segments from p
//     to the light makes a (pixel, item) candidate, appended with one atomic a pair;
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
#include "wedges/wedge_term.glsl"
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
// A leaf holds up to EDGE_CLUSTER_LEAF (32) edges, which one invocation may keep for a block
// between two flushes of its workgroup's appends.
#define CLUSTER_GROUP_SIZE GPU_DCS_CLUSTER_GROUP
#include "common/cluster_walk.glsl"

layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BOUNDS) uniform usamplerBuffer clusterBounds;

/// A leaf's edge is a cluster of its own (ball and cone of its two faces).
void clusterKeep(uint block, uint item, vec4 region, LightHull hull, inout uint tests, inout uint rejected) {
    ++tests;
    if (tableMayAdd(clusterItems, item, region, hull))
        groupAppend(GROUP_KEPT, uvec2(block, item));
    else
        ++rejected;
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
    for (uint e = gl_GlobalInvocationID.x; e < entries; e += stride) {
        uvec2 pair = pairs[listBase(GPU_CLUSTER_KEPT) + e];
        // The edge once for the block's 16 pixels.
        WedgeEdge edge = wedgeEdgeAt(clusterData(clusterItems, pair.y).x);
        WedgeFaces faces = wedgeFacesOf(edge);
        uint silhouette = 0u;
        vec3 p;
        uint receiver;
        // The mirror's first two tests (forEachSilhouette): the edge is a silhouette seen from p,
        // its ball meets the segments from p to the light.
        vec4 ball = edgeBall(edge.v0, edge.v1);
        vec4 lightBall = lights[pc.light].sphere;
        if (faces.count <= 2u) {
            // The faces' normals once for the 16 pixels (dcsTwoFaceWeight).
            uint t0 = wedgeFaceTriangle(faces, faces.first);
            vec3 n0 = dcsFaceNormal(edge.v0, edge.v1, wedgeFaceOpposite(faces, faces.first));
            bool second = faces.count == 2u;
            uint t1 = second ? wedgeFaceTriangle(faces, faces.first + 1u) : GPU_NO_TRIANGLE;
            vec3 n1 = second ? dcsFaceNormal(edge.v0, edge.v1, wedgeFaceOpposite(faces, faces.first + 1u)) : vec3(0.0);
            for (uint lane = 0u; lane < 16u; ++lane) {
                if (!blockPoint(pair.x, lane, p, receiver)) continue;
                if (dcsTwoFaceWeight(p, edge.v0, n0, t0, n1, t1, receiver) != 0 && ballMeetsLightHull(ball, lightHull(vec4(p, 0.0), lightBall))) silhouette |= 1u << lane;
            }
        } else {
            for (uint lane = 0u; lane < 16u; ++lane)
                if (blockPoint(pair.x, lane, p, receiver) && wedgeWorldWeight(p, edge.v0, edge.v1, faces, receiver) != 0 &&
                    ballMeetsLightHull(ball, lightHull(vec4(p, 0.0), lightBall)))
                    silhouette |= 1u << lane;
        }
        appendPixels(GPU_CLUSTER_CANDIDATES, pair.x, silhouette, pair.y);
    }
#else
    uint entries = listEntries(GPU_CLUSTER_CANDIDATES);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
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
        deferredAppend(candidate.x, item.x);
    }
    boundTests = subgroupAdd(boundTests);
    if (subgroupElect()) atomicAdd(stats[pc.light].fragments, boundTests);
#endif
}
