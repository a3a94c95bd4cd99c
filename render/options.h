// Every knob of a frame, declared once with its default (STYLE §8). Filled by the CLI and
// written into --stats so an output says how it was made.
#pragma once

#include "render/methods.h"
#include "sampling/pattern.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace stsv {

/// Which stage builds the STSV volumes on Vulkan, and what it draws.
enum class ExtrusionStage {
    Auto,     ///< Hull
    Geometry, ///< volumes/shaders/stsv.geom, wedge.geom: the paper's ten-vertex prism
    Mesh, ///< task and mesh shaders (stsv.task/.mesh, wedge.task/.mesh): the hulls built, clipped and drawn
          ///< in the draw; UsageError naming VK_EXT_mesh_shader when the device lacks it
    Hull, ///< volumes/shaders/stsv_hull.comp, wedge_hull.comp: the box clipped by the volume's and the
          ///< light's planes, drawn indirect
};

ExtrusionStage parseExtrusionStage(const std::string& name); ///< auto | hull | geometry | mesh
std::string toString(ExtrusionStage stage);

struct Frame;

struct RenderOptions {
    Method method = Method::Stsv;
    Backend backend = Backend::Vulkan; ///< one of methodInfo(method).backends
    int width = 512;                   ///< pixels, 1 … 16384
    int height = 512;                  ///< pixels, 1 … 16384
    int samples = 64;                  ///< light samples per pixel: 16, 32, 64, 128 or 256
    PatternKind pattern = PatternKind::Poisson;
    std::uint32_t seed = 1;  ///< sample patterns and per-pixel decorrelation
    int interleave = 1;      ///< K of K×K interleaved sampling (1 = off), 1 … 8
    bool decorrelate = true; ///< per-pixel rotation of the pattern
    BufferKind buffer =
        BufferKind::Bitmask; ///< light-sample buffer: occlusion bits or depth-complexity counters
    float ambient = 0.05f;   ///< ambient term, fraction of albedo
    std::string device;      ///< Vulkan device: "" = best, an index, or a name substring
    bool validation = false; ///< Vulkan validation layers (always on in tests)
    ExtrusionStage extrusion = ExtrusionStage::Auto; ///< Vulkan: stage that builds the STSV and wedge volumes
    MethodParams params;         ///< the method's knobs (render/methods.h); missing ones take their defaults
    bool keepShadowMaps = false; ///< image-based methods: Frame::shadowMaps holds each light's map
    /// K: K×K visible points per pixel (sub-pixel centres), each with the pixel's own light
    /// samples, averaged into the images; the G-buffer and light-sample buffers keep every
    /// sub-pixel (K·width × K·height). 1 … 4.
    int supersample = 1;
};

/// Throws UsageError naming the first option out of range (method parameters included).
void validate(const RenderOptions& options);

/// The options a frame runs with: `buffer` becomes the kind the method writes
/// (MethodInfo::bufferKind), so stats and light-sample buffers say what was rendered, and width
/// and height are those of the sub-pixel grid (K·width × K·height for supersample K).
RenderOptions frameOptions(RenderOptions options);

/// The end of a supersampled frame (options.supersample = K > 1, the frame rendered on the
/// sub-pixel grid): colour and visibility averaged over each pixel's K×K sub-pixels, the stats'
/// options back to the requested size. Every backend calls it.
void resolveSupersampling(Frame& frame, const RenderOptions& requested);

/// The sample sets of a frame of `options` (pattern, count, seed, interleave, decorrelation, and
/// the supersampling that makes sub-pixels share their pixel's samples).
SamplePlan samplePlanOf(const RenderOptions& options);

/// The shadow-map settings of a frame of `options` (shadowmaps/shadow_map.h), read from its
/// method's parameters on both backends; the defaults for a method without shadow maps.
ShadowMapSettings shadowMapSettings(const RenderOptions& options);
/// Knob `name` of the options' method: the value given, else its default; UsageError when the method
/// has no such knob.
double methodKnob(const RenderOptions& options, std::string_view name);

nlohmann::json toJson(const RenderOptions& options);

} // namespace stsv
