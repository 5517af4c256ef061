/// \file backend_tests.cpp
/// Conformance tests of `backend` plugins (see backend.h), on a seeded noisy loop graph.
#include <asf/errors.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "kit.h"
#include "synthetic.h"

namespace asf::conformance::detail {

using mrpt::poses::CPose2D;

namespace {

constexpr std::uint32_t kGraphSeed = 7;
const std::vector<std::pair<NodeId, NodeId>> kCross = {{3, 7}, {7, 3}, {0, 5}};

bool samePoseExactly(const CPose2D& a, const CPose2D& b) {
  return a.x() == b.x() && a.y() == b.y() && a.phi() == b.phi();
}

bool anyMoved(const PoseGraph& a, const PoseGraph& b) {
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (!samePoseExactly(a.nodes[i].pose, b.nodes[i].pose)) return true;
  return false;
}

double maxAbs(const Eigen::Matrix3d& m) { return m.cwiseAbs().maxCoeff(); }

}  // namespace

Trace standardRun(Backend& p) {
  Trace tr;
  PoseGraph g = makeNoisyLoop(kGraphSeed);
  const OptimizeReport r = p.optimize(g);
  tr.num("report.initial_chi2", r.initial_chi2);
  tr.num("report.final_chi2", r.final_chi2);
  tr.num("report.iterations", r.iterations);
  tr.num("report.converged", r.converged);
  tr.num("revision", static_cast<double>(g.revision));
  for (std::size_t i = 0; i < g.size(); ++i)
    tr.pose("node[" + std::to_string(i) + "]", g.nodes[i].pose);
  const Marginals m = p.marginals(g, kCross);
  tr.num("marginals.nodes", static_cast<double>(m.node.size()));
  for (std::size_t i = 0; i < m.node.size(); ++i)
    tr.mat("cov[" + std::to_string(i) + "]", m.node[i]);
  for (const auto& [ij, c] : m.cross)
    tr.mat("cross[" + std::to_string(ij.first) + "," + std::to_string(ij.second) + "]", c);
  return tr;
}

namespace {

/// optimize() may move poses, nothing else: nodes' ids and timestamps, the edges and
/// graph.fixed stay as they were, and the poses stay finite.
void expectOnlyPosesChanged(const PoseGraph& before, const PoseGraph& g) {
  ASSERT_EQ(g.size(), before.size()) << "optimize() added or removed nodes";
  ASSERT_EQ(g.edges.size(), before.edges.size()) << "optimize() added or removed edges";
  EXPECT_EQ(g.fixed, before.fixed) << "optimize() changed graph.fixed";
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g.nodes[i].id, before.nodes[i].id) << "node " << i << " id changed";
    EXPECT_EQ(g.nodes[i].timestamp, before.nodes[i].timestamp)
        << "node " << i << " timestamp changed";
    const CPose2D& p = g.nodes[i].pose;
    EXPECT_TRUE(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi()))
        << "node " << i << " pose not finite";
  }
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    const PoseEdge &a = g.edges[i], &b = before.edges[i];
    EXPECT_TRUE(a.from == b.from && a.to == b.to && a.kind == b.kind &&
                samePoseExactly(a.mean, b.mean) && a.information == b.information)
        << "edge " << i << " was modified";
  }
}

/// optimize(): no-ops, chi2, structure, errors, fixed nodes.
void registerOptimizeTests(const InfoPtr& info) {
  using T = Backend;

  addTest<T>(info, "empty_and_single_node_graphs_are_no_ops", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    {
      SCOPED_TRACE("empty graph");
      PoseGraph g;
      g.revision = 5;
      h->optimize(g);
      EXPECT_TRUE(g.empty());
      EXPECT_TRUE(g.edges.empty());
      EXPECT_EQ(g.revision, 5u) << "revision changed on an empty graph";
    }
    {
      SCOPED_TRACE("single node");
      PoseGraph g;
      g.addNode(CPose2D(), 1.0);
      g.revision = 5;
      h->optimize(g);
      ASSERT_EQ(g.size(), 1u);
      EXPECT_TRUE(samePoseExactly(g.nodes[0].pose, CPose2D())) << "node 0 moved";
      EXPECT_EQ(g.revision, 5u) << "revision changed on a single-node graph";
      const Marginals m = h->marginals(g);
      ASSERT_EQ(m.node.size(), 1u) << "marginals(): one block per node";
      EXPECT_LE(maxAbs(m.node[0]), 1e-6) << "node 0 (the gauge) must have zero "
                                            "covariance:\n"
                                         << m.node[0];
    }
  });

  addTest<T>(info, "optimize_never_increases_chi2_and_keeps_structure", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               PoseGraph g = makeNoisyLoop(kGraphSeed);
               const PoseGraph before = g;
               const double chi2_before = before.chi2();
               const OptimizeReport r = h->optimize(g);
               const double chi2_after = g.chi2();
               EXPECT_LE(chi2_after, chi2_before * (1 + 1e-9) + 1e-12)
                   << "chi2 of the graph went up (g2o convention, PoseGraph::chi2())";
               EXPECT_TRUE(std::isfinite(r.final_chi2) && std::isfinite(r.initial_chi2))
                   << "report chi2 not finite";
               EXPECT_LE(r.final_chi2, r.initial_chi2 * (1 + 1e-9) + 1e-12)
                   << "report: final chi2 above initial chi2";
               expectOnlyPosesChanged(before, g);
               if (::testing::Test::HasFatalFailure()) return;
               EXPECT_TRUE(samePose(g.nodes[0].pose, before.nodes[0].pose, 1e-9))
                   << "node 0 (the gauge) moved to " << g.nodes[0].pose;
               const bool moved = anyMoved(before, g);
               if (moved)
                 EXPECT_NE(g.revision, before.revision) << "poses moved but revision unchanged";
               else
                 EXPECT_EQ(g.revision, before.revision) << "revision changed but no pose moved";
             });

  addTest<T>(info, "a_graph_with_non_finite_chi2_is_an_error", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    PoseGraph g = makeNoisyLoop(kGraphSeed);
    g.nodes[3].pose = CPose2D(1e308, -1e308, 0);  // its residuals overflow
    ASSERT_FALSE(std::isfinite(g.chi2()));
    EXPECT_THROW(h->optimize(g), asf::Error)
        << "optimize() accepted a graph whose chi2 is " << g.chi2();
  });

  addTest<T>(info, "fixed_nodes_are_held", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    PoseGraph g = makeNoisyLoop(kGraphSeed);
    g.fixed = {10};
    const PoseGraph before = g;
    h->optimize(g);
    ASSERT_EQ(g.size(), before.size());
    EXPECT_TRUE(samePose(g.nodes[0].pose, before.nodes[0].pose, 1e-9)) << "node 0 moved";
    EXPECT_TRUE(samePose(g.nodes[10].pose, before.nodes[10].pose, 1e-9))
        << "node 10 is in graph.fixed but moved from " << before.nodes[10].pose << " to "
        << g.nodes[10].pose;
    EXPECT_LE(g.chi2(), before.chi2() * (1 + 1e-9) + 1e-12);
  });
}

/// marginals(): symmetric PSD blocks, the gauge, cross blocks, disconnected nodes.
void registerMarginalTests(const InfoPtr& info) {
  using T = Backend;

  addTest<T>(
      info, "marginals_symmetric_psd_gauge_zero_with_requested_cross_blocks", Needs::Instance,
      [](KindTest<T>& t) {
        auto h = t.make();
        PoseGraph g = makeNoisyLoop(kGraphSeed);
        h->optimize(g);
        const Marginals m = h->marginals(g, kCross);
        ASSERT_EQ(m.node.size(), g.size()) << "marginals(): one block per node";
        EXPECT_EQ(m.graph_revision, g.revision)
            << "Marginals::graph_revision must be the revision of the graph";
        for (std::size_t i = 0; i < m.node.size(); ++i) {
          const auto ok = isSymmetricPsd(m.node[i]);
          EXPECT_TRUE(ok) << "Cov(x_" << i << ") (later nodes not checked)";
          if (!ok) break;
        }
        EXPECT_LE(maxAbs(m.node[0]), 1e-6) << "node 0 (the gauge) must have zero covariance:\n"
                                           << m.node[0];
        for (const auto& ij : kCross)
          EXPECT_EQ(m.cross.count(ij), 1u)
              << "requested cross block (" << ij.first << ", " << ij.second << ") missing";
        if (m.cross.count({3, 7}) && m.cross.count({7, 3})) {
          const Eigen::Matrix3d a = m.cross.at({3, 7}), b = m.cross.at({7, 3});
          EXPECT_LE((a - b.transpose()).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, maxAbs(a)))
              << "Cov(3,7) != Cov(7,3)^T:\n"
              << a << "\nvs\n"
              << b;
          // The joint covariance of (x_3, x_7) must be PSD too.
          Eigen::Matrix<double, 6, 6> j;
          j << m.node[3], a, a.transpose(), m.node[7];
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(0.5 * (j + j.transpose()),
                                                                        Eigen::EigenvaluesOnly);
          EXPECT_GE(es.eigenvalues().minCoeff(), -1e-9)
              << "the joint covariance of nodes 3 and 7 is not PSD:\n"
              << j;
        }
      });

  // Incremental back-ends answer a growing graph from what they kept: the contract holds
  // there too (a graph replayed node by node, each edge once both its ends exist).
  addTest<T>(
      info, "marginals_of_a_growing_graph_keep_the_contract", Needs::Instance, [](KindTest<T>& t) {
        auto h = t.make();
        const PoseGraph full = makeNoisyLoop(kGraphSeed, 40);
        PoseGraph g;
        for (std::size_t n = 0; n < full.size(); ++n) {
          g.addNode(full.nodes[n].pose, full.nodes[n].timestamp);
          for (const auto& e : full.edges)
            if (std::max(e.from, e.to) == n) g.addEdge(e);
          h->optimize(g);
          const Marginals m = h->marginals(g);
          ASSERT_EQ(m.node.size(), g.size()) << "marginals(): one block per node";
          ASSERT_EQ(m.graph_revision, g.revision) << "after node " << n;
          ASSERT_LE(maxAbs(m.node[0]), 1e-6) << "the gauge, after node " << n;
          for (std::size_t i = 1; i < m.node.size(); ++i)
            ASSERT_TRUE(isSymmetricPsd(m.node[i])) << "Cov(x_" << i << ") after node " << n << ":\n"
                                                   << m.node[i];
        }
      });

  addTest<T>(info, "marginals_of_disconnected_node_throw_asf_error", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               PoseGraph g = makeNoisyLoop(kGraphSeed);
               g.addNode(CPose2D(50, 50, 0), 99.0);  // no edge reaches it
               EXPECT_THROW(h->marginals(g), asf::Error)
                   << "a node not connected to node 0 has no defined covariance";
             });
}

}  // namespace

void registerBackendTests(const InfoPtr& info) {
  registerOptimizeTests(info);
  registerMarginalTests(info);
}

}  // namespace asf::conformance::detail
