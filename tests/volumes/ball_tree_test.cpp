// The tree of balls the STSV passes walk (volumes/ball_tree.h): every ball once
// in leaves of at most LEAF, every node's ball holding its children's and its leaves' balls, so
// that a tile that drops a node (volumes/light_hull_dh.h is monotone in the ball) drops nothing
// a leaf below would have kept.
#include "volumes/ball_tree.h"
#include "volumes/light_hull_dh.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace stsv {
namespace {

bool holds(vec4 outer, vec4 inner) {
    // 1e-5 of the radius: the balls are grown by that much for rounding.
    return length(vec3(inner) - vec3(outer)) + inner.w <= outer.w * (1.0f + 1e-5f) + 1e-6f;
}

TEST(BallTree, EveryBallOnceInSmallLeavesAndEveryNodeHoldsWhatIsBelow) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f), r(0.0f, 0.5f);
    for (const std::size_t count : {0u, 1u, 16u, 17u, 1000u, 20000u}) {
        std::vector<vec4> balls;
        for (std::size_t i = 0; i < count; ++i) balls.emplace_back(u(rng), u(rng), 0.1f * u(rng), r(rng));
        const BallTree tree = buildBallTree(balls);
        if (count == 0) {
            EXPECT_TRUE(tree.nodes.empty());
            continue;
        }
        std::multiset<std::uint32_t> seen;
        std::size_t leaves = 0;
        for (std::size_t n = 0; n < tree.nodes.size(); ++n) {
            const BallTree::Node& node = tree.nodes[n];
            if (node.count == 0) {
                ASSERT_LT(node.first + 1, tree.nodes.size());
                EXPECT_TRUE(holds(node.ball, tree.nodes[node.first].ball)) << count << " node " << n;
                EXPECT_TRUE(holds(node.ball, tree.nodes[node.first + 1].ball)) << count << " node " << n;
                continue;
            }
            ++leaves;
            EXPECT_LE(node.count, BallTree::LEAF);
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
                seen.insert(tree.items[k]);
                EXPECT_TRUE(holds(node.ball, balls[tree.items[k]])) << count << " leaf " << n;
            }
        }
        EXPECT_EQ(seen.size(), count);
        EXPECT_EQ(std::set<std::uint32_t>(seen.begin(), seen.end()).size(), count);
        EXPECT_EQ(tree.nodes.size(), 2 * leaves - 1);
    }
}

TEST(BallTree, AWalkWithTheLightHullKeepsEveryBallThatMeetsIt) {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f), r(0.0f, 0.5f);
    std::vector<vec4> balls;
    for (int i = 0; i < 5000; ++i) balls.emplace_back(u(rng), u(rng), u(rng), r(rng));
    const BallTree tree = buildBallTree(balls);
    std::size_t kept = 0, walked = 0;
    for (int trial = 0; trial < 50; ++trial) {
        const LightHull hull = lightHull(vec4(u(rng), u(rng), u(rng), r(rng)), vec4(0.0f, 20.0f, 0.0f, 2.0f));
        std::set<std::uint32_t> reached;
        std::vector<std::uint32_t> stack{0u};
        while (!stack.empty()) {
            const BallTree::Node& node = tree.nodes[stack.back()];
            stack.pop_back();
            if (!ballMeetsLightHull(node.ball, hull)) continue;
            if (node.count > 0) {
                reached.insert(tree.items.begin() + node.first, tree.items.begin() + node.first + node.count);
            } else {
                stack.push_back(node.first);
                stack.push_back(node.first + 1);
            }
        }
        for (std::uint32_t i = 0; i < balls.size(); ++i)
            if (ballMeetsLightHull(balls[i], hull)) {
                ++kept;
                EXPECT_TRUE(reached.count(i))
                    << "trial " << trial << ": ball " << i << " lost on the way down";
            }
        walked += reached.size();
    }
    EXPECT_GT(kept, 100u);
    EXPECT_LT(walked, 50u * balls.size() / 4) << "the walk should reach a small part of the tree";
}

} // namespace
} // namespace stsv
