#version 450
// Image-based visibility per pixel (DESIGN §4.6): PCF, a step of PCSS, a filtered lookup, or avsm and
// vpcss on the transmittance functions (shadowmaps/avsm_filter_dh.h), with the
// functions of shadowmaps/shadow_filter_dh.h that the CPU backend runs (shadowmaps/cpu/cpu_shadowmaps.cpp).
//   SHADOW_FILTER_STEP 0: a fixed kernel over the depth map (pcf: depthKernelVisibility) → v_coef in the
//                         v_coef image
//                      1: PCSS blocker search → the filter radius (uv), −1 when no blocker
//                      2: PCSS filter of that radius → v_coef
//                      3: a filtered representation (shadowmaps/filtered_lookup_dh.h) over a kernel
//                         of fm_world_radius at the receiver, or of the radius step 1 left
//                         (fm_kernel=1) → v_coef
//                      4: avsm, the transmittance function's lookup (shadowmaps/avsm_filter_dh.h) → v_coef
//                      5: vpcss blocker search → the filter radius (uv), −1 when no light is lost
//                      6: vpcss filter of that radius → v_coef
#extension GL_GOOGLE_include_directive : require
#ifndef SHADOW_FILTER_STEP
#define SHADOW_FILTER_STEP 0
#endif
#if SHADOW_FILTER_STEP == 3
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#define FILTERED_MAP_BINDINGS
#elif SHADOW_FILTER_STEP >= 4
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#define AVSM_BINDINGS
#endif
#include "render/shaders/frame_bindings.glsl"
#include "shadowmaps/shaders/shadow_bindings.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_VCOEF, r32f) uniform image2D vcoefImage;
#if SHADOW_FILTER_STEP <= 1 || SHADOW_FILTER_STEP == 5
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuShadowMapStats stats[]; };
#endif


void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= int(frame.width) || pixel.y >= int(frame.height)) return;
    uint tri = imageLoad(gTriangle, pixel).x;
    if (tri == GPU_NO_TRIANGLE) return;
    ShadowMapView v = shadowViews[pc.light];
    ShadowMapSource src;
    src.size = v.size;
    vec3 p = vec3(imageLoad(gPosition, pixel));
    vec3 n = gpuShadingNormal(triangles[tri], vec3(frame.eye), p);
    ShadowReceiver r = shadowReceiver(v, p, n, shadowParams.bias, shadowParams.normalOffset,
                                      shadowTapRotation(samplePixelOf(uvec2(pixel)), frame.seed, frame.decorrelate != 0u));
#if SHADOW_FILTER_STEP == 0
    bool strided;
    float result = depthKernelVisibility(v, src, r, shadowParams, strided);
    if (strided) atomicAdd(stats[pc.light].kernelClamped, 1u);
#elif SHADOW_FILTER_STEP == 1
    PcssBlockerStep step = pcssBlockerStep(v, r, pcssAverageBlocker(v, src, r, shadowParams.blockerTaps, shadowParams.maxSearch),
                                           shadowParams.maxSearch, shadowParams.maxKernel);
    float result = step.radius;
    if (step.searchClamped != 0u) atomicAdd(stats[pc.light].searchClamped, 1u);
    if (step.kernelClamped != 0u) atomicAdd(stats[pc.light].kernelClamped, 1u);
#elif SHADOW_FILTER_STEP == 2
    float radius = imageLoad(vcoefImage, pixel).x;
    float result = radius < 0.0 ? 1.0
                                : pcssFilter(v, src, r, radius, shadowParams.blockerTaps, shadowParams.filterTaps);
#elif SHADOW_FILTER_STEP == 4
    float result = avsmVisibility(v, avsmSourceOf(v), r);
#elif SHADOW_FILTER_STEP == 5
    PcssBlockerStep step = pcssBlockerStep(v, r, vpcssAverageBlocker(v, avsmSourceOf(v), r, shadowParams.vpcssTaps, shadowParams.maxSearch),
                                           shadowParams.maxSearch, shadowParams.maxKernel);
    float result = step.radius;
    if (step.searchClamped != 0u) atomicAdd(stats[pc.light].searchClamped, 1u);
    if (step.kernelClamped != 0u) atomicAdd(stats[pc.light].kernelClamped, 1u);
#elif SHADOW_FILTER_STEP == 6
    float radius = imageLoad(vcoefImage, pixel).x;
    float result = radius < 0.0 ? 1.0
                                : vpcssFilter(v, avsmSourceOf(v), r, radius, shadowParams.vpcssTaps, shadowParams.vpcssTaps);
#else
    // Step 1 left the radius in uv (−1: no blocker, lit); the lookup takes texels.
    float radius = shadowParams.kernel != 0u ? imageLoad(vcoefImage, pixel).x * float(v.size)
                                             : filteredFixedRadius(r, shadowParams.worldRadius);
    FilteredSource filtered = filteredSourceOf(v);
    float result = radius < 0.0 ? 1.0 : filteredVisibility(v, shadowParams, filtered, r, radius);
#endif
    imageStore(vcoefImage, pixel, vec4(result));
}
