#version 450
// The volume passes from the hulls of stsv_hull.comp and wedge_hull.comp: one vertex of a hull
// triangle, its volume's record index as a flat varying (the fragment reads the record). The
// vertices are read as texels: a texel fetch at a per-lane index is a vector gather on
// lavapipe, a storage-buffer load a loop over the lanes.
#extension GL_GOOGLE_include_directive : require
#include "render/shaders/frame_bindings.glsl"
#include "render/vulkan/gpu_volumes_dh.h"
#include "render/shaders/hull_faces.glsl"

layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_HULL_VERTEX_TEXELS) uniform usamplerBuffer hullTexels;

layout(location = 0) flat out uint outRecord;

void main() {
    // A draw past the buffer (an overflow the host reports) draws nothing there.
    bool inBuffer = gl_VertexIndex < textureSize(hullTexels);
    uvec4 v = inBuffer ? texelFetch(hullTexels, gl_VertexIndex) : uvec4(0u);
    gl_Position = hullClipPosition(uintBitsToFloat(v.xyz));
    outRecord = inBuffer ? v.w : 0xffffffffu;
}
