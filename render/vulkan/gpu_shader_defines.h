// The preprocessor defines the Vulkan frame bakes into its shaders (DESIGN §5), in one place:
// the descriptor layout choices (uniform or storage buffers), the sample count and buffer kind,
// the fixed sample set of the resolve and the light type.
#pragma once

#include "core/dh.h"
#include "gpu/pipeline.h"
#include "gpu/shader_compiler.h"
#include "render/options.h"
#include "sampling/pattern.h"
#include "scene/scene.h"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace stsv {

/// The pattern and the alpha bits are uniform buffers when they fit the minimum
/// maxUniformBufferRange every Vulkan device guarantees; else storage buffers
/// (render/shaders/frame_bindings.glsl).
constexpr std::size_t MAX_UNIFORM_TABLE_BYTES = 16384;

/// How the scene tables are bound: vec4 counts of the uniform buffers, 0 = storage buffer.
struct FrameTableLayout {
    std::size_t patternVec4s = 0;  ///< two pattern points per vec4
    std::size_t alphaBitVec4s = 0; ///< 128 alpha bits per uvec4
};

/// vec4 count of the uniform pattern buffer, 0 when it does not fit (a storage buffer then).
std::size_t patternVec4Count(const SamplePlan& plan);

/// Defines every shader of the frame needs to match the descriptor set layout.
std::vector<ShaderDefine> layoutDefines(const FrameTableLayout& tables);

/// Whether the frame holds 16-bit layer counters per sample: a counters frame (DCS, and --buffer
/// counters), or a transmittance frame whose opaque meshes go through DCS, which counts their
/// layers beside the bits and optical depths of STSV (a count above 0 occludes the sample).
bool frameCountsLayers(const RenderOptions& options);

/// layoutDefines plus SAMPLE_COUNT and the light-sample buffer's kind, which any method's passes
/// read: LS_COUNTERS 1 when it holds layer counters only, 0 for occlusion bits; LS_TRANSMITTANCE
/// 1 when per-sample optical depths come with the bits, and LS_OPAQUE_COUNTERS 1 when DCS's
/// layer counters do too (frameCountsLayers).
std::vector<ShaderDefine> sampleDefines(const RenderOptions& options, const FrameTableLayout& tables);

/// `defines` plus STSV_PATTERN_Q when the plan has one sample set (no interleaving) whose points
/// are all exact multiples of 2^-24 in [0,1): the set as 24-bit fixed-point integers baked into
/// the resolve (render/shaders/frame_bindings.glsl). Otherwise the shader reads the pattern buffer.
/// The resolve unrolls its sample loop with it (the constants need constant indices): 3x faster
/// at 64 and 128 samples on lavapipe (fence 1024²), but at 256 samples llvmpipe's lazy compile
/// of the unrolled shader made the first frame 4x slower, so not above 128 samples.
/// Also for DCS's samples pass over the pairs the walk listed with their edge terms
/// (wedge_samples.comp: a crossing test a sample). Not in stsv.frag: there the unrolled loop
/// (texel tests, early continues) measured 2-3x slower on lavapipe.
std::vector<ShaderDefine> withPatternDefine(std::vector<ShaderDefine> defines, const SamplePlan& plan);

/// `defines` plus FIXED_LIGHT_TYPE (sampling/light_sampling_dh.h): one resolve and one STSV
/// fragment shader per light type in the scene, with the type tests folded.
std::vector<ShaderDefine> lightTypeDefines(std::vector<ShaderDefine> defines, uint lightType);

/// The light types (LIGHT_*) among the scene's lights: the passes that specialise per type build
/// a pipeline for each of these.
std::array<bool, 4> lightTypesIn(const Scene& scene);

/// The compute pipelines of `shader` with `defines`, one per light type marked in `types`
/// (lightTypeDefines), indexed by LIGHT_*.
std::array<Pipeline, 4> lightTypeComputePipelines(const Device& device, const PipelineLayout& layout,
                                                  const std::array<bool, 4>& types, const std::string& shader,
                                                  const std::vector<ShaderDefine>& defines);

} // namespace stsv
