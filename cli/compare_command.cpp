// `stsv compare`: methods against the reference at the same samples, seed and size (error
// table and error images), or two --dump-ls files sample by sample.
#include "cli/cli_util.h"
#include "cli/commands.h"
#include "cli/compare_report.h"
#include "cli/converged_reference.h"
#include "cli/subcommands.h"

#include "core/contact_sheet.h"
#include "core/error.h"
#include "core/files.h"
#include "core/progress.h"
#include "core/timer.h"
#include "core/version.h"
#include "render/renderer.h"
#include "sampling/light_sampling.h"
#include "scene/load.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

namespace stsv {

namespace {

namespace fs = std::filesystem;

/// Captions of the colour scales under the heat maps written to --out.
constexpr const char* VISIBILITY_CAPTION = "|visibility difference|";
constexpr const char* SAMPLE_CAPTION = "fraction of light samples that differ";

bool isNpy(const std::string& path) {
    return lowerExtension(path) == ".npy";
}

bool isExr(const std::string& path) {
    return lowerExtension(path) == ".exr";
}

/// A visibility image from `render --visibility`: an EXR (its Y channel), or a float32 [H, W] .npy.
ImageF readVisibilityFile(const std::string& path) {
    if (isExr(path)) {
        ImageF image = readExr(path);
        if (image.channels != 1) throw InputError(path, "a visibility EXR has one channel, Y");
        return image;
    }
    const NpyArray a = readNpy(path);
    if (a.dtype != "<f4" || a.shape.size() != 2)
        throw InputError(path, "a visibility .npy is float32 [H, W], not " + a.dtype + " of " +
                                   std::to_string(a.shape.size()) + " dimensions");
    ImageF image(int(a.shape[1]), int(a.shape[0]), 1);
    std::memcpy(image.pixels.data(), a.bytes.data(), a.bytes.size());
    return image;
}

/// Two visibility images (.exr, or float32 .npy [H, W]): RMSE, bias, max, SSIM, and the heat map.
int compareVisibilityFiles(const CompareArgs& args) {
    if (!args.kind.empty() || args.samplesGiven)
        throw UsageError(std::string(args.kind.empty() ? "--samples" : "--kind") +
                         " applies to .npy light-sample files; " + args.inputs[0] + " and " + args.inputs[1] +
                         " are visibility images");
    const ImageF a = readVisibilityFile(args.inputs[0]), b = readVisibilityFile(args.inputs[1]);
    if (a.width != b.width || a.height != b.height)
        throw UsageError(args.inputs[0] + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                         ", " + args.inputs[1] + " is " + std::to_string(b.width) + "x" +
                         std::to_string(b.height));
    const ImageError e = compareImages(a, b, 0.1f);
    std::printf("%s vs %s: %dx%d visibility\n", printable(args.inputs[0]).c_str(),
                printable(args.inputs[1]).c_str(), a.width, a.height);
    std::printf(
        "RMSE %.6f, bias %+.6f, max |difference| %.6f, |dv| > 0.1 in %.4f %% of the pixels, SSIM %.6f\n",
        e.rmse, e.bias, e.maxAbs, 100.0 * e.fractionAbove, e.ssim);
    std::printf(
        "(no light-facing figure: visibility files hold no normals or lights; compare a SCENE for the "
        "error over the pixels that face a light)\n");
    if (!args.out.empty()) {
        const std::string path = (fs::path(args.out) / "difference.png").string();
        writePng(path, heatMapWithLegend(e.absDifference, args.heatScale, VISIBILITY_CAPTION));
        std::printf("wrote %s (|difference| per pixel, yellow at %.3g)\n", printable(path).c_str(),
                    double(args.heatScale));
    }
    return 0;
}

struct Row {
    MethodBackend mb;
    std::size_t differingSamples = 0;
    std::size_t comparedSamples = 0;
    std::size_t differingPixels = 0;
    ImageError visibility;          ///< against the equal-sample reference; fractionAbove at 1/255
    ImageError lit;                 ///< against the equal-sample reference; fractionAbove at 1/255
    ImageError visibilityCoarse;    ///< the same, fractionAbove at |Δ| > COARSE_ERROR
    ImageError convergedVisibility; ///< against the converged reference; fractionAbove at COARSE_ERROR
    ImageError convergedLit;        ///< against the converged reference; fractionAbove at 1/255
    /// The visibility error over the light-facing pixels (lightFacingOf), against the equal-sample
    /// and the converged reference: the figure the ranking uses.
    RegionError visibilityFacing;
    RegionError convergedVisibilityFacing;
    std::optional<int> rank;  ///< 1 for the smallest light-facing error; none for the --against row
    ImageF visibilityDisplay; ///< kept for --converged, --report, --sheet
    ImageF litDisplay;
    double frameMs = 0.0;
    bool perSample = true; ///< false when it or the method compared with has a v_coef per pixel only
    /// Per-sample RMSE of the transmittance (0 or 1 for bits and counters) against a reference
    /// that wrote a transmittance buffer; empty otherwise.
    std::optional<double> transmittanceRmse;
    double identicalPercent() const {
        return comparedSamples ? 100.0 * double(comparedSamples - differingSamples) / double(comparedSamples)
                               : 100.0;
    }
};

/// Visibility errors above this count as visible ones (the "|dv|>0.1" column).
constexpr float COARSE_ERROR = 0.1f;

std::string fileStem(const MethodBackend& mb) {
    return toString(mb.method) + "_" + toString(mb.backend);
}

double frameMsOf(const Frame& frame, double fallback) {
    const auto it = frame.stats.find("frame_ms");
    return it != frame.stats.end() && it->is_number() ? it->get<double>() : fallback;
}

/// The pixels the headline figure counts, one mask for every row of a compare: those of the
/// --against frame's G-buffer that face some light.
LightFacingMask lightFacingOf(const Frame& against, const Scene& scene) {
    return lightFacingMask(against.gbuffer, scene.lights, farDistanceFor(scene.bounds()),
                           against.visibility.width, against.visibility.height);
}

Row compareFrames(const MethodBackend& mb, const Frame& frame, const MethodBackend& againstMb,
                  const Frame& against, double frameMs, const LightFacingMask& facing) {
    Row row;
    row.mb = mb;
    row.frameMs = frameMs;
    if (frame.lightSamples.size() != against.lightSamples.size())
        throw Error(toString(mb) + " returned " + std::to_string(frame.lightSamples.size()) +
                    " light-sample buffers, the reference " + std::to_string(against.lightSamples.size()));
    // Bits are counted only where both sides have them: a visibility-only method (pw, pcf, ...)
    // holds no per-sample answer, and its buffer's zeros would read as "every sample lit".
    row.perSample = methodInfo(mb.method).output != MethodOutput::Visibility &&
                    methodInfo(againstMb.method).output != MethodOutput::Visibility;
    for (std::size_t l = 0; row.perSample && l < frame.lightSamples.size(); ++l) {
        const LightSampleDiff d =
            compareLightSamples(frame.lightSamples[l], against.lightSamples[l], 0,
                                transmittanceBoth(frame.lightSamples[l], against.lightSamples[l]));
        row.differingSamples += d.differingSamples;
        row.comparedSamples += d.comparedSamples;
        row.differingPixels += d.differingPixels;
    }
    if (row.perSample && !against.lightSamples.empty() &&
        against.lightSamples[0].kind() == BufferKind::Transmittance) {
        double sum = 0.0;
        std::size_t count = 0;
        for (std::size_t l = 0; l < frame.lightSamples.size(); ++l) {
            const LightSampleBuffer& a = frame.lightSamples[l];
            const LightSampleBuffer& b = against.lightSamples[l];
            for (int y = 0; y < a.height(); ++y)
                for (int x = 0; x < a.width(); ++x)
                    for (int k = 0; k < a.samples(); ++k) {
                        const double d = double(a.transmittance(x, y, k)) - double(b.transmittance(x, y, k));
                        sum += d * d;
                        ++count;
                    }
        }
        row.transmittanceRmse = count ? std::sqrt(sum / double(count)) : 0.0;
    }
    row.visibilityDisplay = toDisplay(frame.visibility, false);
    row.litDisplay = toDisplay(frame.color, true);
    const ImageF againstVisibility = toDisplay(against.visibility, false);
    row.visibility = compareImages(row.visibilityDisplay, againstVisibility);
    row.visibilityCoarse = compareImages(row.visibilityDisplay, againstVisibility, COARSE_ERROR);
    row.visibilityFacing = compareImagesWhere(row.visibilityDisplay, againstVisibility, facing.selected);
    row.lit = compareImages(row.litDisplay, toDisplay(against.color, true));
    return row;
}

void writeImages(const std::string& dir, const MethodBackend& mb, const Frame& frame, const Row* row,
                 const Frame* against, float heatScale) {
    const fs::path base = fs::path(dir) / fileStem(mb);
    writePng(base.string() + "_visibility.png", toImage8(frame.visibility, false));
    writePng(base.string() + "_lit.png", toImage8(frame.color, true));
    if (!row || !against) return;
    writePng(base.string() + "_diff.png",
             heatMapWithLegend(row->visibility.absDifference, heatScale, VISIBILITY_CAPTION));
    if (row->perSample && !frame.lightSamples.empty())
        writePng(base.string() + "_bitdiff.png",
                 heatMapWithLegend(sampleDisagreement(frame.lightSamples[0], against->lightSamples[0]),
                                   heatScale, SAMPLE_CAPTION));
}

/// "a bitmask of 128 samples", "counters of 16 samples".
std::string describeSamples(const LightSampleBuffer& buffer) {
    const std::string kind = toString(buffer.kind());
    return (buffer.kind() == BufferKind::Bitmask ? "a " : "") + kind + " of " +
           std::to_string(buffer.samples()) + " samples";
}

/// One of compare's two light-sample files, read with its kind from its metadata
/// (LightSampleFileInfo), else from --kind, else from its dtype where that alone says it.
LightSampleBuffer readSampleFile(const std::string& path, const NpyArray& array,
                                 const std::optional<LightSampleFileInfo>& info,
                                 const std::optional<BufferKind>& kind) {
    const std::string infoName = fs::path(npyInfoPath(path)).filename().string();
    if (info && kind && info->kind != *kind)
        throw UsageError("--kind " + toString(*kind) + ": " + path + " holds " + toString(info->kind) + " (" +
                         infoName + " says so); --kind is for files without that metadata");
    if (!info && !kind && (array.dtype == "|u1" || array.dtype == "<u1"))
        throw UsageError(path + " has no " + infoName +
                         " beside it (an older stsv's --dump-ls, or an array from NumPy), and its uint8 "
                         "array may be a bitmask or counters: give --kind bitmask or --kind counters (and "
                         "--samples N to check the sample count)");
    return LightSampleBuffer::fromNpy(path, array, info ? std::nullopt : kind);
}

int compareNpy(const CompareArgs& args, const NpyArray& arrayA, const NpyArray& arrayB) {
    std::optional<BufferKind> kind;
    if (!args.kind.empty()) {
        kind = bufferKindNamed(args.kind);
        if (!kind)
            throw UsageError("--kind '" + args.kind + "' is not one of bitmask, counters, transmittance");
    }
    const std::string& pathA = args.inputs[0];
    const std::string& pathB = args.inputs[1];
    const std::optional<LightSampleFileInfo> infoA = readLightSampleInfo(pathA);
    const std::optional<LightSampleFileInfo> infoB = readLightSampleInfo(pathB);
    const LightSampleBuffer a = readSampleFile(pathA, arrayA, infoA, kind);
    const LightSampleBuffer b = readSampleFile(pathB, arrayB, infoB, kind);
    // Samples compare one to one only between buffers of one kind and N: a counters file read as
    // bits would pair the wrong samples (16 counters fill the bytes of 128 bits).
    auto madeBy = [](const std::optional<LightSampleFileInfo>& info) {
        return info && !info->method.empty() ? " (" + info->method + ")" : std::string();
    };
    if (a.kind() != b.kind() || a.samples() != b.samples())
        throw UsageError(pathA + " holds " + describeSamples(a) + madeBy(infoA) + ", " + pathB + " " +
                         describeSamples(b) + madeBy(infoB) +
                         ": compare pairs samples of one kind and count; render both with the same --buffer "
                         "and --samples");
    if (args.samplesGiven && a.samples() != args.options.samples)
        throw UsageError("--samples " + std::to_string(args.options.samples) + ": " + pathA + " and " +
                         pathB + " hold " + std::to_string(a.samples()) + " samples");
    if (a.width() != b.width() || a.height() != b.height())
        throw UsageError(pathA + " is " + std::to_string(a.width()) + "x" + std::to_string(a.height()) +
                         " pixels, " + pathB + " is " + std::to_string(b.width()) + "x" +
                         std::to_string(b.height()));
    const LightSampleDiff d = compareLightSamples(a, b, 8, transmittanceBoth(a, b));
    const double percent =
        d.comparedSamples ? 100.0 * double(d.differingSamples) / double(d.comparedSamples) : 0.0;
    std::printf("%s vs %s: %dx%d pixels, %d samples, %s\n", printable(pathA).c_str(),
                printable(pathB).c_str(), a.width(), a.height(), a.samples(), toString(a.kind()).c_str());
    if (!madeBy(infoA).empty() || !madeBy(infoB).empty())
        std::printf("written by %s and %s\n", infoA && !infoA->method.empty() ? infoA->method.c_str() : "?",
                    infoB && !infoB->method.empty() ? infoB->method.c_str() : "?");
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
        writePng(path, heatMapWithLegend(sampleDisagreement(a, b), args.heatScale, SAMPLE_CAPTION));
        std::printf("wrote %s (fraction of differing samples per pixel, yellow at %.3g)\n",
                    printable(path).c_str(), double(args.heatScale));
    }
    return 0;
}

std::string formatSigned(double value) {
    char text[64];
    std::snprintf(text, sizeof text, "%+.5f", value);
    return text;
}

std::string formatPercent(double fraction) {
    return formatFixed(100.0 * fraction, 4) + "%";
}

/// The columns of the bias tables (against the equal-sample and the converged reference).
const std::vector<std::string> ERROR_HEADER = {"method",   "vis RMSE", "vis bias", "vis max",
                                               "|dv|>0.1", "lit RMSE", "lit bias"};

std::vector<std::string> errorCells(const std::string& name, const ImageError& visibility,
                                    const ImageError& lit) {
    return {name,
            formatFixed(visibility.rmse, 5),
            formatSigned(visibility.bias),
            formatFixed(visibility.maxAbs, 5),
            formatPercent(visibility.fractionAbove),
            formatFixed(lit.rmse, 5),
            formatSigned(lit.bias)};
}

/// A light-facing error: rmse, bias and max_abs (null where no pixel faces a light) and pixels.
nlohmann::json facingJson(const RegionError& e) {
    const auto value = [&](double v) { return e.pixels ? nlohmann::json(v) : nlohmann::json(); };
    return {
        {"rmse", value(e.rmse)}, {"bias", value(e.bias)}, {"max_abs", value(e.maxAbs)}, {"pixels", e.pixels}};
}

nlohmann::json errorJson(const ImageError& visibility, const RegionError& visibilityFacing,
                         const ImageError& lit) {
    return {{"visibility_facing", facingJson(visibilityFacing)},
            {"visibility",
             {{"rmse", visibility.rmse},
              {"bias", visibility.bias},
              {"max_abs", visibility.maxAbs},
              {"fraction_above_0_1", visibility.fractionAbove}}},
            {"lit",
             {{"rmse", lit.rmse},
              {"bias", lit.bias},
              {"max_abs", lit.maxAbs},
              {"ssim", lit.ssim},
              {"fraction_above_1_255", lit.fractionAbove}}}};
}

const char* const BIAS_NOTE =
    "errors in display units [0, 1]: visibility linear, lit image sRGB-encoded; bias = mean of method - "
    "reference over the pixels (negative: darker than the reference); |dv|>0.1 = pixels whose visibility "
    "is off by more than 0.1";

/// What the ranking says of itself, under its table and in the report (docs/user-guide.md).
const char* const RANKING_NOTE =
    "ranked by the visibility error over the light-facing pixels: those whose visible point has N.L > 0 "
    "for some point of some light (part of a light is in front of its surface). On pixels facing away "
    "from every light visibility changes nothing in the lit image, so their error ranks no method; "
    "pixels without a surface count in neither. vis RMSE (all) is over every pixel, as in the other "
    "tables; lit RMSE is the lit image's, over every pixel";

/// The light-facing figure the ranking uses: against the converged reference where there is one.
const RegionError& rankingFigure(const Row& r, bool converged) {
    return converged ? r.convergedVisibilityFacing : r.visibilityFacing;
}

/// Ranks every row but the first (--against) by rankingFigure's RMSE, smallest first, ties in
/// the command's order; returns the rows' indices in rank order.
std::vector<std::size_t> rankRows(std::vector<Row>& rows, bool converged) {
    std::vector<std::size_t> order;
    for (std::size_t i = 1; i < rows.size(); ++i) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return rankingFigure(rows[a], converged).rmse < rankingFigure(rows[b], converged).rmse;
    });
    for (std::size_t k = 0; k < order.size(); ++k) rows[order[k]].rank = int(k) + 1;
    return order;
}

/// "1234 of the 4096 pixels with a surface, 30.13 %".
std::string facingPixelsText(const LightFacingMask& facing) {
    const std::size_t surface = facing.facing + facing.away;
    return std::to_string(facing.facing) + " of the " + std::to_string(surface) + " pixels with a surface, " +
           formatFixed(surface ? 100.0 * double(facing.facing) / double(surface) : 0.0, 2) + " %";
}

/// The headline table: the rows in rank order (with --converged the noise floor first, unranked).
ReportTable rankingTable(const std::vector<Row>& rows, const std::vector<std::size_t>& order, bool converged,
                         const LightFacingMask& facing) {
    ReportTable t;
    t.caption = std::string("ranking by visibility RMSE over the light-facing pixels, against the ") +
                (converged ? "converged" : "equal-sample") + " reference (" + facingPixelsText(facing) + "):";
    t.header = {"rank",           "method",         "facing vis RMSE", "facing vis bias",
                "facing vis max", "vis RMSE (all)", "lit RMSE",        "frame ms"};
    const auto cells = [&](const std::string& rank, const std::string& name, const Row& r) {
        const RegionError& f = rankingFigure(r, converged);
        const ImageError& all = converged ? r.convergedVisibility : r.visibility;
        const ImageError& lit = converged ? r.convergedLit : r.lit;
        const bool any = f.pixels > 0;
        return std::vector<std::string>{rank,
                                        name,
                                        any ? formatFixed(f.rmse, 5) : "n/a",
                                        any ? formatSigned(f.bias) : "n/a",
                                        any ? formatFixed(f.maxAbs, 5) : "n/a",
                                        formatFixed(all.rmse, 5),
                                        formatFixed(lit.rmse, 5),
                                        formatFixed(r.frameMs, 1)};
    };
    if (converged) t.rows.push_back(cells("-", "noise floor", rows.front()));
    for (std::size_t i : order)
        t.rows.push_back(cells(std::to_string(*rows[i].rank), toString(rows[i].mb), rows[i]));
    t.note = "(" + std::string(RANKING_NOTE) +
             (facing.facing ? "" : "; no pixel faces a light here, so the order is the command's") +
             (converged ? "; noise floor = the equal-sample reference against the converged one)" : ")");
    return t;
}

/// The existing table's cells (what the terminal prints first), for the HTML page.
ReportTable equalSampleTable(const std::vector<Row>& rows) {
    ReportTable t;
    t.header = {"method",   "identical %", "diff. bits", "vis RMSE",  "vis max",
                "lit RMSE", "lit max",     "lit SSIM",   ">1/255 px", "frame ms"};
    for (const Row& r : rows)
        t.rows.push_back(
            {toString(r.mb), r.perSample ? formatFixed(r.identicalPercent(), 4) : "n/a",
             r.perSample ? std::to_string(r.differingSamples) : "n/a", formatFixed(r.visibility.rmse, 5),
             formatFixed(r.visibility.maxAbs, 5), formatFixed(r.lit.rmse, 5), formatFixed(r.lit.maxAbs, 5),
             formatFixed(r.lit.ssim, 5), formatPercent(r.lit.fractionAbove), formatFixed(r.frameMs, 1)});
    // With a transmittance reference: each method's per-sample transmittance RMSE.
    if (!rows.empty() && rows.front().transmittanceRmse) {
        t.header.push_back("transmittance RMSE");
        for (std::size_t i = 0; i < rows.size(); ++i)
            t.rows[i].push_back(rows[i].transmittanceRmse ? formatFixed(*rows[i].transmittanceRmse, 5)
                                                          : "n/a");
    }
    return t;
}

/// A value of the options JSON as the report shows it: floats with 6 significant digits (the
/// ambient of 0.05f, not 0.0500000007), objects as "name=value, …".
std::string settingText(const nlohmann::json& value) {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number_float()) {
        char text[32];
        std::snprintf(text, sizeof text, "%.6g", value.get<double>());
        return text;
    }
    if (value.is_object()) {
        std::string text;
        for (const auto& [name, item] : value.items())
            text += (text.empty() ? "" : ", ") + name + "=" + settingText(item);
        return text.empty() ? "none" : text;
    }
    return value.dump();
}

/// What the report and the sheet show of one row: lit image, visibility, error heat map.
struct ImageSet {
    std::string name;
    std::string stem;
    Image8 lit;
    Image8 visibility;
    Image8 heat; ///< empty (width 0) where there is nothing to compare with
};

/// The images --report and --sheet show per row: lit, visibility and |Δ visibility| against the
/// converged reference (or the equal-sample one, none for the reference's own row); then the
/// converged reference itself.
std::vector<ImageSet> imageSets(const std::vector<Row>& rows, const ConvergedReference* converged,
                                int samplesPerPixel, float heatScale) {
    std::vector<ImageSet> sets;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        ImageSet set{toString(r.mb), fileStem(r.mb), toImage8(r.litDisplay, false),
                     toImage8(r.visibilityDisplay, false), Image8{}};
        if (converged)
            set.heat = heatMap(r.convergedVisibility.absDifference, heatScale);
        else if (i > 0)
            set.heat = heatMap(r.visibility.absDifference, heatScale);
        sets.push_back(std::move(set));
    }
    if (converged)
        sets.push_back({"converged reference (" + std::to_string(samplesPerPixel) + " spp)", "converged",
                        toImage8(converged->images.color, true),
                        toImage8(converged->images.visibility, false), Image8{}});
    return sets;
}

/// The page's header: title, command line and settings (the --against frame's options), and
/// the tables.
Report describeReport(const CompareArgs& args, const Scene& scene, const SceneOptions& sceneSets,
                      const RenderOptions& againstOptions, const std::vector<Row>& rows,
                      std::vector<ReportTable> tables, const std::string& convergedSummary) {
    const std::string& spec = args.inputs[0];
    Report report;
    report.title = "stsv compare: " + spec;
    report.commandLine = shellCommandLine(args.argv);
    report.settings.push_back({"scene", spec + (scene.source != spec ? " (" + scene.source + ")" : "")});
    std::string knobs;
    for (const auto& [k, v] : sceneSets.set) knobs += (knobs.empty() ? "" : ", ") + k + "=" + v;
    report.settings.push_back({"--set", knobs.empty() ? "none" : knobs});
    std::string methodList;
    for (const Row& r : rows) methodList += (methodList.empty() ? "" : ", ") + toString(r.mb);
    report.settings.push_back({"methods", methodList});
    report.settings.push_back(
        {"against", toString(MethodBackend{againstOptions.method, againstOptions.backend})});
    const nlohmann::json options = toJson(frameOptions(againstOptions));
    for (const auto& [name, value] : options.items())
        if (name != "method" && name != "backend" && name != "validation" &&
            !(name == "device" && value == ""))
            report.settings.push_back({name, settingText(value)});
    report.settings.push_back({"converged", convergedSummary});
    report.settings.push_back({"heat scale", formatFixed(args.heatScale, 3) + " (yellow)"});
    report.tables = std::move(tables);
    const bool converged = args.converged.has_value();
    std::vector<const Row*> ranked;
    for (const Row& r : rows)
        if (r.rank) ranked.push_back(&r);
    std::sort(ranked.begin(), ranked.end(), [](const Row* a, const Row* b) { return *a->rank < *b->rank; });
    report.headline = std::string("Ranked by visibility RMSE over the light-facing pixels (N.L > 0 for some "
                                  "point of a light), against the ") +
                      (converged ? "converged" : "equal-sample") + " reference:";
    for (const Row* r : ranked)
        report.headline += (r == ranked.front() ? " " : ", ") + std::to_string(*r->rank) + ". " +
                           toString(r->mb) + " " + formatFixed(rankingFigure(*r, converged).rmse, 5) +
                           " (lit RMSE " + formatFixed((converged ? r->convergedLit : r->lit).rmse, 5) + ")";
    if (ranked.empty()) report.headline += " no method besides the reference";
    report.headline += ". Pixels facing away from every light, where visibility changes nothing in the lit "
                       "image, are left out of the ranking; the tables give the whole-image figures too.";
    report.chart.yLabel =
        converged ? "light-facing visibility RMSE vs converged" : "light-facing visibility RMSE vs reference";
    report.chart.caption =
        std::string(
            "each method's frame time and visibility RMSE over the light-facing pixels (the ranking's "
            "figure) against the ") +
        (converged ? "converged reference (the equal-sample reference's point is the noise floor)"
                   : "equal-sample reference") +
        "; lower left is better";
    for (const Row& r : rows)
        report.chart.points.push_back({toString(r.mb), toString(methodInfo(r.mb.method).family), r.frameMs,
                                       rankingFigure(r, converged).rmse});
    report.imagesNote = "heat maps: |visibility - " +
                        std::string(converged ? "converged reference" : "equal-sample reference") +
                        "|, black 0, red " + formatFixed(args.heatScale / 2, 3) + ", yellow " +
                        formatFixed(args.heatScale, 3) + " and above";
    return report;
}

void writeReport(const std::string& dir, const Report& base, const std::vector<ImageSet>& sets,
                 const std::string& heatTitle, float heatScale) {
    Report report = base;
    const Image8 legend = heatLegend(heatScale, 512, "heat maps: " + heatTitle, 2);
    report.heatScale = {"colour scale of the heat maps", "heat_scale.png", legend.width, legend.height};
    writePng((fs::path(dir) / report.heatScale.file).string(), legend);
    for (const ImageSet& set : sets) {
        ReportImageRow row;
        row.name = set.name;
        const int scale = tileScaleFor(set.lit.width, set.lit.height);
        auto add = [&](const Image8& image, const std::string& suffix, const std::string& title) {
            if (image.width == 0) return;
            const std::string file = set.stem + "_" + suffix + ".png";
            writePng((fs::path(dir) / file).string(), image);
            row.images.push_back({set.name + ": " + title, file, image.width * scale, image.height * scale});
        };
        add(set.lit, "lit", "lit");
        add(set.visibility, "visibility", "visibility");
        add(set.heat, "error", heatTitle);
        report.imageRows.push_back(row);
    }
    const std::string path = (fs::path(dir) / "index.html").string();
    const std::string html = reportHtml(report);
    writeFileBytes(path, html.data(), html.size());
}

/// The contact sheet, with the heat maps' colour scale as a strip across its foot.
void writeSheet(const std::string& path, const std::vector<ImageSet>& sets, const std::string& heatTitle,
                float heatScale) {
    std::vector<SheetRow> rows;
    rows.reserve(sets.size());
    for (const ImageSet& set : sets) rows.push_back({set.name, {set.lit, set.visibility, set.heat}});
    const SheetLayout layout =
        sheetLayout(sets.front().lit.width, sets.front().lit.height, 3, int(rows.size()));
    const Image8 sheet = contactSheet(layout, {"lit", "visibility", heatTitle}, rows);
    const Image8 legend = heatLegend(heatScale, sheet.width, "heat maps: " + heatTitle, layout.textScale);
    Image8 out;
    out.width = std::max(sheet.width, legend.width);
    out.height = sheet.height + legend.height;
    out.channels = 3;
    out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 3, 0);
    fillRect(out, 0, 0, out.width, out.height, SHEET_BACKGROUND);
    pasteScaled(out, sheet, 0, 0, 1);
    pasteScaled(out, legend, 0, sheet.height, 1);
    writePng(path, out);
}

/// Every file a compare of a SCENE writes, for checkOutputFiles: --json, --sheet, and the files
/// of --out (writeImages and the converged images) and of --report (writeReport) for the rows
/// of `rows` (--against first). A file named twice in a folder (a method listed twice) is one.
std::vector<OutputFile> sceneCompareOutputs(const CompareArgs& args, const std::vector<MethodBackend>& rows) {
    std::vector<OutputFile> outputs = {{"--json", args.json, {".json"}}, {"--sheet", args.sheet, {".png"}}};
    const bool converged = args.converged.has_value();
    auto inFolder = [&](const std::string& option, const std::string& dir,
                        const std::vector<std::string>& names) {
        std::vector<std::string> seen;
        for (const std::string& name : names) {
            if (std::find(seen.begin(), seen.end(), name) != seen.end()) continue;
            seen.push_back(name);
            outputs.push_back({option, (fs::path(dir) / name).string(), {lowerExtension(name)}});
        }
    };
    if (!args.out.empty()) {
        std::vector<std::string> names;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const std::string stem = fileStem(rows[i]);
            for (const char* suffix : {"_visibility.png", "_lit.png"}) names.push_back(stem + suffix);
            if (i > 0)
                for (const char* suffix : {"_diff.png", "_bitdiff.png"}) names.push_back(stem + suffix);
            if (converged) names.push_back(stem + "_converged_diff.png");
        }
        if (converged)
            for (const char* name : {"converged_visibility.png", "converged_lit.png"}) names.push_back(name);
        inFolder("--out", args.out, names);
    }
    if (!args.report.empty()) {
        std::vector<std::string> names = {"index.html", "heat_scale.png"};
        for (std::size_t i = 0; i < rows.size(); ++i)
            for (const char* suffix : {"_lit.png", "_visibility.png", "_error.png"})
                names.push_back(fileStem(rows[i]) + suffix);
        if (converged)
            for (const char* name : {"converged_lit.png", "converged_visibility.png"}) names.push_back(name);
        inFolder("--report", args.report, names);
    }
    return outputs;
}

/// --heat-scale, --converged and --no-cache, whatever is compared.
void checkCompareOptions(const CompareArgs& args) {
    if (!(args.heatScale > 0.0f && args.heatScale <= 1.0f))
        throw UsageError("--heat-scale must lie in (0, 1]");
    if (args.converged && (*args.converged < 1 || *args.converged > MAX_CONVERGED_FRAMES))
        throw UsageError("--converged " + std::to_string(*args.converged) +
                         ": K, the number of seeds averaged, " + "must lie in 1 to " +
                         std::to_string(MAX_CONVERGED_FRAMES));
    if (args.noCache && !args.converged) throw UsageError("--no-cache applies to --converged only");
}

/// compare of two files: two --dump-ls light-sample files, or two visibility images.
int compareTwoFiles(const CompareArgs& args) {
    const bool files =
        (isNpy(args.inputs[0]) || isExr(args.inputs[0])) && (isNpy(args.inputs[1]) || isExr(args.inputs[1]));
    if (!files)
        throw UsageError("compare takes one SCENE, two .npy light-sample files, or two visibility files "
                         "(.exr or float32 .npy)");
    if (args.converged || !args.report.empty() || !args.sheet.empty() || !args.json.empty() ||
        !args.knobs.empty())
        throw UsageError(std::string(args.converged         ? "--converged"
                                     : !args.report.empty() ? "--report"
                                     : !args.sheet.empty()  ? "--sheet"
                                     : !args.knobs.empty()  ? "--knobs"
                                                            : "--json") +
                         " compares renders of a SCENE, not two files");
    // The files are read once, before anything is written: --out's heat map must be neither.
    std::vector<InputFile> inputs;
    for (const std::string& input : args.inputs) {
        inputs.push_back({"an input", input});
        if (isNpy(input)) inputs.push_back({"an input's metadata", npyInfoPath(input)});
    }
    if (!args.out.empty()) {
        prepareOutputDirectory(args.out, "--out");
        checkOutputFiles({{"--out", (fs::path(args.out) / "difference.png").string(), {".png"}}}, inputs);
    }
    if (isExr(args.inputs[0]) || isExr(args.inputs[1])) return compareVisibilityFiles(args);
    const NpyArray a = readNpy(args.inputs[0]);
    if (a.dtype == "<f4") return compareVisibilityFiles(args);
    return compareNpy(args, a, readNpy(args.inputs[1]));
}

/// A compare of a SCENE: what the command line asks for, and what it measured. The methods
/// (--against first) and their knobs, the rows of the error table, the light-facing mask and
/// the converged reference.
struct SceneComparison {
    explicit SceneComparison(const CompareArgs& commandLine) : args(commandLine) {}
    const CompareArgs& args;
    std::string spec;
    RenderOptions base;
    MethodBackend against;
    std::vector<MethodBackend> methods;
    std::vector<Method> all;               ///< against, then the methods, as listed
    std::vector<MethodParams> params;      ///< [all]
    std::vector<std::string> knobLabels;   ///< [all]: the --knobs entry each method took, if any
    std::vector<MethodBackend> rowMethods; ///< the rows, in order (the methods' files)
    std::vector<Row> rows;
    std::vector<std::size_t> rankOrder;
    LightFacingMask facing;
    std::optional<ConvergedReference> converged;
    int frames = 0; ///< the converged reference's seeds (0: none)

    std::size_t indexOf(Method m) const {
        return std::size_t(std::find(all.begin(), all.end(), m) - all.begin());
    }
    const std::string& knobLabelOf(Method m) const { return knobLabels[indexOf(m)]; }
    /// The frame options of a method: --against's frame, that method's knobs, and bits for a
    /// method without fractional transmittance.
    RenderOptions optionsOf(const MethodBackend& mb) const {
        RenderOptions o = base;
        o.method = mb.method;
        o.backend = mb.backend;
        if (o.buffer == BufferKind::Transmittance && !methodInfo(mb.method).writesTransmittance())
            o.buffer = BufferKind::Bitmask;
        o.params = params[indexOf(mb.method)];
        return o;
    }
};

/// The methods, their knobs and the rows of a compare of a SCENE, from the command line.
SceneComparison planComparison(const CompareArgs& args) {
    SceneComparison c(args);
    c.spec = args.inputs[0];
    c.base = resolveFrameOptions(args);
    const Backend fallback = args.backend.empty() ? defaultBackend() : parseBackend(args.backend);
    c.against = parseMethodBackend(args.against, fallback);
    for (const std::string& m : splitList(args.methods, "--methods"))
        c.methods.push_back(parseMethodBackend(m, fallback));
    if (c.methods.empty()) throw UsageError("--methods is empty");
    c.all = {c.against.method};
    for (const MethodBackend& mb : c.methods) c.all.push_back(mb.method);
    c.params = paramsForMethods(c.all, args.params);
    // --knobs: the file's methods take its knobs (a --param item wins).
    c.knobLabels.resize(c.all.size());
    if (!args.knobs.empty())
        c.knobLabels = applyKnobsFile(readKnobsFile(args.knobs), c.all, c.params, args.params);
    if (!args.kind.empty()) throw UsageError("--kind applies to two .npy light-sample files, not a SCENE");
    c.rowMethods = {c.against};
    for (const MethodBackend& mb : c.methods)
        if (mb.method != c.against.method || mb.backend != c.against.backend) c.rowMethods.push_back(mb);
    return c;
}

/// Renders --against and every method, with the converged reference when asked, into the rows
/// (their images written to --out as they come).
void measureComparison(SceneComparison& c, const Scene& scene, const SceneOptions& sceneSets) {
    const CompareArgs& args = c.args;
    // Each frame compare renders, before the first: an image-based method's maps may outweigh
    // the light-sample buffers.
    checkFrameMemory(c.optionsOf(c.against), scene);
    for (const MethodBackend& mb : c.methods) checkFrameMemory(c.optionsOf(mb), scene);
    auto render = [&](const MethodBackend& mb, double& frameMs) {
        Timer wall;
        Frame frame = renderFrame(scene, c.optionsOf(mb));
        frameMs = frameMsOf(frame, wall.milliseconds());
        for (const std::string& warning : frameWarnings(frame.stats))
            std::fprintf(stderr, "stsv: warning: %s\n", printable(warning).c_str());
        return frame;
    };
    double againstMs = 0.0;
    const Frame reference = render(c.against, againstMs);
    // One mask for every row, from the --against frame's G-buffer.
    c.facing = lightFacingOf(reference, scene);

    // The converged reference: the reference frame above is its seed S, the others follow.
    ImageF convergedVisibility, convergedLit; // display values
    c.frames = args.converged.value_or(0);
    if (args.converged) {
        ConvergedRequest request;
        request.scene = &scene;
        request.spec = c.spec;
        request.sceneSets = sceneSets;
        request.options = c.optionsOf(c.against);
        request.frames = c.frames;
        request.useCache = !args.noCache;
        request.cacheDir = convergedCacheDirectory();
        request.first = &reference;
        request.render = [&](const RenderOptions& o) { return renderFrame(scene, o); };
        if (request.useCache && request.cacheDir.empty())
            std::fprintf(stderr, "note: no cache directory (set STSV_CACHE_DIR, XDG_CACHE_HOME or HOME): the "
                                 "converged reference is not cached\n");
        c.converged = convergedReference(request);
        for (const std::string& m : c.converged->messages) std::fprintf(stderr, "note: %s\n", m.c_str());
        convergedVisibility = toDisplay(c.converged->images.visibility, false);
        convergedLit = toDisplay(c.converged->images.color, true);
    }
    auto addRow = [&](Row row, const Frame& frame) {
        if (c.converged) {
            row.convergedVisibility = compareImages(row.visibilityDisplay, convergedVisibility, COARSE_ERROR);
            row.convergedLit = compareImages(row.litDisplay, convergedLit);
            row.convergedVisibilityFacing =
                compareImagesWhere(row.visibilityDisplay, convergedVisibility, c.facing.selected);
        }
        const bool first = c.rows.empty();
        if (!args.out.empty()) {
            writeImages(args.out, row.mb, frame, first ? nullptr : &row, first ? nullptr : &reference,
                        args.heatScale);
            if (c.converged)
                writePng((fs::path(args.out) / (fileStem(row.mb) + "_converged_diff.png")).string(),
                         heatMapWithLegend(row.convergedVisibility.absDifference, args.heatScale,
                                           "|visibility - converged reference|"));
        }
        c.rows.push_back(std::move(row));
    };
    addRow(compareFrames(c.against, reference, c.against, reference, againstMs, c.facing), reference);
    for (const MethodBackend& mb : c.methods) {
        if (mb.method == c.against.method && mb.backend == c.against.backend)
            continue; // already the first row
        double ms = 0.0;
        const Frame frame = render(mb, ms);
        addRow(compareFrames(mb, frame, c.against, reference, ms, c.facing), frame);
    }
    c.rankOrder = rankRows(c.rows, c.converged.has_value());
    if (c.converged && !args.out.empty()) {
        writePng((fs::path(args.out) / "converged_visibility.png").string(),
                 toImage8(c.converged->images.visibility, false));
        writePng((fs::path(args.out) / "converged_lit.png").string(),
                 toImage8(c.converged->images.color, true));
    }
}

/// Prints the equal-sample table and its notes; returns the note under it (the report's too).
std::string printEqualSampleTable(const SceneComparison& c, const Scene& scene) {
    const RenderOptions& base = c.base;
    std::printf("%s, %dx%d, %d samples (%s, seed %u), against %s\n", printable(scene.source).c_str(),
                base.width, base.height, base.samples, toString(base.pattern).c_str(), base.seed,
                toString(c.against).c_str());
    std::printf("%-16s %12s %12s %10s %10s %10s %10s %10s %10s %11s\n", "method", "identical %", "diff. bits",
                "vis RMSE", "vis max", "lit RMSE", "lit max", "lit SSIM", ">1/255 px", "frame ms");
    for (const Row& r : c.rows) {
        const std::string identical = r.perSample ? formatFixed(r.identicalPercent(), 4) : "n/a";
        const std::string differing = r.perSample ? std::to_string(r.differingSamples) : "n/a";
        std::printf("%-16s %12s %12s %10.5f %10.5f %10.5f %10.5f %10.5f %9.4f%% %11.1f\n",
                    toString(r.mb).c_str(), identical.c_str(), differing.c_str(), r.visibility.rmse,
                    r.visibility.maxAbs, r.lit.rmse, r.lit.maxAbs, r.lit.ssim, 100.0 * r.lit.fractionAbove,
                    r.frameMs);
    }
    for (const Row& r : c.rows)
        if (!c.knobLabelOf(r.mb.method).empty())
            std::printf("knobs of %s from %s: %s\n", toString(r.mb).c_str(), printable(c.args.knobs).c_str(),
                        c.knobLabelOf(r.mb.method).c_str());
    if (c.rows.front().transmittanceRmse) {
        std::printf("per-sample transmittance RMSE against %s:", toString(c.against).c_str());
        for (const Row& r : c.rows)
            std::printf(" %s %s", toString(r.mb).c_str(),
                        r.transmittanceRmse ? formatFixed(*r.transmittanceRmse, 5).c_str() : "n/a");
        std::printf("\n");
    }
    // The n/a rows' methods, from the rows themselves: each method once, by its row in the table.
    std::vector<Method> naMethods;
    for (const Row& r : c.rows)
        if (!r.perSample && methodInfo(r.mb.method).output == MethodOutput::Visibility &&
            std::find(naMethods.begin(), naMethods.end(), r.mb.method) == naMethods.end())
            naMethods.push_back(r.mb.method);
    std::string visibilityOnly;
    for (Method m : naMethods) visibilityOnly += (visibilityOnly.empty() ? "" : ", ") + toString(m);
    if (methodInfo(c.against.method).output == MethodOutput::Visibility)
        visibilityOnly = "every method: " + toString(c.against.method) + ", the method compared with,";
    std::string equalNote =
        std::string("(errors in display units [0, 1]: visibility linear, lit image sRGB-encoded; lit SSIM = "
                    "structural "
                    "similarity of the lit images' luma, 1 when equal; >1/255 px = pixels of the lit image "
                    "off by more "
                    "than one 8-bit step") +
        (visibilityOnly.empty()
             ? ")"
             : "; n/a: " + visibilityOnly + " give(s) a v_coef per pixel, not per-sample bits)");
    std::printf("%s\n", equalNote.c_str());
    return equalNote;
}

/// The bias tables: against the equal-sample reference, and against the converged one with the
/// equal-sample reference's own error as the noise floor (only with --converged), and the
/// converged reference's one-line summary.
struct BiasTables {
    ReportTable equalSamples;
    ReportTable converged;
    std::string
        convergedSummary; ///< "reference/cpu, seeds 1 to 16 (16 x 16 = 256 samples per pixel), cache …"
};

BiasTables biasTables(const SceneComparison& c) {
    const RenderOptions& base = c.base;
    BiasTables t;
    t.equalSamples.caption = "against the equal-sample reference (" + toString(c.against) + ", " +
                             std::to_string(base.samples) + " samples, seed " + std::to_string(base.seed) +
                             "):";
    t.equalSamples.header = ERROR_HEADER;
    for (const Row& r : c.rows)
        t.equalSamples.rows.push_back(errorCells(toString(r.mb), r.visibilityCoarse, r.lit));
    if (!c.converged) {
        t.equalSamples.note = "(" + std::string(BIAS_NOTE) + ")";
        return t;
    }
    const int frames = c.frames;
    const std::uint32_t last = base.seed + std::uint32_t(frames - 1);
    t.convergedSummary = toString(c.against) + ", seeds " + std::to_string(base.seed) +
                         (frames > 1 ? " to " + std::to_string(last) : "") + " (" + std::to_string(frames) +
                         " x " + std::to_string(base.samples) + " = " +
                         std::to_string(frames * base.samples) + " samples per pixel), cache " +
                         toString(c.converged->cache) +
                         (c.converged->entry.empty() ? std::string() : ": " + c.converged->entry);
    t.converged.caption =
        "against the converged reference (" + std::to_string(frames * base.samples) + " samples per pixel):";
    t.converged.header = ERROR_HEADER;
    t.converged.rows.push_back(
        errorCells("noise floor", c.rows.front().convergedVisibility, c.rows.front().convergedLit));
    for (std::size_t i = 1; i < c.rows.size(); ++i)
        t.converged.rows.push_back(
            errorCells(toString(c.rows[i].mb), c.rows[i].convergedVisibility, c.rows[i].convergedLit));
    t.converged.note = "(" + std::string(BIAS_NOTE) + "; noise floor = the equal-sample " +
                       toString(c.against) + " against the converged one)";
    return t;
}

/// --report and --sheet.
void writeComparisonPages(const SceneComparison& c, const Scene& scene, const SceneOptions& sceneSets,
                          const ReportTable& ranking, const std::string& equalNote, const BiasTables& bias) {
    const CompareArgs& args = c.args;
    const std::vector<ImageSet> sets =
        imageSets(c.rows, c.converged ? &*c.converged : nullptr, c.frames * c.base.samples, args.heatScale);
    const std::string heatAgainst = c.converged ? "converged" : "reference";
    if (!args.report.empty()) {
        ReportTable first = equalSampleTable(c.rows);
        first.caption = "against " + toString(c.against) + " at the same samples:";
        first.note = equalNote;
        std::vector<ReportTable> tables = {ranking, first, bias.equalSamples};
        if (c.converged) tables.push_back(bias.converged);
        Report report = describeReport(args, scene, sceneSets, c.optionsOf(c.against), c.rows, tables,
                                       c.converged ? bias.convergedSummary : "not requested");
        for (const Row& r : c.rows)
            if (!c.knobLabelOf(r.mb.method).empty())
                report.settings.push_back({"knobs of " + toString(r.mb) + " (--knobs " + args.knobs + ")",
                                           c.knobLabelOf(r.mb.method)});
        writeReport(args.report, report, sets, "|visibility - " + heatAgainst + "|", args.heatScale);
        std::printf("report in %s\n", printable((fs::path(args.report) / "index.html").string()).c_str());
    }
    if (!args.sheet.empty()) {
        writeSheet(args.sheet, sets, "|dv| " + heatAgainst,
                   args.heatScale); // fits a 192-pixel tile at scale 2
        std::printf("contact sheet in %s\n", printable(args.sheet).c_str());
    }
}

/// --json: every row's errors and knobs, the ranking, the mask's pixels, the converged reference.
nlohmann::json comparisonJson(const SceneComparison& c) {
    const CompareArgs& args = c.args;
    nlohmann::json list = nlohmann::json::array();
    for (const Row& r : c.rows) {
        nlohmann::json row = {
            {"method", toString(r.mb.method)},
            {"backend", toString(r.mb.backend)},
            {"identical_percent", r.perSample ? nlohmann::json(r.identicalPercent()) : nlohmann::json()},
            {"differing_samples", r.differingSamples},
            {"compared_samples", r.comparedSamples},
            {"differing_pixels", r.differingPixels},
            {"visibility",
             {{"rmse", r.visibility.rmse},
              {"bias", r.visibility.bias},
              {"max_abs", r.visibility.maxAbs},
              {"fraction_above_1_255", r.visibility.fractionAbove},
              {"fraction_above_0_1", r.visibilityCoarse.fractionAbove}}},
            {"visibility_facing", facingJson(r.visibilityFacing)},
            {"rank", r.rank ? nlohmann::json(*r.rank) : nlohmann::json()},
            {"lit",
             {{"rmse", r.lit.rmse},
              {"bias", r.lit.bias},
              {"max_abs", r.lit.maxAbs},
              {"ssim", r.lit.ssim},
              {"fraction_above_1_255", r.lit.fractionAbove}}},
            {"frame_ms", r.frameMs}};
        if (c.converged)
            row["converged"] = errorJson(r.convergedVisibility, r.convergedVisibilityFacing, r.convergedLit);
        if (r.transmittanceRmse) row["transmittance_rmse"] = *r.transmittanceRmse;
        row["knobs"] = c.optionsOf(r.mb).params; // every knob of the method, as rendered
        if (!c.knobLabelOf(r.mb.method).empty()) row["knobs_file"] = args.knobs;
        list.push_back(row);
    }
    const bool vulkan = std::any_of(c.rows.begin(), c.rows.end(),
                                    [](const Row& r) { return r.mb.backend == Backend::Vulkan; });
    nlohmann::json j = {{"scene", c.spec},
                        {"version", version()},
                        {"command", shellCommandLine(args.argv)},
                        {"machine", machineJson(vulkan, c.optionsOf(c.against).device)},
                        {"against", toString(c.against)},
                        {"options", toJson(c.optionsOf(c.against))},
                        {"rows", list}};
    nlohmann::json order = nlohmann::json::array();
    for (std::size_t i : c.rankOrder) order.push_back(toString(c.rows[i].mb));
    j["light_facing"] = {{"facing_pixels", c.facing.facing},
                         {"away_pixels", c.facing.away},
                         {"background_pixels", c.facing.background}};
    j["ranking"] = {{"by", c.converged ? "converged.visibility_facing.rmse" : "visibility_facing.rmse"},
                    {"methods", order}};
    if (c.converged) {
        const RenderOptions& base = c.base;
        j["converged_reference"] = {{"frames", c.frames},
                                    {"seeds", {base.seed, base.seed + std::uint32_t(c.frames - 1)}},
                                    {"samples_per_pixel", c.frames * base.samples},
                                    {"cache", toString(c.converged->cache)},
                                    {"cache_entry", c.converged->entry},
                                    {"frames_rendered", c.converged->framesRendered}};
        j["noise_floor"] = errorJson(c.rows.front().convergedVisibility,
                                     c.rows.front().convergedVisibilityFacing, c.rows.front().convergedLit);
    }
    return j;
}

} // namespace

int runCompare(CompareArgs& args) {
    if (args.quiet) Progress::setEnabled(false);
    checkCompareOptions(args);
    if (args.inputs.size() == 2) return compareTwoFiles(args);
    if (args.inputs.size() != 1) throw UsageError("compare takes one SCENE, or two .npy light-sample files");
    if (isNpy(args.inputs[0])) throw UsageError("compare of light-sample files needs two .npy files");

    // auto: the method the scene calls for, so the scene is loaded before the methods are planned.
    const SceneOptions sceneSets = sceneOptionsOf(args);
    std::optional<Scene> loaded;
    if (namesAutoMethod(args.methods, "--methods")) {
        loaded.emplace(loadScene(args.inputs[0], sceneSets));
        args.methods = resolveAutoMethods(args.methods, "--methods", {autoMethod(*loaded)});
        if (!args.quiet) std::fprintf(stderr, "--methods auto: %s\n", printable(args.methods).c_str());
    }
    SceneComparison c = planComparison(args);
    if (!args.out.empty()) prepareOutputDirectory(args.out, "--out");
    if (!args.report.empty()) prepareOutputDirectory(args.report, "--report");
    const std::vector<OutputFile> outputs = sceneCompareOutputs(args, c.rowMethods);
    std::vector<InputFile> inputs;
    if (std::error_code ec; fs::is_regular_file(c.spec, ec)) inputs.push_back({"the scene", c.spec});
    if (!args.knobs.empty()) inputs.push_back({"--knobs", args.knobs});
    checkOutputFiles(outputs, inputs);

    if (!loaded) loaded.emplace(loadScene(c.spec, sceneSets));
    const Scene& scene = *loaded;
    printSceneWarnings(scene, args.quiet);
    checkOutputFiles(outputs, sceneInputFiles(c.spec, scene));

    measureComparison(c, scene, sceneSets);
    const ReportTable ranking = rankingTable(c.rows, c.rankOrder, c.converged.has_value(), c.facing);
    const std::string equalNote = printEqualSampleTable(c, scene);
    const BiasTables bias = biasTables(c);
    if (c.converged)
        std::printf("\nconverged reference: %s\n%s\n%s", bias.convergedSummary.c_str(),
                    formatTextTable(bias.equalSamples).c_str(), formatTextTable(bias.converged).c_str());
    std::printf("\n%s", formatTextTable(ranking).c_str());
    if (!args.out.empty()) std::printf("images in %s\n", printable(args.out).c_str());
    if (!args.report.empty() || !args.sheet.empty())
        writeComparisonPages(c, scene, sceneSets, ranking, equalNote, bias);
    if (!args.json.empty()) {
        writeJson(args.json, comparisonJson(c));
        std::printf("wrote %s\n", printable(args.json).c_str());
    }
    return 0;
}

} // namespace stsv
