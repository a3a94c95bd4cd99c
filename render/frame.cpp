#include "render/frame.h"

#include "core/parallel.h"
#include "core/timer.h"
#include "reference/embree_scene.h"
#include "sampling/light_sampling.h"
#include "reference/reference_visibility.h"
#include "render/cpu_stsv.h"
#include "sampling/light_bounds.h"


namespace stsv {

namespace {
const vec3 BACKGROUND(0.02f, 0.02f, 0.03f);
}

void resolveLight(const Scene& scene, const GBuffer& gbuffer, const Light& light, const SamplePlan& plan,
                  float farDistance, const LightSampleBuffer& samples, float weight, ImageF& color,
                  ImageF& visibility) {
    parallelFor(std::size_t(gbuffer.width) * gbuffer.height, [&](std::size_t i) {
        const int x = static_cast<int>(i % std::size_t(gbuffer.width)), y = static_cast<int>(i / std::size_t(gbuffer.width));
        if (!gbuffer.covered(i)) {
            visibility.at(x, y, 0) += weight;
            return;
        }
        const vec3 albedo = scene.materialOf(gbuffer.triangle[i]).albedo;
        const vec3 direct =
            resolveDirect(samples, plan, x, y, light, gbuffer.position[i], gbuffer.normal[i], albedo, farDistance);
        for (int c = 0; c < 3; ++c) color.at(x, y, c) += direct[c];
        visibility.at(x, y, 0) += weight * samples.visibleFraction(x, y);
    }, 256);
}

Frame renderFrame(const Scene& scene, const RenderOptions& options) {
    validate(options);
    Frame frame;
    nlohmann::json passes = nlohmann::json::object();
    Timer total;
    Timer timer;

    const SamplePlan plan =
        makeSamplePlan(options.pattern, options.samples, options.seed, options.interleave, options.decorrelate);
    const Bounds bounds = scene.bounds();
    const float farDistance = farDistanceFor(bounds);
    const EmbreeScene embree(scene);
    passes["bvh_build"] = timer.milliseconds();

    timer.reset();
    frame.gbuffer = embree.traceGBuffer(options.width, options.height);
    passes["gbuffer"] = timer.milliseconds();

    frame.color = ImageF(options.width, options.height, 3);
    frame.visibility = ImageF(options.width, options.height, 1);
    for (std::size_t i = 0; i < frame.gbuffer.triangle.size(); ++i) {
        const int x = static_cast<int>(i % std::size_t(options.width)), y = static_cast<int>(i / std::size_t(options.width));
        const vec3 c = frame.gbuffer.covered(i) ? options.ambient * scene.materialOf(frame.gbuffer.triangle[i]).albedo
                                                : BACKGROUND;
        for (int k = 0; k < 3; ++k) frame.color.at(x, y, k) = c[k];
    }

    nlohmann::json stsvStats = nlohmann::json::array();
    const auto kind = options.buffer == BufferKind::Bitmask ? LightSampleBuffer::Kind::Bitmask
                                                            : LightSampleBuffer::Kind::Counters;
    std::size_t bufferBytes = 0;
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        const std::string prefix = "light" + std::to_string(l) + "/";
        LightSampleBuffer& buffer = frame.lightSamples.emplace_back(options.width, options.height, options.samples, kind);
        bufferBytes = std::max(bufferBytes, buffer.memoryBytes());
        timer.reset();
        if (options.method == Method::Reference) {
            traceReferenceSamples(embree, frame.gbuffer, light, plan, farDistance, buffer);
            passes[prefix + "reference"] = timer.milliseconds();
        } else {
            const StsvCpuStats s = stsvCpuSamples(scene, frame.gbuffer, light, plan, farDistance, buffer);
            passes[prefix + "stsv_bin"] = s.bin_ms;
            passes[prefix + "stsv_shade"] = s.shade_ms;
            stsvStats.push_back({{"volumes", s.volumes},
                                 {"degenerate_skipped", s.degenerateSkipped},
                                 {"tile_entries", s.tileEntries},
                                 {"point_in_volume_tests", s.pixelVolumeTests},
                                 {"fragments", s.pixelVolumeHits}});
        }
        timer.reset();
        resolveLight(scene, frame.gbuffer, light, plan, farDistance, buffer, 1.0f / float(scene.lights.size()),
                     frame.color, frame.visibility);
        passes[prefix + "resolve"] = timer.milliseconds();
    }

    std::size_t perforated = 0;
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) perforated += scene.perforated(t) ? 1 : 0;
    frame.stats = {{"options", toJson(options)},
                   {"scene", {{"source", scene.source},
                              {"triangles", scene.triangleCount()},
                              {"perforated_triangles", perforated},
                              {"lights", scene.lights.size()}}},
                   {"frame_ms", total.milliseconds()},
                   {"passes", passes},
                   {"light_sample_buffer_bytes", bufferBytes},
                   {"light_sample_buffer_bits_per_pixel", options.samples * (kind == LightSampleBuffer::Kind::Bitmask ? 1 : 16)}};
    if (!stsvStats.empty()) frame.stats["stsv"] = stsvStats;
    return frame;
}

} // namespace stsv
