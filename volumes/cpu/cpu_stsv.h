// The CPU mirror of the STSV pass (DESIGN §3): the same device/host functions the fragment
// shader runs, over the pixels, each screen tile taking the volumes of the triangles that can
// shadow it from a tree of balls over them (render/cpu/cpu_binning.h BallTree).
#pragma once

#include "core/gbuffer.h"
#include "core/parallel.h"
#include "render/cpu/cpu_binning.h"
#include "render/methods.h"
#include "sampling/ls_buffer.h"
#include "sampling/ls_buffer_dh.h"
#include "sampling/pattern.h"
#include "scene/scene.h"
#include "volumes/extrusion_dh.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>

namespace stsv {

struct StsvCpuStats {
    std::size_t volumes = 0;           ///< volumes built (one or two per non-degenerate triangle)
    std::size_t degenerateSkipped = 0; ///< zero-area triangles, no volume
    std::size_t clusters = 0;          ///< leaves of the tree over the volumes (BallTree)
    /// Tree nodes the tiles tested with the ball of their visible points, and of those the ones
    /// no segment from there to the light meets (volumes/light_hull_dh.h).
    std::size_t clusterTests = 0;
    std::size_t clustersRejected = 0;
    std::size_t tileEntries = 0;       ///< (tile, volume) pairs of the leaves the tiles reached
    std::size_t tileEntriesCulled = 0; ///< of those, dropped: the tile's visible points all outside a plane
    std::size_t pixelVolumeTests = 0;  ///< point-in-volume tests run ("fragments", as the GPU counts them)
    std::size_t pixelVolumeHits = 0;   ///< of those, points inside ("inside_fragments")
    std::size_t samplesTested = 0;     ///< light samples tested by the fragments that own the pixel
    double binMs = 0.0;
    double shadeMs = 0.0;
};

nlohmann::json toJson(const StsvCpuStats& stats);

/// Which scene triangles a pass treats (all when empty).
using TriangleFilter = std::function<bool(std::size_t triangle)>;

/// The filter of a method's STSV triangles (render/methods.h): all, or the perforated ones.
TriangleFilter stsvFilter(const Scene& scene, StsvTriangles which);

/// Adds to the light-sample buffer of `light` the occlusion by every triangle of the scene
/// accepted by `include`, each treated as an S-triangle (opaque ones with constant opacity).
/// Bitmask buffers get OR'ed bits; counter buffers get one increment per blocking triangle
/// and sample (exact depth complexity), so DCS+STSV can add to DCS counters.
StsvCpuStats stsvCpuSamples(const Scene& scene, const GBuffer& gbuffer, const Light& light,
                            const SamplePlan& plan, float farDistance, LightSampleBuffer& out,
                            const TriangleFilter& include = {});

} // namespace stsv
