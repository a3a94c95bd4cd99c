#include "reference/reference_visibility.h"

#include "core/parallel.h"
#include "core/progress.h"
#include "sampling/light_sampling.h"
#include "scene/occlusion_rules_dh.h"

#include <array>

namespace stsv {

void traceReferenceSamples(const EmbreeScene& scene, const GBuffer& gbuffer, const Light& light,
                           const SamplePlan& plan, float farDistance, LightSampleBuffer& out) {
    const bool counting = out.kind() == BufferKind::Counters;
    const bool transmittance = out.kind() == BufferKind::Transmittance;
    const Bounds bounds = scene.scene().bounds();
    const float sceneDiameter = bounds.diameter();
    Progress progress("reference rays",
                      std::size_t(tilesAcross(gbuffer.width)) * tilesAcross(gbuffer.height));
    parallelForTiles(gbuffer.width, gbuffer.height, [&](const PixelTile& tile) {
        std::vector<std::uint32_t> scratch;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> crossings;
        std::array<vec2, 256> points;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                const std::size_t i = gbuffer.index(x, y);
                if (!gbuffer.covered(i)) continue;
                const vec3 p = gbuffer.position[i];
                const LightFrame frame = lightFrame(light, p, farDistance);
                const float tMin = shadowTMin(p, frame.center, sceneDiameter);
                pixelSamplePoints(plan, x, y, frame.domain, points.data());
                for (int k = 0; k < plan.count; ++k) {
                    const vec3 s = lightSamplePosition(frame, points[std::size_t(k)]);
                    if (transmittance) {
                        out.addOpticalDepth(x, y, k,
                                            scene.opticalDepth(p, s, tMin, gbuffer.triangle[i], crossings));
                    } else if (counting) {
                        const std::uint32_t layers =
                            scene.countLayers(p, s, tMin, gbuffer.triangle[i], scratch);
                        if (layers) out.addCount(x, y, k, static_cast<int>(layers));
                    } else if (scene.occluded(p, s, tMin, gbuffer.triangle[i])) {
                        out.setOccluded(x, y, k);
                    }
                }
            }
        progress.advance();
    });
}

} // namespace stsv
