#include "core/image.h"

#include "core/error.h"
#include "core/files.h"
#include "core/memory_budget.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <Imath/half.h>

#include <algorithm>
#include <cstring>
#include <exception>

namespace stsv {

std::uint16_t halfBits(float v) {
    return half(v).bits();
}

float halfValue(std::uint16_t bits) {
    half h;
    h.setBits(bits);
    return float(h);
}

namespace {

/// The file in memory, written out by writeFileBytes so that the write is checked to the end.
class MemoryOStream final : public Imf::OStream {
  public:
    MemoryOStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        const std::size_t end = m_pos + std::size_t(n);
        if (end > m_bytes.size()) m_bytes.resize(end);
        std::memcpy(m_bytes.data() + m_pos, c, std::size_t(n));
        m_pos = end;
    }
    uint64_t tellp() override { return m_pos; }
    void seekp(uint64_t pos) override { m_pos = std::size_t(pos); }
    const std::string& bytes() const { return m_bytes; }

  private:
    std::string m_bytes;
    std::size_t m_pos = 0;
};

/// A file's bytes for Imf::InputFile.
class MemoryIStream final : public Imf::IStream {
  public:
    explicit MemoryIStream(std::string bytes) : Imf::IStream("memory"), m_bytes(std::move(bytes)) {}
    bool read(char c[], int n) override {
        // A seek may have moved past the end (to any 64-bit offset a corrupt file names).
        if (n < 0 || m_pos > m_bytes.size() || std::size_t(n) > m_bytes.size() - m_pos)
            throw std::runtime_error("unexpected end of file");
        std::memcpy(c, m_bytes.data() + m_pos, std::size_t(n));
        m_pos += std::size_t(n);
        return m_pos < m_bytes.size();
    }
    uint64_t tellg() override { return m_pos; }
    void seekg(uint64_t pos) override { m_pos = std::size_t(pos); }

  private:
    std::string m_bytes;
    std::size_t m_pos = 0;
};

const char* const RGB_CHANNELS[] = {"R", "G", "B"};

} // namespace

void writeExr(const std::string& path, const ImageF& image, bool halfFloat) {
    if (image.channels != 1 && image.channels != 3)
        throw Error(path + ": an EXR is written from 1 (Y) or 3 (RGB) channels, not " +
                    std::to_string(image.channels));
    std::vector<half> halves;
    if (halfFloat) {
        halves.resize(image.pixels.size());
        std::transform(image.pixels.begin(), image.pixels.end(), halves.begin(),
                       [](float v) { return half(v); });
    }
    MemoryOStream stream;
    try {
        Imf::Header header(image.width, image.height);
        const Imf::PixelType type = halfFloat ? Imf::HALF : Imf::FLOAT;
        Imf::FrameBuffer frame;
        const std::size_t valueBytes = halfFloat ? sizeof(half) : sizeof(float);
        char* base = halfFloat ? reinterpret_cast<char*>(halves.data())
                               : reinterpret_cast<char*>(const_cast<float*>(image.pixels.data()));
        for (int c = 0; c < image.channels; ++c) {
            const char* name = image.channels == 1 ? "Y" : RGB_CHANNELS[c];
            header.channels().insert(name, Imf::Channel(type));
            frame.insert(name,
                         Imf::Slice(type, base + std::size_t(c) * valueBytes,
                                    valueBytes * std::size_t(image.channels),
                                    valueBytes * std::size_t(image.channels) * std::size_t(image.width)));
        }
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        throw Error(path + ": cannot encode the EXR (" + e.what() + ")");
    }
    writeFileBytes(path, stream.bytes().data(), stream.bytes().size());
}

ImageF readExr(const std::string& path) {
    MemoryIStream stream(readFileBytes(path, "EXR file", std::size_t(1) << 32));
    try {
        Imf::InputFile file(stream);
        const Imath::Box2i window = file.header().dataWindow();
        const long width = long(window.max.x) - window.min.x + 1,
                   height = long(window.max.y) - window.min.y + 1;
        if (width < 1 || height < 1 || width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE)
            throw InputError(path, "EXR of " + std::to_string(width) + "x" + std::to_string(height) +
                                       " pixels (1 to " + std::to_string(MAX_IMAGE_SIDE) + " a side)");
        const Imf::ChannelList& channels = file.header().channels();
        std::vector<std::string> names;
        if (channels.findChannel("Y"))
            names = {"Y"};
        else if (channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B"))
            names = {"R", "G", "B"};
        else
            throw InputError(path, "EXR has neither a Y channel nor R, G and B");
        for (const std::string& name : names) {
            const Imf::Channel& channel = *channels.findChannel(name);
            if (channel.xSampling != 1 || channel.ySampling != 1)
                throw InputError(path, "EXR channel " + name + " is subsampled (" +
                                           std::to_string(channel.xSampling) + "x" +
                                           std::to_string(channel.ySampling) +
                                           "); only full-resolution channels are read");
        }
        checkMemory(path + ": EXR of " + std::to_string(width) + "x" + std::to_string(height) + " pixels",
                    double(width) * double(height) * double(names.size()) * sizeof(float));
        ImageF image(int(width), int(height), int(names.size()));
        Imf::FrameBuffer frame;
        // Slice::Make offsets the pointer by the data window's origin in integer arithmetic.
        const std::size_t xStride = sizeof(float) * names.size(), yStride = xStride * std::size_t(width);
        for (std::size_t c = 0; c < names.size(); ++c)
            frame.insert(names[c],
                         Imf::Slice::Make(Imf::FLOAT, image.pixels.data() + c, window, xStride, yStride));
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, std::string("not a readable EXR (") + e.what() + ")");
    }
}

} // namespace stsv
