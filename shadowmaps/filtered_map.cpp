#include "shadowmaps/filtered_map.h"

#include "core/error.h"
#include "core/parallel.h"
#include "shadowmaps/filtered_lookup.h"

namespace stsv {

std::size_t filteredMapBytes(const ShadowMapView& view, const ShadowMapSettings& s) {
    const std::size_t planes = std::size_t(filteredChannelCount(s)) * view.faces, n = view.size;
    if (filteredUsesMip(s)) return planes * filteredMipPlaneTexels(view.size) * sizeof(float);
    return planes * (n + 1) * (n + 1) * sizeof(std::int64_t);
}

FilteredShadowMap::FilteredShadowMap(const ShadowMap& map, const ShadowMapSettings& settings)
    : m_view(map.view), m_params(shadowFilterParams(settings)) {
    const uint channels = m_params.channels;
    if (channels == 0) throw Error("internal error: a filtered shadow map of a percentage-closer filter");
    const int size = int(m_view.size);
    const std::size_t texels = std::size_t(size) * std::size_t(size);
    std::vector<float> values(std::size_t(channels) * texels);
    for (uint face = 0; face < m_view.faces; ++face) {
        const float* depth = map.depth.data() + std::size_t(face) * texels;
        // Channel-major planes of the face: values[c · texels + i].
        parallelForChunks(texels, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const FilteredChannels c = filteredChannelValues(m_params, filteredDepth(m_view, depth[i]));
                for (uint k = 0; k < channels; ++k) values[std::size_t(k) * texels + i] = c.v[k];
            }
        });
        for (uint k = 0; k < channels; ++k) {
            const float* plane = values.data() + std::size_t(k) * texels;
            if (m_params.mip != 0)
                m_mip.push_back(buildMipPyramid(plane, size, m_params.method == SHADOW_FILTER_ESM));
            else
                m_sat.push_back(buildSummedAreaTable(plane, size, size));
        }
    }
}

float FilteredShadowMap::visibility(const ShadowReceiver& r, float radius) const {
    const FilteredSource source{m_sat.data(), m_mip.data()};
    return filteredVisibility(m_view, m_params, source, r, radius);
}

} // namespace stsv
