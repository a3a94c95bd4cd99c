#include "core/image.h"

#include "core/error.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

namespace stsv {

Image8 readPngRgba(const std::string& path) {
    int w = 0, h = 0, n = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 4), stbi_image_free);
    if (!data) {
        std::ifstream probe(path);
        if (!probe) throw InputError(path, "cannot open image file (missing or unreadable)");
        throw InputError(path, std::string("not a readable image: ") + stbi_failure_reason());
    }
    Image8 image;
    image.width = w;
    image.height = h;
    image.channels = 4;
    image.pixels.assign(data.get(), data.get() + std::size_t(w) * h * 4);
    return image;
}

void writePng(const std::string& path, const Image8& image) {
    if (!stbi_write_png(path.c_str(), image.width, image.height, image.channels, image.pixels.data(),
                        image.width * image.channels))
        throw Error(path + ": cannot write PNG");
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
    std::ofstream out(path, std::ios::binary);
    if (!out) throw Error(path + ": cannot open for writing");
    const char magic[] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
    out.write(magic, sizeof magic);
    const auto len = static_cast<std::uint16_t>(header.size());
    const char lenBytes[] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
    out.write(lenBytes, 2);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(static_cast<const char*>(bytes), static_cast<std::streamsize>(byteCount));
    if (!out) throw Error(path + ": write failed");
}

NpyArray readNpy(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot open .npy file");
    char magic[10];
    in.read(magic, 10);
    if (!in || std::memcmp(magic, "\x93NUMPY", 6) != 0 || magic[6] != 1)
        throw InputError(path, "not a version-1 .npy file");
    const std::size_t headerLen = std::uint8_t(magic[8]) | (std::size_t(std::uint8_t(magic[9])) << 8);
    std::string header(headerLen, '\0');
    in.read(header.data(), static_cast<std::streamsize>(headerLen));
    NpyArray array;
    auto descr = header.find("'descr': '");
    auto shape = header.find("'shape': (");
    if (!in || descr == std::string::npos || shape == std::string::npos)
        throw InputError(path, "malformed .npy header");
    descr += 10;
    array.dtype = header.substr(descr, header.find('\'', descr) - descr);
    std::istringstream dims(header.substr(shape + 10, header.find(')', shape) - shape - 10));
    std::string item;
    while (std::getline(dims, item, ','))
        if (item.find_first_not_of(' ') != std::string::npos) array.shape.push_back(std::stoull(item));
    array.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return array;
}

} // namespace stsv
