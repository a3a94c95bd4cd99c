// Images in memory and on disk: 8-bit PNG (stb), OpenEXR (linear floats) and NumPy .npy (raw
// buffers).
// Row 0 is the top row everywhere in stsv.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

/// Interleaved 8-bit image, `channels` values per pixel, rows top to bottom.
struct Image8 {
    int width = 0;
    int height = 0;
    int channels = 4;
    std::vector<std::uint8_t> pixels;

    std::uint8_t& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
    std::uint8_t at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
};

/// Interleaved float image (linear values), rows top to bottom.
struct ImageF {
    int width = 0;
    int height = 0;
    int channels = 3;
    std::vector<float> pixels;

    ImageF() = default;
    ImageF(int w, int h, int c) : width(w), height(h), channels(c), pixels(std::size_t(w) * h * c, 0.0f) {}
    float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
};

/// The largest image side stsv reads (Vulkan's common maxImageDimension2D).
constexpr int MAX_IMAGE_SIDE = 16384;

/// Bytes a pixel costs at the peak of decoding an image to RGBA8 and handing it on as a Texture
/// (stb's buffers, the Image8, the caller's Texture), the encoded file's bytes not included.
/// Measured with /usr/bin/time -v (maximum resident set size) on 8192x8192 images, a program
/// reading the file, decoding it with stb, copying stb's pixels to an Image8 and that to a
/// Texture, less the same run on a 16x16 image (2026-12, Debian 12's libstb):
/// 8-bit PNG 7.97-8.05 bytes a pixel whatever the colour type (stb's inflated rows and its
/// pixels, then its RGBA and the Image8), Adam7-interlaced 10.09 (a pass's pixels besides);
/// 16-bit PNG 16.09, interlaced 20.18 (stb inflates and decodes 16 bits, then converts);
/// JPEG 8.3-8.7 baseline and 4:2:0 progressive, 13.2 progressive 4:4:4 (its coefficients).
constexpr double PNG8_PEAK_BYTES_PER_PIXEL = 8.0;
constexpr double PNG8_INTERLACED_PEAK_BYTES_PER_PIXEL = 10.0;
constexpr double PNG16_PEAK_BYTES_PER_PIXEL = 16.0;
constexpr double PNG16_INTERLACED_PEAK_BYTES_PER_PIXEL = 20.0;
constexpr double JPEG_PEAK_BYTES_PER_PIXEL = 14.0;

/// What an encoded image's header says, read without decoding its pixels.
struct ImageHeader {
    int width = 0;
    int height = 0;
    bool jpeg = false;       ///< a JPEG, else a PNG
    bool sixteenBit = false; ///< a PNG of 16 bits a channel
    bool interlaced = false; ///< an Adam7-interlaced PNG

    /// Bytes decodeImageRgba holds at its peak for this image from `fileBytes` encoded bytes:
    /// the file's bytes plus the measured bytes a pixel above.
    double peakBytes(std::size_t fileBytes) const;
    /// "image of 4096x4096 pixels": how messages name the size.
    std::string sizeText() const;
};

/// Reads the header of a PNG (or, when `allowJpeg`, a JPEG) held in memory. InputError naming
/// `name` when the bytes are neither (stb's other decoders are never reached: Debian's stb has
/// faults in some of them), the header is corrupt, or a side is 0 or above MAX_IMAGE_SIDE.
ImageHeader readImageHeader(const std::string& name, const std::uint8_t* data, std::size_t size,
                            bool allowJpeg = false);

/// Decodes a PNG (or, when `allowJpeg`, a JPEG) held in memory to RGBA8: readImageHeader first,
/// then checkMemory (core/memory_budget.h) with the header's peakBytes plus `heldBytes` (what the
/// caller holds through the decode: the textures read before), naming `name`, its size and the
/// limit, and only then the decoder. InputError naming `name` when the pixel data is corrupt.
Image8 decodeImageRgba(const std::string& name, const std::uint8_t* data, std::size_t size,
                       bool allowJpeg = false, double heldBytes = 0.0);

/// Reads a PNG (any bit depth/colour type stb accepts) expanded to RGBA8 (decodeImageRgba).
/// Throws InputError naming the file when it is missing, not a regular file, not a readable image,
/// larger than MAX_IMAGE_SIDE a side, and UsageError when it is too large for the memory limit.
Image8 readPngRgba(const std::string& path);

/// Writes an 8-bit PNG; throws Error naming the file when any part of the write fails.
void writePng(const std::string& path, const Image8& image);

/// Converts linear floats to 8 bits: optional sRGB encoding, clamped to [0, 1].
Image8 toImage8(const ImageF& image, bool srgb);

/// Writes a C-order NumPy array. `dtype` is a NumPy descriptor such as "|u1", "<u2", "<f4";
/// `bytes` must hold product(shape) elements of that type.
void writeNpy(const std::string& path, const std::string& dtype, const std::vector<std::size_t>& shape,
              const void* bytes, std::size_t byteCount);

/// A float image as float32 .npy: [H, W] for one channel, [H, W, C] otherwise.
void writeNpy(const std::string& path, const ImageF& image);

/// Writes an OpenEXR file of linear values: 3 channels as R, G, B, 1 as Y; half floats when
/// `halfFloat`, else 32-bit floats. Error naming the file when encoding or the write fails.
void writeExr(const std::string& path, const ImageF& image, bool halfFloat);
/// IEEE 754 binary16 bits of v, rounded to nearest even (OpenEXR's half), and back.
std::uint16_t halfBits(float v);
float halfValue(std::uint16_t bits);
/// Reads an OpenEXR file's Y channel, or its R, G and B, as 32-bit floats; InputError naming the
/// file when it is not a readable EXR or has neither.
ImageF readExr(const std::string& path);

/// A NumPy array read back (used by tests and the compare tool).
struct NpyArray {
    std::string dtype;
    std::vector<std::size_t> shape;
    std::vector<std::uint8_t> bytes;
};
/// Reads a C-order .npy (versions 1 to 3); InputError naming the file when it is missing,
/// malformed, in Fortran order, of another dtype than little-endian integers and floats, or
/// holds other than the bytes its shape needs.
NpyArray readNpy(const std::string& path);
/// The same from the file's bytes (`path` only names it in errors).
NpyArray parseNpy(const std::string& path, const std::string& file);

} // namespace stsv
