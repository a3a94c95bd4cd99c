// `stsv compare`: methods against the reference at the same samples, seed and size (error
// table and error images), or two --dump-ls files sample by sample.
#include "cli/cli_util.h"
#include "cli/commands.h"
#include "cli/subcommands.h"

#include "core/error.h"
#include "core/progress.h"
#include "core/timer.h"
#include "render/frame.h"
#include "scene/load.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace stsv {

namespace {

namespace fs = std::filesystem;

std::string formatFixed(double value, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

bool isNpy(const std::string& path) {
    return fs::path(path).extension() == ".npy";
}

struct Row {
    MethodBackend mb;
    std::size_t differingSamples = 0;
    std::size_t comparedSamples = 0;
    std::size_t differingPixels = 0;
    ImageError visibility;
    ImageError lit;
    double frameMs = 0.0;
    bool perSample = true; ///< false for penumbra wedges: a v_coef per pixel, no per-sample result
    double identicalPercent() const {
        return comparedSamples ? 100.0 * double(comparedSamples - differingSamples) / double(comparedSamples)
                               : 100.0;
    }
};

std::string fileStem(const MethodBackend& mb) {
    return toString(mb.method) + "_" + toString(mb.backend);
}

double frameMsOf(const Frame& frame, double fallback) {
    const auto it = frame.stats.find("frame_ms");
    return it != frame.stats.end() && it->is_number() ? it->get<double>() : fallback;
}

Row compareFrames(const MethodBackend& mb, const Frame& frame, const Frame& against, double frameMs) {
    Row row;
    row.mb = mb;
    row.frameMs = frameMs;
    if (frame.lightSamples.size() != against.lightSamples.size())
        throw Error(toString(mb) + " returned " + std::to_string(frame.lightSamples.size()) +
                    " light-sample buffers, the reference " + std::to_string(against.lightSamples.size()));
    row.perSample = methodInfo(mb.method).output != MethodOutput::Visibility;
    for (std::size_t l = 0; row.perSample && l < frame.lightSamples.size(); ++l) {
        const LightSampleDiff d = compareLightSamples(frame.lightSamples[l], against.lightSamples[l], 0);
        row.differingSamples += d.differingSamples;
        row.comparedSamples += d.comparedSamples;
        row.differingPixels += d.differingPixels;
    }
    row.visibility = compareImages(toDisplay(frame.visibility, false), toDisplay(against.visibility, false));
    row.lit = compareImages(toDisplay(frame.color, true), toDisplay(against.color, true));
    return row;
}

void writeImages(const std::string& dir, const MethodBackend& mb, const Frame& frame, const Row* row,
                 const Frame* against, float heatScale) {
    const fs::path base = fs::path(dir) / fileStem(mb);
    writePng(base.string() + "_visibility.png", toImage8(frame.visibility, false));
    writePng(base.string() + "_lit.png", toImage8(frame.color, true));
    if (!row || !against) return;
    writePng(base.string() + "_diff.png", heatMap(row->visibility.absDifference, heatScale));
    if (!frame.lightSamples.empty())
        writePng(base.string() + "_bitdiff.png",
                 heatMap(sampleDisagreement(frame.lightSamples[0], against->lightSamples[0]), heatScale));
}

int compareNpy(const CompareArgs& args) {
    LightSampleBuffer a = LightSampleBuffer::readNpy(args.inputs[0]);
    LightSampleBuffer b = LightSampleBuffer::readNpy(args.inputs[1]);
    // A uint8 file is a bitmask [H, W, N/8] or counters below 256 [H, W, N]: when, read as
    // bitmasks, one file has 8x the other's samples, it holds counters, and the two compare by
    // occlusion (count > 0).
    if (a.kind() == BufferKind::Bitmask && b.kind() == BufferKind::Bitmask && a.samples() == 8 * b.samples())
        a = LightSampleBuffer::readNpy(args.inputs[0], BufferKind::Counters);
    else if (a.kind() == BufferKind::Bitmask && b.kind() == BufferKind::Bitmask &&
             b.samples() == 8 * a.samples())
        b = LightSampleBuffer::readNpy(args.inputs[1], BufferKind::Counters);
    if (a.width() != b.width() || a.height() != b.height() || a.samples() != b.samples())
        throw UsageError(args.inputs[0] + " is " + std::to_string(a.width()) + "x" +
                         std::to_string(a.height()) + " pixels with " + std::to_string(a.samples()) +
                         " samples, " + args.inputs[1] + " is " + std::to_string(b.width()) + "x" +
                         std::to_string(b.height()) + " with " + std::to_string(b.samples()));
    if (!args.out.empty()) prepareOutputDirectory(args.out, "--out");
    const LightSampleDiff d = compareLightSamples(a, b, 8);
    const double percent =
        d.comparedSamples ? 100.0 * double(d.differingSamples) / double(d.comparedSamples) : 0.0;
    std::printf("%s vs %s: %dx%d pixels, %d samples\n", args.inputs[0].c_str(), args.inputs[1].c_str(),
                a.width(), a.height(), a.samples());
    if (a.kind() != b.kind())
        std::printf("%s holds counters, %s bits: comparing occlusion (count > 0)\n",
                    (a.kind() == BufferKind::Counters ? args.inputs[0] : args.inputs[1]).c_str(),
                    (a.kind() == BufferKind::Counters ? args.inputs[1] : args.inputs[0]).c_str());
    std::printf("differing samples: %zu of %zu (%.6f %%), identical %.6f %%\n", d.differingSamples,
                d.comparedSamples, percent, 100.0 - percent);
    std::printf("differing pixels:  %zu of %zu\n", d.differingPixels,
                std::size_t(a.width()) * std::size_t(a.height()));
    if (!d.firstPixels.empty()) {
        std::printf("first differing pixels (x, y):");
        for (const ivec2& p : d.firstPixels) std::printf(" (%d, %d)", p.x, p.y);
        std::printf("\n");
    }
    if (!args.out.empty()) {
        const std::string path = (fs::path(args.out) / "difference.png").string();
        writePng(path, heatMap(sampleDisagreement(a, b), args.heatScale));
        std::printf("wrote %s (fraction of differing samples per pixel, yellow at %.3g)\n", path.c_str(),
                    double(args.heatScale));
    }
    return 0;
}

} // namespace

int runCompare(CompareArgs& args) {
    if (args.quiet) Progress::setEnabled(false);
    if (!(args.heatScale > 0.0f && args.heatScale <= 1.0f))
        throw UsageError("--heat-scale must lie in (0, 1]");
    if (args.inputs.size() == 2) {
        if (!isNpy(args.inputs[0]) || !isNpy(args.inputs[1]))
            throw UsageError("compare takes one SCENE, or two .npy light-sample files");
        return compareNpy(args);
    }
    if (args.inputs.size() != 1) throw UsageError("compare takes one SCENE, or two .npy light-sample files");
    if (isNpy(args.inputs[0])) throw UsageError("compare of light-sample files needs two .npy files");

    const std::string& spec = args.inputs[0];
    const RenderOptions base = resolveFrameOptions(args);
    const Backend fallback = args.backend.empty() ? defaultBackend() : parseBackend(args.backend);
    const MethodBackend against = parseMethodBackend(args.against, fallback);
    std::vector<MethodBackend> methods;
    for (const std::string& m : splitList(args.methods)) methods.push_back(parseMethodBackend(m, fallback));
    if (methods.empty()) throw UsageError("--methods is empty");
    std::vector<Method> all{against.method};
    for (const MethodBackend& mb : methods) all.push_back(mb.method);
    const std::vector<MethodParams> params = paramsForMethods(all, args.params);
    if (!args.out.empty()) prepareOutputDirectory(args.out, "--out");
    if (!args.json.empty()) checkWritableFile(args.json, "--json");

    const Scene scene = loadScene(spec, parseSets(args.sets));
    checkFrameMemory(base, scene.lights.size());

    auto render = [&](const MethodBackend& mb, double& frameMs) {
        RenderOptions o = base;
        o.method = mb.method;
        o.backend = mb.backend;
        o.params = params[std::size_t(std::find(all.begin(), all.end(), mb.method) - all.begin())];
        Timer wall;
        Frame frame = renderFrame(scene, o);
        frameMs = frameMsOf(frame, wall.milliseconds());
        return frame;
    };
    double againstMs = 0.0;
    const Frame reference = render(against, againstMs);
    std::vector<Row> rows;
    rows.push_back(compareFrames(against, reference, reference, againstMs));
    if (!args.out.empty()) writeImages(args.out, against, reference, nullptr, nullptr, args.heatScale);
    for (const MethodBackend& mb : methods) {
        if (mb.method == against.method && mb.backend == against.backend) continue; // already the first row
        double ms = 0.0;
        const Frame frame = render(mb, ms);
        rows.push_back(compareFrames(mb, frame, reference, ms));
        if (!args.out.empty()) writeImages(args.out, mb, frame, &rows.back(), &reference, args.heatScale);
    }

    std::printf("%s, %dx%d, %d samples (%s, seed %u), against %s\n", scene.source.c_str(), base.width,
                base.height, base.samples, toString(base.pattern).c_str(), base.seed,
                toString(against).c_str());
    std::printf("%-16s %12s %12s %10s %10s %10s %10s %10s %11s\n", "method", "identical %", "diff. bits",
                "vis RMSE", "vis max", "lit RMSE", "lit max", ">1/255 px", "frame ms");
    for (const Row& r : rows) {
        const std::string identical = r.perSample ? formatFixed(r.identicalPercent(), 4) : "n/a";
        const std::string differing = r.perSample ? std::to_string(r.differingSamples) : "n/a";
        std::printf("%-16s %12s %12s %10.5f %10.5f %10.5f %10.5f %9.4f%% %11.1f\n", toString(r.mb).c_str(),
                    identical.c_str(), differing.c_str(), r.visibility.rmse, r.visibility.maxAbs, r.lit.rmse,
                    r.lit.maxAbs, 100.0 * r.lit.fractionAbove, r.frameMs);
    }
    std::printf(
        "(errors in display units [0, 1]: visibility linear, lit image sRGB-encoded; >1/255 px = pixels "
        "of the lit image off by more than one 8-bit step; n/a: penumbra wedges give a v_coef per pixel, "
        "not per-sample bits)\n");
    if (!args.out.empty()) std::printf("images in %s\n", args.out.c_str());

    if (!args.json.empty()) {
        nlohmann::json list = nlohmann::json::array();
        for (const Row& r : rows)
            list.push_back(
                {{"method", toString(r.mb.method)},
                 {"backend", toString(r.mb.backend)},
                 {"identical_percent", r.perSample ? nlohmann::json(r.identicalPercent()) : nlohmann::json()},
                 {"differing_samples", r.differingSamples},
                 {"compared_samples", r.comparedSamples},
                 {"differing_pixels", r.differingPixels},
                 {"visibility",
                  {{"rmse", r.visibility.rmse},
                   {"max_abs", r.visibility.maxAbs},
                   {"fraction_above_1_255", r.visibility.fractionAbove}}},
                 {"lit",
                  {{"rmse", r.lit.rmse},
                   {"max_abs", r.lit.maxAbs},
                   {"fraction_above_1_255", r.lit.fractionAbove}}},
                 {"frame_ms", r.frameMs}});
        RenderOptions o = base;
        o.method = against.method;
        o.backend = against.backend;
        o.params = params[0];
        writeJson(args.json,
                  {{"scene", spec}, {"against", toString(against)}, {"options", toJson(o)}, {"rows", list}});
    }
    return 0;
}

} // namespace stsv
