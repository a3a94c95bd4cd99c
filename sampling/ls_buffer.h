// Light-sample buffers (DESIGN §4.4): per pixel, one occlusion bit or one depth-complexity
// counter per light sample, and their resolve to the visibility coefficient v_coef.
#pragma once

#include "core/dh.h"
#include "core/image.h"
#include "sampling/ls_buffer_dh.h"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace stsv {

/// What a light-sample buffer stores per (pixel, sample): an occlusion bit, a depth-complexity
/// counter, or the fraction of light that gets through (an occlusion bit for what blocks fully and
/// the optical depth of the translucent triangles crossed, scene/occlusion_rules_dh.h).
enum class BufferKind { Bitmask, Counters, Transmittance };

/// "bitmask", "counters", "transmittance": a kind as --buffer and the files' metadata name it.
std::string bufferKindName(BufferKind kind);
/// The kind of that name; nullopt for any other text.
std::optional<BufferKind> bufferKindNamed(const std::string& name);

/// What a light-sample .npy holds that its dtype and shape cannot say (a uint8 [H, W, 16] array is
/// a bitmask of 128 samples or counters of 16), and how it was made. LightSampleBuffer::writeNpy
/// writes it beside the array as JSON, in "<file>.json" (lightSampleInfoPath): NumPy's reader
/// refuses a .npy header whose keys are other than descr, fortran_order and shape, so the header
/// cannot carry it.
struct LightSampleFileInfo {
    BufferKind kind = BufferKind::Bitmask;
    int samples = 0;    ///< N, the light samples per pixel
    int width = 0;      ///< pixels
    int height = 0;     ///< pixels
    std::string method; ///< the method and backend that wrote it, "stsv/cpu" (empty: not said)
};

/// "<npyPath>.json": the metadata file beside a .npy (light samples, and the CLI's visibility).
std::string npyInfoPath(const std::string& npyPath);
/// The metadata beside a light-sample .npy, or nullopt when there is none (a file from an older
/// stsv, or made by NumPy); InputError naming the metadata file when it is not such JSON.
std::optional<LightSampleFileInfo> readLightSampleInfo(const std::string& npyPath);

class LightSampleBuffer {
  public:
    LightSampleBuffer() = default;
    /// UsageError unless width, height ≥ 1, samples ∈ [1, 4096] (a multiple of 8 for writeNpy of
    /// a bitmask) and, for counters, width·height·samples < 2^32 (ls_buffer_dh.h's 32-bit slots).
    LightSampleBuffer(int width, int height, int samples, BufferKind kind);

    int width() const { return m_width; }
    int height() const { return m_height; }
    int samples() const { return m_samples; }
    BufferKind kind() const { return m_kind; }
    /// Bitmask: 32-bit words per pixel, ceil(N/32), in the layout of ls_buffer_dh.h (the GPU's).
    int wordsPerPixel() const { return int(lsMaskWordCount(uint(m_samples))); }

    /// Transmittance: adds `units` of optical depth (scene/occlusion_rules_dh.h) to sample k;
    /// OPTICAL_DEPTH_OPAQUE, or a sum that reaches 2^32 units, sets its occlusion bit.
    void addOpticalDepth(int x, int y, int k, std::uint32_t units);
    /// Transmittance: the optical depth of sample k (OPTICAL_DEPTH_OPAQUE when occluded);
    /// bitmask and counters: 0 or OPTICAL_DEPTH_OPAQUE.
    std::uint32_t opticalDepth(int x, int y, int k) const;
    /// The fraction of sample k's light that gets through: 0 or 1 for bits and counters,
    /// exp(−depth) (transmittanceOfDepth) for a transmittance buffer.
    float transmittance(int x, int y, int k) const;

    /// Bitmask and transmittance: sets the bit. Counters: raises a zero count to 1.
    void setOccluded(int x, int y, int k);
    /// The occluding samples 32·word + b of the set bits b of `bits` (mask word `word`,
    /// ls_buffer_dh.h). Bitmask: ORed in; counters: one more layer on each of those samples.
    void addOccludingWord(int x, int y, int word, std::uint32_t bits);
    /// Occlusion bits of mask word `word` (samples 32·word + b, ls_buffer_dh.h): the stored word
    /// of a bitmask; for counters, the samples whose count ≠ 0.
    std::uint32_t occludedWord(int x, int y, int word) const;
    /// Bit set, or count ≠ 0.
    bool occluded(int x, int y, int k) const;
    bool visible(int x, int y, int k) const { return !occluded(x, y, k); }
    /// Counters only (UsageError on a bitmask). Arithmetic is modulo 2^16 like the GPU's
    /// unsigned atomics, so intermediate negative sums (DCS's ±1 edge crossings) are exact as
    /// long as the final count lies in [0, 65535].
    void addCount(int x, int y, int k, int delta);
    /// Counters: the count; bitmask: 0 or 1.
    int count(int x, int y, int k) const;
    /// Visible samples / N (the paper's v_coef); with transmittance, the mean transmittance.
    float visibleFraction(int x, int y) const;

    /// Raw storage for GPU readback, addressed as ls_buffer_dh.h: pixel (x, y) starts at
    /// (y·width + x)·wordsPerPixel() (bitmask) or at counter slot (y·width + x)·samples; row 0 is
    /// the top image row.
    std::vector<std::uint32_t>& words() { return m_words; }
    const std::vector<std::uint32_t>& words() const { return m_words; }
    std::vector<std::uint16_t>& counters() { return m_counters; }
    const std::vector<std::uint16_t>& counters() const { return m_counters; }
    /// Transmittance: the optical depth per sample, slot (y·width + x)·samples + k.
    std::vector<std::uint32_t>& depths() { return m_depths; }
    const std::vector<std::uint32_t>& depths() const { return m_depths; }

    /// Payload size: N·W·H/8 bytes for a bitmask (the paper's §5.1 figure: 8 MiB at 1024² × 64),
    /// 2·N·W·H for 16-bit counters and for float16 transmittance (the --dump-ls array).
    static std::size_t payloadBytes(int width, int height, int samples, BufferKind kind);
    /// Storage size: the bitmask rounds N up to 32-bit words; counters as the payload;
    /// transmittance holds the bitmask and a 32-bit optical depth per sample (4.125·N·W·H).
    static std::size_t storageBytes(int width, int height, int samples, BufferKind kind);
    std::size_t memoryBytes() const { return payloadBytes(m_width, m_height, m_samples, m_kind); }
    std::size_t storageBytes() const { return storageBytes(m_width, m_height, m_samples, m_kind); }

    /// The `--dump-ls` format. Bitmask: uint8 [H, W, N/8], sample k in bit k%8 of
    /// byte k/8, 1 = occluded (UsageError if N is not a multiple of 8). Counters: uint8 if every
    /// count < 256, else uint16 (little endian), shape [H, W, N]. Transmittance: float16
    /// [H, W, N], the transmittance of each sample. Row 0 = top image row. Beside it,
    /// npyInfoPath(path) says the kind, N, the size and `method` (LightSampleFileInfo).
    void writeNpy(const std::string& path, const std::string& method = {}) const;
    /// Inverse of writeNpy. The kind is the metadata file's (readLightSampleInfo), which must
    /// describe this array; without one, `kind`, else what the dtype alone says: uint16 counters,
    /// float16 transmittance (its optical depth back from −ln T, to 2^−16 units). InputError naming
    /// the file for a uint8 array of no known kind, a `kind` other than its metadata's, metadata
    /// of another array, or any other dtype or shape.
    static LightSampleBuffer readNpy(const std::string& path, std::optional<BufferKind> kind = std::nullopt);
    /// readNpy of an array already read from `path` (its metadata is read beside `path`).
    static LightSampleBuffer fromNpy(const std::string& path, const NpyArray& array,
                                     std::optional<BufferKind> kind = std::nullopt);

  private:
    /// writeNpy's array alone.
    void writeArray(const std::string& path) const;
    /// readNpy of a bitmask or counters array (`u16`: little-endian uint16 elements, else uint8).
    static LightSampleBuffer readOcclusion(const std::string& path, const NpyArray& array, BufferKind kind,
                                           bool u16);

    std::size_t pixelIndex(int x, int y) const {
        return lsPixelIndex(uvec2(unsigned(x), unsigned(y)), uint(m_width));
    }
    std::size_t maskWordIndex(int x, int y, int k) const {
        return pixelIndex(x, y) * std::size_t(wordsPerPixel()) + lsMaskWord(uint(k));
    }
    std::size_t counterSlot(int x, int y, int k) const {
        return lsCounterSlot(uint(pixelIndex(x, y)), uint(m_samples), uint(k));
    }

    int m_width = 0;
    int m_height = 0;
    int m_samples = 0;
    BufferKind m_kind = BufferKind::Bitmask;
    std::vector<std::uint32_t> m_words;
    std::vector<std::uint16_t> m_counters;
    std::vector<std::uint32_t> m_depths;
};

/// Sample-by-sample comparison of the occlusion state (occluded vs visible) of two buffers of
/// the same size and N; with `compareCounts` and two counter buffers, of the exact counts; with
/// `compareCounts` and two transmittance buffers, of the exact optical depths.
struct LightSampleDiff {
    std::size_t differingSamples = 0; ///< (pixel, sample) pairs that differ
    std::size_t differingPixels = 0;
    std::size_t comparedSamples = 0; ///< W·H·N
    std::vector<ivec2> firstPixels;  ///< up to maxPixels differing pixels, in row order
};
/// Both buffers hold transmittance: compareLightSamples then compares their optical depths.
inline bool transmittanceBoth(const LightSampleBuffer& a, const LightSampleBuffer& b) {
    return a.kind() == BufferKind::Transmittance && b.kind() == BufferKind::Transmittance;
}
LightSampleDiff compareLightSamples(const LightSampleBuffer& a, const LightSampleBuffer& b,
                                    std::size_t maxPixels = 16, bool compareCounts = false);

/// v_coef per pixel (one channel): visible samples / N.
ImageF resolveVisibility(const LightSampleBuffer& buffer);

} // namespace stsv
