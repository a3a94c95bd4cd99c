// A tree of balls over occluders, which the STSV passes of both backends walk per region of
// receiver points.
#pragma once

#include "core/dh.h"

#include <cstdint>
#include <vector>

namespace stsv {

/// A binary tree over balls (centre, radius; world units): median splits of their centres along
/// the widest axis, leaves of BALL_TREE_LEAF at most, every node's ball holding its children's.
/// STSV's hierarchy over its triangles: a screen tile of the CPU pass (volumes/cpu/cpu_stsv.cpp)
/// or of the Vulkan walk (volumes/vulkan/gpu_stsv_clusters.h) walks it with the ball of its
/// visible points and keeps the leaves whose ball meets the segments from there to the light
/// (volumes/light_hull_dh.h).
struct BallTree {
    static constexpr std::uint32_t LEAF = 16;
    struct Node {
        vec4 ball;
        std::uint32_t first = 0; ///< leaf: into items; inner: its first child (the second follows)
        std::uint32_t count = 0; ///< leaf: items; inner: 0
    };
    std::vector<Node> nodes;          ///< nodes[0] is the root when there is any ball
    std::vector<std::uint32_t> items; ///< indices of the balls, leaf after leaf
};

BallTree buildBallTree(const std::vector<vec4>& balls);

} // namespace stsv
