// The filters of shadow_filter_dh.h on the host: their data access over a ShadowMap and its
// Poisson-disk taps (the CPU backend and the tests; shadowmaps/shaders/shadow_filter.comp has its own).
#pragma once

#include "shadowmaps/shadow_map.h"

namespace stsv {

struct ShadowMapSource {
    const ShadowMap* map;
    const vec2* taps; ///< shadowFilterTaps: the blocker set, then the filter set
};
inline float shadowMapSourceDepth(ShadowMapSource s, uint face, ivec2 texel) {
    return s.map->at(face, texel);
}
inline vec2 shadowMapSourceTap(ShadowMapSource s, uint i) {
    return s.taps[i];
}

} // namespace stsv

#define SHADOW_MAP_SOURCE
#include "shadowmaps/shadow_filter_dh.h"
