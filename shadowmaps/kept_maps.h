// The maps an image-based method keeps for its caller when asked (RenderOptions::keepShadowMaps):
// per light the depth map, the depth grid (`peel`) or the transmittance functions (`avsm`,
// `vpcss`). A frame holds them behind a pointer of a type it does not know (render/frame.h).
#pragma once

#include "shadowmaps/avsm.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"

#include <memory>
#include <vector>

namespace stsv {

struct KeptShadowMaps {
    std::vector<ShadowMap> shadowMaps; ///< one per light: the light-centre depth map and its view
    std::vector<DepthGrid> depthGrids; ///< `peel`: one per light instead
    std::vector<AvsmMap> avsmMaps;     ///< `avsm`, `vpcss`: one per light instead
};

/// The maps in `slot`, made empty the first time a technique keeps one.
inline KeptShadowMaps& keepMapsIn(std::shared_ptr<KeptShadowMaps>& slot) {
    if (!slot) slot = std::make_shared<KeptShadowMaps>();
    return *slot;
}

/// The maps in `slot`, or none when no technique kept any.
inline const KeptShadowMaps& keptMaps(const std::shared_ptr<KeptShadowMaps>& slot) {
    static const KeptShadowMaps none;
    return slot ? *slot : none;
}

} // namespace stsv
