#include "sampling/light_bounds.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace stsv {

float farDistanceFor(const Bounds& sceneBounds) {
    const float diameter = sceneBounds.diameter();
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
        const float sceneRadius = 0.5f * sceneBounds.diameter();
        // Samples of p: p + normal·F + offset with |offset| ≤ F·tan(α), and |p − centre| ≤ R.
        const float radius = farDistance * std::tan(light.angularRadius) + sceneRadius;
        return vec4(centre + light.normal * farDistance, radius * (1.0f + 1e-5f)); // margin for rounding
    }
    default:
        throw UsageError("unknown light type " + std::to_string(light.type));
    }
}

} // namespace stsv
