// One frame: G-buffer, per light a light-sample buffer from the chosen method, then the
// resolve into visibility and Monte-Carlo direct lighting (STSV paper, Algorithm 2).
#pragma once

#include "core/gbuffer.h"
#include "core/image.h"
#include "render/options.h"
#include "sampling/ls_buffer.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <vector>

namespace stsv {

struct Frame {
    GBuffer gbuffer;
    std::vector<LightSampleBuffer> lightSamples; ///< one per scene light
    ImageF color;      ///< linear RGB: ambient + Σ lights direct lighting
    ImageF visibility; ///< one channel: v_coef averaged over the lights (1 on background)
    nlohmann::json stats;
};

Frame renderFrame(const Scene& scene, const RenderOptions& options);

/// Resolve of one light's buffer: adds albedo/π · (1/N) Σ_k V_k · L_k G_k A to `color`
/// (the paper's "Direct MC") and v_coef/lightCount to `visibility`.
void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility);

} // namespace stsv
