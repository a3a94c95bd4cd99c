#include "render/vulkan/gpu_shader_defines.h"

#include "render/methods.h"
#include "sampling/light_sampling_dh.h"

#include <cmath>
#include <cstdint>
#include <string>

namespace stsv {

std::size_t patternVec4Count(const SamplePlan& plan) {
    const std::size_t vec4s = (plan.points.size() + 1) / 2;
    return vec4s * 16 <= MAX_UNIFORM_TABLE_BYTES ? vec4s : 0;
}

std::vector<ShaderDefine> layoutDefines(const FrameTableLayout& tables) {
    std::vector<ShaderDefine> defines;
    if (tables.patternVec4s > 0)
        defines.push_back({"STSV_PATTERN_VEC4S", std::to_string(tables.patternVec4s)});
    if (tables.alphaBitVec4s > 0)
        defines.push_back({"STSV_ALPHA_BIT_VEC4S", std::to_string(tables.alphaBitVec4s)});
    return defines;
}

bool frameCountsLayers(const RenderOptions& options) {
    return options.buffer == BufferKind::Counters || (options.buffer == BufferKind::Transmittance &&
                                                      methodInfo(options.method).wedges == WedgeVariant::Dcs);
}

std::vector<ShaderDefine> sampleDefines(const RenderOptions& options, const FrameTableLayout& tables) {
    std::vector<ShaderDefine> defines = layoutDefines(tables);
    const bool transmittance = options.buffer == BufferKind::Transmittance;
    defines.push_back({"SAMPLE_COUNT", std::to_string(options.samples)});
    defines.push_back({"LS_COUNTERS", options.buffer == BufferKind::Counters ? "1" : "0"});
    defines.push_back({"LS_TRANSMITTANCE", transmittance ? "1" : "0"});
    defines.push_back({"LS_OPAQUE_COUNTERS", transmittance && frameCountsLayers(options) ? "1" : "0"});
    return defines;
}

std::vector<ShaderDefine> withPatternDefine(std::vector<ShaderDefine> defines, const SamplePlan& plan) {
    if (plan.setCount() != 1 || plan.points.size() != std::size_t(plan.count) || plan.count > 128)
        return defines;
    std::string array = "uvec2[" + std::to_string(plan.points.size()) + "](";
    for (std::size_t k = 0; k < plan.points.size(); ++k) {
        const vec2 q = plan.points[k] * SAMPLING_FIXED_ONE;
        for (int c = 0; c < 2; ++c)
            if (!(q[c] >= 0.0f && q[c] < SAMPLING_FIXED_ONE && q[c] == std::floor(q[c]))) return defines;
        array += (k > 0 ? ",uvec2(" : "uvec2(") + std::to_string(std::uint32_t(q.x)) + "u," +
                 std::to_string(std::uint32_t(q.y)) + "u)";
    }
    defines.push_back({"STSV_PATTERN_Q", array + ")"});
    return defines;
}

std::vector<ShaderDefine> lightTypeDefines(std::vector<ShaderDefine> defines, uint lightType) {
    defines.push_back({"FIXED_LIGHT_TYPE", std::to_string(lightType) + "u"});
    return defines;
}

std::array<bool, 4> lightTypesIn(const Scene& scene) {
    std::array<bool, 4> used{};
    for (const Light& light : scene.lights) used.at(light.type) = true;
    return used;
}

std::array<Pipeline, 4> lightTypeComputePipelines(const Device& device, const PipelineLayout& layout,
                                                  const std::array<bool, 4>& types, const std::string& shader,
                                                  const std::vector<ShaderDefine>& defines) {
    const ShaderCompiler compiler;
    std::array<Pipeline, 4> pipelines;
    for (uint type = 0; type < types.size(); ++type)
        if (types[type])
            pipelines[type] = createComputePipeline(
                device, layout, compiler.compileFile(shader, lightTypeDefines(defines, type)));
    return pipelines;
}

} // namespace stsv
