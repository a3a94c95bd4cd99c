#version 450
// z-fail count of dcs_center.geom's volumes (DESIGN §4.5): a back face behind the visible point
// p is where the view ray leaves a volume (+w), a front face where it enters (−w), so p collects
// +1 per volume that contains it. The near cap of the visible triangle itself is skipped
// (self-shadowing rule); wedge_fold.comp accounts for the rest of that triangle's volume.
//
// Front or back is the rasteriser's facing (gl_FrontFacing), not the world plane's: the
// rasteriser covers a pixel with the triangles of a closed surface a consistent number of times
// only counted with its own orientations. A thin quad (a 1 mm edge extruded to the far distance)
// whose snapped corners fold one of its triangles over the other covers some pixels twice; with
// the facing of the plane both count alike (fence-mesh lost the light at 360 of 12 288 pixels at
// 128×96), with the rasteriser's the folded one cancels the other.
//
// "Behind p" is decided in world space, not by the depth buffer: the face is behind p when p
// and the eye lie on the same side of the face's plane (the view ray through the pixel centre
// meets the face, so it meets it beyond p). A near cap starts SHADOW_T_MIN·distance behind its
// triangle, and on a closed box as thin as that gap (a 0.5 mm wire 5 m from the light) the cap
// lies a tenth of a millimetre from the points of the box's far side: closer than the depth
// buffer resolves there, far more than the float plane test does. The pipeline's depth test
// (GREATER, early) only prunes: its bias (setBehindVisiblePointDepth, render/
// gpu_frame_resources.h) lets faces slightly in front of p through, and this test rejects them.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "common/frame_bindings.glsl"
#include "render/vulkan/gpu_wedges_dh.h"

layout(early_fragment_tests) in;

layout(location = 0) flat in int inWeight;
layout(location = 1) flat in uint inSkipTriangle;
layout(location = 2) flat in vec4 inPlane;

layout(set = GPU_SET_FRAME, binding = GPU_BINDING_POSITION, rgba32f) readonly uniform image2D gPosition;
layout(set = GPU_SET_FRAME, binding = GPU_BINDING_TRIANGLE_ID, r32ui) readonly uniform uimage2D gTriangle;
layout(set = GPU_SET_FAMILY, binding = GPU_BINDING_CENTER, r32i) uniform iimage2D centerCount;
layout(std430, set = GPU_SET_FAMILY, binding = GPU_BINDING_FAMILY_STATS) buffer Stats { GpuWedgeStats stats[]; };

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    bool counted = false;
    if (inSkipTriangle == GPU_NO_TRIANGLE || imageLoad(gTriangle, pixel).x != inSkipTriangle) {
        vec3 p = vec3(imageLoad(gPosition, pixel));
        float eyeSide = dot(inPlane.xyz, vec3(frame.eye)) + inPlane.w;
        float pointSide = dot(inPlane.xyz, p) + inPlane.w;
        // Behind p: p and the eye on one side of the face's plane.
        counted = eyeSide > 0.0 ? pointSide > 0.0 : pointSide < 0.0;
        // A front face (the outward side towards the eye): the ray enters the volume there.
        if (counted) imageAtomicAdd(centerCount, pixel, gl_FrontFacing ? -inWeight : inWeight);
    }
    uint fragments = subgroupAdd(1u);
    uint countedCount = subgroupAdd(counted ? 1u : 0u);
    if (subgroupElect()) {
        atomicAdd(stats[pc.light].centerFragments, fragments);
        atomicAdd(stats[pc.light].centerCounted, countedCount);
    }
}
