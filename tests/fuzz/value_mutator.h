// A structure-aware mutation for the fuzz targets: values, not only bytes. libFuzzer's own
// mutations flip bits and splice inputs, which mostly breaks a file's syntax; the inputs that
// crash a renderer are valid files with one extreme value (a texture coordinate of 1e38, a count
// of 2^32). This mutation keeps the file valid and puts one such value in place of a number:
//  - text (JSON, OBJ, OFF, the JSON of a .gltf): a numeric token becomes an extreme token;
//  - binary glTF (.glb): a number of its JSON chunk likewise, the chunk and file lengths rewritten,
//    or a 4-byte word of its BIN chunk an extreme float or integer bit pattern;
//  - anything else: a 4-byte word an extreme bit pattern.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace stsv::fuzz {

/// The tokens a number may become: signed zeros, subnormals, float's extremes and just beyond
/// (1e39 parses to infinity as a float), 2^24 ± 1, 2^31, 2^32, 2^64, NaN and infinities in the
/// spellings parsers accept, and a few plain values that index or count.
const std::vector<std::string>& extremeNumberTokens();

/// The 32-bit patterns a binary word may become (floats: ±0, subnormals, FLT_MAX, ±inf, NaNs,
/// 1e38; integers: 0xffffffff, 2^31, 2^24 + 1).
const std::vector<std::uint32_t>& extremeWords();

/// The [begin, end) byte ranges of the numeric tokens of `text` (an optional sign, digits with
/// an optional fraction, an optional exponent), outside JSON strings when `json`.
std::vector<std::pair<std::size_t, std::size_t>> numberTokens(const std::string& text, bool json);

/// One value mutation of `input`, chosen by `seed` (deterministic): the input with one number or
/// word replaced as above; the input unchanged when it holds none.
std::string mutateValue(const std::string& input, std::uint32_t seed);

} // namespace stsv::fuzz
