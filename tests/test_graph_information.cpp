// Information of walks on graphs and certified optimal edge weights (graph/information.h):
// closed forms, eigen identities, brute force, the E trap on symmetric trees, the cvxopt
// cross-check, the exhaustive search of walks and `asf optimal`.
#include <asf/errors.h>
#include <asf/graph/families.h>
#include <asf/graph/information.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "test_util.h"

using namespace asf::graph;
using Eigen::VectorXd;

namespace {

Multigraph complete(int n) {
  Multigraph g;
  g.n = n;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) g.edges.push_back({a, b, 1});
  return g;
}

Multigraph path(int n) {
  Multigraph g;
  g.n = n;
  for (int i = 0; i + 1 < n; ++i) g.edges.push_back({i, i + 1, 1});
  return g;
}

Multigraph cycle(int n) {
  Multigraph g = path(n);
  g.edges.push_back({n - 1, 0, 1});
  return g;
}

// Centre 0, k hubs, l leaves per hub: symmetric tree whose mu_2 is repeated (k >= 3).
Multigraph starOfStars(int k, int l) {
  Multigraph g;
  g.n = 1 + k + k * l;
  int id = 1 + k;
  for (int a = 0; a < k; ++a) {
    g.edges.push_back({0, 1 + a, 1});
    for (int b = 0; b < l; ++b) g.edges.push_back({1 + a, id++, 1});
  }
  return g;
}

// Random spanning tree plus distinct extra edges: connected simple graph (seeded).

std::string graphLine(const Multigraph& g) {
  std::string s = std::to_string(g.n) + " " + std::to_string(g.m());
  for (const auto& e : g.edges) s += " " + std::to_string(e.u + 1) + "-" + std::to_string(e.v + 1);
  return s;
}

VectorXd uniform(const Multigraph& g) { return VectorXd::Constant(g.m(), 1.0 / g.m()); }

const double kE = kCriterionE;

}  // namespace

TEST(GraphInformation, ParseCriterionAndInputErrors) {
  EXPECT_EQ(parseCriterion("D"), 0.0);
  EXPECT_EQ(parseCriterion("a"), -1.0);
  EXPECT_EQ(parseCriterion("T"), 1.0);
  EXPECT_EQ(parseCriterion("E"), kE);
  EXPECT_EQ(parseCriterion("p=-2"), -2.0);
  EXPECT_EQ(parseCriterion("0.5"), 0.5);
  EXPECT_EQ(criterionName(-2.0), "p=-2");
  EXPECT_TRUE(
      asf_test::has(asf_test::errorOf<asf::InputError>([] { parseCriterion("X"); }), "'X'"));
  EXPECT_THROW(parseCriterion("2"), asf::InputError);  // p > 1 is not an information function
  const Multigraph g = complete(4);
  EXPECT_THROW(information(g, VectorXd::Ones(5), 0), asf::InputError);
  VectorXd neg = VectorXd::Ones(6);
  neg[2] = -1;
  EXPECT_TRUE(
      asf_test::has(asf_test::errorOf<asf::InputError>([&] { information(g, neg, 0); }), "edge 2"));
  EXPECT_THROW(optimalDesign(g, 1.5), asf::InputError);
}

// Sum, product (matrix-tree theorem) and closed-form spectra of the Laplacian.
TEST(GraphInformation, LaplacianEigenIdentities) {
  const Multigraph k4 = complete(4);
  const VectorXd ones = VectorXd::Ones(6);
  const VectorXd mu = reducedSpectrum(k4, ones);
  ASSERT_EQ(mu.size(), 3);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(mu[i], 4.0, 1e-12);
  // K4 has 16 spanning trees: prod mu = n * t(G) = 64, D = 64^(1/3) = 4.
  EXPECT_NEAR(information(k4, ones, kCriterionD).value, 4.0, 1e-12);

  const Multigraph g = asf::graph::randomConnectedGraph(12, 25, 3);
  std::mt19937 r(5);
  VectorXd x(g.m());
  for (int j = 0; j < g.m(); ++j) x[j] = std::uniform_real_distribution<double>(0.1, 2)(r);
  const VectorXd s = reducedSpectrum(g, x);
  EXPECT_NEAR(s.sum(), 2 * x.sum(), 1e-10);  // trace L = 2 sum x
  // Against the eigenvalues of the full Laplacian: the same plus one zero.
  VectorXd full = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(laplacian(g, x)).eigenvalues();
  EXPECT_NEAR(full[0], 0, 1e-10);
  for (int i = 0; i < s.size(); ++i) EXPECT_NEAR(full[i + 1], s[i], 1e-10);
  // T is 2 sum x / (n - 1); T >= D >= A >= E (power means increase with p).
  const double T = information(g, x, kCriterionT).value, D = information(g, x, kCriterionD).value,
               A = information(g, x, kCriterionA).value, E = information(g, x, kE).value;
  EXPECT_NEAR(T, 2 * x.sum() / 11, 1e-12);
  EXPECT_GT(T, D);
  EXPECT_GT(D, A);
  EXPECT_GT(A, E);
  EXPECT_NEAR(E, s[0], 1e-14);
  EXPECT_NEAR(A, 11 / (s.cwiseInverse().sum()), 1e-12);  // 1 / mean(1/mu)
  // Cycle C_n: mu = 2 - 2 cos(2 pi k / n); E = 2 - 2 cos(2 pi / n).
  const Multigraph c7 = cycle(7);
  EXPECT_NEAR(information(c7, VectorXd::Ones(7), kE).value, 2 - 2 * std::cos(2 * M_PI / 7), 1e-12);
  // Self-loops contribute nothing; parallel edges add.
  Multigraph m = path(3);
  m.edges.push_back({1, 1, 1});
  m.edges.push_back({0, 1, 1});
  EXPECT_NEAR(laplacian(m, VectorXd::Ones(4))(0, 1), -2, 0);
  EXPECT_NEAR(laplacian(m, VectorXd::Ones(4))(1, 1), 3, 0);
}

TEST(GraphInformation, DisconnectedIsZeroWithFlagNeverNaN) {
  Multigraph g;
  g.n = 6;
  g.edges = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}, {3, 4, 1}, {4, 5, 1}};
  for (double p : {1.0, 0.0, -1.0, -3.0, kE}) {
    const Information i = information(g, VectorXd::Ones(5), p);
    EXPECT_FALSE(i.connected);
    EXPECT_EQ(i.value, 0.0);
    EXPECT_EQ(i.rate, 0.0);
    const OptimalDesign o = optimalDesign(g, p);
    EXPECT_FALSE(o.connected);
    EXPECT_EQ(o.value, 0.0);
    EXPECT_EQ(o.upper_bound, 0.0);
    EXPECT_FALSE(std::isnan(o.relative_gap));
  }
  // A connected graph whose traversed edges do not span it.
  const Multigraph k4 = complete(4);
  VectorXd x = VectorXd::Ones(6);
  x[0] = x[1] = x[2] = 0;  // node 0 untouched
  EXPECT_FALSE(information(k4, x, 0).connected);
  EXPECT_EQ(information(k4, x, 0).value, 0.0);
  x[0] = 1;
  EXPECT_TRUE(information(k4, x, 0).connected);
  // One node, or no edges: nothing to measure.
  Multigraph one;
  one.n = 1;
  EXPECT_FALSE(optimalDesign(one, 0).connected);
}

TEST(GraphInformation, SparseDOptimalityByTheMatrixTreeTheoremEqualsTheDenseSpectrum) {
  // Closed forms: a path has one spanning tree (prod mu = n), K_n has n^(n-2) (prod = n^(n-1)).
  for (int n : {2, 5, 12}) {
    EXPECT_NEAR(dOptimalitySparse(path(n), VectorXd::Ones(n - 1)), std::pow(n, 1.0 / (n - 1)),
                1e-12);
    const Multigraph k = complete(n);
    EXPECT_NEAR(dOptimalitySparse(k, VectorXd::Ones(k.m())), n, 1e-10 * n);
  }
  // Random weighted multigraphs with parallel edges and self-loops against the eigenvalues.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> w(0.1, 5);
  for (int trial = 0; trial < 20; ++trial) {
    Multigraph g = path(3 + trial);
    for (int k = 0; k < 2 * g.n; ++k) {
      const int u = static_cast<int>(rng() % g.n), v = static_cast<int>(rng() % g.n);
      g.edges.push_back({u, v, 1, w(rng)});
    }
    VectorXd x(g.m());
    for (int j = 0; j < g.m(); ++j) x[j] = w(rng);
    const double dense = information(g, x, kCriterionD).value;
    EXPECT_NEAR(dOptimalitySparse(g, x), dense, 1e-9 * dense) << "trial " << trial;
  }
  // Not spanning: zero, as the dense criterion.
  Multigraph g;
  g.n = 4;
  g.edges = {{0, 1, 1}, {2, 3, 1}};
  EXPECT_EQ(dOptimalitySparse(g, VectorXd::Ones(2)), 0.0);
  const Multigraph k4 = complete(4);
  VectorXd x = VectorXd::Ones(6);
  x[0] = x[1] = x[2] = 0;
  EXPECT_EQ(dOptimalitySparse(k4, x), 0.0);
  Multigraph one;
  one.n = 1;
  EXPECT_EQ(dOptimalitySparse(one, VectorXd()), 0.0);
}

TEST(GraphInformation, WalkInformationRate) {
  const Multigraph k4 = complete(4);  // edges 0:0-1 1:0-2 2:0-3 3:1-2 4:1-3 5:2-3
  // Closed walk 0-1-2-0-3-1 ... : edge sequence must chain.
  const std::vector<int> walk{0, 3, 1, 2, 4};  // 0-1, 1-2, 2-0, 0-3, 3-1
  const VectorXd c = walkEdgeCounts(k4, walk);
  EXPECT_EQ(c.sum(), 5);
  EXPECT_EQ(c[5], 0);
  const Information i = walkInformation(k4, walk, kCriterionD);
  EXPECT_TRUE(i.connected);
  EXPECT_NEAR(i.rate, i.value / 5, 1e-15);
  EXPECT_NEAR(i.value, information(k4, c, kCriterionD).value, 1e-15);
  // Scale invariance: the walk twice has the same rate.
  std::vector<int> twice = walk;
  twice.insert(twice.end(), {3, 1, 2, 4, 0});  // continues from node 1: 1-2, 2-0, 0-3, 3-1, 1-0
  const VectorXd c2 = walkEdgeCounts(k4, twice);
  EXPECT_NEAR(walkInformation(k4, twice, kCriterionA).value, information(k4, c2, kCriterionA).value,
              1e-15);
  EXPECT_NEAR(information(k4, 2 * c, kCriterionA).rate, information(k4, c, kCriterionA).rate,
              1e-14);
  // Every edge once (not a walk on K4, but counts): rate = optimum 2/3, efficiency 1.
  EXPECT_NEAR(efficiency(k4, VectorXd::Ones(6), kE, 2.0 / 3), 1.0, 1e-12);
  // Not a walk: 0-1 then 2-3.
  EXPECT_TRUE(asf_test::has(asf_test::errorOf<asf::InputError>([&] {
                              walkEdgeCounts(k4, {0, 5});
                            }),
                            "position 1"));
  EXPECT_THROW(walkEdgeCounts(k4, {0, 6}), asf::InputError);
}

// K_n: uniform weights are optimal for every criterion and every optimum is 2/(n-1).
TEST(GraphInformation, CompleteGraphEveryCriterionEqual) {
  for (int n : {4, 6, 9}) {
    const Multigraph g = complete(n);
    for (double p : {0.5, 0.0, -1.0, -2.5, kE}) {
      SCOPED_TRACE("n=" + std::to_string(n) + " " + criterionName(p));
      const OptimalDesign o = optimalDesign(g, p);
      EXPECT_TRUE(o.converged);
      EXPECT_NEAR(o.value, 2.0 / (n - 1), 1e-6 * 2.0 / (n - 1));
      EXPECT_GE(o.upper_bound, 2.0 / (n - 1) * (1 - 1e-12));
      EXPECT_NEAR(o.weights.sum(), 1.0, 1e-12);
      if (p != kE) {  // the E optimum is not unique on K_n (only lambda_2 is)
        EXPECT_LT((o.weights - uniform(g)).cwiseAbs().maxCoeff(), 1e-4);
      }
      EXPECT_NEAR(information(g, uniform(g), p).value, 2.0 / (n - 1), 1e-12);
    }
  }
}

// Trees: D is uniform in closed form (prod mu = n prod x_j); the path's E optimum is
// Fiedler's x_j ~ j (n - j) with value 12 / (n (n^2 - 1)); a star is uniform by symmetry.
TEST(GraphInformation, TreesClosedForms) {
  for (int n : {5, 8}) {
    const Multigraph p = path(n);
    const OptimalDesign d = optimalDesign(p, kCriterionD);
    EXPECT_NEAR(d.value, std::pow(n, 1.0 / (n - 1)) / (n - 1), 1e-9);
    EXPECT_LT((d.weights - uniform(p)).cwiseAbs().maxCoeff(), 1e-6);
    const OptimalDesign e = optimalDesign(p, kE);
    EXPECT_NEAR(e.value, 12.0 / (n * (n * n - 1.0)), 1e-5 * e.value);
    double s = 0;
    for (int j = 1; j < n; ++j) s += j * (n - j);
    for (int j = 1; j < n; ++j) EXPECT_NEAR(e.weights[j - 1], j * (n - j) / s, 1e-4);
  }
  Multigraph star;
  star.n = 6;
  for (int v = 1; v < 6; ++v) star.edges.push_back({0, v, 1});
  for (double q : {0.0, -1.0, kE}) {
    const OptimalDesign o = optimalDesign(star, q);
    EXPECT_NEAR(o.value, information(star, uniform(star), q).value, 1e-6 * o.value);
  }
  EXPECT_NEAR(optimalDesign(star, kE).value, 0.2, 1e-6);  // star K_1,5: mu_2 = 1/5
}

// Brute force on the simplex: a fine grid can not beat the certified upper bound and gets
// within the grid resolution of the optimum.
TEST(GraphInformation, BruteForceGridSmallGraph) {
  Multigraph paw;  // triangle 0-1-2 with a pendant 2-3
  paw.n = 4;
  paw.edges = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}, {2, 3, 1}};
  const int steps = 120;
  for (double p : {0.0, -1.0, kE}) {
    SCOPED_TRACE(criterionName(p));
    const OptimalDesign o = optimalDesign(paw, p);
    double best = 0;
    VectorXd x(4);
    for (int a = 0; a <= steps; ++a)
      for (int b = 0; a + b <= steps; ++b)
        for (int c = 0; a + b + c <= steps; ++c) {
          x << a, b, c, steps - a - b - c;
          best = std::max(best, information(paw, x / steps, p).value);
        }
    EXPECT_LE(best, o.upper_bound * (1 + 1e-12));
    EXPECT_LE(o.relative_gap, p == kE ? 1e-5 : 1e-6);
    EXPECT_GE(o.value, best * (1 - 1e-12));  // no grid point beats the solver
    EXPECT_GT(best, o.value * 0.98);         // and the grid gets close to it
  }
}

// The E trap: on a symmetric tree with uniform weights mu_2 is repeated. Uniform is not
// optimal, and its best eigenspace certificate says so; the certified optimum is higher.
TEST(GraphInformation, ETrapSymmetricTreeIsNotCertifiedAtUniform) {
  struct Case {
    int k, l;
    double min_ratio;
  };
  for (const Case& c : {Case{3, 2, 1.2}, Case{3, 3, 1.4}}) {
    const Multigraph g = starOfStars(c.k, c.l);
    const VectorXd u = uniform(g);
    const VectorXd mu = reducedSpectrum(g, u);
    ASSERT_NEAR(mu[0], mu[1], 1e-12 * mu[1]) << "mu_2 must be repeated for the trap";
    const double lambda_uniform = mu[0];
    const double bound_at_uniform = certificateBound(g, u, kE);
    EXPECT_GT(bound_at_uniform, 1.5 * lambda_uniform);  // not certified, by far
    const OptimalDesign o = optimalDesign(g, kE);
    EXPECT_TRUE(o.converged);
    EXPECT_LE(o.relative_gap, 1e-5);
    EXPECT_GT(o.value, c.min_ratio * lambda_uniform);
    // Certified value 1 / (k (4 l + 1)) (a regression number, proven by the dual below).
    EXPECT_NEAR(o.value, 1.0 / (c.k * (4 * c.l + 1)), 1e-5 * o.value);
    // The dual W is a valid certificate on its own.
    EXPECT_NEAR(dualBoundE(g, o.dual), o.upper_bound, 1e-12 * o.upper_bound);
    EXPECT_LT(efficiency(g, VectorXd::Ones(g.m()), kE, o.value), 1 / c.min_ratio);
    // At the optimum the certificate agrees (the optimum is where it is tight).
    EXPECT_LE(certificateBound(g, o.weights, kE, 1e-3), o.value * (1 + 1e-3));
  }
}

TEST(GraphInformation, CertifiedGapsOnRandomGraphs) {
  for (auto [n, m, seed] : {std::tuple{40, 120, 11u}, std::tuple{100, 297, 1u}}) {
    const Multigraph g = asf::graph::randomConnectedGraph(n, m, seed);
    double prev = 0;
    for (double p : {kE, -1.0, 0.0}) {  // optima increase with p
      SCOPED_TRACE("n=" + std::to_string(n) + " " + criterionName(p));
      const OptimalDesign o = optimalDesign(g, p);
      EXPECT_TRUE(o.converged);
      EXPECT_LE(o.relative_gap, p == kE ? 1e-5 : 1e-6);
      EXPECT_GE(o.upper_bound, o.value);
      EXPECT_NEAR(o.weights.sum(), 1, 1e-12);
      EXPECT_GE(o.weights.minCoeff(), 0);
      EXPECT_NEAR(information(g, o.weights, p).value, o.value, 1e-12 * o.value);
      EXPECT_GT(o.value, information(g, uniform(g), p).value);
      EXPECT_GT(o.value, prev);
      prev = o.value;
      // The bound recomputed from the weights alone (smooth) or from W (E).
      if (p == kE)
        EXPECT_NEAR(dualBoundE(g, o.dual), o.upper_bound, 1e-10 * o.upper_bound);
      else
        EXPECT_NEAR(certificateBound(g, o.weights, p), o.upper_bound, 1e-9 * o.upper_bound);
    }
  }
  // General p on a small graph.
  const Multigraph g = asf::graph::randomConnectedGraph(15, 30, 4);
  for (double p : {0.5, -2.0}) {
    const OptimalDesign o = optimalDesign(g, p);
    EXPECT_TRUE(o.converged) << criterionName(p);
    EXPECT_LE(o.relative_gap, 1e-6);
  }
  // p = 1: every x on the simplex has T = 2 / (n - 1).
  EXPECT_NEAR(optimalDesign(g, 1.0).value, 2.0 / 14, 1e-15);
}

// Regressions of the solver's code paths: graph 15 of the `asf optimal-eval` set stalled the A
// Newton iteration at gap 1.7e-6 (Armijo test below round-off; now decided by the
// certificate); the random 100/297 graphs fix zero weights in the Newton system (bordered
// solve) and take chord steps near the optimum. Every gap is the certified one.
TEST(GraphInformation, SolverPathsStayCertified) {
  const Multigraph g15 = asf::graph::generateFamily("mixed", 16, 120, 1)[15];
  const OptimalDesign a = optimalDesign(g15, -1.0);
  EXPECT_TRUE(a.converged);
  EXPECT_LE(a.relative_gap, 1e-6);
  EXPECT_NEAR(certificateBound(g15, a.weights, -1.0), a.upper_bound, 1e-9 * a.upper_bound);
  for (unsigned seed : {1u, 2u, 3u}) {
    const Multigraph g = asf::graph::randomConnectedGraph(100, 297, seed);
    for (double p : {0.0, -1.0, kE}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " " + criterionName(p));
      const OptimalDesign o = optimalDesign(g, p);
      EXPECT_TRUE(o.converged);
      EXPECT_LE(o.relative_gap, p == kE ? 1e-5 : 1e-6);
      EXPECT_NEAR(information(g, o.weights, p).value, o.value, 1e-12 * o.value);
      if (p == kE)
        EXPECT_NEAR(dualBoundE(g, o.dual), o.upper_bound, 1e-10 * o.upper_bound);
      else
        EXPECT_NEAR(certificateBound(g, o.weights, p), o.upper_bound, 1e-9 * o.upper_bound);
    }
  }
}

// DesignOptions::on_iteration: one report per iteration, in order, each a bracket of the
// optimum the solver then certifies (a report that lied would show a lower bound above the
// final upper bound or the reverse).
TEST(GraphInformation, IterationReportsBracketTheOptimum) {
  const Multigraph g = asf::graph::randomConnectedGraph(30, 70, 4);
  for (double p : {0.0, -1.0, kE}) {
    SCOPED_TRACE(criterionName(p));
    std::vector<int> its;
    std::vector<std::pair<double, double>> bounds;
    DesignOptions opt;
    opt.on_iteration = [&](int it, double lower, double upper) {
      its.push_back(it);
      bounds.emplace_back(lower, upper);
    };
    const OptimalDesign o = optimalDesign(g, p, opt);
    ASSERT_TRUE(o.converged);
    ASSERT_FALSE(its.empty());
    for (std::size_t i = 1; i < its.size(); ++i) EXPECT_EQ(its[i], its[i - 1] + 1);
    EXPECT_EQ(its.front(), p == kE ? 1 : 0);
    EXPECT_EQ(its.back(), o.iterations);
    for (const auto& [lower, upper] : bounds) {
      EXPECT_LE(lower, o.upper_bound * (1 + 1e-9));
      EXPECT_GE(upper, o.value * (1 - 1e-9));
    }
    if (p != kE) {  // smooth: the last report is the iterate returned
      EXPECT_DOUBLE_EQ(bounds.back().first, o.value);
      EXPECT_DOUBLE_EQ(bounds.back().second, o.upper_bound);
    }
  }
}

// Cross-check against an independent solver: Debian's python3-cvxopt (cp for D and A, the
// SDP for E), run by tests/scripts/graph_information_cvxopt.py.
TEST(GraphInformation, CrossCheckCvxopt) {
  if (std::system("/usr/bin/python3 -c 'import cvxopt' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with cvxopt (Debian python3-cvxopt) is not available";
  const std::string script =
      std::string(ASF_TEST_SOURCE_DIR) + "/tests/scripts/graph_information_cvxopt.py";
  using asf::graph::randomConnectedGraph;
  std::vector<Multigraph> graphs{randomConnectedGraph(8, 12, 21), randomConnectedGraph(10, 18, 22),
                                 randomConnectedGraph(12, 20, 23), starOfStars(3, 2)};
  for (const Multigraph& g : graphs) {
    const std::string cmd = "/usr/bin/python3 " + script + " '" + graphLine(g) + "'";
    FILE* f = popen(cmd.c_str(), "r");
    ASSERT_NE(f, nullptr);
    std::string out;
    char buf[4096];
    while (std::fgets(buf, sizeof buf, f)) out += buf;
    ASSERT_EQ(pclose(f), 0) << cmd << "\n" << out;
    const auto j = nlohmann::json::parse(out);
    for (auto [name, p, tol] :
         {std::tuple{"D", 0.0, 1e-6}, std::tuple{"A", -1.0, 1e-6}, std::tuple{"E", kE, 1e-5}}) {
      SCOPED_TRACE(graphLine(g) + " " + name);
      const OptimalDesign o = optimalDesign(g, p);
      const double cvx = j[name].get<double>();
      EXPECT_NEAR(o.value, cvx, tol * cvx);
      std::printf(
          "cvxopt cross-check n=%d m=%d %s: asf %.10g (gap %.2g) cvxopt %.10g rel.diff %.2g\n", g.n,
          g.m(), name, o.value, o.relative_gap, cvx, std::abs(o.value - cvx) / cvx);
      // cvxopt's x is feasible, so its value can not exceed our certified bound.
      EXPECT_LE(cvx, o.upper_bound * (1 + 1e-9));
    }
  }
}

// Figures 5.6 - 5.8 on K4: every edge once (d = 6) reaches the optimum 2/3 as a multiset but
// not as a walk (four odd nodes); every edge twice (d = 12) is a closed walk reaching it.
TEST(GraphInformation, ExhaustiveSearchK4) {
  const Multigraph k4 = complete(4);
  ExhaustiveOptions o;
  o.kind = TraversalKind::Multiset;
  o.max_d = 7;
  const ExhaustiveResult ms = exhaustiveSearch(k4, o);
  ASSERT_EQ(ms.d.size(), 7u);
  EXPECT_EQ(ms.candidates[5], 462u);  // C(6 + 5, 5) multisets of 6 out of 6 edges
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(ms.information(1, c), 0.0);  // d = 2 can not connect 4 nodes
    EXPECT_GT(ms.information(2, c), 0.0);  // d = 3: spanning trees
    EXPECT_NEAR(ms.rate(5, c), 2.0 / 3, 1e-12);
    EXPECT_NEAR(ms.information(5, c), 4.0, 1e-12);
    for (int i = 1; i < 7; ++i) EXPECT_GE(ms.information(i, c), ms.information(i - 1, c));
  }
  for (int i = 2; i < 7; ++i)  // T >= D >= A >= E
    for (int c = 1; c < 4; ++c) EXPECT_GE(ms.information(i, c - 1), ms.information(i, c) - 1e-12);

  o.kind = TraversalKind::Walk;
  o.max_d = 12;
  const ExhaustiveResult w = exhaustiveSearch(k4, o);
  EXPECT_LT(w.information(5, 1), 4.0 - 1e-6);  // no Euler trail on K4
  o.kind = TraversalKind::ClosedWalk;
  o.start = 0;
  const ExhaustiveResult cw = exhaustiveSearch(k4, o);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(cw.rate(11, c), 2.0 / 3, 1e-12);
  EXPECT_EQ(cw.information(0, 0), 0.0);  // d = 1 is not closed... and not connected
  // The best walk counts are real walks' counts: verify one against information().
  EXPECT_NEAR(information(k4, w.best[8][2], kCriterionA).value, w.information(8, 2), 1e-12);

  const std::string svg = ::testing::TempDir() + "/graph_information_k4.svg";
  writeExhaustiveSvg(cw, svg, "K4 closed walks", {2.0 / 3, 2.0 / 3, 2.0 / 3, 2.0 / 3});
  std::ifstream f(svg);
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(asf_test::has(text, "<svg"));
  EXPECT_TRUE(asf_test::has(text, "</svg>"));
  std::size_t lines = 0;
  for (std::size_t pos = 0; (pos = text.find("<polyline", pos)) != std::string::npos; ++pos)
    ++lines;
  EXPECT_EQ(lines, 8u);  // 4 criteria x 2 panels

  o.max_states = 10;
  EXPECT_THROW(exhaustiveSearch(k4, o), asf::Error);
}

TEST(GraphInformation, HostOptimalCommand) {
  const std::string dir = ::testing::TempDir();
  const std::string list = dir + "/graph_information_list.txt";
  {
    std::ofstream f(list);
    f << "# two graphs\n4 6 1-2 1-3 1-4 2-3 2-4 3-4\n\n" << graphLine(starOfStars(3, 2)) << "\n";
  }
  auto r = asf_test::runHost("optimal " + list + " --criteria D,A,E --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["index"], 2);
  EXPECT_EQ(j["n"], 4);
  for (const char* c : {"D", "A", "E"}) {
    EXPECT_NEAR(j["optimum"][c].get<double>(), 2.0 / 3, 1e-6) << c;
    EXPECT_NEAR(j["efficiency"]["uniform"][c].get<double>(), 1.0, 1e-5) << c;
    EXPECT_LE(j["relative_gap"][c].get<double>(), 1e-5) << c;
    EXPECT_EQ(j["weights"][c].size(), 6u);
  }
  r = asf_test::runHost("optimal " + list + " --index 4 --criteria E --json", false);
  ASSERT_EQ(r.code, 0) << r.out;
  j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["optimum"]["E"].get<double>(), 1.0 / 27, 1e-6);
  EXPECT_LT(j["efficiency"]["uniform"]["E"].get<double>(), 0.85);
  r = asf_test::runHost("optimal " + list + " --index 3");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(asf_test::has(r.out, ":3: no graph on that line")) << r.out;
  r = asf_test::runHost("optimal " + list + " --criteria Q");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(asf_test::has(r.out, "criterion 'Q'")) << r.out;
  r = asf_test::runHost("optimal " + list + " --criteria D");  // text output
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(asf_test::has(r.out, "uniform efficiency 100.00%")) << r.out;
}
