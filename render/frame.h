// What both backends' frames share: the Frame they fill, the FrameRenderer interface, the
// stats and warnings every frame writes. One frame: G-buffer, per light a light-sample buffer from the chosen
// method, then the resolve into visibility and Monte-Carlo direct lighting (STSV paper, Algorithm 2).
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/options.h"
#include "sampling/ls_buffer.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace stsv {

struct KeptShadowMaps; // shadowmaps/kept_maps.h

/// Linear RGB of the pixels no triangle covers (every backend).
inline const vec3 BACKGROUND(0.02f, 0.02f, 0.03f);

// NOLINTNEXTLINE(bugprone-exception-escape): json's move cannot throw (its invariant check is unmarked)
struct Frame {
    GBuffer gbuffer;
    std::vector<LightSampleBuffer> lightSamples; ///< one per scene light
    ImageF color;                                ///< linear RGB: ambient + Σ lights direct lighting
    ImageF visibility; ///< one channel: v_coef averaged over the lights (1 on background)
    /// The image family's maps, one per light, with RenderOptions::keepShadowMaps (else null;
    /// read them with keptMaps, shadowmaps/kept_maps.h). Copies of a frame share them.
    std::shared_ptr<KeptShadowMaps> keptMaps;
    /// options, scene counts, "startup_ms" (acceleration structures, devices, shader
    /// compilation), "frame_ms" (one frame without start-up) and "passes" (name → ms).
    nlohmann::json stats;
};

/// Renders frames of one scene with one set of options; start-up work (BVH, device,
/// pipelines, uploads) happens once in the constructor, so repeated frames measure the frame.
class FrameRenderer {
  public:
    virtual ~FrameRenderer() = default;
    virtual Frame render() = 0;
};

/// What a frame's stats say of a method on a scene, on every backend: the perforated triangles
/// a method without an STSV pass leaves out of its shadows ("ignored_perforated_triangles" and
/// "ignored_perforated_triangles_use", the method that draws them).
nlohmann::json methodSceneNotes(const Scene& scene, const MethodInfo& method);

/// `--method auto`: the object-based method a scene's triangles call for — dcs+stsv where the scene has an
/// opaque triangle (depth complexity sampling over the opaque meshes, STSV over the perforated and
/// translucent triangles), stsv where every triangle is perforated or translucent (or there is none).
Method autoMethod(const Scene& scene);

/// Sentences a user should read about a frame's result, from its stats: perforated triangles a
/// method left out ("ignored_perforated_triangles"), translucent ones taken as binary, and what
/// the image family says of its maps (shadowMapWarnings). The CLI prints them on stderr.
std::vector<std::string> frameWarnings(const nlohmann::json& stats);

/// Shared by every backend: ambient colour / background of a fresh frame, and scene counts.
void initFrameImages(const Scene& scene, const GBuffer& gbuffer, float ambient, Frame& frame);
nlohmann::json sceneStats(const Scene& scene);

} // namespace stsv
