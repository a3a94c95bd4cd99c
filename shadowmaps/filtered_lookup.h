// The lookup of filtered_lookup_dh.h on the host: its data access over summed-area tables and mip
// pyramids (shadowmaps/summed_area.h), one per plane (the Vulkan shaders have their own).
#pragma once

#include "shadowmaps/shadow_filter.h"
#include "shadowmaps/summed_area.h"

#include <cstdint>

namespace stsv {

struct FilteredSource {
    const SummedAreaTable* sats; ///< [plane], or null
    const MipPyramid* mips;      ///< [plane], or null
};
inline std::int64_t filteredSourceSum(FilteredSource s, uint plane, uint index) {
    return s.sats[plane].sums[index];
}
inline float filteredSourceMip(FilteredSource s, uint plane, uint index) {
    return s.mips[plane].texels[index];
}

} // namespace stsv

#define FILTERED_SUM std::int64_t
#define FILTERED_SOURCE
#include "shadowmaps/filtered_lookup_dh.h"
