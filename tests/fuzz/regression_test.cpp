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

/// The inputs kept under tests/fuzz/regressions; raise it with each one added.
constexpr std::size_t REGRESSION_INPUTS = 14;
/// The seeds under tests/fuzz/seeds, likewise.
constexpr std::size_t SEED_INPUTS = 10;

std::size_t replay(const std::string& folder) {
    std::size_t count = 0;
    for (const std::string& target : targetNames()) {
        const fs::path dir = fs::path(STSV_SOURCE_DIR) / "tests" / "fuzz" / folder / target;
        if (!fs::is_directory(dir)) {
            ADD_FAILURE() << "missing folder " << dir << " (each fuzz target keeps one, if only a README)";
            continue;
        }
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
    // Every file kept in tests/fuzz/regressions (README.md lists them): a lost file fails here.
    EXPECT_GE(replay("regressions"), REGRESSION_INPUTS);
}

TEST(FuzzSeeds, EverySeedLoadsOrIsRefusedCleanly) {
    EXPECT_GE(replay("seeds"), SEED_INPUTS);
}

} // namespace
} // namespace stsv::fuzz
