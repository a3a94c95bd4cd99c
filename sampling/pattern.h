// Light-sample patterns on the unit square (DESIGN §4.1, STSV paper §4.1): uniform grid,
// stratified (jittered), Poisson disk (dart throwing), low-discrepancy (0,2)-sequence, and
// K×K interleaved sets (Keller & Heidrich 2001). Every point is a multiple of 2⁻²⁴, so it is
// exact in float and the per-pixel decorrelation (light_sampling_dh.h) is exact integer math.
#pragma once

#include "core/dh.h"
#include "sampling/light_sampling_dh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

enum class PatternKind { Uniform, Stratified, Poisson, LowDiscrepancy };

/// "uniform", "stratified", "poisson", "lowdisc"; UsageError otherwise.
PatternKind parsePatternKind(const std::string& name);
std::string toString(PatternKind kind);

/// Sample counts the patterns support (N of the paper).
bool isSupportedSampleCount(int count);

/// Grid of the uniform and stratified patterns: columns × rows = count. Square for 16, 64,
/// 256; 8×4 for 32 and 16×8 for 128 (columns along u, the first coordinate).
ivec2 patternGrid(int count);

/// Minimum distance of the Poisson pattern on the unit square (Euclidean, not toroidal).
/// 16 and 64 are the STSV paper's values (§4.1). The others keep the paper's packing density
/// φ = N·π(d/2)² / (1 + d)² (disk area over the square grown by d/2 on each side, which is
/// where the disk centres' half-disks live): φ(16) = 0.48859, φ(64) = 0.47492; 32 uses their
/// mean, 128 and 256 use φ(64) (boundary effects shrink with N, so the larger-N value is the
/// better bulk estimate). Random sequential addition saturates near φ ≈ 0.547, so these are
/// dense but reachable by dart throwing.
float poissonMinDistance(int count);

/// `count` points in [0,1)², deterministic for (kind, count, seed). UsageError for an
/// unsupported count. Point k of the set is sample k of the light-sample buffers.
std::vector<vec2> makePattern(PatternKind kind, int count, std::uint32_t seed);

/// The sample sets of a render: interleave² sets of `count` points, set-major.
struct SamplePlan {
    PatternKind kind = PatternKind::Stratified;
    int count = 0;
    int interleave = 1; ///< K of the K×K interleaved sets
    std::uint32_t seed = 0;
    bool decorrelate = true; ///< per-pixel Cranley–Patterson rotation (light_sampling_dh.h)
    int supersample = 1;     ///< K: sub-pixel (x, y) takes the samples of pixel (x/K, y/K)
    std::vector<vec2> points;

    int setCount() const { return interleave * interleave; }
    /// Keller & Heidrich: the set of pixel (x, y) (interleaveSet, as the shaders take it).
    int setIndex(int x, int y) const {
        return int(interleaveSet(uvec2(unsigned(x), unsigned(y)), unsigned(interleave)));
    }
    /// Pattern point k of (sub-)pixel (x, y), before decorrelation and domain mapping.
    vec2 patternPoint(int x, int y, int k) const {
        return points[std::size_t(setIndex(x / supersample, y / supersample)) * std::size_t(count) +
                      std::size_t(k)];
    }
};

/// K = interleave ∈ [1, 16]. With K = 1 the single set is makePattern(kind, count, seed).
/// With K > 1 the uniform sets are the K² sub-cell offsets of the grid (their union is the
/// regular K·cols × K·rows grid), the other kinds use K² seeds derived from `seed`.
SamplePlan makeSamplePlan(PatternKind kind, int count, std::uint32_t seed, int interleave = 1,
                          bool decorrelate = true);

} // namespace stsv
