// Every seed of the fuzz corpora and every input that ever crashed a loader (tests/fuzz/seeds,
// tests/fuzz/regressions), replayed through the fuzz targets in the normal test suite: each must
// be accepted or refused with stsv::Error, never crash or throw anything else.
#include "tests/fuzz/fuzz_targets.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace stsv::fuzz {
namespace {

namespace fs = std::filesystem;

std::size_t replay(const std::string& folder) {
    std::size_t count = 0;
    for (const std::string& target : targetNames()) {
        const fs::path dir = fs::path(STSV_SOURCE_DIR) / "tests" / "fuzz" / folder / target;
        if (!fs::is_directory(dir)) continue;
        for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
            if (!e.is_regular_file() || e.path().filename() == "README.md") continue;
            std::ifstream in(e.path(), std::ios::binary);
            const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            SCOPED_TRACE(target + ": " + e.path().string());
            EXPECT_NO_THROW(
                runTarget(target, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
            ++count;
        }
    }
    return count;
}

TEST(FuzzRegressions, EveryInputThatEverCrashedIsRefusedCleanly) {
    EXPECT_GE(replay("regressions"), 2u); // the corrupt PNG and the deeply nested JSON at least
}

TEST(FuzzSeeds, EverySeedLoadsOrIsRefusedCleanly) {
    EXPECT_GE(replay("seeds"), 5u); // one per target at least
}

} // namespace
} // namespace stsv::fuzz
