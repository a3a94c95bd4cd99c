// The tree of the opaque triangles that counts a segment's layers (wedges/layer_bvh_dh.h
// layerCount): its tables bound as texel buffers (a vector gather on lavapipe) in the wedge
// family's set, for dcs_center.comp (D(r)) and dcs_rays.comp (the samples of the blocks that cast rays).
#ifndef STSV_SHADERS_LAYER_BVH_GLSL
#define STSV_SHADERS_LAYER_BVH_GLSL

layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_LAYER_NODES) uniform usamplerBuffer layerNodes;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_LAYER_TRIANGLES) uniform usamplerBuffer layerTriangles;

// The value layer_bvh_dh.h takes is empty: the tables are the bindings above.
struct LayerBvh {
    uint unused;
};
uvec4 layerBvhNode(LayerBvh bvh, uint texel) { return texelFetch(layerNodes, int(texel)); }
uvec4 layerBvhTriangle(LayerBvh bvh, uint texel) { return texelFetch(layerTriangles, int(texel)); }
#define LAYER_BVH
#include "wedges/layer_bvh_dh.h"

/// The tree's node count; a scene without opaque triangles binds a one-texel stand-in: none.
uint layerNodeCount() { return uint(textureSize(layerNodes)) / LAYER_BVH_NODE_TEXELS; }

#endif
