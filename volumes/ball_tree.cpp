#include "volumes/ball_tree.h"

#include "volumes/light_hull_dh.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_invoke.h>

namespace stsv {

namespace {

std::uint32_t ballTreeNodes(std::uint32_t count) {
    return count <= BallTree::LEAF ? 1u : 1u + ballTreeNodes(count / 2) + ballTreeNodes(count - count / 2);
}

/// Node `index` over items [first, first + count): its children at `free` and free + 1, their
/// descendants after them, the first child's before the second's (a fixed layout, so that the
/// halves build in parallel).
void buildBallNode(BallTree& tree, const std::vector<vec4>& balls, std::uint32_t index, std::uint32_t first,
                   std::uint32_t count, std::uint32_t free) {
    BallTree::Node& node = tree.nodes[index];
    if (count <= BallTree::LEAF) {
        node.first = first;
        node.count = count;
        vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (std::uint32_t k = first; k < first + count; ++k) {
            const vec4 b = balls[tree.items[k]];
            lo = min(lo, vec3(b) - b.w);
            hi = max(hi, vec3(b) + b.w);
        }
        const vec3 centre = 0.5f * (lo + hi);
        float radius = 0.0f;
        for (std::uint32_t k = first; k < first + count; ++k) {
            const vec4 b = balls[tree.items[k]];
            radius = std::max(radius, length(vec3(b) - centre) + b.w);
        }
        node.ball = vec4(centre, radius * (1.0f + 1e-5f));
        return;
    }
    vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::uint32_t k = first; k < first + count; ++k) {
        lo = min(lo, vec3(balls[tree.items[k]]));
        hi = max(hi, vec3(balls[tree.items[k]]));
    }
    const vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::uint32_t half = count / 2;
    auto begin = tree.items.begin() + first;
    std::nth_element(begin, begin + half, begin + count, [&](std::uint32_t a, std::uint32_t b) {
        const float ka = balls[a][axis], kb = balls[b][axis];
        return ka < kb || (ka == kb && a < b);
    });
    node.first = free;
    node.count = 0;
    const std::uint32_t secondFree = free + 2 + ballTreeNodes(half) - 1;
    const auto left = [&] { buildBallNode(tree, balls, free, first, half, free + 2); };
    const auto right = [&] { buildBallNode(tree, balls, free + 1, first + half, count - half, secondFree); };
    if (count > 8192) {
        tbb::parallel_invoke(left, right);
    } else {
        left();
        right();
    }
    tree.nodes[index].ball = ballAround(tree.nodes[free].ball, tree.nodes[free + 1].ball);
}

} // namespace

BallTree buildBallTree(const std::vector<vec4>& balls) {
    BallTree tree;
    if (balls.empty()) return tree;
    const auto count = static_cast<std::uint32_t>(balls.size());
    tree.items.resize(count);
    for (std::uint32_t i = 0; i < count; ++i) tree.items[i] = i;
    tree.nodes.resize(ballTreeNodes(count));
    buildBallNode(tree, balls, 0, 0, count, 1);
    return tree;
}

} // namespace stsv
