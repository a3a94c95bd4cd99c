// Sample patterns (DESIGN §4.1): determinism, exact grid positions, stratum occupancy,
// Poisson minimum distance, the exact (0,2)-net property, interleaved sets.
#include "core/error.h"
#include "sampling/light_sampling_dh.h"
#include "sampling/pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace stsv {
namespace {

const int COUNTS[] = {16, 32, 64, 128, 256};
const PatternKind KINDS[] = {PatternKind::Uniform, PatternKind::Stratified, PatternKind::Poisson,
                             PatternKind::LowDiscrepancy};

int log2i(int n) {
    int m = 0;
    while ((1 << m) < n) ++m;
    return m;
}

/// Identical points (no NaN can occur, so == is bit equality up to ±0, which patterns never hold).
bool sameBits(const std::vector<vec2>& a, const std::vector<vec2>& b) {
    return a == b;
}

bool sameSet(const SamplePlan& plan, int a, int b) {
    for (int k = 0; k < plan.count; ++k)
        if (plan.patternPoint(a % plan.interleave, a / plan.interleave, k) !=
            plan.patternPoint(b % plan.interleave, b / plan.interleave, k))
            return false;
    return true;
}

/// Every elementary interval [a/2^i, (a+1)/2^i) × [b/2^j, (b+1)/2^j), i + j = log2 N, holds
/// exactly one point. Returns "" or a description of the first failure.
std::string netViolation(const vec2* points, int n) {
    const int m = log2i(n);
    for (int i = 0; i <= m; ++i) {
        const int j = m - i;
        std::vector<int> counts(std::size_t(n), 0);
        for (int k = 0; k < n; ++k) {
            // Multiplying by a power of two is exact, so floor gives the exact interval.
            const int a = int(std::floor(points[k].x * float(1 << i)));
            const int b = int(std::floor(points[k].y * float(1 << j)));
            ++counts[std::size_t(b) * std::size_t(1 << i) + std::size_t(a)];
        }
        for (int c = 0; c < n; ++c)
            if (counts[std::size_t(c)] != 1)
                return "shape 2^-" + std::to_string(i) + " x 2^-" + std::to_string(j) + " interval " +
                       std::to_string(c) + " holds " + std::to_string(counts[std::size_t(c)]);
    }
    return "";
}

double minDistance(const vec2* points, int n) {
    double best = 1e9;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
            best = std::min(best, std::hypot(double(points[a].x) - double(points[b].x),
                                             double(points[a].y) - double(points[b].y)));
    return best;
}

TEST(Pattern, ParsesNamesAndRejectsOthers) {
    for (PatternKind kind : KINDS) EXPECT_EQ(parsePatternKind(toString(kind)), kind);
    EXPECT_EQ(parsePatternKind("lowdisc"), PatternKind::LowDiscrepancy);
    EXPECT_EQ(parsePatternKind("poisson"), PatternKind::Poisson);
    EXPECT_THROW(parsePatternKind("halton"), UsageError);
    EXPECT_THROW(parsePatternKind("Uniform"), UsageError);
    EXPECT_THROW(parsePatternKind(""), UsageError);
}

TEST(Pattern, RejectsUnsupportedCounts) {
    for (int n : {0, -16, 1, 8, 15, 48, 100, 512})
        for (PatternKind kind : KINDS) EXPECT_THROW(makePattern(kind, n, 1u), UsageError) << "n=" << n;
    EXPECT_THROW(poissonMinDistance(24), UsageError);
    EXPECT_THROW(makeSamplePlan(PatternKind::Stratified, 64, 1u, 0), UsageError);
    EXPECT_THROW(makeSamplePlan(PatternKind::Stratified, 64, 1u, 17), UsageError);
}

TEST(Pattern, DeterministicPerSeedAndInUnitSquareOnTheFixedPointGrid) {
    for (PatternKind kind : KINDS)
        for (int n : COUNTS) {
            const auto a = makePattern(kind, n, 12345u);
            const auto b = makePattern(kind, n, 12345u);
            const auto c = makePattern(kind, n, 12346u);
            ASSERT_EQ(int(a.size()), n);
            EXPECT_TRUE(sameBits(a, b)) << toString(kind) << " n=" << n;
            if (kind == PatternKind::Uniform)
                EXPECT_TRUE(sameBits(a, c)) << "the uniform grid does not depend on the seed";
            else
                EXPECT_FALSE(sameBits(a, c)) << toString(kind) << " n=" << n;
            for (const vec2 p : a) {
                ASSERT_TRUE(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f)
                    << toString(kind) << " n=" << n << " p=" << p.x << "," << p.y;
                // Multiples of 2^-24: what makes the decorrelation exact.
                const double sx = double(p.x) * 16777216.0;
                const double sy = double(p.y) * 16777216.0;
                ASSERT_EQ(sx, std::floor(sx)) << toString(kind) << " n=" << n;
                ASSERT_EQ(sy, std::floor(sy)) << toString(kind) << " n=" << n;
            }
        }
}

TEST(Pattern, UniformIsTheGridOfCellCentres) {
    const std::map<int, ivec2> grids = {
        {16, {4, 4}}, {32, {8, 4}}, {64, {8, 8}}, {128, {16, 8}}, {256, {16, 16}}};
    for (const auto& [n, grid] : grids) {
        EXPECT_EQ(patternGrid(n), grid) << "n=" << n;
        const auto points = makePattern(PatternKind::Uniform, n, 7u);
        for (int j = 0; j < grid.y; ++j)
            for (int i = 0; i < grid.x; ++i) {
                const int index = j * grid.x + i;
                const vec2 p = points[std::size_t(index)];
                EXPECT_EQ(p.x, (float(i) + 0.5f) / float(grid.x)) << "n=" << n << " i=" << i << " j=" << j;
                EXPECT_EQ(p.y, (float(j) + 0.5f) / float(grid.y)) << "n=" << n << " i=" << i << " j=" << j;
            }
    }
}

TEST(Pattern, StratifiedHasExactlyOnePointPerStratum) {
    for (int n : COUNTS) {
        const ivec2 grid = patternGrid(n);
        for (std::uint32_t seed = 0; seed < 8; ++seed) {
            const auto points = makePattern(PatternKind::Stratified, n, seed);
            std::vector<int> counts(std::size_t(n), 0);
            for (const vec2 p : points) {
                const int cell = int(p.y * float(grid.y)) * grid.x + int(p.x * float(grid.x));
                ++counts[std::size_t(cell)];
            }
            for (int c = 0; c < n; ++c)
                ASSERT_EQ(counts[std::size_t(c)], 1) << "n=" << n << " seed=" << seed << " cell=" << c;
        }
    }
}

TEST(Pattern, PoissonDistancesArePapersAndHoldForEverySeed) {
    // STSV paper §4.1.
    EXPECT_EQ(poissonMinDistance(16), 0.2456139f);
    EXPECT_EQ(poissonMinDistance(64), 0.1076681f);
    // The other counts keep the paper's boundary-corrected packing density
    // φ = N·π(d/2)²/(1+d)², between its values at 16 and 64 (within rounding of d to 7 digits).
    auto phi = [](int n) {
        const double d = double(poissonMinDistance(n));
        return double(n) * M_PI * d * d / 4.0 / ((1.0 + d) * (1.0 + d));
    };
    for (int n : {32, 128, 256}) {
        EXPECT_GE(phi(n), phi(64) - 1e-6) << "n=" << n;
        EXPECT_LE(phi(n), phi(16) + 1e-6) << "n=" << n;
    }
    for (int n : COUNTS)
        for (std::uint32_t seed : {0u, 1u, 2u, 3u, 42u, 0xdeadbeefu}) {
            const auto points = makePattern(PatternKind::Poisson, n, seed);
            ASSERT_EQ(int(points.size()), n);
            EXPECT_GE(minDistance(points.data(), n), double(poissonMinDistance(n)))
                << "n=" << n << " seed=" << seed;
        }
}

TEST(Pattern, LowDiscrepancyIsAZeroTwoNetForEverySeed) {
    for (int n : COUNTS)
        for (std::uint32_t seed : {0u, 1u, 2u, 3u, 99u, 0xffffffffu}) {
            const auto points = makePattern(PatternKind::LowDiscrepancy, n, seed);
            EXPECT_EQ(netViolation(points.data(), n), "") << "n=" << n << " seed=" << seed;
        }
    // The check can fail: a stratified pattern is not a (0,2)-net in general.
    const auto strat = makePattern(PatternKind::Stratified, 64, 5u);
    EXPECT_NE(netViolation(strat.data(), 64), "");
}

TEST(Pattern, InterleavedSetsDifferAndMapToPixels) {
    for (PatternKind kind : KINDS)
        for (int k : {2, 3, 4}) {
            const SamplePlan plan = makeSamplePlan(kind, 32, 77u, k);
            ASSERT_EQ(plan.setCount(), k * k);
            ASSERT_EQ(plan.points.size(), std::size_t(32 * k * k));
            for (int a = 0; a < k * k; ++a)
                for (int b = a + 1; b < k * k; ++b)
                    EXPECT_FALSE(sameSet(plan, a, b))
                        << toString(kind) << " K=" << k << " sets " << a << " and " << b << " are identical";
            // Keller & Heidrich: pixel (x, y) → set (y mod K)·K + (x mod K), same on both sides.
            for (int y = 0; y < 9; ++y)
                for (int x = 0; x < 9; ++x) {
                    const int expected = (y % k) * k + (x % k);
                    ASSERT_EQ(plan.setIndex(x, y), expected);
                    ASSERT_EQ(int(interleaveSet(uvec2(unsigned(x), unsigned(y)), unsigned(k))), expected);
                    ASSERT_EQ(plan.patternPoint(x, y, 5), plan.points[std::size_t(expected * 32 + 5)]);
                }
        }
    EXPECT_EQ(makeSamplePlan(PatternKind::Stratified, 64, 3u, 4).setIndex(5, 2), 9);
    // K = 1 is the plain pattern.
    for (PatternKind kind : KINDS)
        EXPECT_TRUE(sameBits(makeSamplePlan(kind, 64, 9u).points, makePattern(kind, 64, 9u)))
            << toString(kind);
}

TEST(Pattern, InterleavedSetsKeepTheirKindsProperty) {
    const int k = 3;
    for (int n : {16, 64}) {
        const SamplePlan strat = makeSamplePlan(PatternKind::Stratified, n, 5u, k);
        const SamplePlan poisson = makeSamplePlan(PatternKind::Poisson, n, 5u, k);
        const SamplePlan lowdisc = makeSamplePlan(PatternKind::LowDiscrepancy, n, 5u, k);
        const ivec2 grid = patternGrid(n);
        for (int s = 0; s < k * k; ++s) {
            const int first = s * n;
            const vec2* sp = &strat.points[std::size_t(first)];
            std::vector<int> counts(std::size_t(n), 0);
            for (int i = 0; i < n; ++i) {
                const int cell = int(sp[i].y * float(grid.y)) * grid.x + int(sp[i].x * float(grid.x));
                ++counts[std::size_t(cell)];
            }
            for (int c : counts) EXPECT_EQ(c, 1) << "stratified set " << s;
            EXPECT_GE(minDistance(&poisson.points[std::size_t(s * n)], n), double(poissonMinDistance(n)))
                << "set " << s;
            EXPECT_EQ(netViolation(&lowdisc.points[std::size_t(s * n)], n), "") << "set " << s;
        }
    }
    // Interleaved uniform sets tile the K·cols × K·rows grid: one point at every fine centre.
    for (int kk : {2, 4}) {
        const SamplePlan uni = makeSamplePlan(PatternKind::Uniform, 32, 0u, kk);
        const int cols = 8 * kk;
        const int rows = 4 * kk;
        std::vector<int> counts(std::size_t(cols * rows), 0);
        for (const vec2 p : uni.points) {
            const float fx = p.x * float(cols);
            const float fy = p.y * float(rows);
            EXPECT_EQ(fx - std::floor(fx), 0.5f) << "K=" << kk << " p=" << p.x << "," << p.y;
            EXPECT_EQ(fy - std::floor(fy), 0.5f) << "K=" << kk << " p=" << p.x << "," << p.y;
            const int cell = int(fy) * cols + int(fx);
            ++counts[std::size_t(cell)];
        }
        for (int c : counts) EXPECT_EQ(c, 1) << "K=" << kk;
    }
}

} // namespace
} // namespace stsv
