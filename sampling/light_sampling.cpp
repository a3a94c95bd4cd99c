#include "sampling/light_sampling.h"

#include "core/error.h"

#include <cmath>

namespace stsv {

float farDistanceFor(const Bounds& sceneBounds) {
    const float diameter = sceneBounds.empty() ? 0.0f : length(sceneBounds.extent());
    return 100.0f * std::max(diameter, 0.01f);
}

vec4 lightBoundingSphere(const Light& light, const Bounds& sceneBounds, float farDistance) {
    switch (light.type) {
    case LIGHT_RECTANGLE:
        return vec4(light.position,
                    std::max(length(light.axisU + light.axisV), length(light.axisU - light.axisV)));
    case LIGHT_DISK:
    case LIGHT_SPHERE:
        return vec4(light.position, light.radius);
    case LIGHT_DIRECTIONAL: {
        const vec3 centre = sceneBounds.empty() ? vec3(0.0f) : sceneBounds.center();
        const float sceneRadius = sceneBounds.empty() ? 0.0f : 0.5f * length(sceneBounds.extent());
        // Samples of p: p + normal·F + offset with |offset| ≤ F·tan(α), and |p − centre| ≤ R.
        const float radius = farDistance * std::tan(light.angularRadius) + sceneRadius;
        return vec4(centre + light.normal * farDistance, radius * (1.0f + 1e-5f)); // margin for rounding
    }
    default:
        throw UsageError("unknown light type " + std::to_string(light.type));
    }
}

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
