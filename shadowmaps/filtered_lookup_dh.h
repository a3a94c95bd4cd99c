// The filtered representations' storage and lookup (DESIGN §4.6), as the CPU backend
// (shadowmaps/filtered_map.cpp) and the Vulkan shaders (shadowmaps/shaders/filtered_map.comp,
// shadow_filter.comp) both run them: per light, one plane per face and channel, each either a
// summed-area table of 64-bit fixed-point values ((size + 1)² sums, row 0 and column 0 zero) or a
// mip pyramid of floats (the levels one after another, ESM's in log space).
//
// Data access differs (storage buffers on the GPU, vectors on the CPU), so the includer defines,
// before including this header,
//   struct FilteredSource                                            what the planes are read from
//   FILTERED_SUM filteredSourceSum(FilteredSource s, uint plane, uint index)   a summed-area entry
//   float filteredSourceMip(FilteredSource s, uint plane, uint index)          a mip texel
// with FILTERED_SUM the 64-bit integer type (int64_t; in GLSL with
// GL_EXT_shader_explicit_arithmetic_types_int64), and the macro FILTERED_SOURCE; and includes
// shadowmaps/shadow_filter_dh.h (ShadowReceiver) first.
#ifndef STSV_SHADOWMAPS_FILTERED_LOOKUP_DH_H
#define STSV_SHADOWMAPS_FILTERED_LOOKUP_DH_H

#ifndef FILTERED_SOURCE
#error "define FilteredSource, filteredSourceSum and filteredSourceMip, then FILTERED_SOURCE"
#endif

#include "core/dh.h"
#include "shadowmaps/filtered_shadow_dh.h"
#include "shadowmaps/shadow_map_dh.h"

DH_BEGIN

/// Channel c alone of filteredChannelValues(p, z).
DH_FUNC float filteredChannelValue(ShadowFilterParams p, float z, uint c) {
    if (p.method == SHADOW_FILTER_CSM) {
        float phase = csmPhase(int(c / 2u) + 1, z);
        return (c & 1u) == 0u ? cos(phase) : sin(phase);
    }
    FilteredChannels all = filteredChannelValues(p, z);
    return all.v[c];
}

/// A value in [−1, 1] as the nearest multiple of 2⁻³², exactly, in 32-bit float arithmetic
/// (v·2¹⁶ is exact, so are its floor and the remainder's scaling by 2¹⁶; the remainder is then
/// rounded half to even): the same integer on every backend.
DH_FUNC FILTERED_SUM filteredFixed(float value) {
    float v = clamp(value, -1.0f, 1.0f) * 65536.0f;
    float high = floor(v);
    float low = (v - high) * 65536.0f;
    return FILTERED_SUM(high) * FILTERED_SUM(65536) + FILTERED_SUM(roundEven(low));
}

/// Texels per side of mip level `level` of a size² plane: ⌈size / 2^level⌉.
DH_FUNC uint filteredMipSize(uint size, uint level) {
    return ((size - 1u) >> level) + 1u;
}
DH_FUNC uint filteredMipLevels(uint size) {
    uint levels = 1u;
    while (filteredMipSize(size, levels - 1u) > 1u) levels += 1u;
    return levels;
}
/// Index of level `level`'s first texel within its plane.
DH_FUNC uint filteredMipOffset(uint size, uint level) {
    uint offset = 0u;
    for (uint l = 0u; l < level; ++l) {
        uint n = filteredMipSize(size, l);
        offset += n * n;
    }
    return offset;
}
/// Texels of one plane's pyramid, all levels.
DH_FUNC uint filteredMipPlaneTexels(uint size) {
    return filteredMipOffset(size, filteredMipLevels(size));
}

/// The weighted mean of four values, or of their exponentials in log space (esmLogSum4).
DH_FUNC float filteredBlend4(bool logSpace, vec4 values, vec4 weights) {
    return logSpace ? esmLogSum4(values, weights) : dot(values, weights);
}

/// Texel `texel` of level `level` (> 0): the mean of the 2 × 2 block of level − 1 under it (the
/// texels of the block that exist, at an odd size's last row and column).
DH_FUNC float filteredMipDownsample(FilteredSource s, uint plane, uint size, uint level, uvec2 texel,
                                    bool logSpace) {
    uint from = filteredMipSize(size, level - 1u);
    uint base = filteredMipOffset(size, level - 1u);
    vec4 block = vec4(0.0f);
    vec4 inside = vec4(0.0f);
    for (uint k = 0u; k < 4u; ++k) {
        uint x = 2u * texel.x + (k & 1u), y = 2u * texel.y + (k >> 1u);
        if (x >= from || y >= from) continue;
        block[int(k)] = filteredSourceMip(s, plane, base + y * from + x);
        inside[int(k)] = 1.0f;
    }
    return filteredBlend4(logSpace, block, inside / (inside.x + inside.y + inside.z + inside.w));
}

/// Bilinear lookup of level `level` at uv ∈ [0, 1]², edge clamped.
DH_FUNC float filteredMipBilinear(FilteredSource s, uint plane, uint size, uint level, vec2 uv,
                                  bool logSpace) {
    int n = int(filteredMipSize(size, level));
    uint base = filteredMipOffset(size, level);
    vec2 q = uv * float(n) - vec2(0.5f);
    vec2 f = floor(q);
    vec2 a = q - f;
    int x0 = clamp(int(f.x), 0, n - 1), x1 = clamp(int(f.x) + 1, 0, n - 1);
    int y0 = clamp(int(f.y), 0, n - 1), y1 = clamp(int(f.y) + 1, 0, n - 1);
    vec4 texels = vec4(filteredSourceMip(s, plane, base + uint(y0 * n + x0)),
                       filteredSourceMip(s, plane, base + uint(y0 * n + x1)),
                       filteredSourceMip(s, plane, base + uint(y1 * n + x0)),
                       filteredSourceMip(s, plane, base + uint(y1 * n + x1)));
    vec4 w = vec4((1.0f - a.x) * (1.0f - a.y), a.x * (1.0f - a.y), (1.0f - a.x) * a.y, a.x * a.y);
    return filteredBlend4(logSpace, texels, w);
}

/// Trilinear average over a square footprint `width` level-0 texels wide at uv: the two levels
/// whose texels bracket the width, blended by log₂ of the width.
DH_FUNC float filteredMipTrilinear(FilteredSource s, uint plane, uint size, vec2 uv, float width,
                                   bool logSpace) {
    float top = float(filteredMipLevels(size) - 1u);
    float lod = clamp(log2(max(width, 1.0f)), 0.0f, top);
    uint lo = uint(floor(lod));
    float f = lod - float(lo);
    float a = filteredMipBilinear(s, plane, size, lo, uv, logSpace);
    if (!(f > 0.0f)) return a;
    float b = filteredMipBilinear(s, plane, size, lo + 1u, uv, logSpace);
    return filteredBlend4(logSpace, vec4(a, b, 0.0f, 0.0f), vec4(1.0f - f, f, 0.0f, 0.0f));
}

/// Cells per axis of a filtered lookup's kernel at most (filteredVisibility): of a summed-area
/// table's box (exact means, four reads a channel each), and of a mip pyramid's (filteredBoxTaps:
/// a bilinear tap each, blurred by up to a cell beyond the box's edge, so more of them: 8 against
/// 4 halved ESM's error on the parallel planes' ramp, 0.023 to 0.012).
DH_CONST int FILTERED_KERNEL_CELLS = 4;
DH_CONST int FILTERED_MIP_TAPS = 8;

/// Where a mip pyramid is read for a square footprint `width` level-0 texels wide at uv: an
/// n × n grid of taps (n = ⌈width⌉, at most FILTERED_MIP_TAPS) at the centres of as many
/// equal cells of the square, `step` apart in uv from `first`, each a bilinear lookup of the
/// finest level whose texels are no wider than a cell, so each tap averages its cell and the grid
/// the square. (One trilinear lookup at the width's level instead blends blocks of up to twice
/// the width aligned to the level's grid: on parallel planes under a 0.6 m penumbra its ramp
/// spanned the whole 0.9 m view, VSM 0.10 visibility RMSE, 0.021 with these taps, 0.010
/// through the summed-area table.)
struct FilteredBoxTaps {
    vec2 first;
    float step;
    int n;
    uint level;
};

DH_FUNC FilteredBoxTaps filteredBoxTaps(uint size, vec2 uv, float width) {
    FilteredBoxTaps t;
    t.n = width > 1.0f ? min(int(ceil(width)), FILTERED_MIP_TAPS) : 1;
    float cell = max(width, 1.0f) / float(t.n);
    t.level = uint(clamp(floor(log2(cell)), 0.0f, float(filteredMipLevels(size) - 1u)));
    t.step = cell / float(size);
    t.first = uv - vec2(0.5f * float(t.n - 1) * t.step);
    return t;
}

/// The sum over texels [lo, hi) (within the plane) of a summed-area plane whose rows hold
/// `stride` = width + 1 sums.
DH_FUNC FILTERED_SUM filteredSatSum(FilteredSource s, uint plane, uint stride, ivec2 lo, ivec2 hi) {
    return filteredSourceSum(s, plane, uint(hi.y) * stride + uint(hi.x)) -
           filteredSourceSum(s, plane, uint(lo.y) * stride + uint(hi.x)) -
           filteredSourceSum(s, plane, uint(hi.y) * stride + uint(lo.x)) +
           filteredSourceSum(s, plane, uint(lo.y) * stride + uint(lo.x));
}

/// The channels' means over texels [lo, hi) of face `face` through its summed-area tables; texels
/// outside a single-face map count as the far value, a cube map's are left out (`weight` gets
/// the texels counted, 0 when none is).
DH_FUNC FilteredChannels filteredSatMeans(ShadowMapView v, ShadowFilterParams p, FilteredSource s, uint face,
                                          ivec2 lo, ivec2 hi, DH_OUT(float) weight) {
    FilteredChannels result;
    for (uint i = 0u; i < FILTERED_MAX_CHANNELS; ++i) result.v[i] = 0.0f;
    int size = int(v.size);
    ivec2 clo = clamp(lo, ivec2(0), ivec2(size)), chi = clamp(hi, ivec2(0), ivec2(size));
    float area = float(hi.x - lo.x) * float(hi.y - lo.y);
    float inside = float(max(chi.x - clo.x, 0)) * float(max(chi.y - clo.y, 0));
    bool pad = v.projection != SHADOW_MAP_CUBE;
    weight = pad ? area : inside;
    FilteredChannels far = filteredChannelValues(p, 1.0f);
    for (uint c = 0u; c < p.channels; ++c) {
        float sum = inside > 0.0f ? float(filteredSatSum(s, face * p.channels + c, v.size + 1u, clo, chi)) *
                                        (1.0f / 4294967296.0f)
                                  : 0.0f;
        if (pad) sum += far.v[c] * (area - inside);
        result.v[c] = weight > 0.0f ? sum / weight : far.v[c];
    }
    return result;
}

/// The normalised depth a cell of the kernel centred on face point uv compares with: the
/// receiver's tangent plane there (shadowMapPlaneDepthAt, as PCF's taps), less the bias.
DH_FUNC float filteredReceiverDepth(ShadowMapView v, ShadowReceiver r, vec2 uv) {
    return filteredDepth(v, shadowMapPlaneDepthAt(v, r.face, uv, r.p, r.n, r.depth) - r.bias);
}

/// The lookup's radius (texels either side of the receiver's texel) of a fixed kernel of
/// half-width `worldRadius` (world units) at the receiver: (2·radius + 1) texels span
/// 2·worldRadius there.
DH_FUNC float filteredFixedRadius(ShadowReceiver r, float worldRadius) {
    return max(shadowReceiverTexels(r, worldRadius) - 0.5f, 0.0f);
}

/// Lit fraction of a receiver through a filtered representation, over a kernel of `radius`
/// texels either side. The kernel is cut into cells (up to FILTERED_KERNEL_CELLS² of whole texels
/// of the summed-area table's (2·⌊radius + ½⌋ + 1)² box, or filteredBoxTaps of a mip pyramid); each
/// cell's means are compared with the receiver's plane at the cell's centre, and the lit
/// fractions averaged by area. The representations assume the receiver is the farthest depth
/// under its kernel; on a receiver seen at a slant from the light its own surface on the kernel's
/// far side is deeper than the centre, and one comparison at the centre lets it outweigh the
/// blockers (ESM's exp(c·(z − t)) by up to sinh(a)/a for a plane spanning ±a/c: on `fence` the
/// shadow body read 1.00 lit where the truth is 0.63; VSM's and EVSM's variance grows with
/// it). Per cell, that span is a quarter (an eighth through mips) of the kernel's.
DH_FUNC float filteredVisibility(ShadowMapView v, ShadowFilterParams p, FilteredSource s, ShadowReceiver r,
                                 float radius) {
    if (r.valid == 0.0f) return 1.0f;
    // A kernel wholly outside a single-face map: nothing there blocks.
    float reach = (radius + 1.0f) / float(v.size);
    if (v.projection != SHADOW_MAP_CUBE &&
        (r.uv.x < -reach || r.uv.y < -reach || r.uv.x > 1.0f + reach || r.uv.y > 1.0f + reach))
        return 1.0f;
    float lit = 0.0f, total = 0.0f;
    if (p.mip != 0u) {
        bool logSpace = p.method == SHADOW_FILTER_ESM;
        FilteredBoxTaps b = filteredBoxTaps(v.size, r.uv, 2.0f * radius + 1.0f);
        for (int j = 0; j < b.n; ++j)
            for (int i = 0; i < b.n; ++i) {
                vec2 uv = b.first + vec2(float(i), float(j)) * b.step;
                FilteredChannels a;
                for (uint c = 0u; c < FILTERED_MAX_CHANNELS; ++c)
                    a.v[c] = c < p.channels ? filteredMipBilinear(s, r.face * p.channels + c, v.size, b.level,
                                                                  uv, logSpace)
                                            : 0.0f;
                lit += filteredReconstruct(p, a, filteredReceiverDepth(v, r, uv));
                total += 1.0f;
            }
        return lit / total;
    }
    int size = int(v.size);
    int k = int(floor(radius + 0.5f)), side = 2 * k + 1;
    ivec2 lo = ivec2(floor(r.uv * float(size))) - ivec2(k);
    int n = min(side, FILTERED_KERNEL_CELLS);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            ivec2 clo = lo + ivec2(side * i / n, side * j / n);
            ivec2 chi = lo + ivec2(side * (i + 1) / n, side * (j + 1) / n);
            float weight;
            FilteredChannels a = filteredSatMeans(v, p, s, r.face, clo, chi, weight);
            if (!(weight > 0.0f)) continue;
            vec2 uv = vec2(clo + chi) * (0.5f / float(size));
            lit += weight * filteredReconstruct(p, a, filteredReceiverDepth(v, r, uv));
            total += weight;
        }
    return total > 0.0f ? lit / total : 1.0f;
}

DH_END

#endif // STSV_SHADOWMAPS_FILTERED_LOOKUP_DH_H
