#include "shadowmaps/filtered_map.h"

#include "core/error.h"
#include "core/parallel.h"

#include <algorithm>
#include <cmath>

namespace stsv {

namespace {

/// ESM and EVSM always filter through float (ESM: log-space) mips: their exponentials span more
/// than the 32 fractional bits of a summed-area table (exp(40·(z − 1)) is below 2⁻³² for z < 0.45,
/// and EVSM's variance of such values vanishes; measured on fence: 0.136 RMSE against 0.012 with
/// mips).
bool mipOf(const ShadowMapSettings& s) {
    return s.mip != 0 || s.filter == ShadowFilter::Esm || s.filter == ShadowFilter::Evsm;
}

/// The channels of one normalised depth z, into out.
void channelsOf(const ShadowMapSettings& s, float z, float* out) {
    switch (s.filter) {
    case ShadowFilter::Vsm: {
        const vec2 m = vsmMoments(z);
        out[0] = m.x;
        out[1] = m.y;
        return;
    }
    case ShadowFilter::Esm:
        out[0] = s.esmC * z; // log of exp(c·z): the pyramid averages in log space
        return;
    case ShadowFilter::Evsm: {
        const vec4 m = evsmMoments(z, s.evsmPositive, s.evsmNegative);
        for (int i = 0; i < 4; ++i) out[i] = m[i];
        return;
    }
    case ShadowFilter::Msm: {
        const vec4 m = msmMoments(z);
        for (int i = 0; i < 4; ++i) out[i] = m[i];
        return;
    }
    case ShadowFilter::Csm:
        for (int k = 1; k <= s.csmTerms; ++k) {
            out[2 * (k - 1)] = std::cos(csmFrequency(k) * z);
            out[2 * (k - 1) + 1] = std::sin(csmFrequency(k) * z);
        }
        return;
    default:
        throw Error("internal error: a filtered representation of a percentage-closer filter");
    }
}

} // namespace

int filteredChannels(const ShadowMapSettings& s) {
    switch (s.filter) {
    case ShadowFilter::Vsm:
        return 2;
    case ShadowFilter::Esm:
        return 1;
    case ShadowFilter::Evsm:
    case ShadowFilter::Msm:
        return 4;
    case ShadowFilter::Csm:
        return 2 * s.csmTerms;
    default:
        return 0;
    }
}

std::size_t filteredMapBytes(const ShadowMapView& view, const ShadowMapSettings& s) {
    const std::size_t n = view.size, channels = std::size_t(filteredChannels(s)) * view.faces;
    if (mipOf(s)) return channels * (n * n * 4 / 3 + 1) * sizeof(float);
    return channels * (n + 1) * (n + 1) * sizeof(std::int64_t);
}

FilteredShadowMap::FilteredShadowMap(const ShadowMap& map, const ShadowMapSettings& settings)
    : m_view(map.view), m_settings(settings), m_channels(filteredChannels(settings)) {
    if (m_channels == 0) throw Error("internal error: a filtered shadow map of a percentage-closer filter");
    const int size = int(m_view.size);
    const std::size_t texels = std::size_t(size) * std::size_t(size);
    std::vector<float> channel(texels);
    std::vector<float> values(std::size_t(m_channels) * texels);
    for (uint face = 0; face < m_view.faces; ++face) {
        const float* depth = map.depth.data() + std::size_t(face) * texels;
        // Channel-major planes of the face: values[c · texels + i].
        parallelForChunks(texels, [&](std::size_t begin, std::size_t end) {
            float out[2 * CSM_MAX_TERMS];
            for (std::size_t i = begin; i < end; ++i) {
                channelsOf(m_settings, filteredDepth(m_view, depth[i]), out);
                for (int c = 0; c < m_channels; ++c) values[std::size_t(c) * texels + i] = out[c];
            }
        });
        for (int c = 0; c < m_channels; ++c) {
            const float* plane = values.data() + std::size_t(c) * texels;
            if (mipOf(m_settings))
                m_mip.push_back(buildMipPyramid(plane, size, m_settings.filter == ShadowFilter::Esm));
            else
                m_sat.push_back(buildSummedAreaTable(plane, size, size));
        }
    }
}

void FilteredShadowMap::average(const ShadowReceiver& r, float radius, float* out) const {
    const std::size_t first = std::size_t(r.face) * std::size_t(m_channels);
    if (!m_mip.empty()) {
        const float width = 2.0f * radius + 1.0f;
        for (int c = 0; c < m_channels; ++c)
            out[c] = m_mip[first + std::size_t(c)].trilinear(r.uv.x, r.uv.y, width);
        return;
    }
    const int size = int(m_view.size);
    const int tx = int(std::floor(r.uv.x * float(size))), ty = int(std::floor(r.uv.y * float(size)));
    const int k = int(std::lround(radius));
    // Texels outside a single face see nothing: they count as the far value (a cube map's
    // kernel is cut at its face's edge instead).
    const int x0 = tx - k, y0 = ty - k, x1 = tx + k + 1, y1 = ty + k + 1;
    const float area = float(x1 - x0) * float(y1 - y0);
    const float inside = float(std::max(0, std::min(x1, size) - std::max(x0, 0))) *
                         float(std::max(0, std::min(y1, size) - std::max(y0, 0)));
    const bool cube = m_view.projection == SHADOW_MAP_CUBE;
    float far[2 * CSM_MAX_TERMS];
    channelsOf(m_settings, 1.0f, far);
    for (int c = 0; c < m_channels; ++c) {
        const float mean = m_sat[first + std::size_t(c)].mean(x0, y0, x1, y1);
        out[c] = cube || inside == area ? mean : (mean * inside + far[c] * (area - inside)) / area;
    }
}

float FilteredShadowMap::visibility(const ShadowReceiver& r, float radius) const {
    if (r.valid == 0.0f) return 1.0f;
    // A receiver whose kernel lies wholly outside a single-face map: nothing there blocks.
    const int size = int(m_view.size);
    const float reach = (radius + 1.0f) / float(size);
    if (m_view.projection != SHADOW_MAP_CUBE &&
        (r.uv.x < -reach || r.uv.y < -reach || r.uv.x > 1.0f + reach || r.uv.y > 1.0f + reach))
        return 1.0f;
    float a[2 * CSM_MAX_TERMS];
    average(r, radius, a);
    const float t = filteredDepth(m_view, r.depth - r.bias);
    const ShadowMapSettings& s = m_settings;
    switch (s.filter) {
    case ShadowFilter::Vsm:
        return vsmVisibility(vec2(a[0], a[1]), t, s.minVariance, s.bleed);
    case ShadowFilter::Esm:
        return esmVisibility(a[0], s.esmC, t);
    case ShadowFilter::Evsm:
        return evsmVisibility(vec4(a[0], a[1], a[2], a[3]), t, s.evsmPositive, s.evsmNegative, s.minVariance,
                              s.bleed);
    case ShadowFilter::Msm:
        return msmVisibility(vec4(a[0], a[1], a[2], a[3]), t, s.msmBias);
    case ShadowFilter::Csm: {
        float series = 0.5f;
        for (int k = 1; k <= s.csmTerms; ++k)
            series += csmTerm(a[2 * (k - 1)], a[2 * (k - 1) + 1], t, k, s.csmTerms, s.csmDamp != 0);
        return csmVisibility(series);
    }
    default:
        return 1.0f;
    }
}

} // namespace stsv
