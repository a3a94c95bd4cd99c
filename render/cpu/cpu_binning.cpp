#include "render/cpu/cpu_binning.h"

#include <algorithm>

namespace stsv {

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
