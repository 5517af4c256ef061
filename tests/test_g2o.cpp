// g2o text I/O: round trip, composition of edge-only files, and line-precise errors.
#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <gtest/gtest.h>

#include "test_util.h"

#include <filesystem>

using asf::InputError;

using asf_test::has;
namespace {
const auto errorOf = asf_test::errorOf<asf::InputError>;
}  // namespace

TEST(G2o, RoundTripIsExact) {
  asf::PoseGraph g;
  g.addNode({0, 0, 0});
  g.addNode({1.25, -0.5, 0.3});
  g.addNode({2.0, 1.0 / 3.0, -3.1});
  asf::PoseEdge e;
  e.from = 0, e.to = 1, e.mean = {1.2, -0.4, 0.29};
  e.information << 100, 1, 2, 1, 90, 3, 2, 3, 500;
  g.addEdge(e);
  e.from = 1, e.to = 2, e.mean = {0.7, 0.8, 2.9};
  g.addEdge(e);
  e.from = 0, e.to = 2;
  g.addEdge(e);
  g.fixed.push_back(1);
  const auto tmp = (std::filesystem::temp_directory_path() / "asf_g2o_roundtrip.g2o").string();
  asf::writeG2o(g, tmp);
  const auto r = asf::readG2o(tmp);
  std::filesystem::remove(tmp);
  ASSERT_EQ(r.nodes.size(), 3u);
  ASSERT_EQ(r.edges.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.nodes[i].pose.x(), g.nodes[i].pose.x());
    EXPECT_EQ(r.nodes[i].pose.y(), g.nodes[i].pose.y());
    EXPECT_EQ(r.nodes[i].pose.phi(), g.nodes[i].pose.phi());
    EXPECT_EQ(r.edges[i].from, g.edges[i].from);
    EXPECT_EQ(r.edges[i].to, g.edges[i].to);
    EXPECT_EQ(r.edges[i].mean.phi(), g.edges[i].mean.phi());
    EXPECT_EQ(r.edges[i].information, g.edges[i].information);
  }
  EXPECT_EQ(r.edges[2].kind, asf::EdgeKind::LoopClosure);
  EXPECT_EQ(r.fixed, std::vector<asf::NodeId>{1});
  EXPECT_DOUBLE_EQ(r.chi2(), g.chi2());
}

TEST(G2o, Chi2FollowsTheG2oConvention) {
  // One edge whose measurement is off by (0.1, 0, 0) with information diag(100, 1, 1).
  const auto g = asf::parseG2o(
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 0.9 0 0 100 0 0 1 0 1\n");
  EXPECT_NEAR(g.chi2(), 100 * 0.1 * 0.1, 1e-12);
}

TEST(G2o, EdgeOnlyFilesComposeTheOdometryChain) {
  const auto g = asf::parseG2o(
      "EDGE_SE2 0 1 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 1 2 1 0 1.5707963267948966 1 0 0 1 0 1\n"
      "EDGE_SE2 2 0 1 0 1.5707963267948966 1 0 0 1 0 1\n");
  ASSERT_EQ(g.nodes.size(), 3u);
  EXPECT_NEAR(g.nodes[1].pose.x(), 1, 1e-12);
  EXPECT_NEAR(g.nodes[2].pose.x(), 1, 1e-12);
  EXPECT_NEAR(g.nodes[2].pose.y(), 1, 1e-12);
  EXPECT_NEAR(std::abs(g.nodes[2].pose.phi()), M_PI, 1e-12);
}

TEST(G2o, MalformedInputNamesTheLine) {
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 x 0 0\n", "f.g2o"); }),
                  "f.g2o:2: malformed VERTEX_SE2"));
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0\n", "f.g2o"); }),
                  "f.g2o:2: malformed EDGE_SE2"));
  EXPECT_TRUE(has(errorOf([] {
                    asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\n"
                                  "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n",
                                  "f.g2o");
                  }),
                  "f.g2o:3: information matrix of edge 0 -> 1 is not positive definite"));
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 5 1 0 0 1 0 0 1 0 1\n", "f.g2o"); }),
                  "f.g2o:2: edge 0 -> 5 names an undefined vertex"));
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n", "f.g2o"); }),
                  "f.g2o:1: unknown record 'VERTEX_SE3:QUAT'"));
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 1 0 0\n", "f.g2o"); }),
                  "f.g2o:2: vertex 0 defined twice (first at line 1)"));
  EXPECT_TRUE(has(errorOf([] { asf::readG2o("/nonexistent.g2o"); }), "/nonexistent.g2o: cannot open"));
  // Issue 51, item 7: a self-loop is no constraint (it "converged" before).
  EXPECT_TRUE(has(errorOf([] { asf::parseG2o("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 0 1 0 0 1 0 0 1 0 1\n", "f.g2o"); }),
                  "f.g2o:2: edge 0 -> 0 joins a vertex to itself"));
}

TEST(G2o, SharedBenchmarksParse) {
  const std::string f = ASF_TEST_SHARED_DIR "/datasets/g2o/intel.g2o";
  if (!std::filesystem::exists(f)) GTEST_SKIP() << "needs ../shared/datasets/g2o (not in a user's clone)";
  const auto g = asf::readG2o(f);
  EXPECT_EQ(g.nodes.size(), 1728u);
  EXPECT_EQ(g.edges.size(), 2512u);
  EXPECT_GT(g.chi2(), 0);
}
