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
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

namespace stsv {

Image8 readPngRgba(const std::string& path) {
    // A PNG is at most a few hundred MiB on disk; its declared size is checked before decoding.
    const std::string bytes = readFileBytes(path, "image file", std::size_t(1) << 30);
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = static_cast<int>(bytes.size());
    int w = 0, h = 0, n = 0;
    // Only PNG is read: stb would also try JPEG, BMP, GIF, PSD, PIC, PNM, HDR and TGA on anything
    // else, and Debian's stb has faults in some of those decoders (fuzzing crashed its PNM reader).
    // A PNG starting with the signature goes to stb's PNG decoder, which it tries first.
    if (bytes.size() < 8 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0)
        throw InputError(path, "not a PNG file (it lacks the PNG signature); textures must be PNG");
    if (bytes.size() < 24 || bytes.compare(12, 4, "IHDR") != 0)
        throw InputError(path, "not a readable PNG (no IHDR chunk after the signature)");
    // A PNG's size is read from its header first: stb refuses images over 1 GiB without saying why.
    {
        auto be32 = [&](std::size_t at) {
            return std::uint64_t(std::uint8_t(bytes[at])) << 24 |
                   std::uint64_t(std::uint8_t(bytes[at + 1])) << 16 |
                   std::uint64_t(std::uint8_t(bytes[at + 2])) << 8 |
                   std::uint64_t(std::uint8_t(bytes[at + 3]));
        };
        const std::uint64_t pw = be32(16), ph = be32(20);
        if (pw > std::uint64_t(MAX_IMAGE_SIDE) || ph > std::uint64_t(MAX_IMAGE_SIDE))
            throw InputError(path, "image of " + std::to_string(pw) + "x" + std::to_string(ph) +
                                       " pixels is larger than the " + std::to_string(MAX_IMAGE_SIDE) +
                                       " pixels a side accepted");
    }
    // stb's failure reason is not reset between calls (it may be null, or left over from a format
    // tried earlier), so the messages below do not quote it.
    if (!stbi_info_from_memory(data, length, &w, &h, &n))
        throw InputError(path, "not a readable PNG (its header is corrupt)");
    if (w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE)
        throw InputError(path, "image of " + std::to_string(w) + "x" + std::to_string(h) +
                                   " pixels is larger than the " + std::to_string(MAX_IMAGE_SIDE) +
                                   " pixels a side accepted");
    checkMemory(path + ": image of " + std::to_string(w) + "x" + std::to_string(h) + " pixels",
                4.0 * double(w) * double(h));
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_memory(data, length, &w, &h, &n, 4),
                                                     stbi_image_free);
    if (!pixels) throw InputError(path, "not a readable image (its header reads, its pixel data is corrupt)");
    Image8 image;
    image.width = w;
    image.height = h;
    image.channels = 4;
    image.pixels.assign(pixels.get(), pixels.get() + std::size_t(w) * h * 4);
    return image;
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
