#version 450
// Per-pixel edge term of the opaque occluders (DESIGN §4.5; wedges/wedge_fragment_dh.h, which
// render/cpu_wedges.cpp forEachSilhouette calls too): for a visible point p inside the edge's
// bound, the weight k_e of the edge seen from p (its faces except the visible triangle), the
// edge projected onto the pixel's light frame and clipped to the part between p and the light,
// then
//   DCS (WEDGE_PW 0): for each light sample x, k_e·[r → x crosses the edge]·sign(ℓ·X) added to
//     the sample's 16-bit counter (Forest, Barthe & Paulin 2008). The counters are modular:
//     wedge_fold.comp adds D(r) and reads them as signed (a sample may go below D(r)).
//   PW (WEDGE_PW 1): sign(k_e)·(signed fraction of the light beyond the edge), summed by
//     additive blending (Assarsson & Akenine-Möller 2003).
#extension GL_GOOGLE_include_directive : require
#ifndef SAMPLE_COUNT
#define SAMPLE_COUNT 64
#endif
#ifndef WEDGE_PW
#define WEDGE_PW 0
#endif
// The edge's record from the wedge hull pass (wedge_hull.comp), by index, instead of flat varyings.
#ifndef WEDGE_HULL_PATH
#define WEDGE_HULL_PATH 0
#endif
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "wedge_bindings.glsl"
#include "volumes/extrusion_dh.h"
#include "wedges/dcs_dh.h"
#include "wedges/pw_dh.h"

layout(early_fragment_tests) in;

// The bound's record (GpuWedgeRecord).
#if WEDGE_HULL_PATH
// Read as texels (GPU_WEDGE_RECORD_* offsets): a texel fetch at a per-lane index is a vector
// gather on lavapipe, a storage-buffer load a loop over the lanes.
layout(location = 0) flat in uint inRecord;
layout(set = 0, binding = GPU_BINDING_HULL_RECORD_TEXELS) uniform usamplerBuffer recordTexels;
uvec4 recordTexel(uint i) { return texelFetch(recordTexels, int(inRecord * GPU_HULL_RECORD_TEXELS + i)); }
uvec4 boundIds() { return recordTexel(0u); }
vec4 boundPlane(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_PLANES + i)); }
vec4 boundPlaneSide0(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_PLANES_SIDE0 + i)); }
vec4 boundLightPlane(uint i) { return uintBitsToFloat(recordTexel(GPU_WEDGE_RECORD_LIGHT_PLANES + i)); }
#else
layout(location = 0) flat in uvec4 inIds;
layout(location = 1) flat in vec4 inPlanes[STSV_VOLUME_MAX_PLANES];
layout(location = 6) flat in vec4 inPlanesSide0[STSV_VOLUME_MAX_PLANES];
layout(location = 11) flat in vec4 inLightPlanes[STSV_LIGHT_PLANES_MAX];
uvec4 boundIds() { return inIds; }
vec4 boundPlane(uint i) { return inPlanes[i]; }
vec4 boundPlaneSide0(uint i) { return inPlanesSide0[i]; }
vec4 boundLightPlane(uint i) { return inLightPlanes[i]; }
#endif

layout(set = 0, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = 0, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(std430, set = 0, binding = GPU_BINDING_STATS) buffer Stats { GpuStats stats[]; };
#if WEDGE_PW
layout(location = 0) out float outOcclusion;
#else
layout(std430, set = 0, binding = GPU_BINDING_COUNTERS) buffer Counters { uint counters[]; };
#endif

/// The data access of wedges/wedge_fragment_dh.h: the edge's faces in edgeFaces[].
struct WedgeFaces {
    uint first;
    uint count;
};
uint wedgeFaceTriangle(WedgeFaces faces, uint f) {
    return edgeFaces[f].triangle;
}
vec3 wedgeFaceOpposite(WedgeFaces faces, uint f) {
    return edgeFaces[f].opposite;
}
#define WEDGE_FACES
#include "wedges/wedge_fragment_dh.h"

/// The wedge term of this fragment's edge at pixel `pixel`; false when it has none.
bool edgeTerm(ivec2 pixel, vec3 p, out vec3 l, out vec3 h0, out vec3 h1, out int k, out LightFrame lf) {
#if WEDGE_HULL_PATH
    // A record past the buffer (an overflow the host reports): no term.
    if (inRecord >= uint(textureSize(recordTexels)) / GPU_HULL_RECORD_TEXELS) return false;
#endif
    uvec4 ids = boundIds();
    StsvVolume vol;
    vol.planeCount = ids.z;
    for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol.planes[i] = boundPlane(i);
    if (!stsvPointInVolume(vol, p)) return false;
    StsvLightPlanes lp;
    lp.count = ids.y >> 8u;
    for (uint i = 0u; i < STSV_LIGHT_PLANES_MAX; ++i) lp.planes[i] = boundLightPlane(i);
    if (!stsvPointInLightPlanes(lp, p)) return false;
    if ((ids.w & WEDGE_SIDE0_PRESENT) != 0u) {
        StsvVolume vol0;
        vol0.planeCount = ids.w & 255u;
        for (uint i = 0u; i < STSV_VOLUME_MAX_PLANES; ++i) vol0.planes[i] = boundPlaneSide0(i);
        if (stsvPointInVolume(vol0, p)) return false;
    }
    GpuEdge edge = edges[ids.x];
    WedgeFaces faces;
    faces.first = edge.firstFace;
    faces.count = edge.faceCount;
    uint receiver = imageLoad(gTriangle, pixel).x;
    if (wedgeWorldWeight(p, edge.v0, edge.v1, faces, receiver) == 0) return false;
    Light light = lights[pc.light].light;
    lf = lightFrame(light, p, frame.farDistance);
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    DcsPixel px = dcsSetupPixel(p, lf.center, lf.T, lf.B, shadowTMin(p, lf.center, sceneDiameter));
    if (px.valid == 0.0) return false;
    return wedgeEdgeTerm(px, edge.v0, edge.v1, faces, receiver, l, h0, h1, k);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 p = vec3(imageLoad(gPosition, pixel));
    vec3 l;
    vec3 h0;
    vec3 h1;
    int k;
    LightFrame lf;
    bool inside = edgeTerm(pixel, p, l, h0, h1, k, lf);
    uint fragments = subgroupAdd(1u);
    uint insideCount = subgroupAdd(inside ? 1u : 0u);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].wedgeFragments, fragments);
        atomicAdd(stats[pc.light].wedgeInside, insideCount);
    }
#if WEDGE_PW
    // On lavapipe every wedge fragment pays for the analytic coverage (polygon clipping in
    // local arrays, about 0.5 µs), silhouette or not: PW runs about 10x slower than DCS there.
    if (!inside) discard;
    outOcclusion = float(k > 0 ? 1 : -1) * pwEdgeCoverage(l, h0, h1, lf.domain);
#else
    if (!inside) return; // no outputs: nothing to discard
    uint base = interleaveSet(uvec2(pixel), frame.interleave) * uint(SAMPLE_COUNT);
    uvec2 offset = decorrelationOffset(uvec2(pixel), frame.seed);
    uint counterWord = lsPixelCounterWord(lsPixelIndex(uvec2(pixel), frame.width), uint(SAMPLE_COUNT));
    bool decorrelate = frame.decorrelate != 0u;
    for (uint s = 0u; s < uint(SAMPLE_COUNT); ++s) {
        vec2 ab = pixelSamplePoint(base, s, offset, decorrelate, lf.domain);
        int crossing = dcsSampleCrossing(l, h0, h1, ab);
        // A negative addend wraps modulo 2^32 across the word's two 16-bit counters, which
        // wedge_fold.comp undoes.
        if (crossing != 0)
            atomicAdd(counters[counterWord + lsCounterWord(s)], uint(k * crossing) << lsCounterShift(s));
    }
#endif
}
