#version 450
// STSV fragment (STSV paper Algorithm 2, §2.3–2.4; DESIGN §4.3–4.4): one fragment per pixel
// whose visible point p lies in front of the volume's back faces. Rejects p outside the volume,
// applies the self-shadowing rule, then volumes/stsv_fragment_dh.h — the side-ownership rule and
// per light sample the projective test (Eq. 1–3) and the texel rule (Eq. 4–5) — which the CPU
// mirror (volumes/cpu/cpu_stsv.cpp) calls in its loop. Output: occlusion bits through logic-op OR
// attachments, or packed 16-bit counters (sampling/ls_buffer_dh.h); in a transmittance frame a
// translucent triangle's optical depths too, atomic sums per sample (stsvSampleWord).
#extension GL_GOOGLE_include_directive : require
#ifndef STSV_MESH_PATH
#define STSV_MESH_PATH 0
#endif
// The volume's record from the hull pass (stsv_hull.comp), by index, instead of flat varyings.
#ifndef STSV_HULL_PATH
#define STSV_HULL_PATH 0
#endif
#if STSV_MESH_PATH
#extension GL_EXT_mesh_shader : require
#define STSV_FLAT perprimitiveEXT flat
#else
#define STSV_FLAT flat
#endif
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef LS_COUNTERS
#define LS_COUNTERS 0
#endif
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "render/shaders/frame_bindings.glsl"
#include "volumes/shaders/stsv_volume.glsl"
#include "volumes/shaders/stsv_samples.glsl"


// Counters: the G-buffer depth test must run before the atomics (DESIGN §4.4).
layout(early_fragment_tests) in;

// The volume's record (GpuStsvRecord): ids and planes first, the triangle only for points inside.
#if STSV_HULL_PATH
layout(location = 0) flat in uint inRecord;
uvec4 volumeIds() { return stsvRecordTexel(inRecord, GPU_STSV_RECORD_IDS); }
vec4 volumePlane(uint i) { return stsvRecordVec4(inRecord, GPU_STSV_RECORD_PLANES + i); }
vec4 volumeLightPlane(uint i) { return stsvRecordVec4(inRecord, GPU_STSV_RECORD_LIGHT_PLANES + i); }
StsvTriangle volumeTriangle(uvec4 ids) { return stsvRecordTriangle(inRecord, ids); }
#else
layout(location = 0) STSV_FLAT in vec4 inM0;
layout(location = 1) STSV_FLAT in vec4 inM1;
layout(location = 2) STSV_FLAT in vec4 inM2;
layout(location = 3) STSV_FLAT in vec4 inUv0E1;
layout(location = 4) STSV_FLAT in vec4 inUvE2;
layout(location = 5) STSV_FLAT in uvec4 inIds;
layout(location = 6) STSV_FLAT in vec4 inPlanes[STSV_VOLUME_MAX_PLANES];
layout(location = 11) STSV_FLAT in vec4 inLightPlanes[STSV_LIGHT_PLANES_MAX];
uvec4 volumeIds() { return inIds; }
vec4 volumePlane(uint i) { return inPlanes[i]; }
vec4 volumeLightPlane(uint i) { return inLightPlanes[i]; }
StsvTriangle volumeTriangle(uvec4 ids) { return stsvUnpackTriangle(inM0, inM1, inM2, inUv0E1, inUvE2, ids); }
#endif

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuStsvStats stats[]; };

// Attachment i holds mask words 2i and 2i + 1 (lsMaskAttachment).
#define MASK_ATTACHMENTS ((WORD_COUNT + 1) / 2)

#if !LS_COUNTERS
layout(location = 0) out uvec2 outMask0;
#if MASK_ATTACHMENTS > 1
layout(location = 1) out uvec2 outMask1;
#endif
#if MASK_ATTACHMENTS > 2
layout(location = 2) out uvec2 outMask2;
layout(location = 3) out uvec2 outMask3;
#endif
#endif

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    uint words[8] = uint[8](0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
#if STSV_HULL_PATH
    // A record past the buffer (an overflow the host reports): nothing to write.
    if (!stsvRecordExists(inRecord)) discard;
#endif
    uvec4 ids = volumeIds();
    uint side = ids.w & 255u;
    bool inside = false;
    // Cheapest rejection first: most fragments lie in front of the volume (the depth test only
    // rejects volumes wholly in front of p), and the plane test needs p alone.
    vec3 p = vec3(imageLoad(gPosition, pixel));
    StsvVolume vol;
    vol.planeCount = (ids.w >> 8u) & 255u;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = volumePlane(i);
    StsvLightPlanes lp;
    lp.count = ids.w >> 16u;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = volumeLightPlane(i);
    // Self-shadowing rule: the visible triangle never shadows its own point.
    bool accepted = stsvPointInVolume(vol, p) && stsvPointInLightPlanes(lp, p) && imageLoad(gTriangle, pixel).x != ids.z;
#if STSV_HULL_PATH
    // The samples of an accepted fragment are tested by stsv_samples.comp, one thread a fragment
    // in full batches: a fragment batch on lavapipe runs every instruction for all its lanes and
    // its sample loop as long as its slowest lane, and small hull triangles leave its lanes
    // mostly idle. A frame whose list was too short grows it and runs again
    // (render/vulkan/gpu_renderer.cpp).
    if (accepted) deferredAppend(lsPixelIndex(uvec2(pixel), frame.width), inRecord);
#else
    if (accepted) {
        StsvTriangle t = volumeTriangle(ids);
        StsvPixel px;
        StsvSampleSource src;
        ivec2 size;
        if (stsvPixelSetup(uvec2(pixel), p, t, side, px, src, size)) {
            inside = true;
#if LS_COUNTERS
            uint counterWord = lsPixelCounterWord(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT));
#endif
            // Every sample: on lavapipe a loop over the samples with a uniform index is cheaper
            // than finding the few in the triangle's projection (stsvSampleRegion's clipping in
            // local arrays doubled the pass). Words outside, bits inside: a per-sample dynamic
            // index into words[] would cost a scatter per lane on SIMD CPUs.
            for (uint w = 0u; w < uint(WORD_COUNT); ++w) {
                uint bits = stsvSampleWord(t, px, src, size, w, lsPixelIndex(uvec2(pixel), frame.width));
#if LS_COUNTERS
                stsvAddOccludedLayers(counterWord, w, bits);
#else
                words[w] = bits;
#endif
            }
        }
    }
#endif
    // Fragment statistics, one atomic per subgroup (per-fragment atomics on one address serialise).
    uint fragments = subgroupAdd(1u);
    uint insideCount = subgroupAdd(inside ? 1u : 0u);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].fragments, fragments);
        atomicAdd(stats[pc.light].inside, insideCount);
    }
#if !LS_COUNTERS
    outMask0 = uvec2(words[0], words[1]);
#if MASK_ATTACHMENTS > 1
    outMask1 = uvec2(words[2], words[3]);
#endif
#if MASK_ATTACHMENTS > 2
    outMask2 = uvec2(words[4], words[5]);
    outMask3 = uvec2(words[6], words[7]);
#endif
#endif
}
