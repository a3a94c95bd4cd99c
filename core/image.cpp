#include "core/image.h"

#include "core/error.h"
#include "core/files.h"
#include "core/memory_budget.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

// Defined by Debian's libstb but declared only in stb_image_write.h's implementation part: the
// encoded PNG in memory (freed with free()), so that the file write can be checked to the end.
extern "C" unsigned char* stbi_write_png_to_mem(const unsigned char* pixels, int strideBytes, int x, int y,
                                                int n, int* outLength);

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

namespace stsv {

namespace {

constexpr char PNG_SIGNATURE[] = "\x89PNG\r\n\x1a\n";

std::uint32_t bigEndian32(const std::uint8_t* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
           std::uint32_t(p[3]);
}

std::string sidesText(std::uint64_t width, std::uint64_t height) {
    return std::to_string(width) + "x" + std::to_string(height) + " pixels";
}

/// The bytes a PNG's image data inflates to when it holds the rows its IHDR (at `ihdr`, the
/// chunk's data) declares: each row a filter byte and its packed samples (PNG §7.2), Adam7's seven
/// passes each their own rows (PNG §8.2).
std::uint64_t pngInflatedBytes(const std::uint8_t* ihdr) {
    const std::uint64_t width = bigEndian32(ihdr), height = bigEndian32(ihdr + 4), depth = ihdr[8];
    const std::uint64_t samples = ihdr[9] == 2 ? 3 : ihdr[9] == 4 ? 2 : ihdr[9] == 6 ? 4 : 1;
    const auto rows = [&](std::uint64_t w, std::uint64_t h) {
        return w == 0 ? 0 : h * (1 + (w * samples * depth + 7) / 8);
    };
    if (ihdr[12] != 1) return rows(width, height);
    static const int pass[7][4] = {{0, 0, 8, 8}, {4, 0, 8, 8}, {0, 4, 4, 8}, {2, 0, 4, 4},
                                   {0, 2, 2, 4}, {1, 0, 2, 2}, {0, 1, 1, 2}}; // x0, y0, dx, dy
    std::uint64_t bytes = 0;
    for (const auto& p : pass)
        bytes += rows((width + std::uint64_t(p[2] - p[0] - 1)) / std::uint64_t(p[2]),
                      (height + std::uint64_t(p[3] - p[1] - 1)) / std::uint64_t(p[3]));
    return bytes;
}

/// stb inflates a PNG's image data into a buffer it doubles as long as the data goes on, whatever
/// the header declares: a 300 KB file of 16x16 pixels took 299 MB (/usr/bin/time -v). A deflate
/// stream grows at most 1032-fold, so a file whose IDAT chunks could not go past the limit that
/// way is left alone; any other is inflated first into a buffer of the declared size, which stb's
/// zlib reader does not grow, and refused when its data does not fit.
void checkPngInflation(const std::string& name, const std::uint8_t* data, std::size_t size, double estimate) {
    std::string compressed;
    std::uint64_t idat = 0;
    for (std::size_t at = 8; at + 8 <= size;) {
        const std::uint64_t length = bigEndian32(data + at);
        // stb refuses a chunk that runs past the file's end, but only after it has grown its
        // buffer to the length declared (an IDAT of 2 GiB in a file of 500 bytes).
        if (length + 12 > size - at) {
            std::string type(reinterpret_cast<const char*>(data + at + 4), 4);
            for (char& c : type)
                if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';
            throw InputError(name, "not a readable PNG (its " + type + " chunk at byte " +
                                       std::to_string(at) + " declares " + std::to_string(length) +
                                       " bytes of data, past the file's end)");
        }
        if (std::memcmp(data + at + 4, "IDAT", 4) == 0) idat += length;
        if (std::memcmp(data + at + 4, "IEND", 4) == 0) break;
        at += 12 + std::size_t(length);
    }
    if (estimate + 2.0 * (1032.0 * double(idat) + 1024.0) <= double(memoryLimitBytes())) return;
    const std::uint64_t declared = pngInflatedBytes(data + 16);
    if (declared > std::uint64_t(std::numeric_limits<int>::max()))
        throw InputError(name, "image of " + sidesText(bigEndian32(data + 16), bigEndian32(data + 20)) +
                                   " holds more than the 2 GiB of samples stb decodes");
    compressed.reserve(std::size_t(idat));
    for (std::size_t at = 8; at + 12 <= size;) {
        const std::size_t length = bigEndian32(data + at);
        if (length > size - at - 12) break;
        if (std::memcmp(data + at + 4, "IDAT", 4) == 0)
            compressed.append(reinterpret_cast<const char*>(data + at + 8), length);
        at += 12 + length;
    }
    std::vector<char> inflated(static_cast<std::size_t>(declared));
    if (stbi_zlib_decode_buffer(inflated.data(), int(declared), compressed.data(), int(compressed.size())) <
        0)
        throw InputError(name, "not a readable PNG (its image data inflates past the " +
                                   std::to_string(declared) + " bytes its header declares, or is corrupt)");
}

} // namespace

double ImageHeader::peakBytes(std::size_t fileBytes) const {
    const double perPixel =
        jpeg         ? JPEG_PEAK_BYTES_PER_PIXEL
        : sixteenBit ? (interlaced ? PNG16_INTERLACED_PEAK_BYTES_PER_PIXEL : PNG16_PEAK_BYTES_PER_PIXEL)
                     : (interlaced ? PNG8_INTERLACED_PEAK_BYTES_PER_PIXEL : PNG8_PEAK_BYTES_PER_PIXEL);
    return double(fileBytes) + perPixel * double(width) * double(height);
}

std::string ImageHeader::sizeText() const {
    return "image of " + sidesText(std::uint64_t(width), std::uint64_t(height));
}

ImageHeader readImageHeader(const std::string& name, const std::uint8_t* data, std::size_t size,
                            bool allowJpeg) {
    ImageHeader header;
    // Only PNG (and JPEG where allowed) is read: stb would also try BMP, GIF, PSD, PIC, PNM, HDR
    // and TGA on anything else, and Debian's stb has faults in some of those decoders (fuzzing
    // crashed its PNM reader). A PNG starting with the signature goes to stb's PNG decoder, a JPEG
    // starting with SOI and a marker to its JPEG decoder, which stb tries first and second.
    const bool png = size >= 8 && std::memcmp(data, PNG_SIGNATURE, 8) == 0;
    header.jpeg = allowJpeg && size >= 3 && data[0] == 0xff && data[1] == 0xd8 && data[2] == 0xff;
    if (!png && !header.jpeg)
        throw InputError(name, allowJpeg
                                   ? "not a PNG or JPEG file (it lacks their signatures)"
                                   : "not a PNG file (it lacks the PNG signature); textures must be PNG");
    if (png) {
        // IHDR (PNG §11.2.2) follows the signature: width, height, bit depth, colour type,
        // compression, filter, interlace. The size is read here first: stb refuses images over
        // 1 GiB without saying why.
        if (size < 16 || std::memcmp(data + 12, "IHDR", 4) != 0)
            throw InputError(name, "not a readable PNG (no IHDR chunk after the signature)");
        if (size < 33) throw InputError(name, "not a readable PNG (it ends inside its IHDR chunk)");
        const std::uint64_t w = bigEndian32(data + 16), h = bigEndian32(data + 20);
        if (w > std::uint64_t(MAX_IMAGE_SIDE) || h > std::uint64_t(MAX_IMAGE_SIDE))
            throw InputError(name, "image of " + sidesText(w, h) + " is larger than the " +
                                       std::to_string(MAX_IMAGE_SIDE) + " pixels a side accepted");
        header.sixteenBit = data[24] == 16;
        header.interlaced = data[28] == 1;
    }
    // stb's failure reason is not reset between calls (it may be null, or left over from a format
    // tried earlier), so the messages below do not quote it.
    const int length =
        static_cast<int>(std::min<std::size_t>(size, std::size_t(std::numeric_limits<int>::max())));
    int w = 0, h = 0, n = 0;
    if (!stbi_info_from_memory(data, length, &w, &h, &n))
        throw InputError(name, std::string("not a readable ") + (png ? "PNG" : "JPEG") +
                                   " (its header is corrupt)");
    if (w <= 0 || h <= 0 || w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE)
        throw InputError(name, "image of " +
                                   sidesText(std::uint64_t(std::max(w, 0)), std::uint64_t(std::max(h, 0))) +
                                   " is empty or larger than the " + std::to_string(MAX_IMAGE_SIDE) +
                                   " pixels a side accepted");
    header.width = w;
    header.height = h;
    return header;
}

Image8 decodeImageRgba(const std::string& name, const std::uint8_t* data, std::size_t size, bool allowJpeg,
                       double heldBytes) {
    const ImageHeader header = readImageHeader(name, data, size, allowJpeg);
    if (size > std::size_t(std::numeric_limits<int>::max()))
        throw InputError(name, "image file of more than 2 GiB");
    checkMemory(name + ": " + header.sizeText() +
                    (heldBytes > 0.0 ? " (with the textures read before it)" : ""),
                heldBytes + header.peakBytes(size), "use a smaller image");
    if (!header.jpeg) checkPngInflation(name, data, size, heldBytes + header.peakBytes(size));
    int w = 0, h = 0, n = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(data, static_cast<int>(size), &w, &h, &n, 4), stbi_image_free);
    if (!pixels || w != header.width || h != header.height)
        throw InputError(name, "not a readable image (its header reads, its pixel data is corrupt)");
    Image8 image;
    image.width = w;
    image.height = h;
    image.channels = 4;
    image.pixels.assign(pixels.get(), pixels.get() + std::size_t(w) * std::size_t(h) * 4);
    return image;
}

Image8 readPngRgba(const std::string& path) {
    // A PNG is at most a few hundred MiB on disk; its declared size is checked before decoding.
    const std::string bytes = readFileBytes(path, "image file", std::size_t(1) << 30);
    return decodeImageRgba(path, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

void writePng(const std::string& path, const Image8& image) {
    int length = 0;
    std::unique_ptr<unsigned char, void (*)(void*)> png(
        stbi_write_png_to_mem(image.pixels.data(), image.width * image.channels, image.width, image.height,
                              image.channels, &length),
        std::free);
    if (!png) throw Error(path + ": cannot encode the PNG");
    writeFileBytes(path, png.get(), std::size_t(length));
}

static float linearToSrgb(float v) {
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

Image8 toImage8(const ImageF& image, bool srgb) {
    Image8 out;
    out.width = image.width;
    out.height = image.height;
    out.channels = image.channels;
    out.pixels.resize(image.pixels.size());
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        float v = std::clamp(image.pixels[i], 0.0f, 1.0f);
        if (std::isnan(image.pixels[i])) v = 0.0f;
        if (srgb) v = linearToSrgb(v);
        out.pixels[i] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
    }
    return out;
}

void writeNpy(const std::string& path, const std::string& dtype, const std::vector<std::size_t>& shape,
              const void* bytes, std::size_t byteCount) {
    std::ostringstream dict;
    dict << "{'descr': '" << dtype << "', 'fortran_order': False, 'shape': (";
    for (std::size_t i = 0; i < shape.size(); ++i)
        dict << shape[i] << (shape.size() == 1 || i + 1 < shape.size() ? ", " : "");
    dict << "), }";
    std::string header = dict.str();
    // Magic (6) + version (2) + header length (2) + header, padded with spaces to 64 bytes, ending in \n.
    std::size_t total = 10 + header.size() + 1;
    header.append((64 - total % 64) % 64, ' ');
    header.push_back('\n');
    const char magic[] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
    const auto len = static_cast<std::uint16_t>(header.size());
    const char lenBytes[] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
    std::string file(magic, sizeof magic);
    file.append(lenBytes, 2);
    file += header;
    file.append(static_cast<const char*>(bytes), byteCount);
    writeFileBytes(path, file.data(), file.size());
}

void writeNpy(const std::string& path, const ImageF& image) {
    std::vector<std::size_t> shape{std::size_t(image.height), std::size_t(image.width)};
    if (image.channels != 1) shape.push_back(std::size_t(image.channels));
    writeNpy(path, "<f4", shape, image.pixels.data(), image.pixels.size() * sizeof(float));
}

namespace {

/// The value of `key` in a .npy header dict ("{'descr': '<u2', 'fortran_order': False, ...}"),
/// as written: a quoted string, a word, or a parenthesised tuple.
std::string npyHeaderValue(const std::string& path, const std::string& header, const std::string& key) {
    const std::string quoted = "'" + key + "':";
    auto at = header.find(quoted);
    if (at == std::string::npos) throw InputError(path, "malformed .npy header: no '" + key + "'");
    at = header.find_first_not_of(' ', at + quoted.size());
    if (at == std::string::npos) throw InputError(path, "malformed .npy header: '" + key + "' has no value");
    const char open = header[at];
    const char close = open == '\'' ? '\'' : open == '(' ? ')' : '\0';
    if (close) {
        const auto end = header.find(close, at + 1);
        if (end == std::string::npos)
            throw InputError(path, "malformed .npy header: '" + key + "' is unterminated");
        return header.substr(at + 1, end - at - 1);
    }
    const auto end = header.find_first_of(",}", at);
    std::string word = header.substr(at, end == std::string::npos ? std::string::npos : end - at);
    while (!word.empty() && word.back() == ' ') word.pop_back();
    return word;
}

} // namespace

NpyArray parseNpy(const std::string& path, const std::string& file) {
    // Format: magic "\x93NUMPY", major and minor version, header length (2 bytes in version 1,
    // 4 in versions 2 and 3), an ASCII dict, then the C-order data.
    if (file.size() < 10 || std::memcmp(file.data(), "\x93NUMPY", 6) != 0)
        throw InputError(path, "not a .npy file (no \\x93NUMPY magic)");
    const auto major = std::uint8_t(file[6]);
    if (major < 1 || major > 3)
        throw InputError(path, ".npy version " + std::to_string(major) + " is not supported");
    const std::size_t lengthBytes = major == 1 ? 2 : 4;
    if (file.size() < 8 + lengthBytes) throw InputError(path, "truncated .npy header");
    std::size_t headerLen = 0;
    for (std::size_t b = 0; b < lengthBytes; ++b)
        headerLen |= std::size_t(std::uint8_t(file[8 + b])) << (8 * b);
    const std::size_t dataStart = 8 + lengthBytes + headerLen;
    if (headerLen > 65536 || file.size() < dataStart) throw InputError(path, "truncated .npy header");
    const std::string header = file.substr(8 + lengthBytes, headerLen);

    NpyArray array;
    array.dtype = npyHeaderValue(path, header, "descr");
    static const std::pair<const char*, std::size_t> known[] = {
        {"|u1", 1}, {"<u1", 1}, {"|i1", 1}, {"<u2", 2}, {"<i2", 2}, {"<u4", 4},
        {"<i4", 4}, {"<f2", 2}, {"<f4", 4}, {"<f8", 8}, {"|b1", 1}};
    std::size_t itemBytes = 0;
    for (const auto& [name, bytes] : known)
        if (array.dtype == name) itemBytes = bytes;
    if (itemBytes == 0)
        throw InputError(path,
                         "dtype '" + array.dtype + "' is not supported (little-endian integers or floats)");
    const std::string order = npyHeaderValue(path, header, "fortran_order");
    if (order == "True")
        throw InputError(path, "is in Fortran (column-major) order; save it in C order "
                               "(numpy.ascontiguousarray) to use it here");
    if (order != "False") throw InputError(path, "malformed .npy header: fortran_order is '" + order + "'");

    std::size_t count = 1;
    std::string dims = npyHeaderValue(path, header, "shape");
    std::size_t pos = 0;
    while (pos < dims.size()) {
        const auto end = dims.find(',', pos);
        std::string item = dims.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
        pos = end == std::string::npos ? dims.size() : end + 1;
        item.erase(0, item.find_first_not_of(' '));
        while (!item.empty() && item.back() == ' ') item.pop_back();
        if (item.empty()) continue;
        if (item.size() > 12 || item.find_first_not_of("0123456789") != std::string::npos)
            throw InputError(path, "malformed .npy shape (" + dims + ")");
        const std::size_t extent = std::stoull(item);
        array.shape.push_back(extent);
        count = extent == 0
                    ? 0
                    : (count > (std::size_t(1) << 40) / extent ? (std::size_t(1) << 41) : count * extent);
    }
    const std::size_t dataBytes = file.size() - dataStart;
    if (count > (std::size_t(1) << 40) || count * itemBytes != dataBytes)
        throw InputError(path, "holds " + std::to_string(dataBytes) + " bytes of data where its shape (" +
                                   dims + ") of " + array.dtype + " needs " +
                                   (count > (std::size_t(1) << 40) ? std::string("more than 2^40")
                                                                   : std::to_string(count * itemBytes)));
    array.bytes.assign(file.begin() + std::ptrdiff_t(dataStart), file.end());
    return array;
}

NpyArray readNpy(const std::string& path) {
    return parseNpy(path, readFileBytes(path, ".npy file", std::size_t(1) << 36));
}

} // namespace stsv
