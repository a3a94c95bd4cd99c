// The depth grid of `peel` (shadowmaps/depth_grid_dh.h) on the host: one light's words, their
// data access for the march, and the fill of a texel from the surfaces its centre ray meets
// (the CPU backend traces them; the tests build grids by hand).
#pragma once

#include "shadowmaps/shadow_map.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// One light's grid: faces × size² texels of peelTexelWords(bins) words (depth_grid_dh.h).
struct DepthGrid {
    ShadowMapView view{};
    uint bins = 16;
    std::vector<std::uint32_t> words;

    DepthGrid() = default;
    DepthGrid(const ShadowMapView& v, uint subintervals);
    std::uint32_t* texel(uint face, ivec2 t);
    const std::uint32_t* texel(uint face, ivec2 t) const;
};

/// A surface on a texel's centre ray: its depth in the map's measure and whether it faces the light.
struct GridSurface {
    float depth;
    bool front;
};

/// Texel `words` (peelTexelWords(bins) of them, zero on entry) from the surfaces its ray meets,
/// as the GPU's two passes write them: the depth range, then per surface atomicMax into its
/// subinterval's front or back slot.
void fillDepthGridTexel(std::uint32_t* words, uint bins, const std::vector<GridSurface>& surfaces);

/// What a light's march did (both backends): its rays, the steps they took and the longest, and
/// those that needed more than peel_max_steps.
struct PeelMarchCounts {
    std::uint64_t rays = 0;
    std::uint64_t steps = 0;
    std::uint64_t capped = 0;
    std::uint32_t longest = 0;
    std::uint32_t maxSteps = 0; ///< peel_max_steps
};

struct PeelGridSource {
    const DepthGrid* grid;
};
inline uint peelGridWord(PeelGridSource s, uint index) {
    return s.grid->words[index];
}

} // namespace stsv

#define PEEL_GRID_SOURCE
#include "shadowmaps/depth_grid_dh.h"
