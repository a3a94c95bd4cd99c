// What the CPU passes (STSV and the wedges) share to find, per screen tile and per block, what
// can reach its visible points — the box and ball of those points, a tree of balls to walk —
// and to visit only the light samples a bounded test can reach.
#pragma once

#include "core/gbuffer.h"
#include "core/parallel.h"
#include "sampling/ls_buffer_dh.h"
#include "scene/scene.h"
#include "volumes/ball_tree.h"
#include "volumes/extrusion_dh.h"
#include "volumes/light_hull_dh.h"
#include "wedges/edge_cluster_dh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace stsv {

/// The bounds of the visible points of one screen tile; empty when it covers no surface. The CPU
/// passes drop, per tile, the volumes with the whole box outside one plane
/// (stsvVolumeMissesBox): what the rasteriser's depth test and the fragments' plane tests would
/// reject one pixel at a time.
Bounds tileReceiverBounds(const GBuffer& gbuffer, const PixelTile& tile);

/// Blocks of CPU_BLOCK × CPU_BLOCK pixels within a tile: the CPU passes cull once more per block,
/// by the block's own (smaller) box of visible points.
constexpr int CPU_BLOCK = int(CLUSTER_BLOCK);
constexpr int CPU_BLOCKS = CPU_TILE / CPU_BLOCK;

/// Block (bx, by) of `tile`, clipped to it: empty (x0 ≥ x1 or y0 ≥ y1) past the image's edge.
PixelTile tileBlock(const PixelTile& tile, int bx, int by);

/// A pixel's light samples in a CELLS × CELLS grid over the frame square [−1, 1]²: per cell the
/// mask words (sampling/ls_buffer_dh.h) of the samples in it, so that a per-sample test bounded
/// to a box of the frame (stsvSampleRegion, dcsSampleRegion) visits only the samples of the
/// cells the box touches.
struct SampleCells {
    static constexpr int CELLS = 8;
    std::array<std::array<uint, 8>, CELLS * CELLS> words{};

    static int cellOf(float coordinate) {
        return std::clamp(int(std::floor((coordinate + 1.0f) * (0.5f * float(CELLS)))), 0, CELLS - 1);
    }
    void add(vec2 ab, uint k) {
        words[std::size_t(cellOf(ab.y) * CELLS + cellOf(ab.x))][k >> 5u] |= lsMaskBit(k);
    }
    /// The samples of the cells the box [lo, hi] touches, words 0 … wordCount − 1.
    std::array<uint, 8> within(vec2 lo, vec2 hi, uint wordCount) const {
        std::array<uint, 8> out{};
        for (int cy = cellOf(lo.y); cy <= cellOf(hi.y); ++cy)
            for (int cx = cellOf(lo.x); cx <= cellOf(hi.x); ++cx)
                for (uint w = 0; w < wordCount; ++w) out[w] |= words[std::size_t(cy * CELLS + cx)][w];
        return out;
    }
};

} // namespace stsv
