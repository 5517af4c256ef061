// Wrong loop closures: a pose graph of four laps around a square where 30 % of the loop
// closures are false (random places matched with confident information). Plain least
// squares is dragged away; dynamic covariance scaling on the loop closures must disown the
// false ones and keep the trajectory near the one optimized with the true loops only.
#include <asf/pose_graph.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <random>

#include "../incremental_se2.h"
#include "../sparse_se2.h"

namespace {

using asf::sparse_lm::Kernel;
using asf::sparse_lm::Options;
using asf::sparse_lm::RobustEdges;
using asf::sparse_lm::SparseSe2;
using mrpt::poses::CPose2D;

constexpr int kPerLap = 40, kLaps = 4;

/// Pose k of the true trajectory: laps around a 10 m x 10 m square, 1 m apart.
CPose2D truePose(int k) {
  const int i = k % kPerLap, side = i / 10, along = i % 10;
  const double c[4][2] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const double dx[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  return CPose2D(c[side][0] + along * dx[side][0], c[side][1] + along * dx[side][1],
                 side * M_PI / 2);
}

struct Scenario {
  asf::PoseGraph graph;
  std::vector<std::size_t> wrong;  ///< edge indices of the false loop closures
};

/// Odometry with noise, true loops between laps (every second pose), and false loops making
/// up `wrong_share` of all loops; initial poses by composing the odometry.
Scenario scenario(double wrong_share, std::uint64_t seed,
                  asf::EdgeKind cross_kind = asf::EdgeKind::LoopClosure) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  const double s_xy = 0.05, s_th = 0.01;  // odometry noise per 1 m step
  Eigen::Matrix3d odo_info =
      Eigen::Vector3d(1 / (s_xy * s_xy), 1 / (s_xy * s_xy), 1 / (s_th * s_th)).asDiagonal();
  Eigen::Matrix3d loop_info =
      Eigen::Vector3d(1 / 0.02 / 0.02, 1 / 0.02 / 0.02, 1 / 0.005 / 0.005).asDiagonal();
  Scenario sc;
  auto& g = sc.graph;
  const int n = kPerLap * kLaps;
  g.addNode(truePose(0));
  for (int k = 1; k < n; ++k) {
    const CPose2D d = truePose(k) - truePose(k - 1);
    const CPose2D z(d.x() + s_xy * n01(rng), d.y() + s_xy * n01(rng), d.phi() + s_th * n01(rng));
    g.addNode(g.nodes.back().pose + z);
    asf::PoseEdge e;
    e.from = k - 1;
    e.to = k;
    e.mean = z;
    e.information = odo_info;
    e.kind = asf::EdgeKind::Odometry;
    g.addEdge(e);
  }
  std::vector<asf::PoseEdge> loops;
  for (int k = kPerLap; k < n; k += 2) {  // the same place one lap earlier
    const CPose2D d = truePose(k) - truePose(k - kPerLap);
    asf::PoseEdge e;
    e.from = k - kPerLap;
    e.to = k;
    e.mean = CPose2D(d.x() + 0.02 * n01(rng), d.y() + 0.02 * n01(rng), d.phi() + 0.005 * n01(rng));
    e.information = loop_info;
    e.kind = cross_kind;
    loops.push_back(e);
  }
  const auto n_true = loops.size();
  const auto n_wrong =
      static_cast<std::size_t>(std::lround(wrong_share * n_true / (1 - wrong_share)));
  std::uniform_int_distribution<int> node(0, n - 1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t w = 0; w < n_wrong; ++w) {
    asf::PoseEdge e;
    do {
      e.from = node(rng);
      e.to = node(rng);
    } while (std::abs(static_cast<int>(e.from) - static_cast<int>(e.to)) < 5 ||
             truePose(e.from).distanceTo(truePose(e.to)) < 4);  // a different place
    e.mean = CPose2D(u(rng), u(rng), 0.3 * u(rng));             // "it looks like here"
    e.information = loop_info;
    e.kind = cross_kind;
    loops.push_back(e);
  }
  std::shuffle(loops.begin(), loops.end(), rng);
  for (const auto& e : loops) {
    const bool is_wrong = truePose(e.from).distanceTo(truePose(e.to)) >= 4;
    if (is_wrong) sc.wrong.push_back(g.edges.size());
    g.addEdge(e);
  }
  return sc;
}

/// RMS position error against the truth (node 0 is anchored at its true pose).
double rmsError(const asf::PoseGraph& g) {
  double s = 0;
  for (std::size_t k = 0; k < g.size(); ++k) {
    const CPose2D t = truePose(static_cast<int>(k));
    s += std::pow(g.nodes[k].pose.x() - t.x(), 2) + std::pow(g.nodes[k].pose.y() - t.y(), 2);
  }
  return std::sqrt(s / g.size());
}

asf::PoseGraph withoutWrong(const Scenario& sc) {
  asf::PoseGraph g = sc.graph;
  g.edges.clear();
  std::size_t w = 0;
  for (std::size_t k = 0; k < sc.graph.edges.size(); ++k) {
    if (w < sc.wrong.size() && sc.wrong[w] == k) {
      ++w;
      continue;
    }
    g.edges.push_back(sc.graph.edges[k]);
  }
  return g;
}

}  // namespace

struct Case {
  asf::EdgeKind kind;  ///< of the cross edges (true and false)
  RobustEdges edges;   ///< where the kernel goes
};

class SparseLmOutliers : public ::testing::TestWithParam<Case> {};

TEST_P(SparseLmOutliers, DcsDisownsThirtyPercentWrongCrossEdges) {
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scenario sc = scenario(0.3, seed, GetParam().kind);
    ASSERT_GT(sc.wrong.size(), 20u);
    Options plain;
    plain.lago_init = false;

    asf::PoseGraph ref = withoutWrong(sc);  // the oracle: true loops only
    SparseSe2().optimize(ref, plain);
    const double e_ref = rmsError(ref);
    EXPECT_LT(e_ref, 0.5);

    asf::PoseGraph ls = sc.graph;  // least squares believes every loop
    SparseSe2().optimize(ls, plain);
    const double e_ls = rmsError(ls);
    EXPECT_GT(e_ls, 1.0) << "the false loops must matter, or the test shows nothing";

    Options dcs = plain;
    dcs.kernel = Kernel::Dcs;
    dcs.robust_delta = 2.8;  // Phi = 7.84: the 95 % quantile of a 3-dof chi2
    dcs.robust_edges = GetParam().edges;
    asf::PoseGraph robust = sc.graph;
    SparseSe2().optimize(robust, dcs);
    const double e_dcs = rmsError(robust);
    // For the README: Agarwal et al.'s Phi = 1, from the same odometry start (not asserted).
    Options phi1 = dcs;
    phi1.robust_delta = 1;
    asf::PoseGraph small = sc.graph;
    SparseSe2().optimize(small, phi1);
    std::printf(
        "seed %d: least squares %.3f m, true links only %.3f m, DCS Phi 7.84 %.3f m, "
        "DCS Phi 1 %.3f m\n",
        static_cast<int>(seed), e_ls, e_ref, e_dcs, rmsError(small));
    EXPECT_LT(e_dcs, e_ref + 0.05) << "least squares " << e_ls << ", true loops only " << e_ref;
    // Every false loop is disowned: scaled to (almost) nothing; no true loop is.
    std::size_t w = 0;
    for (std::size_t k = 0; k < robust.edges.size(); ++k) {
      const auto& e = robust.edges[k];
      if (e.kind == asf::EdgeKind::Odometry) continue;
      const Eigen::Vector3d r = robust.edgeError(e);
      const double weight =
          asf::sparse_lm::robustWeight(Kernel::Dcs, 2.8, r.dot(e.information * r));
      if (w < sc.wrong.size() && sc.wrong[w] == k) {
        ++w;
        EXPECT_LT(weight, 1e-3) << "false loop " << e.from << "-" << e.to;
      } else {
        EXPECT_GT(weight, 0.5) << "true loop " << e.from << "-" << e.to;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    EdgeSelection, SparseLmOutliers,
    ::testing::Values(Case{asf::EdgeKind::LoopClosure, RobustEdges::LoopClosures},
                      Case{asf::EdgeKind::ScanMatch, RobustEdges::CrossLinks},
                      Case{asf::EdgeKind::LoopClosure, RobustEdges::All}),
    [](const ::testing::TestParamInfo<Case>& i) {
      return std::string(i.param.kind == asf::EdgeKind::LoopClosure ? "Loops" : "ScanMatches") +
             (i.param.edges == RobustEdges::LoopClosures ? "KernelOnLoops"
              : i.param.edges == RobustEdges::CrossLinks ? "KernelOnLinks"
                                                         : "KernelOnAll");
    });

/// RMS error of `g` optimized from its poses (no LAGO guess), plain or with DCS (delta 2.8)
/// on `edges`.
static double optimizedError(asf::PoseGraph g, std::optional<RobustEdges> edges) {
  Options o;
  o.lago_init = false;
  if (edges) {
    o.kernel = Kernel::Dcs;
    o.robust_delta = 2.8;
    o.robust_edges = *edges;
  }
  SparseSe2().optimize(g, o);
  return rmsError(g);
}

TEST(SparseLmOutliersSelection, KernelOnLoopsLeavesOtherKindsQuadratic) {
  // False nearby-keyframe matches (ScanMatch edges) are not loop closures: a kernel on the
  // loop closures alone leaves them believed, as plain least squares does.
  const Scenario sc = scenario(0.3, 1, asf::EdgeKind::ScanMatch);
  EXPECT_NEAR(optimizedError(sc.graph, RobustEdges::LoopClosures),
              optimizedError(sc.graph, std::nullopt), 1e-6);
}

TEST(SparseLmOutliersSelection, KernelOnEveryEdgeOfAGraphWithoutOutliers) {
  // robust_edges = all puts the kernel on the odometry chain as well; on a graph without
  // outliers (small odometry errors) it must not change the result.
  const Scenario sc = scenario(0.0, 4);
  ASSERT_TRUE(sc.wrong.empty());
  EXPECT_NEAR(optimizedError(sc.graph, RobustEdges::All), optimizedError(sc.graph, std::nullopt),
              1e-3);
}

/// The scenario's graph replayed as it grew: nodes in order, each placed by its odometry from
/// the estimate, each edge once both its ends exist; `solve` after every node.
template <typename Solve>
static asf::PoseGraph grown(const Scenario& sc, Solve solve) {
  std::vector<std::vector<std::size_t>> by_end(sc.graph.size());
  for (std::size_t k = 0; k < sc.graph.edges.size(); ++k)
    by_end[std::max(sc.graph.edges[k].from, sc.graph.edges[k].to)].push_back(k);
  asf::PoseGraph g;
  g.addNode(sc.graph.nodes[0].pose);
  for (std::size_t n = 1; n < sc.graph.size(); ++n) {
    g.addNode(g.nodes[n - 1].pose + sc.graph.edges[n - 1].mean);  // edge n-1: odometry n-1 -> n
    for (std::size_t k : by_end[n]) g.addEdge(sc.graph.edges[k]);
    solve(g);
  }
  return g;
}

TEST(SparseLmOutliersIncremental, WindowSolvesDisownFalseLoopsAsWholeSolvesDo) {
  // DCS in the incremental mode: the bound is of the reweighted Gauss-Newton model, so a
  // false loop's pull must still be disowned when it arrives in a window.
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scenario sc = scenario(0.3, seed);
    Options dcs;
    dcs.lago_init = false;
    dcs.kernel = Kernel::Dcs;
    dcs.robust_delta = 2.8;
    dcs.robust_edges = RobustEdges::LoopClosures;
    Options ls = dcs;
    ls.kernel = Kernel::None;
    SparseSe2 believer;
    const double e_ls = rmsError(grown(sc, [&](asf::PoseGraph& g) { believer.optimize(g, ls); }));
    EXPECT_GT(e_ls, 1.0) << "the false loops must matter, or the test shows nothing";
    SparseSe2 plain;
    const double e_plain = rmsError(grown(sc, [&](asf::PoseGraph& g) { plain.optimize(g, dcs); }));
    asf::sparse_lm::IncrementalSe2 inc;
    asf::sparse_lm::IncrementalOptions io;
    io.enabled = true;
    const double e_inc = rmsError(grown(sc, [&](asf::PoseGraph& g) {
      inc.optimize(g, dcs, io);
      inc.marginals(g, {}, dcs, io);
    }));
    std::printf(
        "seed %d: grown with DCS, whole solves %.3f m, incremental %.3f m (%ld window, %ld "
        "whole)\n",
        static_cast<int>(seed), e_plain, e_inc, inc.counters().window_solves,
        inc.counters().whole_solves);
    EXPECT_GT(inc.counters().window_solves, 20);
    EXPECT_LT(e_inc, e_plain + 0.05);
  }
}
