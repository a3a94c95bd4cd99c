#version 450
// DCS's silhouette edges through the light's cluster tree (DESIGN §4.5; the CPU mirror's walk,
// render/cpu/cpu_wedges.cpp forEachPixel and forEachSilhouette, with the same dh tests): a
// workgroup per 16 × 16 screen tile bounds the visible points of its pixels, walks the tree of
// the light's potential silhouettes (wedges/silhouette_edges.h) with that region and keeps the
// leaves that may add to it (edge_cluster_dh.h clusterMayAdd); then each pixel tests those leaves'
// with the region of its 4 × 4 block of pixels (as the mirror's blocks), and each pixel tests its
// block's leaves' balls with its own point, and each edge of a kept leaf that is a silhouette seen from p,
// clipped non-empty between p and the light, with p inside its carrier's bound, adds
// k_e·[r → x crosses the edge] to each light sample x's 16-bit counter (Forest, Barthe & Paulin
// 2008) — what the wedge draw and wedge_samples.comp add, without a volume, a fragment or a list.
// The tests are conservative, so the culling changes no counter; wedge_fold.comp adds D(r).
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#include "wedges/wedge_term.glsl"
#include "wedges/edge_cluster_dh.h"

// Leaves a walk step keeps before the pixels test them (the walk resumes from its stack after).
#define CLUSTER_LIST 1024u

// 256 invocations a tile, the 16 of each 4 × 4 block of it consecutive: a SIMD batch of them
// shares its block's leaves.
layout(local_size_x = 256) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };
layout(std430, set = GPU_SET_FRAME, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_NODES) uniform usamplerBuffer clusterNodes;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_ITEMS) uniform usamplerBuffer clusterItems;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CLUSTER_BOUNDS) uniform usamplerBuffer clusterBounds;

shared vec3 tileLo[256];
shared vec3 tileHi[256];
shared uint stack[GPU_CLUSTER_STACK];
shared uint stackSize;
shared uint leaves[CLUSTER_LIST];
shared uint leafCount;
shared vec4 blockRegion[16];
shared uint blockLeaves[16][CLUSTER_LIST / 32u]; // bit i: the block keeps leaves[i]
shared uint boundTests;
shared uint visits;
shared uint nodeTests;
shared uint nodesRejected;

/// Node `index`: its ball, cone and texel 2 (first, count, inverseNormal, faceReach).
vec4 nodeBall(uint index) { return uintBitsToFloat(texelFetch(clusterNodes, int(index * GPU_CLUSTER_NODE_TEXELS))); }
vec4 nodeCone(uint index) {
    return uintBitsToFloat(texelFetch(clusterNodes, int(index * GPU_CLUSTER_NODE_TEXELS + 1u)));
}
uvec4 nodeRange(uint index) { return texelFetch(clusterNodes, int(index * GPU_CLUSTER_NODE_TEXELS + 2u)); }

/// Whether p lies in carrier c's bound: in one of its volumes and in its light planes
/// (wedges/silhouette_edges.h FaceBound::contains).
bool insideBound(uint c, vec3 p) {
    uint base = c * GPU_CLUSTER_BOUND_TEXELS;
    uvec4 counts = texelFetch(clusterBounds, int(base));
    bool inside = false;
    for (uint v = 0u; v < counts.x && !inside; ++v) {
        StsvVolume vol;
        vol.planeCount = v == 0u ? counts.y : counts.z;
        for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i)
            vol.planes[i] = uintBitsToFloat(texelFetch(clusterBounds, int(base + 1u + v * STSV_VOLUME_MAX_PLANES + i)));
        inside = stsvPointInVolume(vol, p);
    }
    if (!inside) return false;
    StsvLightPlanes lp;
    lp.count = counts.w;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i)
        lp.planes[i] = uintBitsToFloat(texelFetch(clusterBounds, int(base + 1u + 2u * STSV_VOLUME_MAX_PLANES + i)));
    return stsvPointInLightPlanes(lp, p);
}

void main() {
    uint local = gl_LocalInvocationIndex;
    uint block = local / 16u;
    ivec2 pixel = ivec2(gl_WorkGroupID.xy * 16u + uvec2(4u * (block % 4u) + local % 4u, 4u * (block / 4u) + (local / 4u) % 4u));
    bool inside = pixel.x < int(frame.width) && pixel.y < int(frame.height);
    uint receiver = inside ? imageLoad(gTriangle, pixel).x : GPU_NO_TRIANGLE;
    bool covered = receiver != GPU_NO_TRIANGLE;
    vec3 p = covered ? vec3(imageLoad(gPosition, pixel)) : vec3(0.0);

    // The box of the tile's visible points.
    tileLo[local] = covered ? p : vec3(3.0e38);
    tileHi[local] = covered ? p : vec3(-3.0e38);
    if (local == 0u) {
        boundTests = 0u;
        visits = 0u;
        nodeTests = 0u;
        nodesRejected = 0u;
    }
    barrier();
    // Each block's box (its 16 invocations), then the tile's.
    for (uint stride = 8u; stride > 0u; stride >>= 1u) {
        if (local % 16u < stride) {
            tileLo[local] = min(tileLo[local], tileLo[local + stride]);
            tileHi[local] = max(tileHi[local], tileHi[local + stride]);
        }
        barrier();
    }
    if (local % 16u == 0u)
        blockRegion[block] = tileLo[local].x <= tileHi[local].x ? boxBall(tileLo[local], tileHi[local]) : vec4(0.0, 0.0, 0.0, -1.0);
    barrier();
    for (uint stride = 128u; stride >= 16u; stride >>= 1u) {
        if (local < stride && local % 16u == 0u) {
            tileLo[local] = min(tileLo[local], tileLo[local + stride]);
            tileHi[local] = max(tileHi[local], tileHi[local + stride]);
        }
        barrier();
    }
    vec3 lo = tileLo[0];
    vec3 hi = tileHi[0];
    if (!(lo.x <= hi.x)) return; // no visible point: uniform over the workgroup
    vec4 lightBall = lights[pc.light].sphere;
    vec4 region = boxBall(lo, hi);
    LightHull regionHull = lightHull(region, lightBall);
    bool hasTree = uint(textureSize(clusterNodes)) >= GPU_CLUSTER_NODE_TEXELS;
    if (local == 0u) {
        stackSize = hasTree ? 1u : 0u;
        stack[0] = 0u;
    }

    // The pixel's light frame and its point's light hull.
    Light light = lights[pc.light].light;
    LightFrame lf = lightFrame(light, p, frame.farDistance);
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    DcsPixel px = dcsSetupPixel(p, lf.center, lf.T, lf.B, shadowTMin(p, lf.center, sceneDiameter));
    bool shading = covered && px.valid != 0.0;
    LightHull pointHull = lightHull(vec4(p, 0.0), lightBall);
    uint pixelIndex = lsPixelIndex(uvec2(pixel), frame.width);
    uint counterWord = lsPixelCounterWord(pixelIndex, uint(SAMPLE_COUNT));
    uint base = interleaveSet(samplePixelOf(uvec2(pixel)), frame.interleave) * uint(SAMPLE_COUNT);
    uvec2 offset = decorrelationOffset(samplePixelOf(uvec2(pixel)), frame.seed);
    bool decorrelate = frame.decorrelate != 0u;
    // The pixel's samples, made when its first edge needs them, and its counters' addends
    // (indexed by the loop's sample: one vector access for a SIMD batch of pixels on lavapipe).
    vec2 ab[SAMPLE_COUNT];
    bool sampled = false;
    uint counts[SAMPLE_COUNT / 2];
    for (uint j = 0u; j < uint(SAMPLE_COUNT / 2); ++j) counts[j] = 0u;
    uint myTests = 0u;
    uint myVisits = 0u;
    uint walkTests = 0u;
    uint walkRejected = 0u;
    uint blockTests = 0u;
    uint blockRejected = 0u;
    barrier();

    for (;;) {
        // One invocation walks until the list is full or the stack empty.
        if (local == 0u) {
            uint count = 0u;
            uint size = stackSize;
            while (size > 0u && count < CLUSTER_LIST) {
                uint index = stack[--size];
                uvec4 range = nodeRange(index);
                ++walkTests;
                if (!clusterMayAdd(nodeBall(index), nodeCone(index), uintBitsToFloat(range.z),
                                   uintBitsToFloat(range.w), region, regionHull)) {
                    ++walkRejected;
                } else if (range.y > 0u) {
                    leaves[count++] = index;
                } else {
                    stack[size++] = range.x + 1u;
                    stack[size++] = range.x;
                }
            }
            stackSize = size;
            leafCount = count;
        }
        for (uint w = local; w < 16u * (CLUSTER_LIST / 32u); w += 256u) blockLeaves[w / (CLUSTER_LIST / 32u)][w % (CLUSTER_LIST / 32u)] = 0u;
        barrier();
        uint count = leafCount;
        bool more = stackSize > 0u;
        // Invocation t tests leaves t % 16, t % 16 + 16, … with block t / 16's region.
        {
            vec4 blockBall = blockRegion[block];
            if (blockBall.w >= 0.0) {
                LightHull blockHull = lightHull(blockBall, lightBall);
                for (uint i = local % 16u; i < count; i += 16u) {
                    uint index = leaves[i];
                    uvec4 range = nodeRange(index);
                    ++blockTests;
                    if (clusterMayAdd(nodeBall(index), nodeCone(index), uintBitsToFloat(range.z),
                                      uintBitsToFloat(range.w), blockBall, blockHull))
                        atomicOr(blockLeaves[block][i / 32u], 1u << (i % 32u));
                    else
                        ++blockRejected;
                }
            }
        }
        barrier();
        for (uint i = 0u; i < count && shading; ++i) {
            if ((blockLeaves[block][i / 32u] & (1u << (i % 32u))) == 0u) continue;
            uint index = leaves[i];
            if (!ballMeetsLightHull(nodeBall(index), pointHull)) continue;
            uvec4 range = nodeRange(index);
            for (uint k = range.x; k < range.x + range.y; ++k) {
                uvec4 item = texelFetch(clusterItems, int(k));
                WedgeEdge edge = wedgeEdgeAt(item.x);
                WedgeFaces faces = wedgeFacesOf(edge);
                if (wedgeWorldWeight(p, edge.v0, edge.v1, faces, receiver) == 0) continue;
                if (!ballMeetsLightHull(edgeBall(edge.v0, edge.v1), pointHull)) continue;
                vec3 l;
                vec3 h0;
                vec3 h1;
                int kE;
                if (!wedgeEdgeTerm(px, edge.v0, edge.v1, faces, receiver, l, h0, h1, kE)) continue;
                ++myTests;
                if (!insideBound(item.y, p)) continue;
                ++myVisits;
                // Only the samples in the edge's crossing region can cross it (dcsSampleRegion).
                vec2 regionLo;
                vec2 regionHi;
                if (!dcsSampleRegion(l, h0, h1, vec2(-1.0), vec2(1.0), regionLo, regionHi)) continue;
                if (!sampled) {
                    for (uint s = 0u; s < uint(SAMPLE_COUNT); ++s)
                        ab[s] = pixelSamplePoint(base, s, offset, decorrelate, lf.domain);
                    sampled = true;
                }
                for (uint s = 0u; s < uint(SAMPLE_COUNT); ++s) {
                    if (any(lessThan(ab[s], regionLo)) || any(greaterThan(ab[s], regionHi))) continue;
                    // Modular, as the counters: a negative addend wraps across the word's two
                    // 16-bit halves, which wedge_fold.comp undoes.
                    counts[lsCounterWord(s)] += uint(kE * dcsSampleCrossing(l, h0, h1, ab[s])) << lsCounterShift(s);
                }
            }
        }
        barrier();
        if (!more) break;
    }
    // The pixel's words are this invocation's alone.
    if (sampled)
        for (uint j = 0u; j < uint(SAMPLE_COUNT / 2); ++j) counters[counterWord + j] += counts[j];
    atomicAdd(boundTests, myTests);
    atomicAdd(visits, myVisits);
    atomicAdd(nodeTests, blockTests);
    atomicAdd(nodesRejected, blockRejected);
    barrier();
    if (local == 0u) {
        atomicAdd(stats[pc.light].fragments, boundTests);
        atomicAdd(stats[pc.light].inside, visits);
        atomicAdd(stats[pc.light].clusterTests, walkTests + nodeTests);
        atomicAdd(stats[pc.light].clustersRejected, walkRejected + nodesRejected);
    }
}
