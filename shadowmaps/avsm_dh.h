// Adaptive volumetric shadow maps (Salvi et al. 2010) for the thin surfaces of a scene (DESIGN
// §4.6): a texel's transmittance function and how it is built. Compiles as C++ and GLSL
// (core/dh.h).
//
// A texel of an AVSM holds a transmittance function along its centre ray from the light centre:
// at most AVSM_MAX_NODES nodes (depth, cumulative optical depth), depths increasing. The
// function is a step function: T(z) = exp(−units_j / OPTICAL_DEPTH_SCALE) of the last node j
// with depth_j < z, and 1 in front of the first node; a node of OPTICAL_DEPTH_OPAQUE units is 0.
// Optical depths are the fixed-point sums of the transmittance buffer (scene/occlusion_rules_dh.h),
// so a texel with no more surfaces than nodes holds exactly the optical depth the reference
// accumulates along the same ray. A surface is a node (Salvi's volumes need two per segment; a
// triangle has no thickness).
//
// Building: the surfaces along the ray are appended in depth order (avsmAppend); when one more
// node than the budget results, the node whose removal changes the area under T(z) least goes
// (Salvi §3.2, for steps instead of segments): removing node i either moves its step to the next
// node's depth (area (T_{i−1} − T_i)·(z_{i+1} − z_i), the curve brightens) or merges it into the
// previous node's step (area (T_{i−1} − T_i)·(z_i − z_{i−1}), the curve darkens); the cheaper of
// all these goes, the earlier node and the later move first on ties. Appending in depth order
// makes the result independent of the order the surfaces were produced in, which a GPU's
// unsorted insertion is not (Intel's sample notes the flicker).
//
// The lookups and volumetric PCSS are in avsm_filter_dh.h.
#ifndef STSV_SHADOWMAPS_AVSM_DH_H
#define STSV_SHADOWMAPS_AVSM_DH_H

#include "core/dh.h"
#include "scene/occlusion_rules_dh.h"

DH_BEGIN

/// The largest node budget (the avsm_nodes knob's maximum).
DH_CONST uint AVSM_MAX_NODES = 16u;

/// One texel's function while it is built: the nodes plus room for the one an append adds.
struct AvsmFunction {
    float depth[AVSM_MAX_NODES + 1u];
    uint units[AVSM_MAX_NODES + 1u];
    float transmittance[AVSM_MAX_NODES + 1u]; ///< avsmTransmittance(units[j]), kept for the removals
    uint count;
    uint overflowed; ///< 1 once a node was removed
};

DH_FUNC AvsmFunction avsmEmpty() {
    AvsmFunction f;
    for (uint j = 0u; j < AVSM_MAX_NODES + 1u; ++j) {
        f.depth[j] = 0.0f;
        f.units[j] = 0u;
        f.transmittance[j] = 1.0f;
    }
    f.count = 0u;
    f.overflowed = 0u;
    return f;
}

/// `total` optical-depth units plus `units`, OPTICAL_DEPTH_OPAQUE once either is or the sum
/// reaches 2^32 − 1 (as the reference's sum, reference/embree_scene.cpp opticalDepth).
DH_FUNC uint avsmAddUnits(uint total, uint units) {
    if (total == OPTICAL_DEPTH_OPAQUE || units == OPTICAL_DEPTH_OPAQUE) return OPTICAL_DEPTH_OPAQUE;
    uint sum = total + units;
    return sum < total || sum == OPTICAL_DEPTH_OPAQUE ? OPTICAL_DEPTH_OPAQUE : sum;
}

/// T of a cumulative optical depth: 0 for OPTICAL_DEPTH_OPAQUE.
DH_FUNC float avsmTransmittance(uint units) {
    return units == OPTICAL_DEPTH_OPAQUE ? 0.0f : transmittanceOfDepth(units);
}

/// Removes the node whose removal changes the area under T(z) least (see the top of this file).
DH_FUNC void avsmRemoveCheapest(DH_INOUT(AvsmFunction) f) {
    float bestCost = 3.0e38f;
    uint best = 0u;
    bool merge = false; ///< into the previous node (else: its step moves to the next node)
    for (uint i = 0u; i < f.count; ++i) {
        float before = i == 0u ? 1.0f : f.transmittance[i - 1u];
        float step = before - f.transmittance[i];
        if (i > 0u) {
            float cost = step * (f.depth[i] - f.depth[i - 1u]);
            if (cost < bestCost) {
                bestCost = cost;
                best = i;
                merge = true;
            }
        }
        if (i + 1u < f.count) {
            float cost = step * (f.depth[i + 1u] - f.depth[i]);
            if (cost < bestCost) {
                bestCost = cost;
                best = i;
                merge = false;
            }
        }
    }
    if (merge) {
        f.units[best - 1u] = f.units[best];
        f.transmittance[best - 1u] = f.transmittance[best];
    }
    for (uint j = best; j + 1u < f.count; ++j) {
        f.depth[j] = f.depth[j + 1u];
        f.units[j] = f.units[j + 1u];
        f.transmittance[j] = f.transmittance[j + 1u];
    }
    f.count -= 1u;
    f.overflowed = 1u;
}

/// Appends a surface of `units` optical-depth units (OPTICAL_DEPTH_OPAQUE: it blocks) at `depth`,
/// not nearer than the nodes so far, keeping at most `maxNodes` (1 … AVSM_MAX_NODES). Surfaces
/// behind an opaque node and surfaces of 0 units change nothing and add no node.
DH_FUNC void avsmAppend(DH_INOUT(AvsmFunction) f, float depth, uint units, uint maxNodes) {
    uint before = f.count == 0u ? 0u : f.units[f.count - 1u];
    uint total = avsmAddUnits(before, units);
    if (total == before) return;
    f.depth[f.count] = depth;
    f.units[f.count] = total;
    f.transmittance[f.count] = avsmTransmittance(total);
    f.count += 1u;
    if (f.count > maxNodes) avsmRemoveCheapest(f);
}

DH_END

#endif // STSV_SHADOWMAPS_AVSM_DH_H
