#include "sampling/pattern.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>

namespace stsv {

namespace {

constexpr std::uint32_t FIXED_ONE = 1u << 24; ///< 1.0 in the 24-bit fixed point of pattern points
constexpr float FIXED_TO_FLOAT = 1.0f / 16777216.0f;

vec2 fromFixed(std::uint32_t x, std::uint32_t y) {
    return vec2(float(x) * FIXED_TO_FLOAT, float(y) * FIXED_TO_FLOAT);
}

/// PCG32 (O'Neill 2014): a small, portable generator (std distributions are not portable).
class Pcg32 {
  public:
    Pcg32(std::uint64_t seed, std::uint64_t stream) : m_inc((stream << 1u) | 1u) {
        nextU32();
        m_state += seed;
        nextU32();
    }
    std::uint32_t nextU32() {
        const std::uint64_t old = m_state;
        m_state = old * 6364136223846793005ULL + m_inc;
        const auto xorShifted = std::uint32_t(((old >> 18u) ^ old) >> 27u);
        const auto rot = std::uint32_t(old >> 59u);
        return (xorShifted >> rot) | (xorShifted << ((32u - rot) & 31u));
    }
    /// Uniform in [0, bound) without modulo bias (bound ≥ 1).
    std::uint32_t bounded(std::uint32_t bound) {
        const std::uint32_t threshold = (0u - bound) % bound;
        for (;;) {
            const std::uint32_t r = nextU32();
            if (r >= threshold) return r % bound;
        }
    }

  private:
    std::uint64_t m_state = 0;
    std::uint64_t m_inc;
};

/// Hash of Jarzynski & Olano 2020 (PCG-based), the same as pcgHash in light_sampling_dh.h.
std::uint32_t hashU32(std::uint32_t v) {
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

std::uint32_t reverseBits(std::uint32_t x) {
    x = ((x >> 1u) & 0x55555555u) | ((x & 0x55555555u) << 1u);
    x = ((x >> 2u) & 0x33333333u) | ((x & 0x33333333u) << 2u);
    x = ((x >> 4u) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4u);
    x = ((x >> 8u) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8u);
    return (x >> 16u) | (x << 16u);
}

/// Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)), with the improved
/// Laine–Karras-style hash. Every step flips bit i of the bit-reversed value by a function of
/// the lower (i.e. more significant, once reversed back) bits only — the structure of a nested
/// uniform (Owen) scramble — so it permutes the dyadic intervals of every level and keeps the
/// (0,m,2)-net property exactly.
std::uint32_t owenScramble(std::uint32_t x, std::uint32_t seed) {
    x = reverseBits(x);
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return reverseBits(x);
}

/// Second dimension of Sobol' (generator matrix = Pascal matrix mod 2); with the van der
/// Corput radical inverse as the first dimension, the (0,2)-sequence in base 2.
std::uint32_t sobol2(std::uint32_t index) {
    std::uint32_t result = 0;
    for (std::uint32_t v = 1u << 31u; index != 0; index >>= 1u, v ^= v >> 1u)
        if (index & 1u) result ^= v;
    return result;
}

void checkCount(int count) {
    if (!isSupportedSampleCount(count))
        throw UsageError("sample count " + std::to_string(count) +
                         " is not supported (use 16, 32, 64, 128 or 256)");
}

/// Uniform grid with every point at the same offset inside its cell (in units of 2⁻²⁴).
std::vector<vec2> makeGrid(int count, std::uint32_t offsetX, std::uint32_t offsetY) {
    const ivec2 grid = patternGrid(count);
    const std::uint32_t cellW = FIXED_ONE / std::uint32_t(grid.x);
    const std::uint32_t cellH = FIXED_ONE / std::uint32_t(grid.y);
    std::vector<vec2> points;
    points.reserve(std::size_t(count));
    for (int j = 0; j < grid.y; ++j)
        for (int i = 0; i < grid.x; ++i)
            points.push_back(
                fromFixed(std::uint32_t(i) * cellW + offsetX, std::uint32_t(j) * cellH + offsetY));
    return points;
}

std::vector<vec2> makeStratified(int count, std::uint32_t seed) {
    const ivec2 grid = patternGrid(count);
    const std::uint32_t cellW = FIXED_ONE / std::uint32_t(grid.x);
    const std::uint32_t cellH = FIXED_ONE / std::uint32_t(grid.y);
    Pcg32 rng(seed, 0x5747u);
    std::vector<vec2> points;
    points.reserve(std::size_t(count));
    for (int j = 0; j < grid.y; ++j)
        for (int i = 0; i < grid.x; ++i) {
            const std::uint32_t x = std::uint32_t(i) * cellW + rng.bounded(cellW);
            const std::uint32_t y = std::uint32_t(j) * cellH + rng.bounded(cellH);
            points.push_back(fromFixed(x, y));
        }
    return points;
}

/// Dart throwing (Cook 1986) with a background grid of cells of side ≤ d/√2, so a cell holds
/// at most one point and a candidate checks the 5×5 cells around it. A set that jams (no
/// acceptance within the attempt budget) is restarted from the next RNG stream, so the
/// result stays a deterministic function of the seed.
std::vector<vec2> makePoisson(int count, std::uint32_t seed) {
    const double minDist = double(poissonMinDistance(count));
    const double minDist2 = minDist * minDist;
    const int gridSize = int(std::ceil(std::sqrt(2.0) / minDist));
    const std::size_t maxAttemptsPerPoint = 20000;
    for (std::uint64_t restart = 0; restart < 10000; ++restart) {
        Pcg32 rng(seed, 0x9015u + restart);
        std::vector<vec2> points;
        std::vector<int> cells(std::size_t(gridSize) * std::size_t(gridSize), -1);
        std::size_t attempts = 0;
        while (int(points.size()) < count && attempts < maxAttemptsPerPoint) {
            ++attempts;
            const vec2 c = fromFixed(rng.nextU32() >> 8u, rng.nextU32() >> 8u);
            const int cx = std::min(gridSize - 1, int(double(c.x) * gridSize));
            const int cy = std::min(gridSize - 1, int(double(c.y) * gridSize));
            bool ok = true;
            for (int y = std::max(0, cy - 2); ok && y <= std::min(gridSize - 1, cy + 2); ++y)
                for (int x = std::max(0, cx - 2); ok && x <= std::min(gridSize - 1, cx + 2); ++x) {
                    const int q = cells[std::size_t(y) * std::size_t(gridSize) + std::size_t(x)];
                    if (q < 0) continue;
                    const double dx = double(points[std::size_t(q)].x) - double(c.x);
                    const double dy = double(points[std::size_t(q)].y) - double(c.y);
                    if (dx * dx + dy * dy < minDist2) ok = false;
                }
            if (!ok) continue;
            cells[std::size_t(cy) * std::size_t(gridSize) + std::size_t(cx)] = int(points.size());
            points.push_back(c);
            attempts = 0;
        }
        if (int(points.size()) == count) return points;
    }
    throw Error("Poisson dart throwing jammed for " + std::to_string(count) + " samples, seed " +
                std::to_string(seed));
}

std::vector<vec2> makeLowDiscrepancy(int count, std::uint32_t seed) {
    const std::uint32_t seedX = hashU32(seed ^ 0x0b5c1d2eu);
    const std::uint32_t seedY = hashU32(seedX + 0x68e31da4u);
    std::vector<vec2> points;
    points.reserve(std::size_t(count));
    for (std::uint32_t i = 0; i < std::uint32_t(count); ++i) {
        const std::uint32_t x = owenScramble(reverseBits(i), seedX); // van der Corput
        const std::uint32_t y = owenScramble(sobol2(i), seedY);
        points.push_back(fromFixed(x >> 8u, y >> 8u));
    }
    return points;
}

} // namespace

PatternKind parsePatternKind(const std::string& name) {
    if (name == "uniform") return PatternKind::Uniform;
    if (name == "stratified") return PatternKind::Stratified;
    if (name == "poisson") return PatternKind::Poisson;
    if (name == "lowdisc") return PatternKind::LowDiscrepancy;
    throw UsageError("unknown sample pattern '" + name + "' (use uniform, stratified, poisson or lowdisc)");
}

std::string toString(PatternKind kind) {
    switch (kind) {
    case PatternKind::Uniform:
        return "uniform";
    case PatternKind::Stratified:
        return "stratified";
    case PatternKind::Poisson:
        return "poisson";
    case PatternKind::LowDiscrepancy:
        return "lowdisc";
    }
    return "unknown";
}

bool isSupportedSampleCount(int count) {
    return count == 16 || count == 32 || count == 64 || count == 128 || count == 256;
}

ivec2 patternGrid(int count) {
    checkCount(count);
    switch (count) {
    case 16:
        return {4, 4};
    case 32:
        return {8, 4};
    case 64:
        return {8, 8};
    case 128:
        return {16, 8};
    default:
        return {16, 16};
    }
}

float poissonMinDistance(int count) {
    checkCount(count);
    // d = 1 / (sqrt(N·π / (4φ)) − 1), the packing density of poissonMinDistance's comment.
    switch (count) {
    case 16:
        return 0.2456139f; // STSV paper §4.1 (φ = 0.488595)
    case 32:
        return 0.1606997f; // φ = (φ16 + φ64) / 2 = 0.481760
    case 64:
        return 0.1076681f; // STSV paper §4.1 (φ = 0.474925)
    case 128:
        return 0.0738054f; // φ = φ64
    default:
        return 0.0510840f; // 256, φ = φ64
    }
}

std::vector<vec2> makePattern(PatternKind kind, int count, std::uint32_t seed) {
    checkCount(count);
    switch (kind) {
    case PatternKind::Uniform: {
        const ivec2 grid = patternGrid(count);
        return makeGrid(count, FIXED_ONE / std::uint32_t(2 * grid.x), FIXED_ONE / std::uint32_t(2 * grid.y));
    }
    case PatternKind::Stratified:
        return makeStratified(count, seed);
    case PatternKind::Poisson:
        return makePoisson(count, seed);
    case PatternKind::LowDiscrepancy:
        return makeLowDiscrepancy(count, seed);
    }
    throw UsageError("unknown sample pattern kind");
}

SamplePlan makeSamplePlan(PatternKind kind, int count, std::uint32_t seed, int interleave, bool decorrelate) {
    checkCount(count);
    if (interleave < 1 || interleave > 16)
        throw UsageError("interleave " + std::to_string(interleave) + " is out of range (1 to 16)");
    SamplePlan plan;
    plan.kind = kind;
    plan.count = count;
    plan.interleave = interleave;
    plan.seed = seed;
    plan.decorrelate = decorrelate;
    if (interleave == 1) {
        plan.points = makePattern(kind, count, seed);
        return plan;
    }
    const ivec2 grid = patternGrid(count);
    const auto k = std::uint32_t(interleave);
    const std::uint32_t cellW = FIXED_ONE / std::uint32_t(grid.x);
    const std::uint32_t cellH = FIXED_ONE / std::uint32_t(grid.y);
    plan.points.reserve(std::size_t(count) * std::size_t(plan.setCount()));
    for (int set = 0; set < plan.setCount(); ++set) {
        std::vector<vec2> points;
        if (kind == PatternKind::Uniform) {
            // Keller & Heidrich's interleaved regular grids: set (sx, sy) sits at sub-cell
            // centre ((sx + ½)/K, (sy + ½)/K) of every cell.
            const auto sx = std::uint32_t(set % interleave);
            const auto sy = std::uint32_t(set / interleave);
            points =
                makeGrid(count, std::uint32_t((std::uint64_t(2 * sx + 1) * cellW) / (2 * std::uint64_t(k))),
                         std::uint32_t((std::uint64_t(2 * sy + 1) * cellH) / (2 * std::uint64_t(k))));
        } else {
            points = makePattern(kind, count, hashU32(seed + hashU32(std::uint32_t(set) + 0x1234567u)));
        }
        plan.points.insert(plan.points.end(), points.begin(), points.end());
    }
    return plan;
}

} // namespace stsv
