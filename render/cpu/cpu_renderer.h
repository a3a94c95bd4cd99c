// The CPU backend of a frame (DESIGN §2): the Embree G-buffer, per light the row's techniques
// (render/cpu/cpu_techniques.h), then the Monte-Carlo resolve. Links neither Vulkan nor glslang.
#pragma once

#include "render/frame.h"

#include <memory>

namespace stsv {

/// The CPU renderer of `options` (validated; the method must run on the CPU). `scene` must
/// outlive it.
std::unique_ptr<FrameRenderer> makeCpuRenderer(const Scene& scene, const RenderOptions& options);

/// Resolve of one light's buffer: adds albedo/π · (1/N) Σ_k V_k · L_k G_k A to `color`
/// (the paper's "Direct MC") and v_coef·weight to `visibility`. With `vcoef` (the per-pixel
/// v_coef of a visibility-only method), v_coef is read from it and scales the direct lighting
/// of `samples` instead.
void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility, const ImageF* vcoef = nullptr);

} // namespace stsv
