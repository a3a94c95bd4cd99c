// CPU dispatch shaped like a GPU dispatch (pbrt-v4's ParallelFor), on oneTBB's work-stealing
// pool: the CPU passes call the same per-pixel function a shader's main() calls, over 16 × 16
// pixel tiles as a compute dispatch runs 16 × 16 workgroups. This header is the one place that
// decides how work is split (the tile size and the grain of item loops).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstddef>

namespace stsv {

/// Pixels per side of a CPU tile: the unit of parallel work and of the CPU passes' screen binning.
inline constexpr int CPU_TILE = 16;
/// Items per task of parallelForChunks (cheap per-item work: copies, unpacking).
inline constexpr std::size_t CPU_ITEM_GRAIN = 4096;

/// Pixels [x0, x1) × [y0, y1) of tile (tx, ty).
struct PixelTile {
    int x0, y0, x1, y1;
    int tx, ty;
};

/// Tiles per row and per column of a width × height image.
inline int tilesAcross(int pixels) {
    return (pixels + CPU_TILE - 1) / CPU_TILE;
}

/// body(tile) for every CPU_TILE × CPU_TILE tile of a width × height image (edge tiles clipped),
/// on all cores. The first exception a tile throws is rethrown here after the loop was cancelled.
template <class Body> void parallelForTiles(int width, int height, const Body& body) {
    const tbb::blocked_range2d<int> tiles(0, tilesAcross(height), 0, tilesAcross(width));
    tbb::parallel_for(tiles, [&](const tbb::blocked_range2d<int>& r) {
        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
            for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx)
                body(PixelTile{tx * CPU_TILE, ty * CPU_TILE, std::min(width, (tx + 1) * CPU_TILE),
                               std::min(height, (ty + 1) * CPU_TILE), tx, ty});
    });
}

/// body(x, y) for every pixel, tile by tile.
template <class Body> void parallelForPixels(int width, int height, const Body& body) {
    parallelForTiles(width, height, [&](const PixelTile& t) {
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) body(x, y);
    });
}

/// body(i) for every i in [0, count), one task per item at most (items of real work: tiles,
/// jobs). Exceptions as parallelForTiles.
template <class Body> void parallelFor(std::size_t count, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i < r.end(); ++i) body(i);
                      });
}

/// body(begin, end) over [0, count) in chunks of up to CPU_ITEM_GRAIN items (cheap items).
template <class Body> void parallelForChunks(std::size_t count, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, CPU_ITEM_GRAIN),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

/// join over body(begin, end) of chunks of [0, count) of up to CPU_ITEM_GRAIN items, starting
/// from `identity`; `join` must be associative (the chunks meet in no fixed order).
template <class T, class Body, class Join>
T parallelReduce(std::size_t count, const T& identity, const Body& body, const Join& join) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, count, CPU_ITEM_GRAIN), identity,
        [&](const tbb::blocked_range<std::size_t>& r, T acc) { return join(acc, body(r.begin(), r.end())); },
        join);
}

} // namespace stsv
