#include "sampling/light_sampling.h"

namespace stsv {

vec2 pixelSamplePoint(const SamplePlan& plan, int x, int y, int k, uint domain) {
    return samplePoint(plan.patternPoint(x, y, k), uvec2(unsigned(x), unsigned(y)), plan.seed,
                       plan.decorrelate, domain);
}

vec3 pixelLightSample(const SamplePlan& plan, int x, int y, int k, const LightFrame& frame) {
    return lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
}

vec3 resolveDirect(const LightSampleBuffer& buffer, const SamplePlan& plan, int x, int y, const Light& light,
                   vec3 p, vec3 n, vec3 albedo, float farDistance) {
    const LightFrame frame = lightFrame(light, p, farDistance);
    vec3 sum(0.0f);
    for (int k = 0; k < plan.count; ++k) {
        if (!buffer.visible(x, y, k)) continue;
        sum += sampleContribution(light, frame, p, n, pixelLightSample(plan, x, y, k, frame));
    }
    return albedo * (1.0f / SAMPLING_PI) * sum / float(plan.count);
}

} // namespace stsv
