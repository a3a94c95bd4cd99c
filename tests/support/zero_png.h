// A large PNG in a small file, written without an encoder: side × side grey texels of 0, its
// zlib stream one fixed-Huffman block (RFC 1951 §3.2.6) of a literal 0 and copies of 258 bytes at
// distance 1. 4096² texels take 106 KB and decode to 64 MiB of RGBA; the memory tests of the
// image readers use it. With `inflatedBytes` the stream holds that many zeros instead of the
// side × (side + 1) bytes of the image's rows: a file whose data inflates past its header.
#pragma once

#include <cstdint>
#include <string>

namespace stsv::test {

inline std::string zeroPng(int side, std::uint64_t inflatedBytes = 0) {
    std::string stream = "\x78\x01"; // zlib: deflate, 32 KiB window, no dictionary
    std::uint32_t bits = 0;
    int count = 0;
    const auto put = [&](std::uint32_t value, int n) { // least significant bit first
        bits |= value << count;
        count += n;
        for (; count >= 8; count -= 8, bits >>= 8) stream += char(bits & 0xff);
    };
    const auto huffman = [&](std::uint32_t code, int n) { // Huffman codes go most significant bit first
        for (int i = n - 1; i >= 0; --i) put((code >> i) & 1, 1);
    };
    put(1, 1); // BFINAL
    put(1, 2); // BTYPE 01: fixed Huffman codes
    // Each row is its filter byte (0, none) and its texels: all zeros.
    const std::uint64_t raw =
        inflatedBytes > 0 ? inflatedBytes : std::uint64_t(side) * std::uint64_t(side + 1);
    huffman(0x30, 8); // literal 0
    std::uint64_t left = raw - 1;
    for (; left >= 258; left -= 258) {
        huffman(0xc5, 8); // length code 285: 258 bytes
        huffman(0, 5);    // distance code 0: 1 byte back
    }
    for (; left > 0; --left) huffman(0x30, 8);
    huffman(0, 7); // end of block
    if (count > 0) put(0, 8 - count);
    // Adler-32 of zeros: a stays 1, b adds it once a byte.
    const std::uint32_t adler = std::uint32_t(raw % 65521) << 16 | 1u;
    for (int shift = 24; shift >= 0; shift -= 8) stream += char((adler >> shift) & 0xff);

    const auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
    };
    const auto chunk = [&](const std::string& type, const std::string& data) {
        std::uint32_t crc = 0xffffffffu;
        for (char c : type + data) {
            crc ^= std::uint8_t(c);
            for (int k = 0; k < 8; ++k) crc = crc & 1 ? (crc >> 1) ^ 0xedb88320u : crc >> 1;
        }
        return be32(std::uint32_t(data.size())) + type + data + be32(~crc);
    };
    const std::string ihdr = be32(std::uint32_t(side)) + be32(std::uint32_t(side)) +
                             std::string("\x08\x00\x00\x00\x00", 5); // 8 bits, grey, no interlace
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", stream) +
           chunk("IEND", "");
}

} // namespace stsv::test
