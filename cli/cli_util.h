// Helpers shared by the `stsv` subcommands: list and knob parsing, output checks, statistics
// over repeated frames, error images. Everything here throws UsageError/Error; only runCli
// turns exceptions into exit codes.
#pragma once

#include "core/contact_sheet.h"
#include "core/image.h"
#include "render/frame.h"
#include "scene/load.h"
#include "shadowmaps/shadow_map.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

/// "a, b,c" → {"a", "b", "c"} (surrounding spaces dropped); {} for an empty or blank `text`.
/// UsageError naming `option`, the list and the item's place for an empty item ("a,,b", "a,").
std::vector<std::string> splitList(const std::string& text, const std::string& option);

/// "16,64,256" → {16, 64, 256}; UsageError naming `option` on anything that is not a
/// positive integer.
std::vector<int> parseIntList(const std::string& text, const std::string& option);

/// `--set key=value` items → SceneOptions; UsageError on an item without '=' or without a key.
SceneOptions parseSets(const std::vector<std::string>& sets);

/// The `--param` items of several methods run side by side (bench, compare): UsageError naming
/// the item when its name is a knob of none of `methods`, then each method's parameters from the
/// items that name its knobs (defaults for the rest), validated.
std::vector<MethodParams> paramsForMethods(const std::vector<Method>& methods,
                                           const std::vector<std::string>& items);

/// The default backend of render/compare/bench: vulkan where render/ implements it.
Backend defaultBackend();

/// A method with an optional backend, "stsv" or "stsv/cpu" (compare's --methods/--against).
struct MethodBackend {
    Method method = Method::Stsv;
    Backend backend = Backend::Cpu;
};
/// Parses "method[/backend]"; without a backend, defaultBackendFor(method, fallback). UsageError
/// for an unknown name or a backend that does not implement the method.
MethodBackend parseMethodBackend(const std::string& text, Backend fallback);
std::string toString(const MethodBackend& mb);

/// Whether a method list (`--method`, `--methods`: "method[/backend]" items) names `auto`.
bool namesAutoMethod(const std::string& list, const std::string& option);
/// The list with each `auto` item replaced by `chosen` (autoMethod, render/frame.h, of each scene
/// the list is for), its backend kept; a method the list already names is not repeated.
std::string resolveAutoMethods(const std::string& list, const std::string& option,
                               const std::vector<Method>& chosen);

/// `value` with `decimals` digits after the point ("%.*f"): the tables' figures.
std::string formatFixed(double value, int decimals);

/// Whether the method table lists `backend` for `method` (render/methods.h).
bool backendImplements(Method method, Backend backend);
/// One phrase saying why `method` does not run on `backend`.
std::string unsupportedReason(Method method, Backend backend);
/// UsageError when backendImplements(method, backend) is false.
void checkBackendSupports(Method method, Backend backend);
/// `preferred` when it implements `method`, else the method's first backend.
Backend defaultBackendFor(Method method, Backend preferred);

/// Throws UsageError before any work when `path` cannot be written: its directory is
/// missing, not a directory or not writable, or the path names a directory, a device, a pipe or
/// a socket (core/files.h notAnOutputReason). `what` names the option ("-o", "--stats").
void checkWritableFile(const std::string& path, const std::string& what);
/// An output file of a command: the option that names it, its path (empty: not requested) and
/// the extensions of the format it is written in.
struct OutputFile {
    std::string option;
    std::string path;
    std::vector<std::string> extensions; ///< lower case, with the dot: ".png"
};
/// A file a command reads: what names it ("the scene", "texture of the scene", "A.npy") and its path.
struct InputFile {
    std::string what;
    std::string path;
};
/// UsageError before any work when an output's extension is not one of its format's (the format
/// follows the extension; nothing is written under another format's name), when it cannot be
/// written (checkWritableFile), when two outputs name the same file, or when an output names a
/// file the command reads (`inputs`: the same path, or another name of the same file).
void checkOutputFiles(const std::vector<OutputFile>& outputs, const std::vector<InputFile>& inputs = {});

/// The files a loaded scene was read from that still exist: its source file and its textures'.
std::vector<InputFile> sceneInputFiles(const std::string& spec, const Scene& scene);

/// Prints the scene's warnings (Scene::warnings), "stsv: warning: <scene source>: <text>" on
/// stderr, unless `quiet`.
void printSceneWarnings(const Scene& scene, bool quiet);

/// "wrote <path>" on stderr, unless `quiet`: every file a command writes is named once.
void reportWritten(const std::string& path, bool quiet);

/// Creates `dir` (and parents) if needed; UsageError when that fails or it is not writable.
void prepareOutputDirectory(const std::string& dir, const std::string& what);

/// UsageError when one frame of `options` on `scene` would need more memory than the limit
/// (G-buffer, images, light-sample buffers, the sample passes' list and the lights' maps).
void checkFrameMemory(const RenderOptions& options, const Scene& scene);
/// Bytes one frame of `options` on `scene` holds on the host, estimated from the buffers' sizes
/// (for an image-based method, each light's map as the frame fits it).
double estimateFrameBytes(const RenderOptions& options, const Scene& scene);
/// Bytes a light's map of `view` takes at its peak on `backend` with what the method of
/// `settings` builds from it: the depths, the filtered representation (and on the CPU the channel
/// values it is made from), the depth grid or the transmittance functions; `keep`: --shadow-map.
double shadowMapPeakBytes(const ShadowMapView& view, const ShadowMapSettings& settings, Backend backend,
                          bool keep);

void writeJson(const std::string& path, const nlohmann::json& json);

/// median/min/max of a non-empty series (the median of an even count is the mean of the two
/// middle values).
struct Summary {
    double median = 0.0;
    double min = 0.0;
    double max = 0.0;
};
Summary summarize(std::vector<double> values);
nlohmann::json toJson(const Summary& summary);

/// Linear [0, 1] → sRGB-encoded [0, 1] (the curve toImage8 applies).
float encodeSrgb(float linear);
/// The displayed values of a linear image: sRGB-encoded (when `srgb`) and clamped to [0, 1].
ImageF toDisplay(const ImageF& image, bool srgb);

/// Per-pixel error of image `a` against the reference `b` (same size; display values in [0, 1]).
struct ImageError {
    double rmse = 0.0;          ///< over every pixel and channel
    double bias = 0.0;          ///< mean signed a − b over every pixel and channel (a above b: positive)
    double maxAbs = 0.0;        ///< largest |a − b| of any channel
    double fractionAbove = 0.0; ///< pixels where some channel differs by more than `threshold`
    double ssim = 1.0;          ///< structural similarity of the two images' luma (structuralSimilarity)
    ImageF absDifference;       ///< one channel: max over channels of |a − b|
};

/// Mean structural similarity (SSIM, Wang, Bovik, Sheikh and Simoncelli 2004, Eq. 13 with the
/// 11×11 Gaussian window of σ = 1.5, K1 = 0.01, K2 = 0.03, dynamic range L = 1) of the luma
/// (Rec. 709 weights, of the values as given: display-encoded for the lit image) of two images of
/// one size; the window is cut at the borders and its weights renormalised, so every pixel counts.
/// 1 for equal images, lower as structure, contrast or brightness differ; −1 at worst.
double structuralSimilarity(const ImageF& a, const ImageF& b);
ImageError compareImages(const ImageF& a, const ImageF& b, float threshold = 1.0f / 255.0f);

/// The error of image `a` against the reference `b` over some of their pixels.
struct RegionError {
    double rmse = 0.0;      ///< over the selected pixels' channels
    double bias = 0.0;      ///< mean signed a − b over the selected pixels' channels
    double maxAbs = 0.0;    ///< largest |a − b| of a selected pixel's channel
    std::size_t pixels = 0; ///< selected pixels; 0: every figure is 0 (nothing to measure)
};

/// compareImages' RMSE, bias and max over the pixels where `selected` (row-major, one byte per
/// pixel of a and b) is non-zero. UsageError for images of different sizes or a mask of another.
RegionError compareImagesWhere(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& selected);

/// The pixels compare's headline figure counts: per pixel of a width × height image, 1 where it
/// faces some light (lightFacingPixels of sampling/light_sampling.h), and how many pixels are of
/// each kind.
struct LightFacingMask {
    std::vector<std::uint8_t> selected; ///< row-major, 1 where the pixel faces a light
    std::size_t facing = 0;
    std::size_t away = 0;       ///< a surface that faces no light
    std::size_t background = 0; ///< no surface
};
LightFacingMask lightFacingMask(const GBuffer& gbuffer, const std::vector<Light>& lights, float farDistance,
                                int width, int height);

/// The machine a measurement ran on, for --json files: "cpu_model", "cpu_threads",
/// "memory_bytes", and with `vulkan` the name of the device the Vulkan backend picks by `select`
/// (--device's rule; else why there is none) as "device" and every listed device's name as
/// "vulkan_devices" (null and empty without).
nlohmann::json machineJson(bool vulkan, const std::string& select);

/// The heat maps' colour at t in [0, 1] (clamped): black → red over [0, 1/2], red → yellow over
/// [1/2, 1].
Rgb8 heatColour(float t);

/// Heat map of a one-channel image: 0 black → scale/2 red → ≥ scale yellow.
Image8 heatMap(const ImageF& values, float scale);

/// The heat maps' colour scale as an RGB strip on the sheets' dark background: `caption` on the
/// first line, then the gradient bar from 0 to `scale`, then the numbers 0, scale/2 and "scale+"
/// under its left end, middle and right end, text at `textScale` pixels per font unit. The strip is
/// `width` pixels wide, or wider where the caption or the numbers need it.
Image8 heatLegend(float scale, int width, const std::string& caption, int textScale);

/// A heat map with its colour scale beneath: the top values.height rows are heatMap(values, scale)
/// pixel for pixel (its left columns, where the legend needs more width than the frame has); below
/// them heatLegend at 1 pixel per font unit (2 for frames of 512 pixels or wider).
Image8 heatMapWithLegend(const ImageF& values, float scale, const std::string& caption);

/// Per pixel, the fraction of the N samples whose occlusion state differs between a and b
/// (same size and N; UsageError otherwise).
ImageF sampleDisagreement(const LightSampleBuffer& a, const LightSampleBuffer& b);

} // namespace stsv
