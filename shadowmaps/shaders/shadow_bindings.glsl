// Descriptor declarations of the image-based passes (set GPU_SET_FAMILY, shadowmaps/vulkan/gpu_shadowmaps_dh.h): the
// light's map, the map views and filter knobs, the Poisson-disk taps; with AVSM_LISTS the
// transmittance functions' fragment lists, with AVSM_BINDINGS the functions themselves.
#ifndef STSV_SHADERS_SHADOW_BINDINGS_GLSL
#define STSV_SHADERS_SHADOW_BINDINGS_GLSL

#include "shadowmaps/vulkan/gpu_shadowmaps_dh.h"
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

#ifndef SHADOW_MAP_WRITE
// The data access of shadowmaps/shadow_filter_dh.h: the rasterised map, the uploaded taps.
struct ShadowMapSource {
    uint size;
};
float shadowMapSourceDepth(ShadowMapSource s, uint face, ivec2 texel) {
    return gpuShadowDepthOf(shadowDepth[(face * s.size + uint(texel.y)) * s.size + uint(texel.x)]);
}
vec2 shadowMapSourceTap(ShadowMapSource s, uint i) {
    return shadowTaps[i];
}
#define SHADOW_MAP_SOURCE
#include "shadowmaps/shadow_filter_dh.h"
#endif

#ifdef FILTERED_MAP_BINDINGS
// The light's planes, summed-area sums or mip texels (the row's filter decides which), reached by
// device address (ShadowMapView::representationLow/High): they outgrow a storage buffer's range. Needs
// GL_EXT_shader_explicit_arithmetic_types_int64 and GL_EXT_buffer_reference.
layout(buffer_reference, std430, buffer_reference_align = 8) buffer FilteredSumRef { int64_t value; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer FilteredMipRef { float value; };

// The data access of shadowmaps/filtered_lookup_dh.h over the light's planes.
struct FilteredSource {
    uint64_t address;
    uint satPlane; ///< entries per summed-area plane: (size + 1)²
    uint mipPlane; ///< texels per mip plane: filteredMipPlaneTexels(size)
};
FilteredSumRef filteredSumAt(FilteredSource s, uint plane, uint index) {
    return FilteredSumRef(s.address + 8ul * (uint64_t(plane) * uint64_t(s.satPlane) + uint64_t(index)));
}
FilteredMipRef filteredMipAt(FilteredSource s, uint plane, uint index) {
    return FilteredMipRef(s.address + 4ul * (uint64_t(plane) * uint64_t(s.mipPlane) + uint64_t(index)));
}
int64_t filteredSourceSum(FilteredSource s, uint plane, uint index) {
    return filteredSumAt(s, plane, index).value;
}
float filteredSourceMip(FilteredSource s, uint plane, uint index) {
    return filteredMipAt(s, plane, index).value;
}
#define FILTERED_SUM int64_t
#define FILTERED_SOURCE
#include "shadowmaps/filtered_lookup_dh.h"

FilteredSource filteredSourceOf(ShadowMapView v) {
    FilteredSource s;
    s.address = packUint2x32(uvec2(v.representationLow, v.representationHigh));
    s.satPlane = (v.size + 1u) * (v.size + 1u);
    s.mipPlane = filteredMipPlaneTexels(v.size);
    return s;
}
#endif

#ifdef AVSM_LISTS
// The light's fragment lists: the heads, and the fragments by device address (GpuAvsmLists).
// Needs GL_EXT_shader_explicit_arithmetic_types_int64 and GL_EXT_buffer_reference.
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_AVSM_HEADS) buffer AvsmHeads { uint avsmHeads[]; };
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_AVSM_LISTS) readonly buffer AvsmLists { GpuAvsmLists avsmLists; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer AvsmFragmentRef { uvec4 value; };

/// Fragment `i` of the lists (0 ≤ i < avsmLists.capacity).
AvsmFragmentRef avsmFragmentAt(uint i) {
    return AvsmFragmentRef(packUint2x32(uvec2(avsmLists.fragmentsLow, avsmLists.fragmentsHigh)) + 16ul * uint64_t(i));
}
#endif

#ifdef AVSM_BINDINGS
// The light's transmittance functions (`avsm`, `vpcss`), words as gpuAvsmHeader and
// gpuAvsmNodeWord lay them out, reached by device address (ShadowMapView::representationLow/High):
// they outgrow a storage buffer's range. Needs GL_EXT_shader_explicit_arithmetic_types_int64 and
// GL_EXT_buffer_reference.
layout(buffer_reference, std430, buffer_reference_align = 4) buffer AvsmWordRef { uint value; };

AvsmWordRef avsmWordAt(uint64_t address, uint word) {
    return AvsmWordRef(address + 4ul * uint64_t(word));
}

// The data access of shadowmaps/avsm_filter_dh.h.
struct AvsmSource {
    uint64_t address;
    uint size;
    uint texels;   ///< faces × size²
    uint maxNodes; ///< avsm_nodes
};
AvsmSource avsmSourceOf(ShadowMapView v) {
    AvsmSource s;
    s.address = packUint2x32(uvec2(v.representationLow, v.representationHigh));
    s.size = v.size;
    s.texels = v.faces * v.size * v.size;
    s.maxNodes = shadowParams.avsmNodes;
    return s;
}
uint avsmTexelIndex(AvsmSource s, uint face, ivec2 texel) {
    return (face * s.size + uint(texel.y)) * s.size + uint(texel.x);
}
uint avsmSourceCount(AvsmSource s, uint face, ivec2 texel) {
    return gpuAvsmHeaderCount(avsmWordAt(s.address, avsmTexelIndex(s, face, texel)).value);
}
float avsmSourceDepth(AvsmSource s, uint face, ivec2 texel, uint j) {
    uint word = gpuAvsmNodeWord(s.texels, avsmTexelIndex(s, face, texel), s.maxNodes, j);
    return uintBitsToFloat(avsmWordAt(s.address, word).value);
}
uint avsmSourceUnits(AvsmSource s, uint face, ivec2 texel, uint j) {
    uint word = gpuAvsmNodeWord(s.texels, avsmTexelIndex(s, face, texel), s.maxNodes, j);
    return avsmWordAt(s.address, word + 1u).value;
}
vec2 avsmSourceTap(AvsmSource s, uint i) {
    return shadowTaps[i];
}
#define AVSM_SOURCE
#include "shadowmaps/avsm_filter_dh.h"
#endif

#endif // STSV_SHADERS_SHADOW_BINDINGS_GLSL
