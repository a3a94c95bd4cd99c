// The preprocessor defines the Vulkan frame bakes into its shaders (DESIGN §5), in one place:
// the descriptor layout choices (uniform or storage buffers), the sample count and buffer kind,
// the fixed sample set of the resolve and the light type.
#pragma once

#include "core/dh.h"
#include "gpu/shader_compiler.h"
#include "render/options.h"
#include "sampling/pattern.h"
#include "scene/scene.h"

#include <array>
#include <cstddef>
#include <vector>

namespace stsv {

/// The pattern and the alpha bits are uniform buffers when they fit the minimum
/// maxUniformBufferRange every Vulkan device guarantees; else storage buffers
/// (shaders/common/frame_bindings.glsl).
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

/// layoutDefines plus SAMPLE_COUNT and LS_COUNTERS: 1 when the light-sample buffer holds layer
/// counters (DCS, and --buffer counters), 0 for occlusion bits; any method's passes read it.
std::vector<ShaderDefine> sampleDefines(const RenderOptions& options, const FrameTableLayout& tables);

/// `defines` plus STSV_PATTERN_Q when the plan has one sample set (no interleaving) whose points
/// are all exact multiples of 2^-24 in [0,1): the set as 24-bit fixed-point integers baked into
/// the resolve (shaders/common/frame_bindings.glsl). Otherwise the shader reads the pattern buffer.
/// The resolve unrolls its sample loop with it (the constants need constant indices): 3x faster
/// at 64 and 128 samples on lavapipe (fence 1024²), but at 256 samples llvmpipe's lazy compile
/// of the unrolled shader made the first frame 4x slower, so not above 128 samples.
/// Only for the resolve: in stsv.frag the unrolled loop (texel tests, early continues) measured
/// 2-3x slower on lavapipe.
std::vector<ShaderDefine> withPatternDefine(std::vector<ShaderDefine> defines, const SamplePlan& plan);

/// `defines` plus FIXED_LIGHT_TYPE (sampling/light_sampling_dh.h): one resolve and one STSV
/// fragment shader per light type in the scene, with the type tests folded.
std::vector<ShaderDefine> lightTypeDefines(std::vector<ShaderDefine> defines, uint lightType);

/// The light types (LIGHT_*) among the scene's lights: the passes that specialise per type build
/// a pipeline for each of these.
std::array<bool, 4> lightTypesIn(const Scene& scene);

} // namespace stsv
