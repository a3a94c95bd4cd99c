#include "shadowmaps/depth_grid.h"

#include <algorithm>

namespace stsv {

DepthGrid::DepthGrid(const ShadowMapView& v, uint subintervals)
    : view(v), bins(subintervals),
      words(std::size_t(v.faces) * v.size * v.size * peelTexelWords(subintervals), 0u) {}

std::uint32_t* DepthGrid::texel(uint face, ivec2 t) {
    return words.data() + peelTexelBase(view, face, t, bins);
}
const std::uint32_t* DepthGrid::texel(uint face, ivec2 t) const {
    return words.data() + peelTexelBase(view, face, t, bins);
}

void fillDepthGridTexel(std::uint32_t* words, uint bins, const std::vector<GridSurface>& surfaces) {
    for (const GridSurface& s : surfaces) {
        words[0] = std::max(words[0], peelNearWord(s.depth));
        words[1] = std::max(words[1], peelDepthWord(s.depth));
    }
    if (words[1] == 0u) return;
    const float lo = peelWordDepth(~words[0]), hi = peelWordDepth(words[1]);
    for (const GridSurface& s : surfaces) {
        const int b = peelBin(s.depth, lo, hi, bins);
        std::uint32_t& slot = words[2u + 2u * uint(b) + (s.front ? 0u : 1u)];
        slot = std::max(slot, peelDepthWord(s.depth));
    }
}

} // namespace stsv
