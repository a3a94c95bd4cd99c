// The fuzzers' value mutation (tests/fuzz/value_mutator.h): it finds the numbers of a file and puts
// an extreme value in place of one, keeping the rest of the file as it was.
#include "tests/fuzz/value_mutator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace stsv::fuzz {
namespace {

TEST(ValueMutator, FindsTheNumbersOfTextOutsideJsonStrings) {
    const std::string json = R"({"uvRepeat": [16, -8.5e-3], "name": "v12 3", "TEXCOORD_0": 7})";
    std::vector<std::string> found;
    for (const auto& [b, e] : numberTokens(json, true)) found.push_back(json.substr(b, e - b));
    EXPECT_EQ(found, (std::vector<std::string>{"16", "-8.5e-3", "7"}));

    const std::string obj = "v 1 2.5 -3\nvt 0.25 1e2\nf 1/1 2/2 3/3\ng part_12\n";
    found.clear();
    for (const auto& [b, e] : numberTokens(obj, false)) found.push_back(obj.substr(b, e - b));
    EXPECT_EQ(found,
              (std::vector<std::string>{"1", "2.5", "-3", "0.25", "1e2", "1", "1", "2", "2", "3", "3"}));
}

TEST(ValueMutator, ReplacesOneNumberWithAnExtremeTokenAndKeepsTheRest) {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n";
    std::set<std::string> tokensSeen;
    for (std::uint32_t seed = 0; seed < 2000; ++seed) {
        const std::string out = mutateValue(obj, seed);
        // Exactly one token differs: the text before and after it is the input's.
        const auto before = numberTokens(obj, false);
        std::size_t prefix = 0;
        while (prefix < std::min(obj.size(), out.size()) && obj[prefix] == out[prefix]) ++prefix;
        const auto token = std::find_if(before.begin(), before.end(),
                                        [&](auto t) { return prefix >= t.first && prefix <= t.second; });
        ASSERT_NE(token, before.end()) << "seed " << seed << " changed text outside a number: " << out;
        const std::string tail = obj.substr(token->second);
        ASSERT_GE(out.size(), tail.size());
        ASSERT_EQ(out.substr(out.size() - tail.size()), tail) << "seed " << seed;
        const std::string put = out.substr(token->first, out.size() - tail.size() - token->first);
        ASSERT_NE(std::find(extremeNumberTokens().begin(), extremeNumberTokens().end(), put),
                  extremeNumberTokens().end())
            << "seed " << seed << " put '" << put << "'";
        tokensSeen.insert(put);
    }
    EXPECT_EQ(tokensSeen.size(), extremeNumberTokens().size()) << "every extreme token is reachable";
}

TEST(ValueMutator, KeepsABinaryGltfWellFormed) {
    // A .glb of a JSON chunk "{"a":[1,2]}" padded to 12 bytes and an 8-byte BIN chunk.
    auto le32 = [](std::uint32_t v) {
        std::string s(4, '\0');
        for (int k = 0; k < 4; ++k) s[std::size_t(k)] = char((v >> (8 * k)) & 0xffu);
        return s;
    };
    const std::string json = R"({"a":[1,2]} )";
    const std::string bin(8, '\x11');
    const std::string glb = "glTF" + le32(2) + le32(std::uint32_t(12 + 8 + json.size() + 8 + bin.size())) +
                            le32(std::uint32_t(json.size())) + "JSON" + json + le32(8) +
                            std::string("BIN\0", 4) + bin;
    std::size_t jsonChanged = 0, binChanged = 0;
    for (std::uint32_t seed = 0; seed < 400; ++seed) {
        const std::string out = mutateValue(glb, seed);
        auto read = [&](std::size_t at) {
            std::uint32_t v = 0;
            for (int k = 3; k >= 0; --k) v = v << 8 | std::uint8_t(out[at + std::size_t(k)]);
            return v;
        };
        ASSERT_EQ(read(8), out.size()) << "seed " << seed << ": the file length is rewritten";
        const std::uint32_t jsonLength = read(12);
        ASSERT_EQ(jsonLength % 4, 0u);
        ASSERT_EQ(out.substr(16, 4), "JSON");
        ASSERT_EQ(read(20 + jsonLength), 8u) << "seed " << seed << ": the BIN chunk follows intact";
        jsonChanged += out.substr(20, jsonLength) != json;
        binChanged += out.substr(out.size() - 8) != bin;
    }
    EXPECT_GT(jsonChanged, 100u);
    EXPECT_GT(binChanged, 100u);
}

} // namespace
} // namespace stsv::fuzz
