#include "sampling/light_sampling.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <string>

namespace stsv {

/// The data access of sampling/resolve_dh.h on the CPU: the pixel's bits from a LightSampleBuffer,
/// its sample points from the SamplePlan.
struct ResolveSource {
    const LightSampleBuffer* buffer;
    const vec2* points; ///< the pixel's samples (pixelSamplePoints)
    int x;              ///< pixel
    int y;
};
inline vec2 resolveSourcePoint(ResolveSource s, uint k) {
    return s.points[k];
}
inline uint resolveSourceWord(ResolveSource s, uint w) {
    return s.buffer->occludedWord(s.x, s.y, int(w));
}
inline bool resolveSourceOccluded(ResolveSource, uint word, uint k) {
    return (word & lsMaskBit(k)) != 0u;
}
inline float resolveSourceTransmittance(ResolveSource s, uint k) {
    return s.buffer->kind() == BufferKind::Transmittance ? s.buffer->transmittance(s.x, s.y, int(k)) : 1.0f;
}

} // namespace stsv

#define RESOLVE_SOURCE
#define RESOLVE_TRANSMITTANCE
#include "sampling/resolve_dh.h"

namespace stsv {

vec2 pixelSamplePoint(const SamplePlan& plan, int x, int y, int k, uint domain) {
    // Sub-pixels of a supersampled frame share their pixel's samples.
    const uvec2 pixel(unsigned(x / plan.supersample), unsigned(y / plan.supersample));
    return samplePoint(plan.patternPoint(x, y, k), pixel, plan.seed, plan.decorrelate, domain);
}

void pixelSamplePoints(const SamplePlan& plan, int x, int y, uint domain, vec2* out) {
    const uvec2 pixel(unsigned(x / plan.supersample), unsigned(y / plan.supersample));
    const uvec2 offset = decorrelationOffset(pixel, plan.seed);
    const vec2* pattern =
        &plan.points[std::size_t(plan.setIndex(x / plan.supersample, y / plan.supersample)) *
                     std::size_t(plan.count)];
    for (int k = 0; k < plan.count; ++k)
        out[k] = domainPoint(plan.decorrelate ? decorrelateBy(pattern[k], offset) : pattern[k], domain);
}

vec3 pixelLightSample(const SamplePlan& plan, int x, int y, int k, const LightFrame& frame) {
    return lightSamplePosition(frame, pixelSamplePoint(plan, x, y, k, frame.domain));
}

vec3 resolveDirect(const LightSampleBuffer& buffer, const SamplePlan& plan, int x, int y, const Light& light,
                   vec3 p, vec3 n, vec3 albedo, float farDistance, float scale) {
    const LightFrame frame = lightFrame(light, p, farDistance);
    std::array<vec2, 256> points;
    pixelSamplePoints(plan, x, y, frame.domain, points.data());
    const ResolveSource src{&buffer, points.data(), x, y};
    const uint count = uint(plan.count);
    const ResolveSums sums =
        resolveSamples(light, frame, p, n, src, lsMaskWordCount(count), std::min(32u, count));
    return resolveDirectLighting(albedo, resolveContributionSum(light, frame, sums), scale, count);
}

std::vector<PixelFacing> lightFacingPixels(const GBuffer& gbuffer, const std::vector<Light>& lights,
                                           float farDistance, int width, int height) {
    const int k = width > 0 ? gbuffer.width / width : 0;
    if (width <= 0 || height <= 0 || k < 1 || gbuffer.width != k * width || gbuffer.height != k * height ||
        gbuffer.position.size() != std::size_t(gbuffer.width) * std::size_t(gbuffer.height) ||
        gbuffer.normal.size() != gbuffer.position.size() ||
        gbuffer.triangle.size() != gbuffer.position.size())
        throw Error("lightFacingPixels: a " + std::to_string(gbuffer.width) + "x" +
                    std::to_string(gbuffer.height) + " G-buffer is not the point grid of a " +
                    std::to_string(width) + "x" + std::to_string(height) + " image");
    std::vector<PixelFacing> out(std::size_t(width) * std::size_t(height), PixelFacing::Background);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            PixelFacing& pixel = out[std::size_t(y) * std::size_t(width) + std::size_t(x)];
            for (int j = 0; j < k && pixel != PixelFacing::Facing; ++j)
                for (int i = 0; i < k && pixel != PixelFacing::Facing; ++i) {
                    const std::size_t g = gbuffer.index(x * k + i, y * k + j);
                    if (!gbuffer.covered(g)) continue;
                    pixel = PixelFacing::Away;
                    const vec3 p = gbuffer.position[g];
                    const vec3 n = gbuffer.normal[g];
                    for (const Light& light : lights)
                        if (receiverFacesLight(light, lightFrame(light, p, farDistance), p, n)) {
                            pixel = PixelFacing::Facing;
                            break;
                        }
                }
        }
    return out;
}

} // namespace stsv
