#include "shadowmaps/avsm.h"

#include <algorithm>

namespace stsv {

AvsmMap::AvsmMap(const ShadowMapView& v, uint nodes) : view(v), maxNodes(nodes) {
    const std::size_t texels = std::size_t(v.faces) * v.size * v.size;
    counts.assign(texels, 0u);
    depth.assign(texels * nodes, 0.0f);
    units.assign(texels * nodes, 0u);
    overflowed.assign(texels, 0u);
}

void AvsmMap::store(std::size_t index, const AvsmFunction& f) {
    counts[index] = f.count;
    overflowed[index] = std::uint8_t(f.overflowed);
    for (uint j = 0; j < f.count; ++j) {
        depth[index * maxNodes + j] = f.depth[j];
        units[index * maxNodes + j] = f.units[j];
    }
}

AvsmFunction buildAvsmTexel(const std::vector<AvsmSurface>& surfaces, uint maxNodes) {
    AvsmFunction f = avsmEmpty();
    for (const AvsmSurface& s : surfaces) avsmAppend(f, s.depth, s.units, maxNodes);
    return f;
}

AvsmStats avsmStats(const AvsmMap& map) {
    AvsmStats s;
    s.texels = map.counts.size();
    std::size_t nodes = 0;
    for (std::size_t i = 0; i < map.counts.size(); ++i) {
        const std::uint32_t n = map.counts[i];
        if (n == 0) continue;
        ++s.texelsWithNodes;
        nodes += n;
        s.maxNodes = std::max(s.maxNodes, n);
        s.overflowedTexels += map.overflowed[i];
    }
    s.meanNodes = s.texelsWithNodes ? double(nodes) / double(s.texelsWithNodes) : 0.0;
    return s;
}

} // namespace stsv
