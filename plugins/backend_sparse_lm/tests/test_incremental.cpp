// Tests of sparse_lm's incremental mode (incremental_se2.h): the decrement bound against the
// dense Gauss-Newton decrement, the estimate's chi2 against a whole solve's at every step of
// a growing graph, propagated marginals against exact ones, and the fallbacks.
#include <asf/se2_edge.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>

#include "../incremental_se2.h"

namespace {

using asf::NodeId;
using asf::sparse_lm::IncrementalOptions;
using asf::sparse_lm::IncrementalSe2;
using asf::sparse_lm::Options;
using asf::sparse_lm::SparseSe2;
using mrpt::poses::CPose2D;

Options tight() {
  Options o;
  o.tolerance = 1e-12;
  return o;
}

/// A robot's growing pose graph: a random walk kept in a 6 m box, odometry edges, and an edge
/// to every older node within 1.5 m (every 4th node: like a front-end's loop and revisit
/// matches), with Gaussian noise of `noise` times the standard deviation their information
/// says. Each new node starts where the previous estimate and its odometry put it.
class GrowingGraph {
 public:
  GrowingGraph(unsigned seed, double noise) : rng_(seed), noise_(noise) {
    truth_.push_back(CPose2D(0, 0, 0));
    g_.addNode(truth_.back());
  }

  /// Adds one node and its edges to `g` (the caller's graph, which holds the estimate).
  void grow(asf::PoseGraph& g) {
    std::uniform_real_distribution<double> u(-1, 1);
    const CPose2D& last = truth_.back();
    CPose2D step(0.4, 0.1 * u(rng_), 0.5 * u(rng_));
    CPose2D next = last + step;
    if (std::abs(next.x()) > 3 || std::abs(next.y()) > 3) {  // turn back into the box
      step = CPose2D(0.2, 0, M_PI / 2);
      next = last + step;
    }
    truth_.push_back(next);
    const NodeId j = static_cast<NodeId>(truth_.size() - 1);
    const asf::PoseEdge odo = noisyEdge(j - 1, j, 400);
    g.addNode(g.nodes[j - 1].pose + odo.mean);
    g.addEdge(odo);
    if (j % 4 != 0) return;
    for (NodeId i = 0; i + 2 < j; ++i)
      if (truth_[i].distanceTo(next) < 1.5) g.addEdge(noisyEdge(i, j, 100));
  }

 private:
  asf::PoseEdge noisyEdge(NodeId i, NodeId j, double info) {
    std::normal_distribution<double> n01;
    const CPose2D d = truth_[j] - truth_[i];
    const double sigma = noise_ / std::sqrt(info);
    asf::PoseEdge e;
    e.from = i;
    e.to = j;
    e.mean =
        CPose2D(d.x() + sigma * n01(rng_), d.y() + sigma * n01(rng_), d.phi() + sigma * n01(rng_));
    e.information = info * Eigen::Matrix3d::Identity();
    e.kind = j == i + 1 ? asf::EdgeKind::Odometry : asf::EdgeKind::LoopClosure;
    return e;
  }

  std::mt19937_64 rng_;
  double noise_;
  std::vector<CPose2D> truth_;
  asf::PoseGraph g_;
};

asf::PoseGraph originOnly() {
  asf::PoseGraph g;
  g.addNode(CPose2D(0, 0, 0));
  return g;
}

IncrementalOptions enabled() {
  IncrementalOptions io;
  io.enabled = true;
  return io;
}

/// b^T H^-1 b of the whole graph at its poses (dense: the oracle).
double denseDecrement(const asf::PoseGraph& g) {
  std::vector<int> index;
  const Eigen::MatrixXd H = asf::denseInformation(g, index);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(H.rows());
  for (const auto& e : g.edges) {
    const Eigen::Vector3d xi(g.nodes[e.from].pose.x(), g.nodes[e.from].pose.y(),
                             g.nodes[e.from].pose.phi());
    const Eigen::Vector3d xj(g.nodes[e.to].pose.x(), g.nodes[e.to].pose.y(),
                             g.nodes[e.to].pose.phi());
    const Eigen::Vector3d z(e.mean.x(), e.mean.y(), e.mean.phi());
    const auto lin = asf::se2::linearizeEdge(xi, xj, z);
    if (index[e.from] >= 0)
      b.segment<3>(index[e.from]) += lin.Ji.transpose() * e.information * lin.e;
    if (index[e.to] >= 0) b.segment<3>(index[e.to]) += lin.Jj.transpose() * e.information * lin.e;
  }
  return b.dot(H.ldlt().solve(b));
}

double minEigenRatio(const Eigen::Matrix3d& upper, const Eigen::Matrix3d& exact) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(upper - exact);
  return es.eigenvalues().minCoeff() / exact.norm();
}

TEST(IncrementalSparseLm, DecrementBoundIsAtLeastTheDenseGaussNewtonDecrement) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    GrowingGraph world(seed, 1.0);
    asf::PoseGraph g = originOnly();
    for (int k = 0; k < 60; ++k) world.grow(g);
    SparseSe2 whole, window;
    whole.optimize(g, tight());
    whole.marginals(g, {}, tight());  // the factor: undamped, at the optimum
    const std::size_t old_nodes = g.size(), old_edges = g.edges.size();
    for (int k = 0; k < 12; ++k) world.grow(g);
    ASSERT_GT(g.edges.size(), old_edges + 12) << "no new loop edge: the test shows nothing";
    // The new nodes at their optimum with the old ones held, as the incremental mode does.
    std::vector<NodeId> w;
    for (std::size_t v = old_nodes; v < g.size(); ++v) w.push_back(static_cast<NodeId>(v));
    std::vector<std::size_t> edges;
    for (std::size_t k = 0; k < g.edges.size(); ++k)
      if (g.edges[k].from >= old_nodes || g.edges[k].to >= old_nodes) edges.push_back(k);
    window.optimizeWindow(g, w, edges, tight());

    const std::optional<double> bound = whole.decrementBound(g, tight());
    ASSERT_TRUE(bound.has_value());
    const double truth = denseDecrement(g);
    EXPECT_GT(truth, 1e-3) << "seed " << seed << ": nothing to gain, the test shows nothing";
    EXPECT_GE(*bound, truth * (1 - 1e-9)) << "seed " << seed;
    // And a whole solve gains about that much (the model is good at this noise).
    asf::PoseGraph solved = g;
    SparseSe2().optimize(solved, tight());
    EXPECT_NEAR(g.chi2() - solved.chi2(), truth, 0.05 * truth + 1e-9) << "seed " << seed;
  }
}

TEST(IncrementalSparseLm, StaysWithinTheGapOfTheWholeOptimumAtEveryStep) {
  const double gap = 0.5;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    GrowingGraph world(seed, 1.0);
    asf::PoseGraph g = originOnly();
    IncrementalSe2 inc;
    IncrementalOptions io = enabled();
    io.gap = gap;
    io.hops = 1;  // small windows: the bound has work to do
    double worst = 0;
    for (int k = 0; k < 200; ++k) {
      world.grow(g);
      const double before = g.chi2();
      const asf::OptimizeReport r = inc.optimize(g, tight(), io);
      // The report's chi2 is kept by bookkeeping, not recomputed: it must be the graph's.
      ASSERT_NEAR(r.initial_chi2, before, 1e-9 * before) << "node " << g.size();
      ASSERT_NEAR(r.final_chi2, g.chi2(), 1e-9 * before) << "node " << g.size();
      ASSERT_LE(r.final_chi2, r.initial_chi2);
      inc.marginals(g, {}, tight(), io);
      asf::PoseGraph opt = g;
      SparseSe2().optimize(opt, tight());
      const double excess = g.chi2() - opt.chi2();
      worst = std::max(worst, excess);
      // The bound is of the Gauss-Newton model: a little slack for the curvature.
      ASSERT_LE(excess, 1.1 * gap + 1e-6) << "seed " << seed << ", node " << g.size();
    }
    const auto& c = inc.counters();
    EXPECT_GT(c.window_solves, 100) << "seed " << seed;
    EXPECT_GT(c.bound_exceeded, 0) << "seed " << seed << ": the bound never decided anything";
    EXPECT_GT(worst, 0.05 * gap) << "seed " << seed << ": always at the optimum, nothing shown";
  }
}

/// The lowest min-eigenvalue of (propagated - exact) / |exact| over every node, every time
/// the marginals were propagated along a growing graph; `checked` counts the blocks.
double lowestPropagatedMargin(double noise, long& checked) {
  GrowingGraph world(7, noise);
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();
  io.marginals = asf::sparse_lm::MarginalsMode::Propagated;
  io.gap = 1e9;  // window solves only, once the graph is big enough
  double lowest = 1;
  for (int k = 0; k < 120; ++k) {
    world.grow(g);
    inc.optimize(g, tight(), io);
    const long before = inc.counters().propagated_marginals;
    const asf::Marginals m = inc.marginals(g, {}, tight(), io);
    if (inc.counters().propagated_marginals == before) continue;
    const asf::Marginals exact = SparseSe2().marginals(g, {}, tight());
    EXPECT_EQ(m.node.size(), g.size());
    for (std::size_t i = 1; i < g.size(); ++i) {
      lowest = std::min(lowest, minEigenRatio(m.node[i], exact.node[i]));
      ++checked;
    }
  }
  return lowest;
}

TEST(IncrementalSparseLm, PropagatedMarginalsBoundTheExactOnes) {
  // Exact measurements: no window moves anything, so the bound is exact linear algebra
  // (information only grows).
  long checked = 0;
  EXPECT_GE(lowestPropagatedMargin(0.0, checked), -1e-9);
  EXPECT_GT(checked, 1000);
  // With noise the windows move poses, and the blocks are bounds to first order in those
  // moves (here about a percent: the poses move by about one standard deviation).
  checked = 0;
  EXPECT_GE(lowestPropagatedMargin(1.0, checked), -2e-2);
  EXPECT_GT(checked, 1000);
}

/// A chain's marginals are its dead reckoning: propagation is exact there, whichever way
/// round the edges point.
void expectExactOnAChain(bool reversed) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();
  io.marginals = asf::sparse_lm::MarginalsMode::Propagated;
  long compared = 0;
  for (int k = 1; k < 80; ++k) {
    asf::PoseEdge e;
    e.from = k - 1;
    e.to = k;
    e.mean = CPose2D(0.5 + 0.2 * u(rng), 0.1 * u(rng), 0.4 * u(rng));
    Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    e.information = 50 * (A * A.transpose() + Eigen::Matrix3d::Identity());
    g.addNode(g.nodes.back().pose + e.mean);
    if (reversed) {  // the edge k -> k-1 (any information: a chain's marginal is its edge's)
      e.from = k;
      e.to = k - 1;
      e.mean = CPose2D(0, 0, 0) - e.mean;
    }
    g.addEdge(e);
    inc.optimize(g, tight(), io);
    const long before = inc.counters().propagated_marginals;
    const asf::Marginals m = inc.marginals(g, {}, tight(), io);
    if (inc.counters().propagated_marginals == before) continue;
    const asf::Marginals exact = SparseSe2().marginals(g, {}, tight());
    for (std::size_t i = 1; i < g.size(); ++i) {
      EXPECT_LE((m.node[i] - exact.node[i]).norm(), 1e-9 * exact.node[i].norm()) << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 500);
}

TEST(IncrementalSparseLm, PropagatedMarginalsAreExactOnAChain) { expectExactOnAChain(false); }
TEST(IncrementalSparseLm, PropagatedMarginalsAreExactOnAReversedChain) {
  expectExactOnAChain(true);
}

/// The largest relative difference ||updated - exact|| / ||exact|| over every node's block,
/// every time the marginals were updated along a growing graph (node 3 fixed besides the
/// gauge); `updated` counts those calls, `epochs` the whole factorizations between them.
double largestUpdatedError(double noise, std::size_t max_nodes, long& updated, long& epochs,
                           long& checked) {
  GrowingGraph world(13, noise);
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();
  io.marginals = asf::sparse_lm::MarginalsMode::Updated;
  io.update_max_nodes = max_nodes;
  io.gap = 1e9;  // window solves only, once the graph is big enough
  double worst = 0;
  for (int k = 0; k < 150; ++k) {
    world.grow(g);
    if (k == 3) g.fixed = {3};
    inc.optimize(g, tight(), io);
    const long before = inc.counters().updated_marginals;
    const asf::Marginals m = inc.marginals(g, {}, tight(), io);
    if (inc.counters().updated_marginals == before) continue;
    const asf::Marginals exact = SparseSe2().marginals(g, {}, tight());
    EXPECT_EQ(m.node.size(), g.size());
    EXPECT_EQ(m.graph_revision, g.revision);
    EXPECT_TRUE(m.node[3].isZero()) << "a fixed node has no covariance";
    for (std::size_t i = 1; i < g.size(); ++i) {
      if (i == 3) continue;
      worst = std::max(worst, (m.node[i] - exact.node[i]).norm() / exact.node[i].norm());
      ++checked;
    }
  }
  updated = inc.counters().updated_marginals;
  epochs = inc.counters().exact_marginals;
  return worst;
}

TEST(IncrementalSparseLm, UpdatedMarginalsAreTheFactorizationsOwn) {
  // Exact measurements: no window moves anything, so an update is exact linear algebra, old
  // nodes (the Woodbury term), touched ones and new ones alike.
  long updated = 0, epochs = 0, checked = 0;
  EXPECT_LE(largestUpdatedError(0.0, 20, updated, epochs, checked), 1e-8);
  EXPECT_GT(updated, 80);
  EXPECT_GT(epochs, 5) << "the limit never ended an epoch";
  EXPECT_GT(checked, 5000);
  // With noise the windows move poses since the factorization: first order in those moves
  // (measured: 0.22 % at noise 0.1, 2.4 % at 1, 5.0 % at 2).
  checked = 0;
  EXPECT_LE(largestUpdatedError(0.1, 64, updated, epochs, checked), 3e-3);
  EXPECT_LE(largestUpdatedError(1.0, 64, updated, epochs, checked), 3e-2);
  EXPECT_GT(updated, 80);
  EXPECT_GT(checked, 5000);
}

TEST(IncrementalSparseLm, UpdatedMarginalsSeeALoopAcrossTheWholeGraph) {
  // A long chain, then one edge from its end back to node 1: every node's covariance
  // shrinks, the old ones only through the Woodbury term.
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();
  io.marginals = asf::sparse_lm::MarginalsMode::Updated;
  io.gap = 1e9;
  for (int k = 1; k <= 40; ++k) {
    const double a = 2 * M_PI * k / 40;
    g.addNode(CPose2D(5 * std::cos(a) - 5, 5 * std::sin(a), a + M_PI / 2));
    asf::PoseEdge e;
    e.from = k - 1;
    e.to = k;
    e.mean = g.nodes[k].pose - g.nodes[k - 1].pose;
    e.information = 100 * Eigen::Matrix3d::Identity();
    g.addEdge(e);
    inc.optimize(g, tight(), io);
    inc.marginals(g, {}, tight(), io);
  }
  const asf::Marginals before = inc.marginals(g, {}, tight(), io);
  asf::PoseEdge loop;
  loop.from = 40;
  loop.to = 1;
  loop.mean = g.nodes[1].pose - g.nodes[40].pose;
  loop.information = 100 * Eigen::Matrix3d::Identity();
  g.addEdge(loop);
  inc.optimize(g, tight(), io);
  const long updated = inc.counters().updated_marginals;
  const asf::Marginals m = inc.marginals(g, {}, tight(), io);
  ASSERT_EQ(inc.counters().updated_marginals, updated + 1) << "not answered by an update";
  const asf::Marginals exact = SparseSe2().marginals(g, {}, tight());
  for (std::size_t i = 2; i < 40; ++i) {
    EXPECT_LE((m.node[i] - exact.node[i]).norm(), 1e-9 * exact.node[i].norm()) << i;
    if (i >= 10) {  // near node 0 the chain was already short
      EXPECT_LT(m.node[i].trace(), 0.9 * before.node[i].trace()) << i << ": the loop did nothing";
    }
  }
}

TEST(IncrementalSparseLm, ExactMarginalsAfterWindowSolvesAreTheGraphsOwn) {
  GrowingGraph world(9, 1.0);
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();  // exact marginals by default
  long compared = 0;
  for (int k = 0; k < 80; ++k) {
    world.grow(g);
    const long windows = inc.counters().window_solves;
    inc.optimize(g, tight(), io);
    const asf::Marginals m = inc.marginals(g, {}, tight(), io);
    if (inc.counters().window_solves == windows) continue;
    const asf::Marginals exact = SparseSe2().marginals(g, {}, tight());
    for (std::size_t i = 1; i < g.size(); ++i) {
      ASSERT_LE((m.node[i] - exact.node[i]).norm(), 1e-9 * exact.node[i].norm()) << i;
      ++compared;
    }
  }
  EXPECT_EQ(inc.counters().propagated_marginals, 0);
  EXPECT_GT(compared, 1000);
}

TEST(IncrementalSparseLm, AnythingButGrowthSolvesTheWholeGraph) {
  GrowingGraph world(11, 1.0);
  asf::PoseGraph g = originOnly();
  IncrementalSe2 inc;
  IncrementalOptions io = enabled();
  io.gap = 1e9;
  for (int k = 0; k < 60; ++k) {
    world.grow(g);
    inc.optimize(g, tight(), io);
  }
  ASSERT_GT(inc.counters().window_solves, 10);
  auto expectWhole = [&](const char* what) {
    const long before = inc.counters().whole_solves;
    asf::PoseGraph plain = g;
    inc.optimize(g, tight(), io);
    EXPECT_EQ(inc.counters().whole_solves, before + 1) << what;
    SparseSe2().optimize(plain, tight());
    for (std::size_t i = 0; i < g.size(); ++i)
      EXPECT_LT(g.nodes[i].pose.distanceTo(plain.nodes[i].pose), 1e-6) << what << ", node " << i;
  };
  g.nodes[20].pose = g.nodes[20].pose + CPose2D(0.1, 0, 0);
  expectWhole("a pose moved by someone else");
  g.edges[5].information *= 2;
  expectWhole("an edge's information changed");
  g.edges.pop_back();
  expectWhole("an edge removed");
  g.fixed.push_back(3);
  expectWhole("a node fixed");
  // Growth again: back to windows.
  const long windows = inc.counters().window_solves;
  world.grow(g);  // the world's node ids follow g's: nothing was removed from the nodes
  inc.optimize(g, tight(), io);
  EXPECT_EQ(inc.counters().window_solves, windows + 1);
}

TEST(IncrementalSparseLm, OffIsThePlainBackEnd) {
  GrowingGraph w1(5, 1.0), w2(5, 1.0);
  asf::PoseGraph a, b;
  a.addNode(CPose2D(0, 0, 0));
  b.addNode(CPose2D(0, 0, 0));
  IncrementalSe2 inc;
  SparseSe2 plain;
  const Options o;
  for (int k = 0; k < 50; ++k) {
    w1.grow(a);
    w2.grow(b);
    inc.optimize(a, o, IncrementalOptions{});
    plain.optimize(b, o);
    const asf::Marginals ma = inc.marginals(a, {}, o, IncrementalOptions{});
    const asf::Marginals mb = plain.marginals(b, {}, o);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a.nodes[i].pose, b.nodes[i].pose);
      ASSERT_EQ(ma.node[i], mb.node[i]);
    }
  }
}

}  // namespace
