#include "wedges/layer_bvh.h"

#include "core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace stsv {
namespace {

struct LayerBvh {
    const uvec4* nodes;
    const uvec4* triangles;
};
inline uvec4 layerBvhNode(LayerBvh bvh, uint texel) {
    return bvh.nodes[texel];
}
inline uvec4 layerBvhTriangle(LayerBvh bvh, uint texel) {
    return bvh.triangles[texel];
}

} // namespace
} // namespace stsv

#define LAYER_BVH
#include "wedges/layer_bvh_dh.h"

namespace stsv {

namespace {

struct Box {
    vec3 lo{std::numeric_limits<float>::max()};
    vec3 hi{-std::numeric_limits<float>::max()};

    void add(vec3 p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    void add(const Box& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
};

class Builder {
  public:
    Builder(const Scene& scene, LayerBvhTables& out) : m_scene(scene), m_out(out) {
        for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
            if (!scene.opaqueOccluder(t)) continue;
            const uvec3 tri = scene.triangles[t];
            Prim prim;
            for (int k = 0; k < 3; ++k) prim.box.add(scene.positions[tri[k]]);
            prim.center = 0.5f * (prim.box.lo + prim.box.hi);
            prim.triangle = static_cast<std::uint32_t>(t);
            m_prims.push_back(prim);
        }
        // The crossing test rounds the edge products of a segment from a point of the scene's
        // bounds by about 2^-21 of its distance to the triangle: every box grows by 2^-18 of the
        // scene's reach, so that a triangle whose test accepts a segment has a box it meets.
        const Bounds bounds = scene.bounds();
        const vec3 reach = max(abs(bounds.lo), abs(bounds.hi));
        m_margin = std::ldexp(std::max({reach.x, reach.y, reach.z}) + bounds.diameter(), -18);
        if (m_prims.size() >= (std::size_t(1) << 28))
            throw Error(scene.source + ": " + std::to_string(m_prims.size()) +
                        " opaque triangles, more than the layer count's tree addresses (2^28)");
    }

    void build() {
        if (m_prims.empty()) return;
        m_out.nodes.resize(LAYER_BVH_NODE_TEXELS);
        const auto n = static_cast<std::uint32_t>(m_prims.size());
        if (n <= LAYER_BVH_LEAF_MAX) {
            // A root with one leaf and an empty child.
            writeNode(0, {boxOf(0, n), leaf(0, n)}, {Box{}, LAYER_BVH_EMPTY});
            m_out.depth = 1;
            return;
        }
        m_out.depth = split(0, 0, n, 1);
    }

  private:
    struct Prim {
        Box box;
        vec3 center;
        std::uint32_t triangle;
    };
    struct Child {
        Box box;
        std::uint32_t ref;
    };

    Box boxOf(std::uint32_t first, std::uint32_t end) const {
        Box box;
        for (std::uint32_t i = first; i < end; ++i) box.add(m_prims[i].box);
        return box;
    }

    /// Leaf of prims [first, first + count): their triangles appended to the table.
    std::uint32_t leaf(std::uint32_t first, std::uint32_t count) {
        const auto at = static_cast<std::uint32_t>(m_out.triangles.size() / LAYER_BVH_TRIANGLE_TEXELS);
        for (std::uint32_t i = first; i < first + count; ++i) {
            const std::uint32_t t = m_prims[i].triangle;
            const uvec3 tri = m_scene.triangles[t];
            for (int k = 0; k < 3; ++k)
                m_out.triangles.push_back(uvec4(floatBitsToUint(m_scene.positions[tri[k]]), k == 0 ? t : 0u));
        }
        return LAYER_BVH_LEAF | (at << 3) | (count - 1);
    }

    /// Orders prims [first, end) so that the first half has the smaller centres along the
    /// longest axis of their centres' box (ties by triangle: deterministic); returns the middle.
    std::uint32_t median(std::uint32_t first, std::uint32_t end) {
        Box centers;
        for (std::uint32_t i = first; i < end; ++i) centers.add(m_prims[i].center);
        const vec3 extent = centers.hi - centers.lo;
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t mid = first + (end - first) / 2;
        std::nth_element(m_prims.begin() + first, m_prims.begin() + mid, m_prims.begin() + end,
                         [axis](const Prim& a, const Prim& b) {
                             return a.center[axis] != b.center[axis] ? a.center[axis] < b.center[axis]
                                                                     : a.triangle < b.triangle;
                         });
        return mid;
    }

    /// Node `node` over prims [first, end) (more than a leaf holds); returns the levels below
    /// and including it.
    std::uint32_t split(std::uint32_t node, std::uint32_t first, std::uint32_t end, std::uint32_t level) {
        if (level > LAYER_BVH_STACK)
            throw Error(m_scene.source + ": the layer count's tree is deeper than its traversal holds");
        const std::uint32_t mid = median(first, end);
        const std::uint32_t ranges[2][2] = {{first, mid}, {mid, end}};
        Child sides[2];
        std::uint32_t inner[2] = {0, 0};
        for (int s = 0; s < 2; ++s) {
            const std::uint32_t a = ranges[s][0], b = ranges[s][1];
            sides[s].box = boxOf(a, b);
            if (b - a <= LAYER_BVH_LEAF_MAX) {
                sides[s].ref = leaf(a, b - a);
            } else {
                inner[s] = allocate();
                sides[s].ref = inner[s];
            }
        }
        writeNode(node, sides[0], sides[1]);
        std::uint32_t depth = level;
        for (int s = 0; s < 2; ++s)
            if (inner[s] != 0)
                depth = std::max(depth, split(inner[s], ranges[s][0], ranges[s][1], level + 1));
        return depth;
    }

    std::uint32_t allocate() {
        const auto node = static_cast<std::uint32_t>(m_out.nodes.size() / LAYER_BVH_NODE_TEXELS);
        m_out.nodes.resize(m_out.nodes.size() + LAYER_BVH_NODE_TEXELS);
        return node;
    }

    Box grown(Box b) const {
        if (b.lo.x > b.hi.x) return b; // empty: stays empty
        b.lo -= vec3(m_margin);
        b.hi += vec3(m_margin);
        return b;
    }

    void writeNode(std::uint32_t node, const Child& c0, const Child& c1) {
        const Box b0 = grown(c0.box), b1 = grown(c1.box);
        const auto bits = [](float f) { return floatBitsToUint(f); };
        uvec4* texels = &m_out.nodes[LAYER_BVH_NODE_TEXELS * node];
        texels[0] = uvec4(bits(b0.lo.x), bits(b0.lo.y), bits(b0.lo.z), bits(b0.hi.x));
        texels[1] = uvec4(bits(b0.hi.y), bits(b0.hi.z), bits(b1.lo.x), bits(b1.lo.y));
        texels[2] = uvec4(bits(b1.lo.z), bits(b1.hi.x), bits(b1.hi.y), bits(b1.hi.z));
        texels[3] = uvec4(c0.ref, c1.ref, 0u, 0u);
    }

    const Scene& m_scene;
    LayerBvhTables& m_out;
    std::vector<Prim> m_prims; ///< the opaque triangles, in leaf order once built
    float m_margin = 0.0f;     ///< what every box grows by (world units)
};

} // namespace

LayerBvhTables buildLayerBvh(const Scene& scene) {
    LayerBvhTables tables;
    Builder(scene, tables).build();
    return tables;
}

std::uint32_t layerCount(const LayerBvhTables& tables, vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                         LayerCountWork& work, std::uint32_t maxVisits) {
    const LayerBvh bvh{tables.nodes.data(), tables.triangles.data()};
    return layerCount(bvh, tables.nodeCount(), p, r, tMin, ignore, maxVisits, work);
}

std::uint32_t layerCountGaps(const LayerBvhTables& tables, vec3 p, vec3 r, float tMin, std::uint32_t ignore,
                             const LayerGaps& gaps, LayerCountWork& work, bool& gapMet,
                             std::uint32_t maxVisits) {
    const LayerBvh bvh{tables.nodes.data(), tables.triangles.data()};
    return layerCountGaps(bvh, tables.nodeCount(), p, r, tMin, ignore, maxVisits, gaps, work, gapMet);
}

} // namespace stsv
