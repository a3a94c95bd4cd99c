#include "tests/fuzz/value_mutator.h"

#include <cctype>
#include <random>

namespace stsv::fuzz {

namespace {

bool isDigit(char c) {
    return c >= '0' && c <= '9';
}

std::uint32_t readLe32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | std::uint8_t(s[at + std::size_t(k)]);
    return v;
}

void writeLe32(std::string& s, std::size_t at, std::uint32_t v) {
    for (int k = 0; k < 4; ++k) s[at + std::size_t(k)] = char((v >> (8 * k)) & 0xffu);
}

std::string replaceToken(const std::string& text, bool json, std::mt19937& rng) {
    const auto tokens = numberTokens(text, json);
    if (tokens.empty()) return text;
    const auto [begin, end] = tokens[rng() % tokens.size()];
    const std::vector<std::string>& values = extremeNumberTokens();
    // Another token than the one there (the list holds more than one).
    std::size_t pick = rng() % values.size();
    if (text.compare(begin, end - begin, values[pick]) == 0) pick = (pick + 1) % values.size();
    return text.substr(0, begin) + values[pick] + text.substr(end);
}

std::string replaceWord(std::string bytes, std::size_t begin, std::size_t end, std::mt19937& rng) {
    if (end < begin + 4) return bytes;
    const std::size_t words = (end - begin) / 4;
    const std::vector<std::uint32_t>& values = extremeWords();
    writeLe32(bytes, begin + 4 * (rng() % words), values[rng() % values.size()]);
    return bytes;
}

/// A .glb: header (magic, version, length), then chunks (length, type, data padded to 4).
std::string mutateGlb(const std::string& input, std::mt19937& rng) {
    constexpr std::uint32_t kJson = 0x4e4f534au, kBin = 0x004e4942u;
    if (input.size() < 20) return replaceWord(input, 0, input.size(), rng);
    const std::uint32_t jsonLength = readLe32(input, 12);
    if (readLe32(input, 16) != kJson || jsonLength > input.size() - 20)
        return replaceWord(input, 0, input.size(), rng);
    const std::size_t binAt = 20 + std::size_t(jsonLength);
    const bool hasBin = input.size() >= binAt + 8 && readLe32(input, binAt + 4) == kBin &&
                        readLe32(input, binAt) <= input.size() - binAt - 8;
    if (hasBin && rng() % 2 == 0)
        return replaceWord(input, binAt + 8, binAt + 8 + readLe32(input, binAt), rng);
    std::string json = replaceToken(input.substr(20, jsonLength), true, rng);
    json.append((4 - json.size() % 4) % 4, ' ');
    std::string out = input.substr(0, 20) + json + input.substr(binAt);
    writeLe32(out, 8, std::uint32_t(out.size()));
    writeLe32(out, 12, std::uint32_t(json.size()));
    return out;
}

} // namespace

const std::vector<std::string>& extremeNumberTokens() {
    static const std::vector<std::string> tokens = {
        "0",
        "-0",
        "-0.0",
        "1",
        "-1",
        "0.5",
        "1e-45",
        "1.4e-45",
        "-1e-45",
        "1e-38",
        "1.17549435e-38",
        "3.4028235e38",
        "-3.4028235e38",
        "3.5e38",
        "1e38",
        "-1e38",
        "1e39",
        "-1e39",
        "1e308",
        "1e309",
        "16777216",
        "16777217",
        "-16777217",
        "2147483647",
        "2147483648",
        "-2147483649",
        "4294967295",
        "4294967296",
        "18446744073709551615",
        "18446744073709551616",
        "1e18",
        "nan",
        "NaN",
        "-nan",
        "inf",
        "-inf",
        "Infinity",
        "-Infinity",
        "1e9",
        "1000000001",
        "65536",
    };
    return tokens;
}

const std::vector<std::uint32_t>& extremeWords() {
    static const std::vector<std::uint32_t> words = {
        0x00000000u, 0x80000000u, 0x00000001u, 0x007fffffu, 0x7f7fffffu, 0xff7fffffu,
        0x7f800000u, 0xff800000u, 0x7fc00000u, 0xffc00000u, 0x7e967699u, 0xfe967699u,
        0xffffffffu, 0x7fffffffu, 0x01000001u, 0x4b800001u,
    };
    return words;
}

std::vector<std::pair<std::size_t, std::size_t>> numberTokens(const std::string& text, bool json) {
    std::vector<std::pair<std::size_t, std::size_t>> tokens;
    bool inString = false;
    std::size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (json && inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
            ++i;
            continue;
        }
        if (json && c == '"') {
            inString = true;
            ++i;
            continue;
        }
        // A number starts with a sign or a digit not glued to a name (v1, TEXCOORD_0, part_12):
        // such a name is skipped whole.
        const bool glued =
            i > 0 && (std::isalpha(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '_');
        if (glued && isDigit(c)) {
            while (i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_'))
                ++i;
            continue;
        }
        if (!glued &&
            (isDigit(c) || ((c == '-' || c == '+') && i + 1 < text.size() && isDigit(text[i + 1])))) {
            std::size_t end = i + 1;
            while (end < text.size() && isDigit(text[end])) ++end;
            if (end < text.size() && text[end] == '.') {
                ++end;
                while (end < text.size() && isDigit(text[end])) ++end;
            }
            if (end + 1 < text.size() && (text[end] == 'e' || text[end] == 'E')) {
                std::size_t exp = end + 1;
                if (text[exp] == '-' || text[exp] == '+') ++exp;
                if (exp < text.size() && isDigit(text[exp])) {
                    end = exp;
                    while (end < text.size() && isDigit(text[end])) ++end;
                }
            }
            tokens.emplace_back(i, end);
            i = end;
            continue;
        }
        ++i;
    }
    return tokens;
}

std::string mutateValue(const std::string& input, std::uint32_t seed) {
    std::mt19937 rng(seed);
    if (input.size() >= 4 && input.compare(0, 4, "glTF") == 0) return mutateGlb(input, rng);
    // Text: most bytes printable. Binary formats take a word.
    std::size_t printable = 0;
    for (char c : input) printable += (c >= 32 && c < 127) || c == '\n' || c == '\r' || c == '\t';
    if (!input.empty() && printable * 10 >= input.size() * 9) {
        const bool json = input.find_first_not_of(" \t\r\n") != std::string::npos &&
                          (input[input.find_first_not_of(" \t\r\n")] == '{' ||
                           input[input.find_first_not_of(" \t\r\n")] == '[');
        return replaceToken(input, json, rng);
    }
    return replaceWord(input, 0, input.size(), rng);
}

} // namespace stsv::fuzz
