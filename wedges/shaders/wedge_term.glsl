// The per-pixel edge term of a potential silhouette edge (DESIGN §4.5; wedges/
// wedge_fragment_dh.h, which wedges/cpu/cpu_wedges.cpp forEachSilhouette calls too), for wedge.frag
// (PW), wedge_samples.comp (DCS's pairs the wedge draw listed) and dcs_clusters.comp (the pairs
// the walk lists, with their term): the edge's faces from edgeFaces[], the pixel's light frame,
// the edge projected onto it, and DCS's signed crossings per light sample.
#ifndef STSV_SHADERS_WEDGE_TERM_GLSL
#define STSV_SHADERS_WEDGE_TERM_GLSL

#include "wedges/shaders/wedge_bindings.glsl"
#include "render/shaders/deferred_list.glsl"

/// The data access of wedges/wedge_fragment_dh.h: the edge's faces, GpuEdgeFace texel 0
/// (opposite, triangle).
struct WedgeFaces {
    uint first;
    uint count;
};
uint wedgeFaceTriangle(WedgeFaces faces, uint f) {
    return texelFetch(edgeFaceTexels, int(f * GPU_EDGE_FACE_TEXELS)).w;
}
vec3 wedgeFaceOpposite(WedgeFaces faces, uint f) {
    return uintBitsToFloat(texelFetch(edgeFaceTexels, int(f * GPU_EDGE_FACE_TEXELS)).xyz);
}
#define WEDGE_FACES
#include "wedges/wedge_fragment_dh.h"
#include "volumes/light_hull_dh.h"

WedgeFaces wedgeFacesOf(WedgeEdge edge) {
    WedgeFaces faces;
    faces.first = edge.firstFace;
    faces.count = edge.faceCount;
    return faces;
}

/// Edge `edge` seen from the visible point p of triangle `receiver`, light pc.light: the
/// pixel's light frame lf, the edge projected onto it (h0, h1, l = h0 × h1) and its weight k;
/// false when it adds nothing (no valid frame, the edge's ball misses the cone from p to the
/// light's ball, k = 0, nothing between p and the light).
bool wedgePixelTerm(vec3 p, WedgeEdge edge, uint receiver, out vec3 l, out vec3 h0, out vec3 h1, out int k,
                    out LightFrame lf) {
    Light light = lights[pc.light].light;
    lf = lightFrame(light, p, frame.farDistance);
    float sceneDiameter = length(vec3(frame.boxHi) - vec3(frame.boxLo));
    DcsPixel px = dcsSetupPixel(p, lf.center, lf.T, lf.B, shadowTMin(p, lf.center, sceneDiameter));
    l = vec3(0.0);
    h0 = vec3(0.0);
    h1 = vec3(0.0);
    k = 0;
    if (px.valid == 0.0) return false;
    if (!ballMeetsLightCone(edgeBall(edge.v0, edge.v1), lightCone(p, lights[pc.light].sphere)))
        return false;
    return wedgeEdgeTerm(px, edge.v0, edge.v1, wedgeFacesOf(edge), receiver, l, h0, h1, k);
}

/// The edge term of deferred pair `slot` (GPU_DEFERRED_TERM_TEXELS uvec4: (l, k), (h0.xy, h1.xy):
/// dcsSampleCrossing reads only x and y of the clipped edge's frame points).
void wedgeTermStore(uint slot, vec3 l, vec3 h0, vec3 h1, int k) {
    deferredTerms[GPU_DEFERRED_TERM_TEXELS * slot] = uvec4(floatBitsToUint(l), uint(k));
    deferredTerms[GPU_DEFERRED_TERM_TEXELS * slot + 1u] = floatBitsToUint(vec4(h0.xy, h1.xy));
}
void wedgeTermLoad(uint slot, out vec3 l, out vec3 h0, out vec3 h1, out int k) {
    uvec4 t0 = deferredTerms[GPU_DEFERRED_TERM_TEXELS * slot];
    vec4 t1 = uintBitsToFloat(deferredTerms[GPU_DEFERRED_TERM_TEXELS * slot + 1u]);
    l = uintBitsToFloat(t0.xyz);
    k = int(t0.w);
    h0 = vec3(t1.xy, 0.0);
    h1 = vec3(t1.zw, 0.0);
}

#endif
