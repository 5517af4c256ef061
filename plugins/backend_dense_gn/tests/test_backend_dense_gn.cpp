// Tests of the dense_gn back-end against analytic and numeric oracles.
#include <asf/se2_edge.h>

#include <asf/backend.h>
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <random>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/backend_dense_gn.so");
  return i;
}

asf::framework::PluginHandle<asf::Backend> make(const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Backend>(info());
  h->configure(asf::Params::fromSpecs("dense_gn", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

using mrpt::poses::CPose2D;

Eigen::Matrix3d randomInformation(std::mt19937_64& rng, double scale = 100) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i / 3, i % 3) = u(rng);
  Eigen::Matrix3d W = A * A.transpose() + 0.5 * Eigen::Matrix3d::Identity();
  return scale * W;
}

asf::PoseEdge exactEdge(const asf::PoseGraph& truth, asf::NodeId i, asf::NodeId j,
                        const Eigen::Matrix3d& info) {
  asf::PoseEdge e;
  e.from = i;
  e.to = j;
  e.mean = truth.nodes[j].pose - truth.nodes[i].pose;
  e.information = info;
  return e;
}

/// Poses on a circle with edges i -> i+1 (closing the loop) and chords i -> i+3.
asf::PoseGraph circle(int n, std::mt19937_64& rng) {
  asf::PoseGraph g;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    g.addNode(CPose2D(3 * std::cos(t) + 1, 3 * std::sin(t) - 2, t + M_PI / 2));
  }
  for (int i = 0; i < n; ++i)
    g.addEdge(exactEdge(g, i, (i + 1) % n, randomInformation(rng)));
  for (int i = 0; i + 3 < n; i += 4) g.addEdge(exactEdge(g, i, i + 3, randomInformation(rng)));
  return g;
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

TEST(DenseGn, ErrorFollowsThePoseGraphConvention) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int k = 0; k < 200; ++k) {
    const CPose2D a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), z(u(rng), u(rng), u(rng));
    const CPose2D ref = (b - a) - z;  // mean^-1 (+) (from^-1 (+) to)
    const Eigen::Vector3d e = asf::se2::edgeError({a.x(), a.y(), a.phi()},
                                                      {b.x(), b.y(), b.phi()},
                                                      {z.x(), z.y(), z.phi()});
    EXPECT_NEAR(e.x(), ref.x(), 1e-9);
    EXPECT_NEAR(e.y(), ref.y(), 1e-9);
    EXPECT_NEAR(angleDiff(e.z(), ref.phi()), 0, 1e-9);
    EXPECT_LE(std::abs(e.z()), M_PI);
    asf::PoseGraph g;
    g.addNode(a);
    g.addNode(b);
    asf::PoseEdge pe;
    pe.from = 0;
    pe.to = 1;
    pe.mean = z;
    g.addEdge(pe);
    const Eigen::Vector3d fe = g.edgeError(pe);
    EXPECT_NEAR(fe.x(), e.x(), 1e-9);
    EXPECT_NEAR(fe.y(), e.y(), 1e-9);
    EXPECT_NEAR(angleDiff(fe.z(), e.z()), 0, 1e-9);
  }
}

TEST(DenseGn, JacobiansMatchNumericDifferentiation) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-4, 4);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d xi(u(rng), u(rng), u(rng)), xj(u(rng), u(rng), u(rng)),
        z(u(rng), u(rng), u(rng));
    const auto L = asf::se2::linearizeEdge(xi, xj, z);
    if (std::abs(L.e.z()) > M_PI - 1e-3) continue;  // wrap discontinuity
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[c] = h;
      const Eigen::Vector3d ni = (asf::se2::edgeError(xi + d, xj, z) -
                                  asf::se2::edgeError(xi - d, xj, z)) / (2 * h);
      const Eigen::Vector3d nj = (asf::se2::edgeError(xi, xj + d, z) -
                                  asf::se2::edgeError(xi, xj - d, z)) / (2 * h);
      EXPECT_LT((ni - L.Ji.col(c)).norm(), 1e-6) << "Ji col " << c << "\n" << L.Ji;
      EXPECT_LT((nj - L.Jj.col(c)).norm(), 1e-6) << "Jj col " << c << "\n" << L.Jj;
    }
    ++checked;
  }
  EXPECT_GT(checked, 150);
}

TEST(DenseGn, NoiseFreeLoopConvergesToTheTruth) {
  std::mt19937_64 rng(3);
  const asf::PoseGraph truth = circle(24, rng);
  asf::PoseGraph g = truth;
  std::normal_distribution<double> n01;
  for (std::size_t i = 1; i < g.size(); ++i)
    g.nodes[i].pose = CPose2D(g.nodes[i].pose.x() + 0.3 * n01(rng),
                              g.nodes[i].pose.y() + 0.3 * n01(rng),
                              g.nodes[i].pose.phi() + 0.2 * n01(rng));
  g.revision = 7;
  auto be = make();
  const double chi0 = g.chi2();
  const asf::OptimizeReport r = be->optimize(g);
  EXPECT_NEAR(r.initial_chi2, chi0, 1e-9 * chi0);
  EXPECT_GT(r.initial_chi2, 10.0);
  EXPECT_LT(r.final_chi2, 1e-12);
  EXPECT_NEAR(g.chi2(), r.final_chi2, 1e-12);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(g.revision, 8u);
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_NEAR(g.nodes[i].pose.x(), truth.nodes[i].pose.x(), 1e-6) << i;
    EXPECT_NEAR(g.nodes[i].pose.y(), truth.nodes[i].pose.y(), 1e-6) << i;
    EXPECT_NEAR(angleDiff(g.nodes[i].pose.phi(), truth.nodes[i].pose.phi()), 0, 1e-6) << i;
  }
  EXPECT_EQ(g.nodes[0].pose.x(), truth.nodes[0].pose.x());  // the gauge never moves
}

TEST(DenseGn, Chi2NeverIncreases) {
  std::mt19937_64 rng(4);
  asf::PoseGraph g = circle(30, rng);
  std::normal_distribution<double> n01;
  for (auto& e : g.edges)  // noisy measurements: the optimum has chi2 > 0
    e.mean = CPose2D(e.mean.x() + 0.05 * n01(rng), e.mean.y() + 0.05 * n01(rng),
                     e.mean.phi() + 0.05 * n01(rng));
  std::uniform_real_distribution<double> u(-5, 5);
  for (std::size_t i = 1; i < g.size(); ++i)  // a terrible initial guess
    g.nodes[i].pose = CPose2D(u(rng), u(rng), u(rng));
  auto be = make({{"max_iterations", "1"}});
  double prev = g.chi2();
  const double first = prev;
  for (int it = 0; it < 60; ++it) {
    const auto r = be->optimize(g);
    EXPECT_NEAR(r.initial_chi2, prev, 1e-9 * prev);
    EXPECT_LE(r.final_chi2, r.initial_chi2);
    EXPECT_NEAR(g.chi2(), r.final_chi2, 1e-9 * std::max(1.0, r.final_chi2));
    prev = g.chi2();
  }
  EXPECT_LT(prev, 0.5 * first);
  auto full = make();
  const auto r = full->optimize(g);
  EXPECT_LE(r.final_chi2, r.initial_chi2);
}

TEST(DenseGn, FixedNodesStayAndTrivialGraphsAreNoOps) {
  std::mt19937_64 rng(5);
  asf::PoseGraph g = circle(8, rng);
  for (auto& n : g.nodes) n.pose = CPose2D(n.pose.x() + 0.1, n.pose.y(), n.pose.phi());
  g.fixed = {3, 5};
  const asf::PoseGraph before = g;
  auto be = make();
  const auto r = be->optimize(g);
  EXPECT_LT(r.final_chi2, r.initial_chi2);
  for (asf::NodeId i : {0u, 3u, 5u}) {
    EXPECT_EQ(g.nodes[i].pose.x(), before.nodes[i].pose.x()) << i;
    EXPECT_EQ(g.nodes[i].pose.phi(), before.nodes[i].pose.phi()) << i;
  }
  asf::PoseGraph empty, one;
  one.addNode(CPose2D(1, 2, 3));
  EXPECT_EQ(be->optimize(empty).final_chi2, 0);
  be->optimize(one);
  EXPECT_EQ(one.revision, 0u);
  EXPECT_EQ(one.nodes[0].pose.x(), 1);
  EXPECT_FALSE(be->marginals(empty).valid());
  const auto m1 = be->marginals(one);
  ASSERT_EQ(m1.node.size(), 1u);
  EXPECT_TRUE(m1.node[0].isZero());
}

TEST(DenseGn, TwoNodeMarginalIsTheRotatedEdgeCovariance) {
  std::mt19937_64 rng(6);
  const CPose2D z(1.0, 0.5, 0.7);
  asf::PoseGraph g;
  g.addNode(CPose2D());
  g.addNode(z);
  asf::PoseEdge e;
  e.from = 0;
  e.to = 1;
  e.mean = z;
  e.information = randomInformation(rng);
  g.addEdge(e);
  g.revision = 3;
  auto be = make();
  const asf::Marginals m = be->marginals(g, {{0, 1}, {1, 1}});
  ASSERT_EQ(m.node.size(), 2u);
  EXPECT_EQ(m.graph_revision, 3u);
  EXPECT_TRUE(m.node[0].isZero());
  // x1 = z (+) noise in z's frame: Cov(x1) = R Omega^-1 R^T, R = blockdiag(Rot(z.phi), 1).
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R.topLeftCorner<2, 2>() << std::cos(0.7), -std::sin(0.7), std::sin(0.7), std::cos(0.7);
  const Eigen::Matrix3d expect = R * e.information.inverse() * R.transpose();
  EXPECT_TRUE(m.node[1].isApprox(expect, 1e-9)) << m.node[1] << "\nvs\n" << expect;
  EXPECT_TRUE(m.cross.at({0, 1}).isZero());
  EXPECT_TRUE(m.cross.at({1, 1}).isApprox(m.node[1], 1e-12));

  // Without rotation it is exactly the inverse information.
  g.nodes[1].pose = CPose2D(1.0, 0.5, 0);
  g.edges[0].mean = CPose2D(1.0, 0.5, 0);
  EXPECT_TRUE(be->marginals(g).node[1].isApprox(e.information.inverse(), 1e-9));
}

TEST(DenseGn, ChainMarginalsEqualFirstOrderPropagation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  asf::PoseGraph g;
  g.addNode(CPose2D());
  std::vector<Eigen::Matrix3d> P{Eigen::Matrix3d::Zero()};
  std::vector<Eigen::Matrix3d> F;  // F[k] = d x_{k+1} / d x_k
  for (int k = 0; k < 7; ++k) {
    const CPose2D prev = g.nodes.back().pose;
    const CPose2D zk(0.5 + 0.5 * u(rng), 0.3 * u(rng), 0.8 * u(rng));
    asf::PoseEdge e;
    e.from = k;
    e.to = k + 1;
    e.mean = zk;
    e.information = randomInformation(rng, 50);
    g.addNode(prev + zk);
    g.addEdge(e);
    // x_{k+1} = x_k (+) z_k (+) eps, eps ~ N(0, Omega^-1) in the frame of x_{k+1} (the g2o
    // error convention): J1 = d/dx_k, J2 = d/d eps = blockdiag(Rot(phi_{k+1}), 1).
    const double c = std::cos(prev.phi()), s = std::sin(prev.phi());
    const double c1 = std::cos(prev.phi() + zk.phi()), s1 = std::sin(prev.phi() + zk.phi());
    Eigen::Matrix3d J1 = Eigen::Matrix3d::Identity(), J2 = Eigen::Matrix3d::Identity();
    J1(0, 2) = -s * zk.x() - c * zk.y();
    J1(1, 2) = c * zk.x() - s * zk.y();
    J2.topLeftCorner<2, 2>() << c1, -s1, s1, c1;
    P.push_back(J1 * P.back() * J1.transpose() +
                J2 * e.information.inverse() * J2.transpose());
    F.push_back(J1);
  }
  auto be = make();
  const asf::Marginals m = be->marginals(g, {{2, 6}, {6, 2}, {0, 4}});
  for (std::size_t i = 0; i < g.size(); ++i)
    EXPECT_TRUE(m.node[i].isApprox(P[i], 1e-8) || (P[i].isZero() && m.node[i].isZero()))
        << i << "\n" << m.node[i] << "\nvs\n" << P[i];
  // Cov(x6, x2) = F5 F4 F3 F2 P2 for a chain.
  const Eigen::Matrix3d Phi = F[5] * F[4] * F[3] * F[2];
  EXPECT_TRUE(m.cross.at({6, 2}).isApprox(Phi * P[2], 1e-8));
  EXPECT_TRUE(m.cross.at({2, 6}).isApprox(m.cross.at({6, 2}).transpose(), 1e-12));
  EXPECT_TRUE(m.cross.at({0, 4}).isZero());
  for (const auto& b : m.node) {
    EXPECT_TRUE(b.isApprox(b.transpose(), 1e-12) || b.isZero());
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(b).eigenvalues().minCoeff(),
              -1e-12);
  }
}

TEST(DenseGn, LoopMarginalsAreSmallerThanTheChainsAndCrossBlocksConsistent) {
  std::mt19937_64 rng(8);
  asf::PoseGraph loop = circle(12, rng);
  asf::PoseGraph chain = loop;
  chain.edges.clear();
  for (const auto& e : loop.edges)
    if (e.to == e.from + 1) chain.edges.push_back(e);
  auto be = make();
  const auto ml = be->marginals(loop, {{3, 9}, {9, 3}});
  const auto mc = be->marginals(chain);
  // Extra constraints can only shrink covariances (Loewner order).
  const Eigen::Matrix3d d = mc.node[11] - ml.node[11];
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(d).eigenvalues().minCoeff(), 0);
  EXPECT_TRUE(ml.cross.at({3, 9}).isApprox(ml.cross.at({9, 3}).transpose(), 1e-12));
}

TEST(DenseGn, DisconnectedNodeHasNoCovariance) {
  std::mt19937_64 rng(9);
  asf::PoseGraph g;
  for (int i = 0; i < 4; ++i) g.addNode(CPose2D(i, 0, 0));
  g.addEdge(exactEdge(g, 0, 1, randomInformation(rng)));
  g.addEdge(exactEdge(g, 2, 3, randomInformation(rng)));
  auto be = make();
  try {
    be->marginals(g);
    FAIL() << "no exception";
  } catch (const asf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("node 2"), std::string::npos) << e.what();
  }
  // Anchored by a fixed node, the second component has a covariance.
  g.fixed = {2};
  const auto m = be->marginals(g);
  EXPECT_TRUE(m.node[2].isZero());
  EXPECT_GT(m.node[3].trace(), 0);
  EXPECT_THROW(be->marginals(g, {{0, 7}}), asf::Error);
}

TEST(DenseGn, RefusesGraphsAboveMaxNodes) {
  std::mt19937_64 rng(10);
  asf::PoseGraph g = circle(6, rng);
  auto be = make({{"max_nodes", "5"}});
  try {
    be->optimize(g);
    FAIL() << "no exception";
  } catch (const asf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("sparse"), std::string::npos) << e.what();
  }
  EXPECT_THROW(be->marginals(g), asf::Error);
}

}  // namespace
