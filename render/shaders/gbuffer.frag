#version 450
// G-buffer pass: world position and triangle id of the visible surface. Perforated triangles
// are alpha-tested with the shared texel rule, so the visible point is the surface behind a hole;
// translucent ones are not drawn into it (as the Embree G-buffer's primary rays).
#extension GL_GOOGLE_include_directive : require
#include "render/shaders/frame_bindings.glsl"

layout(location = 0) in vec2 inBary;
layout(location = 0) out vec4 outPosition; ///< world units, w = 1
layout(location = 1) out uint outTriangle;

void main() {
    uint tri = uint(gl_PrimitiveID);
    GpuTriangle t = triangles[tri];
    // Translucent triangles are not receivers: the visible point is what lies behind them.
    if ((t.flags & GPU_TRIANGLE_TRANSLUCENT) != 0u) discard;
    if ((t.flags & STSV_FLAG_OPAQUE) == 0u) {
        vec2 uv = t.t0 + inBary.x * (t.t1 - t.t0) + inBary.y * (t.t2 - t.t0);
        uint wrap = (t.flags & STSV_FLAG_CLAMP) != 0u ? WRAP_CLAMP : WRAP_REPEAT;
        ivec2 texel = texelAt(uv, textureSizeOf(t.texture), wrap);
        if (!alphaBlocks(alphaAt(t.texture, texel))) discard;
    }
    // p from the barycentrics (as Embree's G-buffer): it lies on the triangle's plane to round-off.
    outPosition = vec4(gpuPointOnTriangle(t, inBary), 1.0);
    outTriangle = tri;
}
