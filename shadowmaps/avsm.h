// The transmittance functions of `avsm` and `vpcss` (shadowmaps/avsm_dh.h) on the host: one
// light's map, a texel built from the surfaces its centre ray crosses, the statistics of a map,
// and the data access of the lookups (avsm_filter_dh.h) over it.
#pragma once

#include "shadowmaps/avsm_dh.h"
#include "shadowmaps/shadow_map.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// One light's map: faces × size² texels of at most `maxNodes` nodes, texel-major.
struct AvsmMap {
    ShadowMapView view{};
    uint maxNodes = 8;
    std::vector<std::uint32_t> counts;    ///< nodes per texel
    std::vector<float> depth;             ///< [texel · maxNodes + j]: depth of node j (the map's measure)
    std::vector<std::uint32_t> units;     ///< [texel · maxNodes + j]: its cumulative optical depth
    std::vector<std::uint8_t> overflowed; ///< per texel: 1 where a node was dropped

    AvsmMap() = default;
    AvsmMap(const ShadowMapView& v, uint nodes);
    std::size_t texel(uint face, ivec2 t) const {
        return (std::size_t(face) * view.size + std::size_t(t.y)) * view.size + std::size_t(t.x);
    }
    /// Texel `index`'s function: the nodes of `f`.
    void store(std::size_t index, const AvsmFunction& f);
};

/// A surface on a texel's centre ray: its depth in the map's measure and the optical-depth units
/// it takes (OPTICAL_DEPTH_OPAQUE: it blocks).
struct AvsmSurface {
    float depth;
    std::uint32_t units;
};

/// A texel's function from its surfaces, nearest first (avsmAppend in that order).
AvsmFunction buildAvsmTexel(const std::vector<AvsmSurface>& surfaces, uint maxNodes);

/// What a map holds: texels with nodes, their mean and largest node count, and the texels that
/// had more surfaces than nodes (a node dropped).
struct AvsmStats {
    std::size_t texels = 0;
    std::size_t texelsWithNodes = 0;
    double meanNodes = 0.0; ///< over the texels with nodes
    std::uint32_t maxNodes = 0;
    std::size_t overflowedTexels = 0;
};
AvsmStats avsmStats(const AvsmMap& map);

struct AvsmSource {
    const AvsmMap* map;
    const vec2* taps; ///< shadowFilterTaps: the blocker set, then the filter set
};
inline uint avsmSourceCount(AvsmSource s, uint face, ivec2 texel) {
    return s.map->counts[s.map->texel(face, texel)];
}
inline float avsmSourceDepth(AvsmSource s, uint face, ivec2 texel, uint j) {
    return s.map->depth[s.map->texel(face, texel) * s.map->maxNodes + j];
}
inline uint avsmSourceUnits(AvsmSource s, uint face, ivec2 texel, uint j) {
    return s.map->units[s.map->texel(face, texel) * s.map->maxNodes + j];
}
inline vec2 avsmSourceTap(AvsmSource s, uint i) {
    return s.taps[i];
}

} // namespace stsv

#define AVSM_SOURCE
#include "shadowmaps/avsm_filter_dh.h"
