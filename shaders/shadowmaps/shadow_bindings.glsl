// Descriptor declarations of the image-based passes (set GPU_SET_FAMILY, render/vulkan/gpu_shadowmaps_dh.h): the
// light's map, the map views and filter knobs, the Poisson-disk taps.
#ifndef STSV_SHADERS_SHADOW_BINDINGS_GLSL
#define STSV_SHADERS_SHADOW_BINDINGS_GLSL

#include "render/vulkan/gpu_shadowmaps_dh.h"
#include "shadowmaps/shadow_map_dh.h"

#ifdef SHADOW_MAP_WRITE
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_SHADOW_MAP) buffer ShadowDepth { uint shadowDepth[]; };
#else
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_SHADOW_MAP) readonly buffer ShadowDepth { uint shadowDepth[]; };
#endif
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_SHADOW_VIEWS) readonly buffer ShadowViews {
    ShadowFilterParams shadowParams;
    ShadowMapView shadowViews[];
};
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_SHADOW_TAPS) readonly buffer ShadowTaps { vec2 shadowTaps[]; };

#endif // STSV_SHADERS_SHADOW_BINDINGS_GLSL
