#include "cli/cli_util.h"

#include "core/error.h"
#include "core/files.h"
#include "core/memory_budget.h"
#include "gpu/device.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_renderer.h"
#include "sampling/light_sampling.h"
#include "shadowmaps/depth_grid_dh.h"
#include "shadowmaps/filtered_map.h"
#include "shadowmaps/shadow_fit.h"
#include "shadowmaps/vulkan/gpu_shadowmap_passes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace stsv {

namespace fs = std::filesystem;

std::vector<std::string> splitList(const std::string& text, const std::string& option) {
    std::vector<std::string> items;
    if (text.find_first_not_of(" \t") == std::string::npos) return items; // the caller says it is empty
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        std::string item = text.substr(start, comma - start);
        const auto first = item.find_first_not_of(" \t");
        const auto last = item.find_last_not_of(" \t");
        if (first == std::string::npos)
            throw UsageError(option + " '" + printable(text) + "': item " + std::to_string(items.size() + 1) +
                             " is empty; separate the items with single commas, none at either end");
        items.push_back(item.substr(first, last - first + 1));
        start = comma + 1;
    }
    return items;
}

std::vector<int> parseIntList(const std::string& text, const std::string& option) {
    std::vector<int> values;
    for (const std::string& item : splitList(text, option)) {
        const bool digits =
            std::all_of(item.begin(), item.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
        if (!digits)
            throw UsageError(std::string(option).append(" '").append(text).append("': '").append(item).append(
                "' is not a positive integer"));
        if (item.size() > 9 || std::stoi(item) <= 0)
            throw UsageError(std::string(option).append(" '").append(text).append("': ").append(item).append(
                " is out of range (1 to 999999999)"));
        values.push_back(std::stoi(item));
    }
    if (values.empty()) throw UsageError(option + " is empty");
    return values;
}

SceneOptions parseSets(const std::vector<std::string>& sets) {
    SceneOptions options;
    for (const std::string& s : sets) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError("--set '" + s + "' is not of the form key=value");
        options.set[s.substr(0, eq)] = s.substr(eq + 1);
    }
    return options;
}

std::vector<MethodParams> paramsForMethods(const std::vector<Method>& methods,
                                           const std::vector<std::string>& items) {
    std::vector<std::vector<std::string>> perMethod(methods.size());
    for (const std::string& item : items) {
        const std::string name = item.substr(0, item.find('='));
        bool known = false;
        for (std::size_t i = 0; i < methods.size(); ++i)
            if (methodInfo(methods[i]).knob(name)) {
                perMethod[i].push_back(item);
                known = true;
            }
        if (!known) {
            if (const char* why = retiredShadowMapKnob(name))
                throw UsageError("--param " + name + ": " + why);
            std::string list;
            for (Method m : methods)
                for (const MethodKnob& k : methodInfo(m).knobs)
                    list += (list.empty() ? "" : ", ") + methodInfo(m).name + ": " + k.name;
            throw UsageError("--param '" + item + "' names no parameter of the methods given (theirs: " +
                             (list.empty() ? "none" : list) + ")");
        }
    }
    std::vector<MethodParams> params;
    for (std::size_t i = 0; i < methods.size(); ++i)
        params.push_back(parseMethodParams(methodInfo(methods[i]), perMethod[i]));
    return params;
}

Backend defaultBackend() {
    return Backend::Vulkan;
}

bool backendImplements(Method method, Backend backend) {
    return methodInfo(method).implementedOn(backend);
}

std::string unsupportedReason(Method method, Backend backend) {
    const MethodInfo& m = methodInfo(method);
    std::string runsOn;
    for (Backend b : m.backends) runsOn += (runsOn.empty() ? "" : " and ") + toString(b);
    if (m.backends.size() == 1 && m.backends[0] == Backend::Cpu) runsOn = "the CPU only";
    return "method " + m.name + " is not implemented on " + toString(backend) + " (it runs on " + runsOn +
           ": use --backend " + toString(m.backends.front()) + ")";
}

void checkBackendSupports(Method method, Backend backend) {
    if (!backendImplements(method, backend)) throw UsageError(unsupportedReason(method, backend));
}

Backend defaultBackendFor(Method method, Backend preferred) {
    return backendImplements(method, preferred) ? preferred : methodInfo(method).backends.front();
}

MethodBackend parseMethodBackend(const std::string& text, Backend fallback) {
    const auto slash = text.find('/');
    MethodBackend mb;
    mb.method = parseMethod(text.substr(0, slash));
    if (slash == std::string::npos) {
        mb.backend = defaultBackendFor(mb.method, fallback);
    } else {
        mb.backend = parseBackend(text.substr(slash + 1));
        checkBackendSupports(mb.method, mb.backend);
    }
    return mb;
}

bool namesAutoMethod(const std::string& list, const std::string& option) {
    const std::vector<std::string> items = splitList(list, option);
    return std::any_of(items.begin(), items.end(),
                       [](const std::string& item) { return item.substr(0, item.find('/')) == AUTO_METHOD; });
}

std::string resolveAutoMethods(const std::string& list, const std::string& option,
                               const std::vector<Method>& chosen) {
    std::vector<std::string> resolved;
    const auto add = [&](const std::string& item) {
        if (std::find(resolved.begin(), resolved.end(), item) == resolved.end()) resolved.push_back(item);
    };
    for (const std::string& item : splitList(list, option)) {
        const auto slash = item.find('/');
        if (item.substr(0, slash) != AUTO_METHOD) {
            add(item);
            continue;
        }
        const std::string backend = slash == std::string::npos ? "" : item.substr(slash);
        for (Method method : chosen) add(toString(method) + backend);
    }
    std::string text;
    for (const std::string& item : resolved) text += (text.empty() ? "" : ",") + item;
    return text;
}

std::string toString(const MethodBackend& mb) {
    return toString(mb.method) + "/" + toString(mb.backend);
}

void checkWritableFile(const std::string& path, const std::string& what) {
    if (path.empty()) throw UsageError(what + ": empty path");
    const std::string shown = printable(path);
    if (const std::string reason = notAnOutputReason(path); !reason.empty())
        throw UsageError(what + " " + shown + ": " + reason + "; name a regular file");
    std::error_code ec;
    const fs::path parent =
        fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
    if (!fs::exists(parent, ec))
        throw UsageError(what + " " + shown + ": directory " + printable(parent.string()) +
                         " does not exist");
    if (!fs::is_directory(parent, ec))
        throw UsageError(what + " " + shown + ": " + printable(parent.string()) + " is not a directory");
    if (::access(parent.c_str(), W_OK) != 0)
        throw UsageError(what + " " + shown + ": directory " + printable(parent.string()) +
                         " is not writable");
    if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0)
        throw UsageError(what + " " + shown + ": file is not writable");
}

namespace {

/// Whether two paths name one file: the same file where both exist (hard and symbolic links
/// included), else the same absolute path once "." and ".." and the links of its existing part
/// are resolved.
bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) {
        const bool same = fs::equivalent(a, b, ec);
        if (!ec) return same;
    }
    auto canonical = [](const std::string& path) {
        std::error_code error;
        fs::path p = fs::weakly_canonical(fs::absolute(path), error);
        return error ? fs::absolute(path).lexically_normal() : p;
    };
    return canonical(a) == canonical(b);
}

} // namespace

void checkOutputFiles(const std::vector<OutputFile>& outputs, const std::vector<InputFile>& inputs) {
    std::vector<const OutputFile*> seen;
    for (const OutputFile& out : outputs) {
        if (out.path.empty()) continue;
        checkWritableFile(out.path, out.option);
        const std::string ext = lowerExtension(out.path);
        if (std::find(out.extensions.begin(), out.extensions.end(), ext) == out.extensions.end()) {
            std::string accepted;
            for (const std::string& e : out.extensions) accepted += (accepted.empty() ? "" : " or ") + e;
            throw UsageError(out.option + " " + printable(out.path) +
                             ": the file's extension chooses its format, and " + out.option + " writes " +
                             accepted + "; name a " + accepted + " file");
        }
        for (const InputFile& in : inputs)
            if (!in.path.empty() && sameFile(out.path, in.path))
                throw UsageError(out.option + " " + printable(out.path) + ": is " + in.what + " (" +
                                 printable(in.path) +
                                 "), which this command reads; give the output another path");
        for (const OutputFile* other : seen)
            if (sameFile(out.path, other->path))
                throw UsageError(out.option + " " + printable(out.path) + ": " + other->option +
                                 " names the same file; give each output its own path");
        seen.push_back(&out);
    }
}

std::vector<InputFile> sceneInputFiles(const std::string& spec, const Scene& scene) {
    std::vector<InputFile> files;
    std::error_code ec;
    if (fs::is_regular_file(spec, ec)) files.push_back({"the scene", spec});
    // A texture's name is its file for the textures read from files (relative to the current
    // directory, as the loaders resolved it), or a generator's name that names no file.
    for (const Texture& t : scene.textures)
        if (fs::is_regular_file(t.name, ec)) files.push_back({"a texture of the scene", t.name});
    return files;
}

void printSceneWarnings(const Scene& scene, bool quiet) {
    if (quiet) return;
    for (const std::string& warning : scene.warnings)
        std::fprintf(stderr, "stsv: warning: %s: %s\n", printable(scene.source).c_str(),
                     printable(warning).c_str());
}

void reportWritten(const std::string& path, bool quiet) {
    if (!quiet) std::fprintf(stderr, "wrote %s\n", printable(path).c_str());
}

void prepareOutputDirectory(const std::string& dir, const std::string& what) {
    if (dir.empty()) throw UsageError(what + ": empty path");
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw UsageError(what + " " + printable(dir) + ": exists and is not a directory");
    fs::create_directories(dir, ec);
    if (ec)
        throw UsageError(what + " " + printable(dir) + ": cannot create the directory (" + ec.message() +
                         ")");
    if (::access(dir.c_str(), W_OK) != 0)
        throw UsageError(what + " " + printable(dir) + ": directory is not writable");
}

double shadowMapPeakBytes(const ShadowMapView& view, const ShadowMapSettings& s, Backend backend, bool keep) {
    const double texels = double(view.faces) * double(view.size) * double(view.size);
    const bool vulkan = backend == Backend::Vulkan;
    double bytes = 0.0;
    if (s.filter == ShadowMapMethod::Peel) {
        bytes += double(depthGridBytes(view, s));
    } else if (readsTransmittanceFunctions(s.filter)) {
        bytes += double(avsmBytes(view, s));
        // Vulkan lists each texel's fragments first (avsmInitialListBytes); the CPU flags each
        // texel that dropped a node (AvsmMap::overflowed, a byte).
        bytes += vulkan ? double(avsmInitialListBytes(std::uint64_t(texels))) : texels;
    } else {
        bytes += double(shadowMapBytes(view));
        if (keep && vulkan) bytes += double(shadowMapBytes(view)); // read back for --shadow-map
    }
    if (isFilteredRepresentation(s.filter)) {
        bytes += double(filteredMapBytes(view, s));
        // The CPU makes the tables or mips of a face from its channel values, one float a texel
        // and channel (shadowmaps/filtered_map.cpp); Vulkan computes them in place.
        if (!vulkan) bytes += double(filteredChannelCount(s)) * double(view.size) * double(view.size) * 4.0;
    }
    return bytes;
}

// The shadow-map term is each light's map as the frame fits it (fitFrameShadowMap: faces and
// size) and what its method builds from it (shadowMapPeakBytes). Measured on fence (one face, a
// 512x512 frame of 64 samples; lavapipe for Vulkan, whose buffers are host memory), as the peak
// resident size less that of the same method at its smallest map, against the estimate less the
// same; MiB:
//   /usr/bin/time -v stsv render fence --method M --backend B -q -o o.png --param SIZE
//   baseline SIZE sm_size=256 (peel_size=16, avsm_size=256 for peel, avsm, vpcss)
//                       default settings          sm_size=4096 (peel_size=2048, avsm_size=4096)
//                      measured   estimate            measured   estimate
//   cpu    pcf, pcss       13.2       15.8                61.1       63.8
//   cpu    vsm             88.4       89.3               360.4      361.3
//   cpu    vsm fm_mip=0   109.7      110.3               445.9      446.4
//   cpu    esm             50.4       52.5               210.4      212.5
//   cpu    evsm           162.8      162.8               658.6      658.8
//   cpu    msm            204.9      204.9               828.9      829.0
//   cpu    csm           1529.0     1528.6              6185.7     6185.6
//   cpu    peel            32.1       34.0               542.2      544.0
//   cpu    avsm, vpcss     64.6       64.7              1099.7     1099.7
//   vulkan pcf, pcss   7.2-17.9       15.8           58.2-68.1       63.8
//   vulkan vsm             23.1       57.8               202.5      233.8
//   vulkan vsm fm_mip=0    49.1       78.8               292.1      318.9
//   vulkan esm             37.3       36.8               151.6      148.8
//   vulkan evsm           100.1       99.8               407.0      403.8
//   vulkan msm            142.8      141.9               578.0      574.0
//   vulkan csm           1025.2     1024.6     refused: 4 GiB, over one Vulkan allocation
//   vulkan peel            24.4       34.0               534.8      544.0
//   vulkan avsm, vpcss     74.6      127.5              1414.4     2167.5
// (pcf and pcss allocate alike on Vulkan: their spread is the measurement's, a few MiB; vsm reads
// mips by default, fm_mip=0 its summed-area table.) Vulkan's
// fragment lists are allocated whole but touched only where fragments land, so its avsm peak
// stays below the estimate; the address space holds all of it. The old estimate, one float a
// texel on six faces, was 96 MiB for csm at sm_size=2048.
double estimateFrameBytes(const RenderOptions& o, const Scene& scene) {
    const std::size_t lights = scene.lights.size();
    const double pixels = double(o.width) * double(o.height);
    // G-buffer (position, normal, triangle), colour (3 floats), visibility, and per light the
    // light-sample buffer in its storage layout (32-bit words, or 16-bit counters).
    const double gbuffer = pixels * (12.0 + 12.0 + 4.0);
    const double images = pixels * (12.0 + 4.0);
    const BufferKind kind = methodInfo(o.method).bufferKind(o.buffer);
    double perLight = double(LightSampleBuffer::storageBytes(o.width, o.height, o.samples, kind));
    // Transmittance with DCS: its layer counters beside the bits and depths (on both backends).
    if (kind == BufferKind::Transmittance && methodInfo(o.method).wedges == WedgeVariant::Dcs)
        perLight +=
            double(LightSampleBuffer::storageBytes(o.width, o.height, o.samples, BufferKind::Counters));
    // Image-based methods: each light's map and what its method builds from it.
    double maps = 0.0;
    if (methodInfo(o.method).shadowMap != ShadowMapMethod::None && !scene.triangles.empty()) {
        const ShadowMapSettings s = shadowMapSettings(o);
        const Bounds receivers =
            s.fit == 0 ? Bounds{} : shadowReceiverBounds(scene, float(o.width) / float(o.height));
        for (const Light& light : scene.lights)
            maps += shadowMapPeakBytes(fitFrameShadowMap(scene, light, receivers, s), s, o.backend,
                                       o.keepShadowMaps);
    }
    // Vulkan STSV with hulls and DCS: the list of fragments whose samples a compute pass tests
    // (initialDeferredFragments) and, for STSV bits
    // (bitmask and transmittance frames), their word buffer.
    double shared = 0.0;
    const MethodInfo& method = methodInfo(o.method);
    const bool vulkan = o.backend == Backend::Vulkan;
    const bool stsv = method.stsv != StsvTriangles::None;
    if (vulkan && (stsv || method.wedges == WedgeVariant::Dcs))
        shared += double(initialDeferredFragments(std::uint64_t(pixels)) * DEFERRED_FRAGMENT_BYTES);
    if (vulkan && stsv && kind != BufferKind::Counters)
        shared += double(LightSampleBuffer::storageBytes(o.width, o.height, o.samples, BufferKind::Bitmask));
    return gbuffer + images + shared + maps + perLight * double(std::max<std::size_t>(lights, 1));
}

void checkFrameMemory(const RenderOptions& o, const Scene& scene) {
    char what[200];
    std::snprintf(what, sizeof what, "a %dx%d frame of %s on %s with %d samples and %zu light(s)", o.width,
                  o.height, toString(o.method).c_str(), toString(o.backend).c_str(), o.samples,
                  scene.lights.size());
    checkMemory(what, estimateFrameBytes(o, scene),
                "use a smaller --size, fewer --samples or a smaller sm_size (peel_size, avsm_size)");
}

void writeJson(const std::string& path, const nlohmann::json& json) {
    const std::string text = json.dump(2) + "\n";
    writeFileBytes(path, text.data(), text.size());
}

Summary summarize(std::vector<double> values) {
    if (values.empty()) return {};
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
    return {median, values.front(), values.back()};
}

nlohmann::json toJson(const Summary& s) {
    return {{"median", s.median}, {"min", s.min}, {"max", s.max}};
}

float encodeSrgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

ImageF toDisplay(const ImageF& image, bool srgb) {
    ImageF out = image;
    for (float& v : out.pixels) {
        v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
        if (srgb) v = encodeSrgb(v);
    }
    return out;
}

ImageError compareImages(const ImageF& a, const ImageF& b, float threshold) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels)
        throw UsageError("cannot compare images of different sizes");
    ImageError e;
    e.absDifference = ImageF(a.width, a.height, 1);
    double sumSquares = 0.0;
    double sum = 0.0;
    std::size_t above = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            float worst = 0.0f;
            for (int c = 0; c < a.channels; ++c) {
                const double signedDifference = double(a.at(x, y, c)) - double(b.at(x, y, c));
                const float d = std::abs(a.at(x, y, c) - b.at(x, y, c));
                sum += signedDifference;
                sumSquares += double(d) * double(d);
                worst = std::max(worst, d);
            }
            e.absDifference.at(x, y, 0) = worst;
            e.maxAbs = std::max(e.maxAbs, double(worst));
            above += worst > threshold ? 1 : 0;
        }
    const double values = double(a.pixels.size());
    const double pixels = double(a.width) * double(a.height);
    e.rmse = values > 0 ? std::sqrt(sumSquares / values) : 0.0;
    e.bias = values > 0 ? sum / values : 0.0;
    e.fractionAbove = pixels > 0 ? double(above) / pixels : 0.0;
    e.ssim = structuralSimilarity(a, b);
    return e;
}

RegionError compareImagesWhere(const ImageF& a, const ImageF& b, const std::vector<std::uint8_t>& selected) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels)
        throw UsageError("cannot compare images of different sizes");
    if (selected.size() != std::size_t(a.width) * std::size_t(a.height))
        throw UsageError("the pixel mask does not match the images' size");
    RegionError e;
    double sumSquares = 0.0;
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (!selected[std::size_t(y) * std::size_t(a.width) + std::size_t(x)]) continue;
            ++e.pixels;
            for (int c = 0; c < a.channels; ++c) {
                const double d = double(a.at(x, y, c)) - double(b.at(x, y, c));
                sum += d;
                sumSquares += d * d;
                e.maxAbs = std::max(e.maxAbs, std::abs(d));
            }
        }
    const double values = double(e.pixels) * double(a.channels);
    e.rmse = values > 0 ? std::sqrt(sumSquares / values) : 0.0;
    e.bias = values > 0 ? sum / values : 0.0;
    return e;
}

LightFacingMask lightFacingMask(const GBuffer& gbuffer, const std::vector<Light>& lights, float farDistance,
                                int width, int height) {
    const std::vector<PixelFacing> pixels = lightFacingPixels(gbuffer, lights, farDistance, width, height);
    LightFacingMask mask;
    mask.selected.reserve(pixels.size());
    for (PixelFacing p : pixels) {
        mask.selected.push_back(p == PixelFacing::Facing ? 1 : 0);
        (p == PixelFacing::Facing ? mask.facing : p == PixelFacing::Away ? mask.away : mask.background) += 1;
    }
    return mask;
}

namespace {

ImageF lumaOf(const ImageF& image) {
    ImageF y(image.width, image.height, 1);
    for (int j = 0; j < image.height; ++j)
        for (int i = 0; i < image.width; ++i)
            y.at(i, j, 0) = image.channels >= 3 ? 0.2126f * image.at(i, j, 0) + 0.7152f * image.at(i, j, 1) +
                                                      0.0722f * image.at(i, j, 2)
                                                : image.at(i, j, 0);
    return y;
}

} // namespace

double structuralSimilarity(const ImageF& a, const ImageF& b) {
    if (a.width != b.width || a.height != b.height)
        throw UsageError("cannot compare images of different sizes");
    const ImageF x = lumaOf(a), y = lumaOf(b);
    constexpr int R = 5; // 11×11 window
    constexpr double SIGMA = 1.5;
    constexpr double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03; // (K1·L)², (K2·L)² with L = 1
    double weights[2 * R + 1];
    for (int k = -R; k <= R; ++k) weights[k + R] = std::exp(-0.5 * k * k / (SIGMA * SIGMA));
    double total = 0.0;
    for (int j = 0; j < x.height; ++j)
        for (int i = 0; i < x.width; ++i) {
            double w = 0.0, mx = 0.0, my = 0.0, xx = 0.0, yy = 0.0, xy = 0.0;
            for (int dj = -R; dj <= R; ++dj) {
                const int v = j + dj;
                if (v < 0 || v >= x.height) continue;
                for (int di = -R; di <= R; ++di) {
                    const int u = i + di;
                    if (u < 0 || u >= x.width) continue;
                    const double g = weights[di + R] * weights[dj + R];
                    const double p = x.at(u, v, 0), q = y.at(u, v, 0);
                    w += g;
                    mx += g * p;
                    my += g * q;
                    xx += g * p * p;
                    yy += g * q * q;
                    xy += g * p * q;
                }
            }
            mx /= w, my /= w;
            const double vx = std::max(xx / w - mx * mx, 0.0), vy = std::max(yy / w - my * my, 0.0);
            const double cxy = xy / w - mx * my;
            total += (2.0 * mx * my + C1) * (2.0 * cxy + C2) / ((mx * mx + my * my + C1) * (vx + vy + C2));
        }
    const double pixels = double(x.width) * double(x.height);
    return pixels > 0 ? total / pixels : 1.0;
}

/// The name of the device the Vulkan backend picks (DeviceOptions::select's rule), or a
/// short reason why there is none.
namespace {

std::string vulkanDeviceName(const std::string& select, nlohmann::json& allNames) {
    try {
        const std::vector<DeviceInfo> devices = listDevices();
        for (const DeviceInfo& d : devices) allNames.push_back(d.name);
        if (!select.empty() &&
            std::all_of(select.begin(), select.end(), [](unsigned char c) { return std::isdigit(c); })) {
            const unsigned long index = select.size() > 9 ? ~0ul : std::stoul(select);
            return index < devices.size() ? devices[index].name : "no device " + select;
        }
        if (!select.empty()) {
            auto lower = [](std::string s) {
                for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
                return s;
            };
            for (const DeviceInfo& d : devices)
                if (lower(d.name).find(lower(select)) != std::string::npos) return d.name;
            return "no device matching " + select;
        }
        for (VkPhysicalDeviceType type :
             {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
              VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_CPU,
              VK_PHYSICAL_DEVICE_TYPE_OTHER})
            for (const DeviceInfo& d : devices)
                if (d.type == type && d.vulkan13) return d.name;
        return "no Vulkan 1.3 device";
    } catch (const Error& e) {
        return "vulkan unavailable: " + printable(e.message());
    }
}

/// The CPU's model name from /proc/cpuinfo ("unknown" where it has none).
std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const std::size_t colon = line.find(':');
            if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
        }
    return "unknown";
}

} // namespace

std::string formatFixed(double value, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

nlohmann::json machineJson(bool vulkan, const std::string& select) {
    nlohmann::json machine = {{"cpu_model", cpuModel()},
                              {"cpu_threads", std::thread::hardware_concurrency()},
                              {"memory_bytes", physicalMemoryBytes()},
                              {"device", nullptr},
                              {"vulkan_devices", nlohmann::json::array()}};
    if (vulkan) machine["device"] = vulkanDeviceName(select, machine["vulkan_devices"]);
    return machine;
}

Rgb8 heatColour(float t) {
    t = std::clamp(t, 0.0f, 1.0f);
    const float r = std::min(1.0f, 2.0f * t);
    const float g = std::max(0.0f, 2.0f * t - 1.0f);
    return {static_cast<std::uint8_t>(std::lround(r * 255.0f)),
            static_cast<std::uint8_t>(std::lround(g * 255.0f)), 0};
}

Image8 heatMap(const ImageF& values, float scale) {
    Image8 out;
    out.width = values.width;
    out.height = values.height;
    out.channels = 3;
    out.pixels.assign(std::size_t(values.width) * std::size_t(values.height) * 3, 0);
    for (int y = 0; y < values.height; ++y)
        for (int x = 0; x < values.width; ++x) {
            const float v = values.at(x, y, 0);
            const float t = scale > 0.0f ? v / scale : (v > 0.0f ? 1.0f : 0.0f);
            const Rgb8 c = heatColour(t);
            for (int ch = 0; ch < 3; ++ch) out.at(x, y, ch) = c[std::size_t(ch)];
        }
    return out;
}

namespace {

/// A tick label: three significant digits, no trailing zeros (0.1, 0.05, 0.25).
std::string tickText(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", double(value));
    return text;
}

} // namespace

Image8 heatLegend(float scale, int width, const std::string& caption, int textScale) {
    const int s = std::max(1, textScale);
    const int pad = 4 * s, line = textLineHeight(s), barHeight = 6 * s, gap = 2 * s;
    Image8 out;
    // Room for the caption, and for the three numbers with space between them.
    out.width = std::max({width, textWidth(caption, s) + 2 * pad, 120 * s});
    out.height = pad + line + barHeight + gap + line + pad;
    out.channels = 3;
    out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 3, 0);
    fillRect(out, 0, 0, out.width, out.height, SHEET_BACKGROUND);
    drawText(out, pad, pad, caption, s, SHEET_TEXT);
    const int x0 = pad, x1 = out.width - pad; // the bar covers [x0, x1)
    const int barY = pad + line;
    for (int x = x0; x < x1; ++x)
        fillRect(out, x, barY, 1, barHeight, heatColour(float(x - x0) / float(std::max(1, x1 - x0 - 1))));
    const int labelY = barY + barHeight + gap;
    const std::string mid = tickText(scale / 2.0f), top = tickText(scale) + "+";
    drawText(out, x0, labelY, "0", s, SHEET_TEXT);
    drawText(out, (x0 + x1) / 2 - textWidth(mid, s) / 2, labelY, mid, s, SHEET_TEXT);
    drawText(out, x1 - textWidth(top, s), labelY, top, s, SHEET_TEXT);
    return out;
}

Image8 heatMapWithLegend(const ImageF& values, float scale, const std::string& caption) {
    const Image8 heat = heatMap(values, scale);
    const int textScale = heat.width >= 512 ? 2 : 1;
    const Image8 legend = heatLegend(scale, heat.width, caption, textScale);
    Image8 out;
    out.width = legend.width;
    out.height = heat.height + legend.height;
    out.channels = 3;
    out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 3, 0);
    fillRect(out, 0, 0, out.width, heat.height, SHEET_BACKGROUND);
    pasteScaled(out, heat, 0, 0, 1);
    pasteScaled(out, legend, 0, heat.height, 1);
    return out;
}

ImageF sampleDisagreement(const LightSampleBuffer& a, const LightSampleBuffer& b) {
    if (a.width() != b.width() || a.height() != b.height() || a.samples() != b.samples())
        throw UsageError("light-sample buffers differ in size: " + std::to_string(a.width()) + "x" +
                         std::to_string(a.height()) + "x" + std::to_string(a.samples()) + " vs " +
                         std::to_string(b.width()) + "x" + std::to_string(b.height()) + "x" +
                         std::to_string(b.samples()));
    ImageF out(a.width(), a.height(), 1);
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            int differing = 0;
            for (int k = 0; k < a.samples(); ++k)
                differing += a.occluded(x, y, k) != b.occluded(x, y, k) ? 1 : 0;
            out.at(x, y, 0) = float(differing) / float(a.samples());
        }
    return out;
}

} // namespace stsv
