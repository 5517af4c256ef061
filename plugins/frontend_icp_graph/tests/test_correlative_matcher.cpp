// The correlative scan matcher (correlative_matcher.h) against a brute-force oracle (every
// pose of the lattice scored), on a known pose far from the guess, and on the cue the loop
// verification takes from it: in a corridor of identical doors the best pose outside the peak
// scores as well as the peak, in a room it does not.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "../correlative_matcher.h"
#include "test_worlds.h"

namespace {

using asf::icp_graph::correlativeMatch;
using asf::icp_graph::CorrelativeOptions;
using asf::icp_graph::correlativeScore;
using asf::icp_graph::LikelihoodGrid;
using asf::icp_graph::Points2;

struct Cloud2 {
  std::vector<float> x, y;
  Points2 points() const { return {x, y}; }
};

/// The world's walls as points 2 cm apart.
Cloud2 sampled(const asf_test_worlds::World& w) {
  Cloud2 c;
  asf_test_worlds::sample(w, 0.02, c.x, c.y);
  return c;
}
Cloud2 room() { return sampled(asf_test_worlds::room()); }
Cloud2 corridor(double length) { return sampled(asf_test_worlds::doors(length)); }

/// The points of `world` within `range` of `pose`, in the frame of `pose`, with noise.
Cloud2 seenFrom(const Cloud2& world, const Eigen::Vector3d& pose, double range, double noise,
                unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, noise);
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  Cloud2 out;
  for (std::size_t i = 0; i < world.x.size(); i += 2) {
    const double dx = world.x[i] - pose.x(), dy = world.y[i] - pose.y();
    if (std::hypot(dx, dy) > range) continue;
    out.x.push_back(static_cast<float>(c * dx + s * dy + n(rng)));
    out.y.push_back(static_cast<float>(-s * dx + c * dy + n(rng)));
  }
  return out;
}

/// Best score over every pose of the lattice the matcher searches (outside the disc).
double bruteForce(const LikelihoodGrid& g, Points2 scan, const Eigen::Vector3d& guess,
                  const CorrelativeOptions& o, const Eigen::Vector2d& ex = {0, 0},
                  double ex_r = 0) {
  const int nk = static_cast<int>(std::ceil(o.window_phi / o.step_phi));
  const int w = static_cast<int>(std::ceil(o.window_xy / g.resolution()));
  double best = -1;
  for (int k = -nk; k <= nk; ++k)
    for (int dx = -w; dx <= w; ++dx)
      for (int dy = -w; dy <= w; ++dy) {
        const Eigen::Vector3d p(guess.x() + dx * g.resolution(), guess.y() + dy * g.resolution(),
                                guess.z() + k * o.step_phi);
        if (ex_r > 0 && (p.head<2>() - ex).norm() < ex_r) continue;
        best = std::max(best, correlativeScore(g, scan, p));
      }
  return best;
}

}  // namespace

TEST(CorrelativeMatcher, BranchAndBoundFindsTheExhaustiveOptimum) {
  const Cloud2 world = room();
  const Eigen::Vector3d truth(3.1, 2.2, 0.4);
  const Cloud2 scan = seenFrom(world, truth, 8, 0.01, 3);
  for (int levels : {1, 3, 5}) {
    const LikelihoodGrid g(world.points(), 0.0625, 0.05, levels, 0.5);
    CorrelativeOptions o;
    o.window_xy = 0.5;
    o.window_phi = 0.1;
    o.step_phi = 0.02;
    for (const Eigen::Vector3d& guess :
         {Eigen::Vector3d(3.0, 2.0, 0.35), Eigen::Vector3d(2.8, 2.5, 0.45)}) {
      SCOPED_TRACE(testing::Message() << "levels " << levels << ", guess " << guess.transpose());
      const auto r = correlativeMatch(g, scan.points(), guess, o);
      ASSERT_TRUE(r.found);
      EXPECT_NEAR(r.score, bruteForce(g, scan.points(), guess, o), 1e-9);
      EXPECT_NEAR(correlativeScore(g, scan.points(), r.pose), r.score, 1e-9);
      EXPECT_EQ(r.lattice, 11u * 17 * 17);
      if (levels == 5) {
        EXPECT_LT(r.scored, r.lattice / 4) << "branch and bound pruned little";
      }
      // The best pose outside a disc around the optimum: the oracle with the disc removed.
      const auto second = correlativeMatch(g, scan.points(), guess, o, r.pose.head<2>(), 0.2);
      ASSERT_TRUE(second.found);
      EXPECT_NEAR(second.score, bruteForce(g, scan.points(), guess, o, r.pose.head<2>(), 0.2),
                  1e-9);
      EXPECT_GE((second.pose.head<2>() - r.pose.head<2>()).norm(), 0.2);
      // One prepared search run twice, the second run first: the same two answers.
      const asf::icp_graph::CorrelativeSearch search(g, scan.points(), guess, o);
      const auto s2 = search.run(o.min_score, r.pose.head<2>(), 0.2);
      const auto s1 = search.run(o.min_score);
      EXPECT_EQ(s1.pose, r.pose);
      EXPECT_EQ(s1.score, r.score);
      EXPECT_EQ(s1.scored, r.scored);
      EXPECT_EQ(s2.pose, second.pose);
      EXPECT_EQ(s2.score, second.score);
    }
  }
}

TEST(CorrelativeMatcher, FindsTheTruePoseFarFromTheGuess) {
  const Cloud2 world = room();
  const LikelihoodGrid g(world.points(), 0.05, 0.05, 6, 1.0);
  const Eigen::Vector3d truth(2.7, 1.9, -0.6);
  const Cloud2 scan = seenFrom(world, truth, 10, 0.01, 5);
  CorrelativeOptions o;
  o.window_xy = 1.5;
  o.window_phi = 0.5;
  const Eigen::Vector3d guess = truth + Eigen::Vector3d(0.9, -1.1, 0.3);
  const auto r = correlativeMatch(g, scan.points(), guess, o);
  ASSERT_TRUE(r.found);
  EXPECT_LT((r.pose.head<2>() - truth.head<2>()).norm(), 0.05);
  EXPECT_LT(std::abs(r.pose.z() - truth.z()), 0.02);
  EXPECT_GT(r.score, 0.8);
  // Outside the window the truth cannot be found: a score well below.
  o.window_xy = 0.3;
  const auto off = correlativeMatch(g, scan.points(), guess, o);
  EXPECT_LT(off.score, 0.6 * r.score);
}

TEST(CorrelativeMatcher, RepeatedDoorsLeaveASecondPeakARoomDoesNot) {
  CorrelativeOptions o;
  o.window_xy = 4.0;
  o.window_phi = 0.2;
  auto ratio = [&](const Cloud2& world, const Eigen::Vector3d& truth) {
    const LikelihoodGrid g(world.points(), 0.05, 0.05, 7, 1.0);
    const Cloud2 scan = seenFrom(world, truth, 4, 0.01, 7);
    const auto best = correlativeMatch(g, scan.points(), truth, o);
    const auto second = correlativeMatch(g, scan.points(), truth, o, best.pose.head<2>(), 0.5);
    return second.score / best.score;
  };
  EXPECT_GT(ratio(corridor(30), {13.0, 1.0, 0.0}), 0.95);
  EXPECT_LT(ratio(room(), {3.0, 2.0, 0.2}), 0.8);
}

// A grid told to cover a box (so that a search's moved scan stays inside and is read without
// bounds tests) holds the same values at the same places, and a search in it gives the same
// answer to the bit, in the fast and the bounds-tested paths alike.
TEST(CorrelativeMatcher, ACoveredGridHasTheSameValuesAndAnswers) {
  const Cloud2 world = room();
  const Eigen::Vector3d truth(3.1, 2.2, 0.4);
  const Cloud2 scan = seenFrom(world, truth, 8, 0.01, 3);
  const std::array<double, 4> cover{-9.3, -7.1, 15.2, 12.9};
  for (int levels : {1, 4, 6}) {
    SCOPED_TRACE(testing::Message() << "levels " << levels);
    const LikelihoodGrid plain(world.points(), 0.05, 0.05, levels, 0.0);
    const LikelihoodGrid covered(world.points(), 0.05, 0.05, levels, 0.0, &cover);
    ASSERT_GT(covered.width(), plain.width() + 200);
    // The box is inside: its corners fall on cells of the grid.
    EXPECT_GE(covered.cellX(cover[0]), 0);
    EXPECT_GE(covered.cellY(cover[1]), 0);
    EXPECT_LT(covered.cellX(cover[2]), covered.width());
    EXPECT_LT(covered.cellY(cover[3]), covered.height());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> ux(-1, 8), uy(-1, 6);
    for (int n = 0; n < 2000; ++n) {
      const double x = ux(rng), y = uy(rng);
      for (int h = 0; h < levels; ++h)
        ASSERT_EQ(plain.at(h, plain.cellX(x), plain.cellY(y)),
                  covered.at(h, covered.cellX(x), covered.cellY(y)))
            << "at (" << x << ", " << y << "), level " << h;
    }
    CorrelativeOptions o;
    o.window_xy = 1.5;
    o.window_phi = 0.3;
    const Eigen::Vector3d guess = truth + Eigen::Vector3d(0.7, -0.5, 0.2);
    const auto a = correlativeMatch(plain, scan.points(), guess, o);
    const auto b = correlativeMatch(covered, scan.points(), guess, o);
    ASSERT_TRUE(a.found && b.found);
    EXPECT_EQ(a.pose, b.pose);
    EXPECT_EQ(a.score, b.score);
    EXPECT_EQ(a.scored, b.scored);
    if (levels == 6) {
      EXPECT_LT((b.pose.head<2>() - truth.head<2>()).norm(), 0.05);
    }
  }
}
