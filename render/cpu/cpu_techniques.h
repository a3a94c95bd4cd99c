// The CPU side of each family's technique (DESIGN §2): one family's work for one light of a
// frame, behind one small interface. A method's row lists the families it composes
// (MethodInfo::techniques); CpuRenderer runs them in that order for every light, then lets each
// combine what the others wrote (the fold of the wedges with STSV), then resolves.
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/frame.h"
#include "render/methods.h"
#include "render/options.h"
#include "sampling/ls_buffer.h"
#include "sampling/pattern.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace stsv {

class EmbreeScene;

/// What a technique reads of the renderer, the same for every frame and light.
struct CpuTechniqueContext {
    const Scene& scene;
    const RenderOptions& options; ///< the frame's (the sub-pixel grid with --supersample)
    const MethodInfo& method;
    const SamplePlan& plan;
    float farDistance; ///< world units: a directional light's samples (sampling/light_bounds.h)
    const EmbreeScene& embree;
};

/// One light of one frame: its inputs, and the outputs the techniques write.
struct CpuLightWork {
    const GBuffer& gbuffer;
    const Light& light;
    std::size_t index;          ///< the light's index in the scene
    LightSampleBuffer& samples; ///< per-sample occlusion (MethodInfo::bufferKind), zeroed
    ImageF& vcoef;          ///< v_coef per pixel for MethodOutput::Visibility methods (1 channel), else empty
    Frame& frame;           ///< kept shadow maps go to frame.keptMaps
    nlohmann::json& passes; ///< "light<i>/<pass>" → milliseconds

    /// The pass's key in "passes": "light<i>/<name>".
    std::string pass(const std::string& name) const { return "light" + std::to_string(index) + "/" + name; }
};

class CpuTechnique {
  public:
    virtual ~CpuTechnique() = default;
    /// The family's work for one light: its occlusion into work.samples, or its v_coef.
    virtual void run(CpuLightWork& work) = 0;
    /// After every technique of the row has run for the light: combine the outputs (the fold).
    virtual void combine(CpuLightWork&) {}
    /// Moves what the technique counted over the frame's lights into `stats` under its family's
    /// keys (render/vulkan writes the same keys); the next frame counts afresh.
    virtual void takeStats(nlohmann::json& stats) = 0;
};

/// Each family's technique, made by the family's CPU side (volumes/cpu, wedges/cpu, shadowmaps/cpu).
std::unique_ptr<CpuTechnique> makeStsvCpuTechnique(const CpuTechniqueContext& context);
std::unique_ptr<CpuTechnique> makeWedgesCpuTechnique(const CpuTechniqueContext& context);
std::unique_ptr<CpuTechnique> makeShadowMapsCpuTechnique(const CpuTechniqueContext& context);

/// The row's techniques, in its order (start-up work such as the opaque edge adjacency happens
/// here). `context` must outlive them.
std::vector<std::unique_ptr<CpuTechnique>> makeCpuTechniques(const CpuTechniqueContext& context);

} // namespace stsv
