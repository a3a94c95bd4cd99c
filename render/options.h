// Every knob of a frame, declared once with its default (STYLE §8). Filled by the CLI and
// written into --stats so an output says how it was made.
#pragma once

#include "sampling/pattern.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace stsv {

enum class Method {
    Reference, ///< Embree shadow rays (CPU only)
    Stsv,      ///< every triangle through STSV
    Pw,        ///< opaque triangles through penumbra wedges (perforated ones ignored)
    Dcs,       ///< opaque triangles through depth complexity sampling (perforated ones ignored)
    PwStsv,    ///< pw for opaque, STSV for perforated triangles
    DcsStsv,   ///< dcs for opaque, STSV for perforated triangles
};

/// True for the methods that produce per-sample depth-complexity counters.
inline bool countsLayers(Method m) {
    return m == Method::Dcs || m == Method::DcsStsv;
}
/// True for the penumbra-wedge methods, whose visibility is a per-pixel coefficient.
inline bool wedgeCoverage(Method m) {
    return m == Method::Pw || m == Method::PwStsv;
}
enum class Backend { Cpu, Vulkan };
enum class BufferKind { Bitmask, Counters };

struct RenderOptions {
    Method method = Method::Stsv;
    Backend backend = Backend::Vulkan; ///< Vulkan renders STSV; the Embree reference always runs on the CPU
    int width = 512;                   ///< pixels, 1 … 16384
    int height = 512;                  ///< pixels, 1 … 16384
    int samples = 64;                  ///< light samples per pixel: 16, 32, 64, 128 or 256
    PatternKind pattern = PatternKind::Poisson;
    std::uint32_t seed = 1;  ///< sample patterns and per-pixel decorrelation
    int interleave = 1;      ///< K of K×K interleaved sampling (1 = off), 1 … 8
    bool decorrelate = true; ///< per-pixel rotation of the pattern
    BufferKind buffer =
        BufferKind::Bitmask; ///< light-sample buffer: occlusion bits or depth-complexity counters
    float ambient = 0.05f;   ///< ambient term, fraction of albedo
    std::string device;      ///< Vulkan device: "" = best, an index, or a name substring
    bool validation = false; ///< Vulkan validation layers (always on in tests)
};

Method parseMethod(const std::string& name);
Backend parseBackend(const std::string& name);
BufferKind parseBufferKind(const std::string& name);
std::string toString(Method method);
std::string toString(Backend backend);
std::string toString(BufferKind kind);

/// Throws UsageError naming the first option out of range.
void validate(const RenderOptions& options);

nlohmann::json toJson(const RenderOptions& options);

} // namespace stsv
