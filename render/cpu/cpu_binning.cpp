#include "render/cpu/cpu_binning.h"

#include <limits>

namespace stsv {

/// Pixel rectangle that may hold points of the convex volume (its strip vertices projected, edges
/// crossing the near plane clipped there). False when nothing lies in front of the camera.
bool volumeScreenRect(const StsvVolume& v, const mat4& clipFromWorld, int width, int height, ivec4& rect) {
    constexpr float NEAR_W = 1e-4f;
    vec4 clip[STSV_STRIP_VERTEX_COUNT];
    for (uint i = 0; i < STSV_STRIP_VERTEX_COUNT; ++i)
        clip[i] = clipFromWorld * vec4(vec3(v.vertices[i]), 1.0f);
    vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    bool any = false;
    auto add = [&](vec4 c) {
        const vec2 ndc = vec2(c) / c.w;
        lo = min(lo, ndc);
        hi = max(hi, ndc);
        any = true;
    };
    for (uint i = 0; i < STSV_STRIP_VERTEX_COUNT; ++i) {
        if (clip[i].w > NEAR_W) add(clip[i]);
        for (uint j = i + 1; j < std::min(i + 3, STSV_STRIP_VERTEX_COUNT); ++j) {
            const float wa = clip[i].w - NEAR_W, wb = clip[j].w - NEAR_W;
            if ((wa > 0.0f) != (wb > 0.0f)) {
                vec4 c = clip[i] + (wa / (wa - wb)) * (clip[j] - clip[i]);
                c.w = NEAR_W;
                add(c);
            }
        }
    }
    if (!any) return false;
    lo = clamp(lo, vec2(-1.0f), vec2(1.0f));
    hi = clamp(hi, vec2(-1.0f), vec2(1.0f));
    rect = ivec4(int(std::floor((lo.x * 0.5f + 0.5f) * float(width))),
                 int(std::floor((lo.y * 0.5f + 0.5f) * float(height))),
                 int(std::ceil((hi.x * 0.5f + 0.5f) * float(width))),
                 int(std::ceil((hi.y * 0.5f + 0.5f) * float(height))));
    rect = clamp(rect, ivec4(0), ivec4(width - 1, height - 1, width - 1, height - 1));
    return true;
}

mat4 binningClipFromView(const Camera& camera, int width, int height) {
    return clipFromView(camera, float(width) / float(height), 0.01f, 1e4f);
}

PixelTile tileBlock(const PixelTile& tile, int bx, int by) {
    return {tile.x0 + bx * CPU_BLOCK,
            tile.y0 + by * CPU_BLOCK,
            std::min(tile.x1, tile.x0 + (bx + 1) * CPU_BLOCK),
            std::min(tile.y1, tile.y0 + (by + 1) * CPU_BLOCK),
            tile.tx,
            tile.ty};
}

Bounds tileReceiverBounds(const GBuffer& gbuffer, const PixelTile& tile) {
    Bounds box;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x)
            if (const std::size_t i = gbuffer.index(x, y); gbuffer.covered(i))
                box.extend(gbuffer.position[i]);
    return box;
}

} // namespace stsv
