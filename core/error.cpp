#include "core/error.h"

#include <cstdio>

namespace stsv {

InputError::InputError(const std::string& file, std::size_t line, const std::string& problem)
    : Error(file + ":" + std::to_string(line) + ": " + problem), m_file(file), m_line(line) {}

InputError::InputError(const std::string& file, const std::string& problem)
    : Error(file + ": " + problem), m_file(file) {}

std::string printable(const std::string& text, std::size_t maxLength) {
    std::string out;
    auto escape = [&](unsigned char c) {
        char escaped[8];
        std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
        out += escaped;
    };
    std::size_t i = 0;
    while (i < text.size() && out.size() < maxLength) {
        const auto c = static_cast<unsigned char>(text[i]);
        // The length of a UTF-8 sequence from its lead byte (0: not a lead byte).
        const std::size_t length = c < 0x80           ? 1
                                   : (c >> 5) == 0x6  ? 2
                                   : (c >> 4) == 0xe  ? 3
                                   : (c >> 3) == 0x1e ? 4
                                                      : 0;
        bool valid = length > 0 && i + length <= text.size();
        for (std::size_t k = 1; valid && k < length; ++k)
            valid = (static_cast<unsigned char>(text[i + k]) & 0xc0) == 0x80;
        if (!valid || (length == 1 && (c < 0x20 || c == 0x7f))) {
            escape(c);
            ++i;
        } else {
            out.append(text, i, length);
            i += length;
        }
    }
    if (i < text.size()) out += "...";
    return out;
}

} // namespace stsv
