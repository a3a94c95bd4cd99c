#include "sampling/ls_buffer.h"

#include "core/error.h"
#include "core/files.h"
#include "scene/occlusion_rules_dh.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>

namespace stsv {

namespace {

/// The "format" value of a light-sample file's metadata.
constexpr const char* LIGHT_SAMPLE_FORMAT = "stsv light samples";

/// The longest metadata file read: a few hundred bytes are written.
constexpr std::size_t MAX_INFO_BYTES = 1 << 16;

} // namespace

std::string bufferKindName(BufferKind kind) {
    return kind == BufferKind::Bitmask    ? "bitmask"
           : kind == BufferKind::Counters ? "counters"
                                          : "transmittance";
}

std::optional<BufferKind> bufferKindNamed(const std::string& name) {
    for (BufferKind kind : {BufferKind::Bitmask, BufferKind::Counters, BufferKind::Transmittance})
        if (bufferKindName(kind) == name) return kind;
    return std::nullopt;
}

std::string npyInfoPath(const std::string& npyPath) {
    return npyPath + ".json";
}

std::optional<LightSampleFileInfo> readLightSampleInfo(const std::string& npyPath) {
    const std::string path = npyInfoPath(npyPath);
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return std::nullopt;
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(readFileBytes(path, "light-sample metadata", MAX_INFO_BYTES));
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(path, std::string("the light-sample metadata is not valid JSON (") + e.what() + ")");
    }
    if (!j.is_object() || j.value("format", nlohmann::json()) != LIGHT_SAMPLE_FORMAT)
        throw InputError(path,
                         std::string("is not light-sample metadata (a JSON object whose \"format\" is \"") +
                             LIGHT_SAMPLE_FORMAT + "\")");
    auto integer = [&](const char* key, int lo, int hi) {
        const nlohmann::json& v = j.contains(key) ? j[key] : nlohmann::json();
        if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi)
            throw InputError(path, std::string("\"") + key + "\" must be an integer in [" +
                                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return int(v.get<std::int64_t>());
    };
    LightSampleFileInfo info;
    const nlohmann::json& kind = j.contains("kind") ? j["kind"] : nlohmann::json();
    const std::optional<BufferKind> named =
        kind.is_string() ? bufferKindNamed(kind.get<std::string>()) : std::nullopt;
    if (!named) throw InputError(path, "\"kind\" must be \"bitmask\", \"counters\" or \"transmittance\"");
    info.kind = *named;
    info.samples = integer("samples", 1, 4096);
    info.width = integer("width", 1, 1 << 16);
    info.height = integer("height", 1, 1 << 16);
    if (j.contains("method")) {
        if (!j["method"].is_string()) throw InputError(path, "\"method\" must be a string");
        info.method = j["method"].get<std::string>();
    }
    return info;
}

LightSampleBuffer::LightSampleBuffer(int width, int height, int samples, BufferKind kind)
    : m_width(width), m_height(height), m_samples(samples), m_kind(kind) {
    if (width < 1 || height < 1 || samples < 1 || samples > 4096 ||
        std::size_t(width) * std::size_t(height) > (1u << 28) ||
        (kind != BufferKind::Bitmask &&
         std::size_t(width) * std::size_t(height) * std::size_t(samples) > 0xFFFFFFFFu))
        throw UsageError("light-sample buffer of " + std::to_string(width) + "x" + std::to_string(height) +
                         " pixels × " + std::to_string(samples) + " samples is out of range");
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    if (kind != BufferKind::Counters) m_words.assign(pixels * std::size_t(wordsPerPixel()), 0u);
    if (kind == BufferKind::Counters) m_counters.assign(pixels * std::size_t(samples), 0u);
    if (kind == BufferKind::Transmittance) m_depths.assign(pixels * std::size_t(samples), 0u);
}

void LightSampleBuffer::addOpticalDepth(int x, int y, int k, std::uint32_t units) {
    if (m_kind != BufferKind::Transmittance)
        throw UsageError("addOpticalDepth on a " +
                         std::string(m_kind == BufferKind::Bitmask ? "bitmask" : "counter") +
                         " light-sample buffer");
    if (units == 0u) return;
    std::uint32_t& depth = m_depths[counterSlot(x, y, k)];
    const std::uint32_t sum = depth + units; // modulo 2^32, as the GPU's atomicAdd
    if (units == OPTICAL_DEPTH_OPAQUE || sum < depth) setOccluded(x, y, k);
    depth = sum;
}

std::uint32_t LightSampleBuffer::opticalDepth(int x, int y, int k) const {
    if (occluded(x, y, k)) return OPTICAL_DEPTH_OPAQUE;
    return m_kind == BufferKind::Transmittance ? m_depths[counterSlot(x, y, k)] : 0u;
}

float LightSampleBuffer::transmittance(int x, int y, int k) const {
    const std::uint32_t depth = opticalDepth(x, y, k);
    return depth == OPTICAL_DEPTH_OPAQUE ? 0.0f : transmittanceOfDepth(depth);
}

void LightSampleBuffer::setOccluded(int x, int y, int k) {
    if (m_kind != BufferKind::Counters) {
        m_words[maskWordIndex(x, y, k)] |= lsMaskBit(uint(k));
    } else {
        std::uint16_t& c = m_counters[counterSlot(x, y, k)];
        if (c == 0) c = 1;
    }
}

void LightSampleBuffer::addOccludingWord(int x, int y, int word, std::uint32_t bits) {
    if (m_kind != BufferKind::Counters) {
        m_words[pixelIndex(x, y) * std::size_t(wordsPerPixel()) + std::size_t(word)] |= bits;
        return;
    }
    for (; bits != 0u; bits &= bits - 1u) addCount(x, y, 32 * word + std::countr_zero(bits), 1);
}

std::uint32_t LightSampleBuffer::occludedWord(int x, int y, int word) const {
    if (m_kind != BufferKind::Counters)
        return m_words[pixelIndex(x, y) * std::size_t(wordsPerPixel()) + std::size_t(word)];
    std::uint32_t bits = 0u;
    for (int b = 0; b < 32 && 32 * word + b < m_samples; ++b)
        if (m_counters[counterSlot(x, y, 32 * word + b)] != 0) bits |= lsMaskBit(uint(b));
    return bits;
}

bool LightSampleBuffer::occluded(int x, int y, int k) const {
    return count(x, y, k) != 0;
}

void LightSampleBuffer::addCount(int x, int y, int k, int delta) {
    if (m_kind != BufferKind::Counters)
        throw UsageError("addCount on a light-sample buffer without counters");
    std::uint16_t& c = m_counters[counterSlot(x, y, k)];
    c = std::uint16_t(unsigned(c) + unsigned(delta)); // modulo 2^16 (see the header)
}

int LightSampleBuffer::count(int x, int y, int k) const {
    if (m_kind != BufferKind::Counters)
        return (m_words[maskWordIndex(x, y, k)] & lsMaskBit(uint(k))) != 0u ? 1 : 0;
    return m_counters[counterSlot(x, y, k)];
}

float LightSampleBuffer::visibleFraction(int x, int y) const {
    const uint samples = uint(m_samples);
    if (m_kind == BufferKind::Transmittance) {
        float sum = 0.0f;
        for (int k = 0; k < m_samples; ++k) sum += transmittance(x, y, k);
        return lsMeanTransmittance(sum, samples);
    }
    uint occludedCount = 0u;
    if (m_kind == BufferKind::Bitmask) {
        const std::uint32_t* w = &m_words[pixelIndex(x, y) * std::size_t(wordsPerPixel())];
        for (int i = 0; i < wordsPerPixel(); ++i)
            occludedCount += lsMaskWordOccludedCount(w[i], uint(i), samples);
    } else {
        const std::uint16_t* c = &m_counters[counterSlot(x, y, 0)];
        for (int k = 0; k < m_samples; ++k) occludedCount += c[k] != 0 ? 1u : 0u;
    }
    return lsVisibleFraction(occludedCount, samples);
}

std::size_t LightSampleBuffer::payloadBytes(int width, int height, int samples, BufferKind kind) {
    const std::size_t pixelSamples = std::size_t(width) * std::size_t(height) * std::size_t(samples);
    return kind == BufferKind::Bitmask ? pixelSamples / 8 : pixelSamples * 2;
}

std::size_t LightSampleBuffer::storageBytes(int width, int height, int samples, BufferKind kind) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const std::size_t bits = pixels * 4 * std::size_t((samples + 31) / 32);
    if (kind == BufferKind::Bitmask) return bits;
    if (kind == BufferKind::Counters) return payloadBytes(width, height, samples, kind);
    return bits + pixels * std::size_t(samples) * 4;
}

void LightSampleBuffer::writeNpy(const std::string& path, const std::string& method) const {
    writeArray(path);
    nlohmann::json info = {{"format", LIGHT_SAMPLE_FORMAT},
                           {"kind", bufferKindName(m_kind)},
                           {"samples", m_samples},
                           {"width", m_width},
                           {"height", m_height}};
    if (!method.empty()) info["method"] = method;
    const std::string text = info.dump(2) + "\n";
    // The array without its metadata would be read as another kind: neither is left.
    try {
        writeFileBytes(npyInfoPath(path), text.data(), text.size());
    } catch (const Error&) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw;
    }
}

void LightSampleBuffer::writeArray(const std::string& path) const {
    const auto h = std::size_t(m_height);
    const auto w = std::size_t(m_width);
    const auto n = std::size_t(m_samples);
    if (m_kind == BufferKind::Transmittance) {
        std::vector<std::uint8_t> bytes(h * w * n * 2);
        std::size_t i = 0;
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x)
                for (int k = 0; k < m_samples; ++k, i += 2) {
                    const std::uint16_t bits = halfBits(transmittance(x, y, k));
                    bytes[i] = std::uint8_t(bits & 0xFFu);
                    bytes[i + 1] = std::uint8_t(bits >> 8u);
                }
        stsv::writeNpy(path, "<f2", {h, w, n}, bytes.data(), bytes.size());
        return;
    }
    if (m_kind == BufferKind::Bitmask) {
        if (m_samples % 8 != 0)
            throw UsageError("--dump-ls needs a sample count that is a multiple of 8, not " +
                             std::to_string(m_samples));
        const std::size_t bytesPerPixel = n / 8;
        std::vector<std::uint8_t> bytes(h * w * bytesPerPixel);
        const auto wpp = std::size_t(wordsPerPixel());
        for (std::size_t p = 0; p < h * w; ++p)
            for (std::size_t j = 0; j < bytesPerPixel; ++j)
                bytes[p * bytesPerPixel + j] = std::uint8_t(m_words[p * wpp + j / 4] >> (8 * (j % 4)));
        stsv::writeNpy(path, "|u1", {h, w, bytesPerPixel}, bytes.data(), bytes.size());
        return;
    }
    const std::uint16_t maxCount =
        m_counters.empty() ? 0 : *std::max_element(m_counters.begin(), m_counters.end());
    if (maxCount < 256) {
        std::vector<std::uint8_t> bytes(m_counters.size());
        std::transform(m_counters.begin(), m_counters.end(), bytes.begin(),
                       [](std::uint16_t c) { return std::uint8_t(c); });
        stsv::writeNpy(path, "|u1", {h, w, n}, bytes.data(), bytes.size());
    } else {
        std::vector<std::uint8_t> bytes(m_counters.size() * 2);
        for (std::size_t i = 0; i < m_counters.size(); ++i) {
            bytes[2 * i] = std::uint8_t(m_counters[i] & 0xFFu);
            bytes[2 * i + 1] = std::uint8_t(m_counters[i] >> 8u);
        }
        stsv::writeNpy(path, "<u2", {h, w, n}, bytes.data(), bytes.size());
    }
}

namespace {

LightSampleBuffer readTransmittance(const std::string& path, const NpyArray& array) {
    if (array.shape.size() != 3 || array.shape[0] == 0 || array.shape[1] == 0 || array.shape[2] == 0)
        throw InputError(path, "transmittance buffer must have shape [H, W, N]");
    const std::size_t h = array.shape[0], w = array.shape[1], n = array.shape[2];
    if (h > (1u << 16) || w > (1u << 16) || n > 4096)
        throw InputError(path, "light-sample buffer shape is out of range");
    if (array.bytes.size() != h * w * n * 2) throw InputError(path, "light-sample buffer is truncated");
    LightSampleBuffer buffer(int(w), int(h), int(n), BufferKind::Transmittance);
    std::size_t i = 0;
    for (int y = 0; y < int(h); ++y)
        for (int x = 0; x < int(w); ++x)
            for (int k = 0; k < int(n); ++k, i += 2) {
                const float t = halfValue(std::uint16_t(array.bytes[i] | (array.bytes[i + 1] << 8u)));
                if (!(t >= 0.0f && t <= 1.0f))
                    throw InputError(path, "transmittance " + std::to_string(t) +
                                               " outside [0, 1] at pixel (" + std::to_string(x) + ", " +
                                               std::to_string(y) + ") sample " + std::to_string(k));
                if (t == 0.0f)
                    buffer.setOccluded(x, y, k);
                else
                    buffer.addOpticalDepth(
                        x, y, k,
                        std::uint32_t(std::llround(-std::log(double(t)) * double(OPTICAL_DEPTH_SCALE))));
            }
    return buffer;
}

} // namespace

LightSampleBuffer LightSampleBuffer::readNpy(const std::string& path, std::optional<BufferKind> kind) {
    return fromNpy(path, stsv::readNpy(path), kind);
}

LightSampleBuffer LightSampleBuffer::fromNpy(const std::string& path, const NpyArray& array,
                                             std::optional<BufferKind> kind) {
    const std::optional<LightSampleFileInfo> info = readLightSampleInfo(path);
    const std::string infoName = std::filesystem::path(npyInfoPath(path)).filename().string();
    if (info && kind && *kind != info->kind)
        throw InputError(path, "holds " + bufferKindName(info->kind) + " (" + infoName + " says so), not " +
                                   bufferKindName(*kind));
    const bool f16 = array.dtype == "<f2";
    const bool u8 = array.dtype == "|u1" || array.dtype == "<u1";
    const bool u16 = array.dtype == "<u2";
    if (!f16 && !u8 && !u16)
        throw InputError(path, "light-sample buffer must be uint8, uint16 or float16, not " + array.dtype);
    std::optional<BufferKind> k = info ? std::optional(info->kind) : kind;
    if (!k && f16) k = BufferKind::Transmittance;
    if (!k && u16) k = BufferKind::Counters;
    if (!k)
        throw InputError(path, "a uint8 light-sample array is a bitmask [H, W, N/8] or counters [H, W, N], "
                               "and without " +
                                   infoName + " beside it nothing says which");
    if ((*k == BufferKind::Transmittance) != f16 || (*k == BufferKind::Bitmask && !u8))
        throw InputError(path, "a " + array.dtype + " array is not a light-sample " + bufferKindName(*k) +
                                   " (bitmask: uint8; counters: uint8 or uint16; transmittance: float16)");
    LightSampleBuffer buffer = *k == BufferKind::Transmittance ? readTransmittance(path, array)
                                                               : readOcclusion(path, array, *k, u16);
    if (info && (buffer.width() != info->width || buffer.height() != info->height ||
                 buffer.samples() != info->samples))
        throw InputError(path, "holds " + std::to_string(buffer.width()) + "x" +
                                   std::to_string(buffer.height()) + " pixels of " +
                                   std::to_string(buffer.samples()) + " samples, where " + infoName +
                                   " describes " + std::to_string(info->width) + "x" +
                                   std::to_string(info->height) + " of " + std::to_string(info->samples) +
                                   ": the metadata is another array's (remove it and give the kind)");
    return buffer;
}

LightSampleBuffer LightSampleBuffer::readOcclusion(const std::string& path, const NpyArray& array,
                                                   BufferKind k, bool u16) {
    if (array.shape.size() != 3 || array.shape[0] == 0 || array.shape[1] == 0 || array.shape[2] == 0)
        throw InputError(path, "light-sample buffer must have shape [H, W, N/8] or [H, W, N]");
    const std::size_t h = array.shape[0];
    const std::size_t w = array.shape[1];
    const std::size_t depth = array.shape[2];
    const std::size_t samples = k == BufferKind::Bitmask ? depth * 8 : depth;
    if (h > (1u << 16) || w > (1u << 16) || samples > 4096)
        throw InputError(path, "light-sample buffer shape is out of range");
    const std::size_t elementBytes = u16 ? 2 : 1;
    if (array.bytes.size() != h * w * depth * elementBytes)
        throw InputError(path, "light-sample buffer is truncated");
    LightSampleBuffer buffer(int(w), int(h), int(samples), k);
    if (k == BufferKind::Bitmask) {
        const auto wpp = std::size_t(buffer.wordsPerPixel());
        for (std::size_t p = 0; p < h * w; ++p)
            for (std::size_t j = 0; j < depth; ++j)
                buffer.m_words[p * wpp + j / 4] |= std::uint32_t(array.bytes[p * depth + j]) << (8 * (j % 4));
    } else {
        for (std::size_t i = 0; i < buffer.m_counters.size(); ++i)
            buffer.m_counters[i] = u16 ? std::uint16_t(array.bytes[2 * i] | (array.bytes[2 * i + 1] << 8u))
                                       : std::uint16_t(array.bytes[i]);
    }
    return buffer;
}

LightSampleDiff compareLightSamples(const LightSampleBuffer& a, const LightSampleBuffer& b,
                                    std::size_t maxPixels, bool compareCounts) {
    if (a.width() != b.width() || a.height() != b.height() || a.samples() != b.samples())
        throw UsageError("cannot compare light-sample buffers of " + std::to_string(a.width()) + "x" +
                         std::to_string(a.height()) + "x" + std::to_string(a.samples()) + " and " +
                         std::to_string(b.width()) + "x" + std::to_string(b.height()) + "x" +
                         std::to_string(b.samples()));
    const bool counts = compareCounts && a.kind() == BufferKind::Counters && b.kind() == BufferKind::Counters;
    const bool depths =
        compareCounts && a.kind() == BufferKind::Transmittance && b.kind() == BufferKind::Transmittance;
    LightSampleDiff diff;
    diff.comparedSamples = std::size_t(a.width()) * std::size_t(a.height()) * std::size_t(a.samples());
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            std::size_t here = 0;
            for (int k = 0; k < a.samples(); ++k) {
                const bool differ = counts   ? a.count(x, y, k) != b.count(x, y, k)
                                    : depths ? a.opticalDepth(x, y, k) != b.opticalDepth(x, y, k)
                                             : a.occluded(x, y, k) != b.occluded(x, y, k);
                here += differ ? 1 : 0;
            }
            if (here == 0) continue;
            diff.differingSamples += here;
            ++diff.differingPixels;
            if (diff.firstPixels.size() < maxPixels) diff.firstPixels.push_back(ivec2(x, y));
        }
    return diff;
}

ImageF resolveVisibility(const LightSampleBuffer& buffer) {
    ImageF image(buffer.width(), buffer.height(), 1);
    for (int y = 0; y < buffer.height(); ++y)
        for (int x = 0; x < buffer.width(); ++x) image.at(x, y, 0) = buffer.visibleFraction(x, y);
    return image;
}

} // namespace stsv
