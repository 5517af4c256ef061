// Expected uncertainty of a path (Algorithm 1 against the 2^m enumeration), the Gaussian
// window integral (against Monte Carlo and exact products), the reduced-graph path search
// (against brute-force enumeration) and `asf plan` end to end.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "test_util.h"

namespace {

using asf::NodeId;
using Eigen::Matrix3d;
using mrpt::poses::CPose2D;
namespace planning = asf::planning;

Matrix3d randomSpd(std::mt19937_64& rng, double scale) {
  std::normal_distribution<double> n(0, 1);
  Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i / 3, i % 3) = n(rng);
  return scale * (A * A.transpose() + 0.1 * Matrix3d::Identity());
}

/// A chain graph 0..m with random poses and edge informations, and marginals taken from one
/// random joint covariance (so node and cross blocks are consistent).
struct RandomChain {
  asf::PoseGraph g;
  asf::Marginals m;
  std::vector<NodeId> path;
};

RandomChain randomChain(std::mt19937_64& rng, int steps) {
  RandomChain c;
  std::uniform_real_distribution<double> u(-1, 1);
  CPose2D p(0, 0, 0);
  for (int i = 0; i <= steps; ++i) {
    c.g.addNode(p);
    c.path.push_back(static_cast<NodeId>(i));
    p = p + CPose2D(0.5 + 0.3 * u(rng), 0.3 * u(rng), 0.5 * u(rng));
  }
  for (int i = 0; i < steps; ++i) {
    asf::PoseEdge e;
    // Random direction so both the forward and the inverted edge covariance are exercised.
    const bool fwd = rng() % 2;
    e.from = fwd ? i : i + 1;
    e.to = fwd ? i + 1 : i;
    e.mean = c.g.nodes[e.to].pose - c.g.nodes[e.from].pose;
    e.information = randomSpd(rng, 0.01).inverse();
    c.g.addEdge(e);
  }
  const int n = 3 * (steps + 1);
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n) * 0.1;
  const Eigen::MatrixXd J = A * A.transpose() + 0.001 * Eigen::MatrixXd::Identity(n, n);
  c.m.node.resize(steps + 1);
  for (int i = 0; i <= steps; ++i) {
    c.m.node[i] = J.block<3, 3>(3 * i, 3 * i);
    for (int j = i + 1; j <= steps; ++j)
      c.m.cross[{static_cast<NodeId>(i), static_cast<NodeId>(j)}] = J.block<3, 3>(3 * i, 3 * j);
  }
  return c;
}

void expectNear(const Matrix3d& a, const Matrix3d& b, double rel, const std::string& what) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), rel * scale) << what << "\n" << a << "\nvs\n" << b;
}

// ---------------------------------------------------------------------------------------
// Algorithm 1

TEST(ExpectedUncertainty, MergeEqualsBruteForceOnRandomPaths) {
  std::mt19937_64 rng(20240611);
  for (int trial = 0; trial < 40; ++trial) {
    const int m = 1 + trial % 10;
    const RandomChain c = randomChain(rng, m);
    const planning::PathModel path = planning::makePathModel(c.g, &c.m, c.path);
    // A probability that depends on the hypothesis (k), the step (t) and the covariance.
    std::vector<double> base(m + 1);
    for (auto& b : base) b = std::uniform_real_distribution<double>(0, 1)(rng);
    const planning::RelocProbFn synthetic = [&](const planning::RelocQuery& q) {
      return base[q.t] * std::exp(-0.3 * q.robot_cov.trace() * (1 + q.k % 3)) *
             (0.5 + 0.5 * std::tanh(q.chain(0, 2)));
    };
    expectNear(planning::expectedCovariance(path, synthetic).mean,
               planning::expectedCovarianceBruteForce(path, synthetic), 1e-10,
               "synthetic p, m = " + std::to_string(m));
    // The real relocalization probability (window integral with cross-covariances).
    planning::RelocalizationOptions o;
    o.half_x = o.half_y = 0.2;
    o.p_recognition = 0.9;
    const planning::RelocProbFn real = planning::relocalizationProbability(path, o);
    const planning::ExpectedCovariance merged = planning::expectedCovariance(path, real);
    expectNear(merged.mean, planning::expectedCovarianceBruteForce(path, real), 1e-10,
               "window p, m = " + std::to_string(m));
    double total = 0;
    for (double p : merged.prob) total += p;
    EXPECT_NEAR(total, 1, 1e-12);
    EXPECT_EQ(merged.evaluations, static_cast<std::size_t>(m * (m + 1) / 2));
  }
}

TEST(ExpectedUncertainty, CertainRelocalizationGivesTheGoalMarginal) {
  std::mt19937_64 rng(7);
  const RandomChain c = randomChain(rng, 8);
  const planning::PathModel path = planning::makePathModel(c.g, &c.m, c.path);
  const auto r = planning::expectedCovariance(path, [](const planning::RelocQuery&) { return 1.0; });
  expectNear(r.mean, c.m.node.back(), 1e-14, "p = 1");
  EXPECT_DOUBLE_EQ(r.prob.back(), 1.0);
}

TEST(ExpectedUncertainty, NoRelocalizationIsPureOdometry) {
  std::mt19937_64 rng(8);
  const RandomChain c = randomChain(rng, 9);
  const planning::PathModel path = planning::makePathModel(c.g, &c.m, c.path);
  // Independent propagation: composeWithCov along the edges, each edge's covariance
  // brought to the traversal direction by sampling-free algebra below.
  Matrix3d C = c.m.node[0];
  CPose2D x = c.g.nodes[0].pose;
  for (std::size_t t = 1; t < c.path.size(); ++t) {
    const asf::PoseEdge& e = c.g.edges[t - 1];
    // Covariance of the edge's mean in its from-frame: R Cov(e) R^T.
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R.topLeftCorner<2, 2>() << std::cos(e.mean.phi()), -std::sin(e.mean.phi()),
        std::sin(e.mean.phi()), std::cos(e.mean.phi());
    Matrix3d O = R * e.information.inverse() * R.transpose();
    CPose2D d = e.mean;
    if (e.from != t - 1) {  // traversed backwards: O of the inverse motion, numerically
      const CPose2D inv = CPose2D() - e.mean;
      Matrix3d J;
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        double v[3] = {e.mean.x(), e.mean.y(), e.mean.phi()};
        v[k] += h;
        const CPose2D ip = CPose2D() - CPose2D(v[0], v[1], v[2]);
        v[k] -= 2 * h;
        const CPose2D im = CPose2D() - CPose2D(v[0], v[1], v[2]);
        J.col(k) << (ip.x() - im.x()) / (2 * h), (ip.y() - im.y()) / (2 * h),
            mrpt::math::wrapToPi(ip.phi() - im.phi()) / (2 * h);
      }
      O = J * O * J.transpose();
      d = inv;
    }
    x = asf::composeWithCov(x, C, d, O, C);
  }
  const auto r = planning::expectedCovariance(path, [](const planning::RelocQuery&) { return 0.0; });
  expectNear(r.mean, C, 1e-6, "p = 0");
  EXPECT_DOUBLE_EQ(r.prob[0], 1.0);
}

TEST(ExpectedUncertainty, PruningDropsOnlyNegligibleMass) {
  std::mt19937_64 rng(9);
  const RandomChain c = randomChain(rng, 60);
  const planning::PathModel path = planning::makePathModel(c.g, &c.m, c.path);
  const planning::RelocProbFn p = [](const planning::RelocQuery& q) { return 0.3 + 0.4 * (q.t % 2); };
  const auto exact = planning::expectedCovariance(path, p);
  const auto pruned = planning::expectedCovariance(path, p, 1e-12);
  EXPECT_LT(pruned.evaluations, exact.evaluations);
  EXPECT_GT(pruned.pruned_mass, 0);
  EXPECT_LT(pruned.pruned_mass, 1e-9);
  expectNear(pruned.mean, exact.mean, 1e-8, "pruned");
}

TEST(ExpectedUncertainty, PathModelRejectsNonAdjacentNodes) {
  std::mt19937_64 rng(10);
  const RandomChain c = randomChain(rng, 3);
  const std::string msg = asf_test::errorOf<asf::Error>(
      [&] { planning::makePathModel(c.g, &c.m, {0, 2}); });
  EXPECT_TRUE(asf_test::has(msg, "share no edge")) << msg;
}

// ---------------------------------------------------------------------------------------
// Gaussian window

double monteCarlo(const Eigen::Vector3d& mu, const Matrix3d& cov, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi, int n, std::uint64_t seed, double& se) {
  // Eigen decomposition instead of Cholesky so a singular covariance works too.
  Eigen::SelfAdjointEigenSolver<Matrix3d> es(cov);
  const Matrix3d A =
      es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0, 1);
  int inside = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x = mu + A * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    inside += (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
  const double p = static_cast<double>(inside) / n;
  se = std::sqrt(std::max(p * (1 - p), 1.0 / n) / n);
  return p;
}

TEST(GaussianWindow, MatchesMonteCarloOnCorrelatedCovariances) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    Matrix3d cov = randomSpd(rng, 0.05);
    if (trial == 11) {  // rank-deficient: x and y perfectly correlated
      cov << 0.04, 0.04, 0.01, 0.04, 0.04, 0.01, 0.01, 0.01, 0.02;
    }
    const Eigen::Vector3d mu(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
    const Eigen::Vector3d half(0.3, 0.3, 0.5236);
    const planning::BoxProbability q =
        planning::gaussianBoxProbability(mu, cov, -half, half, 512, 8, 1000 + trial);
    double se;
    const double mc = monteCarlo(mu, cov, -half, half, 400000, trial, se);
    EXPECT_NEAR(q.value, mc, 4 * se + 4 * q.error + 1e-4)
        << "trial " << trial << " se " << se << " qmc error " << q.error;
    EXPECT_LT(q.error, 5e-3);
  }
}

TEST(GaussianWindow, DiagonalCovarianceIsTheProductOfMarginals) {
  const Eigen::Vector3d sd(0.2, 0.35, 0.4), mu(0.05, -0.1, 0.2), half(0.3, 0.3, 0.5236);
  double product = 1;
  for (int i = 0; i < 3; ++i)
    product *= 0.5 * (std::erfc(-(half(i) - mu(i)) / sd(i) / std::sqrt(2.0)) -
                      std::erfc(-(-half(i) - mu(i)) / sd(i) / std::sqrt(2.0)));
  const Matrix3d cov = sd.cwiseAbs2().asDiagonal();
  const planning::BoxProbability q = planning::gaussianBoxProbability(mu, cov, -half, half);
  EXPECT_NEAR(q.value, product, 1e-12);
  // And a correlated covariance with the same marginals gives a different mass.
  Matrix3d corr = cov;
  corr(0, 1) = corr(1, 0) = 0.9 * sd(0) * sd(1);
  const planning::BoxProbability qc = planning::gaussianBoxProbability(mu, corr, -half, half);
  EXPECT_GT(std::abs(qc.value - product), 0.01);
}

TEST(GaussianWindow, DeterministicForASeedAndValidatesInput) {
  Matrix3d cov;
  cov << 0.1, 0.05, 0.01, 0.05, 0.2, 0.02, 0.01, 0.02, 0.3;
  const Eigen::Vector3d z = Eigen::Vector3d::Zero(), h(0.3, 0.3, 0.5);
  EXPECT_EQ(planning::gaussianBoxProbability(z, cov, -h, h, 128, 8, 5).value,
            planning::gaussianBoxProbability(z, cov, -h, h, 128, 8, 5).value);
  EXPECT_DOUBLE_EQ(planning::gaussianBoxProbability(z, Matrix3d::Zero(), -h, h).value, 1.0);
  Matrix3d bad = cov;
  bad(0, 0) = -1;
  EXPECT_THROW(planning::gaussianBoxProbability(z, bad, -h, h), asf::Error);
}

// ---------------------------------------------------------------------------------------
// Reduced graph and path search

asf::PoseGraph graphOf(int n, const std::vector<std::pair<int, int>>& edges) {
  asf::PoseGraph g;
  for (int i = 0; i < n; ++i) g.addNode(CPose2D(std::cos(i), std::sin(i), 0));
  for (auto [a, b] : edges) {
    asf::PoseEdge e;
    e.from = a;
    e.to = b;
    e.mean = g.nodes[b].pose - g.nodes[a].pose;
    g.addEdge(e);
  }
  return g;
}

std::set<std::vector<NodeId>> bruteForcePaths(const asf::PoseGraph& g, NodeId s, NodeId t) {
  std::set<std::vector<NodeId>> out;
  std::vector<NodeId> cur{s};
  std::vector<char> on(g.size(), 0);
  std::function<void(NodeId)> dfs = [&](NodeId v) {
    if (v == t) {
      out.insert(cur);
      return;
    }
    on[v] = 1;
    for (NodeId w = 0; w < g.size(); ++w) {
      if (on[w]) continue;
      bool joined = false;
      for (const auto& e : g.edges)
        joined |= (e.from == v && e.to == w) || (e.from == w && e.to == v);
      if (!joined) continue;
      cur.push_back(w);
      dfs(w);
      cur.pop_back();
    }
    on[v] = 0;
  };
  dfs(s);
  return out;
}

void expectSamePaths(const asf::PoseGraph& g, NodeId s, NodeId t, const std::string& what) {
  planning::PathSearchOptions o;
  o.merge_radius = 0;  // the reduction alone: every simple path of the graph
  const auto r = planning::allSimplePaths(g, s, t, o);
  EXPECT_FALSE(r.capped);
  const std::set<std::vector<NodeId>> got(r.paths.begin(), r.paths.end());
  EXPECT_EQ(got.size(), r.paths.size()) << what << ": a path was produced twice";
  EXPECT_EQ(got, bruteForcePaths(g, s, t)) << what << " " << s << " -> " << t;
}

TEST(PathSearch, ReducedGraphPreservesAllSimplePathsOnHandMadeGraphs) {
  // A loop of two chains with parallel (aliased) loop closures, plus a dangling chain.
  const auto loop = graphOf(10, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 0}, {2, 5},
                                 {2, 5}, {5, 2}, {3, 6}, {6, 7}, {7, 8}, {8, 9}});
  // A ladder: consecutive loop closures between two corridors.
  const auto ladder = graphOf(10, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {5, 6}, {6, 7}, {7, 8},
                                   {8, 9}, {0, 5}, {1, 6}, {2, 7}, {3, 8}, {4, 9}, {1, 6}});
  // Two kept nodes joined by three distinct chains, and a self-loop.
  const auto theta = graphOf(8, {{0, 1}, {1, 2}, {2, 7}, {0, 3}, {3, 7}, {0, 4}, {4, 5},
                                 {5, 6}, {6, 7}, {4, 4}});
  for (const auto* g : {&loop, &ladder, &theta})
    for (NodeId s = 0; s < g->size(); ++s)
      for (NodeId t = 0; t < g->size(); ++t) expectSamePaths(*g, s, t, "hand-made");
  const auto red = planning::reduceGraph(theta, 0, 7);
  EXPECT_EQ(red.kept, (std::vector<NodeId>{0, 7}));
  EXPECT_EQ(red.edges.size(), 3u);
  const auto red_loop = planning::reduceGraph(loop, 0, 1);
  EXPECT_LT(red_loop.kept.size(), loop.size());
}

TEST(PathSearch, ReducedGraphPreservesAllSimplePathsOnRandomGraphs) {
  std::mt19937_64 rng(77);
  for (int trial = 0; trial < 150; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 8);
    std::vector<std::pair<int, int>> edges;
    for (int i = 1; i < n; ++i) edges.emplace_back(i - 1, i);  // a trajectory...
    const int extra = static_cast<int>(rng() % 4);
    for (int k = 0; k < extra; ++k)  // ...with a few loop closures
      edges.emplace_back(static_cast<int>(rng() % n), static_cast<int>(rng() % n));
    const auto g = graphOf(n, edges);
    expectSamePaths(g, static_cast<NodeId>(rng() % n), static_cast<NodeId>(rng() % n),
                    "trial " + std::to_string(trial));
  }
}

TEST(PathSearch, CapIsReported) {
  const auto ladder = graphOf(10, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {5, 6}, {6, 7}, {7, 8},
                                   {8, 9}, {0, 5}, {1, 6}, {2, 7}, {3, 8}, {4, 9}});
  planning::PathSearchOptions o;
  o.max_paths = 3;
  o.merge_radius = 0;
  const auto r = planning::allSimplePaths(ladder, 0, 9, o);
  EXPECT_TRUE(r.capped);
  EXPECT_EQ(r.paths.size(), 3u);
  EXPECT_THROW(planning::allSimplePaths(ladder, 0, 99), asf::Error);
}

TEST(PathSearch, TimeBudgetKeepsTheBestSoFarAndSaysSo) {
  // The ladder has many simple paths 0 -> 9; with a budget already spent after the first
  // evaluation, planBest returns that first path and a note; without one, all are compared.
  const auto ladder = graphOf(10, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {5, 6}, {6, 7}, {7, 8},
                                   {8, 9}, {0, 5}, {1, 6}, {2, 7}, {3, 8}, {4, 9}});
  asf::PlanRequest req;
  req.graph = &ladder;
  req.start = 0;
  req.goal = 9;
  planning::PathSearchOptions all, budget;
  all.merge_radius = budget.merge_radius = 0;
  all.method = budget.method = planning::SearchMethod::All;
  budget.max_seconds = 1e-12;
  std::string note_all, note_budget;
  const auto r_all = planning::planBest(req, planning::Criterion::Distance, {}, all, &note_all);
  const auto r_budget = planning::planBest(req, planning::Criterion::Distance, {}, budget, &note_budget);
  ASSERT_TRUE(r_all.found);
  ASSERT_TRUE(r_budget.found);
  EXPECT_EQ(note_all.find("time budget"), std::string::npos) << note_all;
  EXPECT_NE(note_budget.find("time budget of"), std::string::npos) << note_budget;
  EXPECT_NE(note_budget.find("after 1 of"), std::string::npos) << note_budget;
  EXPECT_LE(r_all.cost, r_budget.cost);

  // The search itself: a 2 x 30 ladder has about 2^29 simple paths end to end; with a spent
  // budget the search stops early and says so.
  std::vector<std::pair<int, int>> rungs;
  for (int i = 0; i + 1 < 30; ++i) {
    rungs.emplace_back(i, i + 1);
    rungs.emplace_back(30 + i, 31 + i);
  }
  for (int i = 0; i < 30; ++i) rungs.emplace_back(i, 30 + i);
  const auto big = graphOf(60, rungs);
  planning::PathSearchOptions quick;
  quick.max_paths = 1u << 30;
  quick.max_seconds = 1e-12;
  quick.merge_radius = 0;
  const auto r = planning::allSimplePaths(big, 0, 59, quick);
  EXPECT_TRUE(r.timed_out);
  EXPECT_TRUE(r.capped);
  EXPECT_LT(r.paths.size(), 100000u);
}

// ---------------------------------------------------------------------------------------
// Alias-merged search graph, Yen's k shortest simple paths, the candidate search

/// A graph with the given node positions; `closures` are marked as loop closures, `chain`
/// edges as odometry.
asf::PoseGraph graphAt(const std::vector<std::pair<double, double>>& xy,
                       const std::vector<std::pair<int, int>>& chain,
                       const std::vector<std::pair<int, int>>& closures) {
  asf::PoseGraph g;
  for (auto [x, y] : xy) g.addNode(CPose2D(x, y, 0));
  auto add = [&](int a, int b, asf::EdgeKind k) {
    asf::PoseEdge e;
    e.from = a;
    e.to = b;
    e.kind = k;
    e.mean = g.nodes[b].pose - g.nodes[a].pose;
    g.addEdge(e);
  };
  for (auto [a, b] : chain) add(a, b, asf::EdgeKind::Odometry);
  for (auto [a, b] : closures) add(a, b, asf::EdgeKind::LoopClosure);
  return g;
}

/// The vertex sequence a node path visits (consecutive repeats collapsed).
std::vector<NodeId> project(const planning::SearchGraph& sg, const std::vector<NodeId>& path) {
  std::vector<NodeId> out;
  for (NodeId v : path)
    if (out.empty() || out.back() != sg.vertex_of[v]) out.push_back(sg.vertex_of[v]);
  return out;
}

bool simple(const std::vector<NodeId>& seq) {
  return std::set<NodeId>(seq.begin(), seq.end()).size() == seq.size();
}

bool adjacent(const asf::PoseGraph& g, NodeId a, NodeId b) {
  for (const auto& e : g.edges)
    if ((e.from == a && e.to == b) || (e.from == b && e.to == a)) return a != b;
  return false;
}

/// The oracle: the distinct vertex sequences of all simple node paths s -> t that do not
/// re-enter a vertex must be exactly the routes the search returns, one path each, and each
/// returned path must be a simple chain of graph edges visiting its route in order.
std::size_t expectSameRoutes(const asf::PoseGraph& g, NodeId s, NodeId t, double radius,
                             const std::string& what) {
  const auto sg = planning::buildSearchGraph(g, s, t, radius);
  std::set<std::vector<NodeId>> oracle;
  for (const auto& p : bruteForcePaths(g, s, t)) {
    const auto seq = project(sg, p);
    if (simple(seq)) oracle.insert(seq);
  }
  planning::PathSearchOptions o;
  o.merge_radius = radius;
  o.max_paths = 1u << 20;
  const auto r = planning::allSimplePaths(g, s, t, o);
  EXPECT_FALSE(r.capped) << what;
  std::set<std::vector<NodeId>> got;
  for (const auto& p : r.paths) {
    if (p.empty()) {
      ADD_FAILURE() << what << ": empty path";
      continue;
    }
    EXPECT_EQ(p.front(), s) << what;
    EXPECT_EQ(p.back(), t) << what;
    EXPECT_TRUE(simple(p)) << what << ": a returned path repeats a node";
    for (std::size_t i = 1; i < p.size(); ++i)
      EXPECT_TRUE(adjacent(g, p[i - 1], p[i])) << what << ": " << p[i - 1] << " - " << p[i];
    const auto seq = project(sg, p);
    EXPECT_TRUE(simple(seq)) << what;
    EXPECT_TRUE(got.insert(seq).second) << what << ": a route was returned twice";
  }
  EXPECT_EQ(got, oracle) << what << " " << s << " -> " << t << " radius " << radius;
  return sg.merged_vertices;
}

TEST(SearchGraph, AliasedLadderBecomesOneRoute) {
  // A corridor driven twice: nodes 0..5 along y = 0, then 6..11 back along y = 0.2, a loop
  // closure between each pair of aliases, and a detour 12-13 from node 2 to node 4.
  std::vector<std::pair<double, double>> xy;
  for (int i = 0; i < 6; ++i) xy.emplace_back(i, 0);
  for (int i = 5; i >= 0; --i) xy.emplace_back(i, 0.2);
  xy.emplace_back(2, 3);
  xy.emplace_back(4, 3);
  std::vector<std::pair<int, int>> chain, closures;
  for (int i = 0; i + 1 < 12; ++i) chain.emplace_back(i, i + 1);
  chain.insert(chain.end(), {{2, 12}, {12, 13}, {13, 4}});
  for (int i = 0; i < 6; ++i) closures.emplace_back(i, 11 - i);
  const auto g = graphAt(xy, chain, closures);

  const auto sg = planning::buildSearchGraph(g, 0, 5, 0.5);
  EXPECT_EQ(sg.merged_vertices, 6u);  // 0|11 .. 5|6
  EXPECT_EQ(sg.vertex_of[0], sg.vertex_of[11]);
  EXPECT_EQ(sg.vertex_of[2], sg.vertex_of[9]);
  // Start and goal never share a vertex: with a radius spanning the corridor, 0 and 5 stay
  // apart (the rest may merge).
  const auto wide = planning::buildSearchGraph(g, 0, 5, 10);
  EXPECT_NE(wide.vertex_of[0], wide.vertex_of[5]);
  planning::PathSearchOptions o;
  o.merge_radius = 0.5;
  // Without the merge the ladder has dozens of simple paths 0 -> 5; merged: the corridor
  // (with or without the detour), and the starts/ends through the alias nodes.
  planning::PathSearchOptions raw = o;
  raw.merge_radius = 0;
  const auto merged = planning::allSimplePaths(g, 0, 5, o);
  const auto all = planning::allSimplePaths(g, 0, 5, raw);
  EXPECT_LT(merged.paths.size() * 4, all.paths.size())
      << merged.paths.size() << " vs " << all.paths.size();
  for (NodeId s = 0; s < g.size(); ++s)
    for (NodeId t = 0; t < g.size(); ++t)
      for (double radius : {0.0, 0.25, 0.5, 1.5})
        expectSameRoutes(g, s, t, radius, "ladder");
}

TEST(SearchGraph, MergedGraphPreservesAllDistinctRoutesOnRandomGraphs) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0, 3);
  int with_merges = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 3 + static_cast<int>(rng() % 8);
    std::vector<std::pair<double, double>> xy;
    for (int i = 0; i < n; ++i) xy.emplace_back(u(rng), u(rng));
    std::vector<std::pair<int, int>> chain, closures;
    for (int i = 1; i < n; ++i) chain.emplace_back(i - 1, i);
    const int extra = static_cast<int>(rng() % 6);
    for (int k = 0; k < extra; ++k)
      closures.emplace_back(static_cast<int>(rng() % n), static_cast<int>(rng() % n));
    const auto g = graphAt(xy, chain, closures);
    const double radius = std::uniform_real_distribution<double>(0, 2.5)(rng);
    with_merges += expectSameRoutes(g, static_cast<NodeId>(rng() % n),
                                    static_cast<NodeId>(rng() % n), radius,
                                    "trial " + std::to_string(trial)) > 0;
  }
  EXPECT_GT(with_merges, 100);  // the oracle saw merged vertices, not only the reduction
}

TEST(SearchGraph, ExpandRouteRejectsBadRoutes) {
  const auto g = graphAt({{0, 0}, {1, 0}, {2, 0}, {1, 1}}, {{0, 1}, {1, 2}, {0, 3}, {3, 2}}, {});
  const auto sg = planning::buildSearchGraph(g, 0, 2, 0, false);
  EXPECT_EQ(planning::expandRoute(g, sg, {0, 1, 2}, 0, 2), (std::vector<NodeId>{0, 1, 2}));
  EXPECT_EQ(planning::expandRoute(g, sg, {0, 3, 2}, 0, 2), (std::vector<NodeId>{0, 3, 2}));
  EXPECT_THROW(planning::expandRoute(g, sg, {0, 2}, 0, 2), asf::Error);        // not adjacent
  EXPECT_THROW(planning::expandRoute(g, sg, {0, 1, 0, 1, 2}, 0, 2), asf::Error);  // repeated
  EXPECT_THROW(planning::expandRoute(g, sg, {1, 2}, 0, 2), asf::Error);        // wrong start
}

/// All simple s -> t paths of a multigraph as edge sequences, by (cost, length, edges).
std::vector<std::vector<std::size_t>> bruteForceEdgePaths(std::size_t n,
                                                          const std::vector<planning::WeightedEdge>& e,
                                                          std::uint32_t s, std::uint32_t t) {
  std::vector<std::pair<double, std::vector<std::size_t>>> all;
  std::vector<std::size_t> cur;
  std::vector<char> on(n, 0);
  std::function<void(std::uint32_t, double)> dfs = [&](std::uint32_t v, double c) {
    if (v == t) {
      all.emplace_back(c, cur);
      return;
    }
    on[v] = 1;
    for (std::size_t i = 0; i < e.size(); ++i) {
      if (e[i].a == e[i].b) continue;
      std::uint32_t w;
      if (e[i].a == v)
        w = e[i].b;
      else if (e[i].b == v)
        w = e[i].a;
      else
        continue;
      if (on[w]) continue;
      cur.push_back(i);
      dfs(w, c + e[i].w);
      cur.pop_back();
    }
    on[v] = 0;
  };
  dfs(s, 0);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    if (a.first != b.first) return a.first < b.first;
    if (a.second.size() != b.second.size()) return a.second.size() < b.second.size();
    return a.second < b.second;
  });
  std::vector<std::vector<std::size_t>> out;
  for (auto& p : all) out.push_back(std::move(p.second));
  return out;
}

TEST(Yen, EqualsTheSortedBruteForceListOnRandomGraphs) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> w(0.1, 5);
  std::size_t compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::size_t n = 2 + rng() % 7;
    std::vector<planning::WeightedEdge> e;
    const int m = static_cast<int>(rng() % 14);
    for (int k = 0; k < m; ++k)  // parallel edges and self-loops included
      e.push_back({static_cast<std::uint32_t>(rng() % n), static_cast<std::uint32_t>(rng() % n),
                   w(rng)});
    const auto s = static_cast<std::uint32_t>(rng() % n), t = static_cast<std::uint32_t>(rng() % n);
    const auto oracle = bruteForceEdgePaths(n, e, s, t);
    for (std::size_t k : {std::size_t{1}, std::size_t{3}, oracle.size() + 2}) {
      const auto got = planning::kShortestSimplePaths(n, e, s, t, k);
      const std::size_t want = std::min(k, oracle.size());
      ASSERT_EQ(got.size(), want) << "trial " << trial << " k " << k;
      for (std::size_t i = 0; i < want; ++i)
        EXPECT_EQ(got[i], oracle[i]) << "trial " << trial << " k " << k << " rank " << i;
      compared += want;
    }
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_THROW(planning::kShortestSimplePaths(2, {{0, 5, 1.0}}, 0, 1, 3), asf::Error);
}

TEST(PathSearch, AutoFallsBackToYenOnALoopyGraphAndSaysSo) {
  // A 2 x 30 ladder (rails 1 m apart, so no merge at 0.5 m): about 2^29 simple paths.
  std::vector<std::pair<double, double>> xy;
  std::vector<std::pair<int, int>> chain, closures;
  for (int i = 0; i < 30; ++i) xy.emplace_back(i, 0);
  for (int i = 0; i < 30; ++i) xy.emplace_back(i, 1);
  for (int i = 0; i + 1 < 30; ++i) {
    chain.emplace_back(i, i + 1);
    chain.emplace_back(30 + i, 31 + i);
  }
  for (int i = 0; i < 30; ++i) closures.emplace_back(i, 30 + i);
  const auto g = graphAt(xy, chain, closures);
  planning::PathSearchOptions o;
  o.merge_radius = 0.5;
  o.max_paths = 100;
  o.k_paths = 12;
  o.diverse_paths = 0;
  const auto r = planning::searchPaths(g, 0, 59, o);
  EXPECT_TRUE(r.fell_back);
  EXPECT_FALSE(r.capped);
  EXPECT_EQ(r.method, planning::SearchMethod::Yen);
  ASSERT_EQ(r.paths.size(), 12u);  // the Dijkstra path is Yen's first: not added again
  EXPECT_FALSE(r.added_shortest);
  EXPECT_EQ(r.paths.front(), planning::shortestPath(g, 0, 59));
  std::set<std::vector<NodeId>> distinct(r.paths.begin(), r.paths.end());
  EXPECT_EQ(distinct.size(), r.paths.size());
  double prev = 0;
  for (const auto& p : r.paths) {
    EXPECT_TRUE(simple(p));
    double len = 0;
    for (std::size_t i = 1; i < p.size(); ++i) {
      ASSERT_TRUE(adjacent(g, p[i - 1], p[i]));
      len += (g.nodes[p[i]].pose - g.nodes[p[i - 1]].pose).norm();
    }
    EXPECT_GE(len, prev - 1e-9);  // no merge: route lengths are the path lengths
    prev = len;
  }
  // search = all: the cap is reported instead.
  o.method = planning::SearchMethod::All;
  const auto capped = planning::searchPaths(g, 0, 59, o);
  EXPECT_TRUE(capped.capped);
  EXPECT_FALSE(capped.fell_back);
  // Rails 0.2 m apart and a 0.5 m merge radius: one corridor, one route.
  for (int i = 30; i < 60; ++i) xy[i].second = 0.2;
  const auto corridor = graphAt(xy, chain, closures);
  o.method = planning::SearchMethod::Auto;
  const auto one = planning::searchPaths(corridor, 0, 59, o);
  EXPECT_FALSE(one.fell_back);
  EXPECT_LE(one.paths.size(), 3u);
}


TEST(PathSearch, PenaltyRoutesReachTheDetourYensVariantsMiss) {
  // A ladder 0..9 / 10..19 (rails 1 m apart: no merge) and a long detour 0-20..27-9 below.
  std::vector<std::pair<double, double>> xy;
  for (int i = 0; i < 10; ++i) xy.emplace_back(i, 0);
  for (int i = 0; i < 10; ++i) xy.emplace_back(i, 1);
  for (auto [x, y] : {std::pair{0.0, -1.0}, {0, -3}, {0, -5}, {3, -5}, {6, -5}, {9, -5}, {9, -3},
                      {9, -1}})
    xy.emplace_back(x, y);
  std::vector<std::pair<int, int>> chain, closures;
  for (int i = 0; i + 1 < 10; ++i) {
    chain.emplace_back(i, i + 1);
    chain.emplace_back(10 + i, 11 + i);
  }
  chain.emplace_back(0, 20);
  for (int i = 20; i < 27; ++i) chain.emplace_back(i, i + 1);
  chain.emplace_back(27, 9);
  for (int i = 0; i < 10; ++i) closures.emplace_back(i, 10 + i);
  const auto g = graphAt(xy, chain, closures);
  auto detour = [](const std::vector<NodeId>& p) {
    return std::find(p.begin(), p.end(), NodeId{24}) != p.end();
  };
  planning::PathSearchOptions o;
  o.method = planning::SearchMethod::Yen;
  o.merge_radius = 0.5;
  o.k_paths = 10;
  o.diverse_paths = 0;
  const auto yen = planning::searchPaths(g, 0, 9, o);
  EXPECT_EQ(yen.paths.size(), 10u);
  EXPECT_TRUE(std::none_of(yen.paths.begin(), yen.paths.end(), detour));
  o.diverse_paths = 10;
  const auto both = planning::searchPaths(g, 0, 9, o);
  EXPECT_GT(both.diverse_added, 0u);
  EXPECT_TRUE(std::any_of(both.paths.begin(), both.paths.end(), detour));
  std::set<std::vector<NodeId>> distinct(both.paths.begin(), both.paths.end());
  EXPECT_EQ(distinct.size(), both.paths.size());
  for (const auto& p : both.paths) {
    EXPECT_TRUE(simple(p));
    for (std::size_t i = 1; i < p.size(); ++i) EXPECT_TRUE(adjacent(g, p[i - 1], p[i]));
  }
  // The first route of the penalty method is the shortest path.
  std::vector<planning::WeightedEdge> we{{0, 1, 1.0}, {1, 2, 1.0}, {0, 2, 3.0}, {0, 2, 2.5}};
  const auto d = planning::diversePaths(3, we, 0, 2, 5, 1.0);
  ASSERT_GE(d.size(), 2u);
  EXPECT_EQ(d[0], (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(d[1], (std::vector<std::size_t>{3}));  // 2.5 < 2 x 2
}


TEST(PathSearch, NearTiesGoToTheShorterPath) {
  // 0-1-2 straight (2 m) or 0-3-2 over (1, 1) (2.83 m); sum_dopt of the detour is smaller by
  // a relative 1e-9: a tie under the default tolerance (the shorter path wins), not at 0.
  const auto g = graphAt({{0, 0}, {1, 0}, {2, 0}, {1, 1}}, {{0, 1}, {1, 2}, {0, 3}, {3, 2}}, {});
  asf::Marginals m;
  for (int i = 0; i < 4; ++i) m.node.push_back(Matrix3d::Identity() * 0.1);
  m.node[3] *= std::cbrt(1 - 3e-9);
  asf::PlanRequest req;
  req.graph = &g;
  req.marginals = &m;
  req.start = 0;
  req.goal = 2;
  planning::CriterionOptions o;
  planning::PathSearchOptions search;
  search.merge_radius = 0;
  auto r = planning::planBest(req, planning::Criterion::SumDopt, o, search);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, (std::vector<NodeId>{0, 1, 2}));
  o.tie_tolerance = 0;
  r = planning::planBest(req, planning::Criterion::SumDopt, o, search);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, (std::vector<NodeId>{0, 3, 2}));
  // A real difference is not a tie.
  m.node[3] *= 0.5;
  o.tie_tolerance = 1e-6;
  r = planning::planBest(req, planning::Criterion::SumDopt, o, search);
  EXPECT_EQ(r.nodes, (std::vector<NodeId>{0, 3, 2}));
}

// ---------------------------------------------------------------------------------------
// Criteria and recognition probabilities

TEST(Criteria, BaselinesFollowTheirDefinitions) {
  std::mt19937_64 rng(12);
  const RandomChain c = randomChain(rng, 4);
  const planning::PathModel path = planning::makePathModel(c.g, &c.m, c.path);
  planning::CriterionOptions o;
  double dopt = 0, dist = 0, work = 0;
  auto U = [&](int t, const Matrix3d& O) {
    return (O.inverse() + c.m.node[t].inverse()).inverse().determinant();
  };
  double prev = U(0, path.motion_cov[1]);
  for (int t = 0; t <= 4; ++t) {
    dopt += c.m.node[t].determinant();
    if (t == 0) continue;
    dist += (c.g.nodes[t].pose - c.g.nodes[t - 1].pose).norm();
    const double u = U(t, path.motion_cov[t]);
    work += std::max(0.0, u - prev);
    prev = u;
  }
  EXPECT_NEAR(planning::evaluatePath(planning::Criterion::SumDopt, path, o).cost, dopt, 1e-15);
  EXPECT_NEAR(planning::evaluatePath(planning::Criterion::Distance, path, o).cost, dist, 1e-12);
  EXPECT_NEAR(planning::evaluatePath(planning::Criterion::MechanicalWork, path, o).cost, work,
              1e-9 * std::max(work, 1e-12));
  const auto e = planning::evaluatePath(planning::Criterion::ExpectedUncertainty, path, o);
  EXPECT_NEAR(e.cost, e.expected.determinant(), 1e-18);
  EXPECT_EQ(e.label, "det(E[C])");
  EXPECT_EQ(e.missing_cross, 0u);
}

TEST(Criteria, RecognitionFileErrorsNameTheLine) {
  const auto dir = std::filesystem::temp_directory_path() / "asf_test_eu";
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "good.txt").string(), bad = (dir / "bad.txt").string();
  std::ofstream(good) << "# node p\n0 0.5\n\n3 1  # comment\n";
  std::ofstream(bad) << "0 0.5\n1 x\n";
  const auto m = planning::readRecognitionProbabilities(good);
  EXPECT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(m.at(3), 1.0);
  std::string msg = asf_test::errorOf<asf::InputError>(
      [&] { planning::readRecognitionProbabilities(bad); });
  EXPECT_TRUE(asf_test::has(msg, bad + ":2")) << msg;
  std::ofstream(bad) << "0 0.5\n1 1.5\n";
  msg = asf_test::errorOf<asf::InputError>([&] { planning::readRecognitionProbabilities(bad); });
  EXPECT_TRUE(asf_test::has(msg, ":2") && asf_test::has(msg, "outside")) << msg;
}

// ---------------------------------------------------------------------------------------
// asf plan

/// A loop: the short side 0-1-2-3 has weak edges (wheel odometry in a featureless zone),
/// the long side 0-4-5-6-7-8-9-3 strong ones.
std::string writeLoop() {
  const auto dir = std::filesystem::temp_directory_path() / "asf_test_eu";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "loop.g2o").string();
  const double xy[10][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {0, 1},
                            {0, 2}, {1, 2}, {2, 2}, {3, 2}, {3, 1}};
  std::ofstream f(path);
  for (int i = 0; i < 10; ++i) f << "VERTEX_SE2 " << i << " " << xy[i][0] << " " << xy[i][1] << " 0\n";
  auto edge = [&](int a, int b, double sd_xy, double sd_phi) {
    f << "EDGE_SE2 " << a << " " << b << " " << xy[b][0] - xy[a][0] << " " << xy[b][1] - xy[a][1]
      << " 0 " << 1 / (sd_xy * sd_xy) << " 0 0 " << 1 / (sd_xy * sd_xy) << " 0 "
      << 1 / (sd_phi * sd_phi) << "\n";
  };
  for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {2, 3}}) edge(a, b, 0.5, 0.3);
  for (auto [a, b] : {std::pair{0, 4}, {4, 5}, {5, 6}, {6, 7}, {7, 8}, {8, 9}, {9, 3}})
    edge(a, b, 0.01, 0.005);
  return path;
}

TEST(AsfPlan, ExpectedUncertaintyAvoidsTheWeakSideShortestTakesIt) {
  const std::string g2o = writeLoop();
  const std::vector<int> long_side{0, 4, 5, 6, 7, 8, 9, 3}, short_side{0, 1, 2, 3};
  const std::string png = (std::filesystem::temp_directory_path() / "asf_test_eu" / "plan.png").string();
  std::filesystem::remove(png);
  auto r = asf_test::runHost("plan --graph " + g2o + " --start 0 --goal 3 --planner "
                             "expected_uncertainty --json --image " + png, false);
  ASSERT_EQ(r.code, 0) << r.out;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["path"].get<std::vector<int>>(), long_side) << r.out;
  EXPECT_TRUE(std::filesystem::exists(png));
  for (const char* c : {"expected_uncertainty", "mechanical_work", "sum_dopt", "distance"})
    EXPECT_TRUE(j["costs"].contains(c)) << c << "\n" << r.out;
  EXPECT_NEAR(j["costs"]["distance"].get<double>(), 7, 1e-6);

  r = asf_test::runHost("plan --graph " + g2o + " --start 0 --goal 3 --planner shortest --json",
                        false);
  ASSERT_EQ(r.code, 0) << r.out;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["path"].get<std::vector<int>>(), short_side) << r.out;
  // Figs. 3.1-3.2 on the weak side: 3 steps, 2^3 relocalization sequences, 4 merged
  // hypotheses, at most 3 * 4 / 2 probability queries; relocalizing on the weak side is
  // uncertain, so E[C] is a mixture, and the enumeration of the sequences agrees.
  const auto& h = j["hypotheses"];
  EXPECT_EQ(h["steps"].get<int>(), 3) << h;
  EXPECT_EQ(h["sequences"].get<double>(), 8) << h;
  EXPECT_EQ(h["hypotheses"].get<int>(), 4) << h;
  EXPECT_GT(h["evaluations"].get<int>(), 0) << h;
  EXPECT_LE(h["evaluations"].get<int>(), 6) << h;
  EXPECT_EQ(h["checked_steps"].get<int>(), 3) << h;
  EXPECT_GE(h["checked_mixed_prefixes"].get<int>(), 1) << h;
  EXPECT_LT(h["relative_difference"].get<double>(), 1e-12) << h;

  // Human-readable output and a bad key.
  r = asf_test::runHost("plan --graph " + g2o + " --start 0 --goal 3 --planner "
                        "expected_uncertainty --set scalar=trace");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "0 4 5 6 7 8 9 3")) << r.out;
  r = asf_test::runHost("plan --graph " + g2o + " --start 0 --goal 3 --planner "
                        "expected_uncertainty --set no_such_key=1");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "no_such_key")) << r.out;
  r = asf_test::runHost("plan --graph " + g2o + " --start 0 --goal 42");
  EXPECT_NE(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "42")) << r.out;
  // A negative id is named as given, not wrapped around to 4294967295 (issue 20, item 7).
  r = asf_test::runHost("plan --graph " + g2o + " --start -1 --goal 3");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "node -1 does not exist")) << r.out;
  EXPECT_FALSE(asf_test::has(r.out, "4294967295")) << r.out;
}

}  // namespace
