// The wedge bounds as items of the hull builders — the compute hull pass (wedge_hull.comp) and the
// task and mesh shaders (wedge.task, wedge.mesh): an item is a side of a carrier face, every side 0
// first, then every side 1.
#ifndef STSV_SHADERS_WEDGE_HULL_ITEMS_GLSL
#define STSV_SHADERS_WEDGE_HULL_ITEMS_GLSL

#include "wedges/shaders/wedge_bindings.glsl"
#include "volumes/extrusion_dh.h"

/// Item `item` as (carrier, side), and whether it may have a bound (wedgeMayHaveBound).
bool hullItem(uint item, out uint c, out uint side) {
    uint count = carrierCount();
    side = item >= count ? 1u : 0u;
    c = item - side * count;
    uint silhouettes;
    return side <= 1u && c < count && wedgeMayHaveBound(c, side, pc.light, silhouettes);
}

/// The bound of side `side` of carrier `c` (wedgeSetupBound) as the set-up of its hull — the
/// carrier's volume and light planes inside the scene box — and its record; false when it has
/// none.
#define HULL_RECORD GpuWedgeRecord
bool hullVolume(uint c, uint side, out StsvHullSetup h, out GpuWedgeRecord r) {
    WedgeBound b;
    if (!wedgeSetupBound(c, side, pc.light, false, b)) return false;
    h = stsvVolumeHullSetup(b.vol, b.lp, b.v0, b.v1, b.v2, vec3(frame.boxLo), vec3(frame.boxHi));
    r = b.record;
    return h.empty == 0u;
}

#endif
