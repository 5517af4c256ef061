// Tests of the expected_uncertainty planner: it avoids a weak (featureless) side of a loop,
// its keys change the outcome as documented, and bad input is reported.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/planner.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <map>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/planner_expected_uncertainty.so");
  return i;
}

asf::framework::PluginHandle<asf::Planner> make(
    const std::map<std::string, std::string>& keys = {}) {
  auto h = asf::framework::Registry::create<asf::Planner>(info());
  h->configure(asf::Params::fromSpecs("expected_uncertainty", info()->descriptor->keys,
                                      info()->descriptor->num_keys, keys),
               asf::PluginContext{});
  return h;
}

/// Loop 0-1-2-3 (short, weak edges) / 0-4-5-6-7-8-9-3 (long, strong edges).
asf::PoseGraph loop(double weak_sd) {
  const double xy[10][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {0, 1},
                            {0, 2}, {1, 2}, {2, 2}, {3, 2}, {3, 1}};
  asf::PoseGraph g;
  for (auto& p : xy) g.addNode(mrpt::poses::CPose2D(p[0], p[1], 0));
  auto edge = [&](asf::NodeId a, asf::NodeId b, double sd, double sd_phi) {
    asf::PoseEdge e;
    e.from = a;
    e.to = b;
    e.mean = g.nodes[b].pose - g.nodes[a].pose;
    e.information =
        Eigen::Vector3d(1 / (sd * sd), 1 / (sd * sd), 1 / (sd_phi * sd_phi)).asDiagonal();
    g.addEdge(e);
  };
  for (auto [a, b] : {std::pair{0, 1}, {1, 2}, {2, 3}}) edge(a, b, weak_sd, weak_sd / 2);
  for (auto [a, b] : {std::pair{0, 4}, {4, 5}, {5, 6}, {6, 7}, {7, 8}, {8, 9}, {9, 3}})
    edge(a, b, 0.01, 0.005);
  return g;
}

/// Exact marginals (node and every cross block) from the dense information matrix.
asf::Marginals denseMarginals(const asf::PoseGraph& g) {
  std::vector<int> index;
  const Eigen::MatrixXd S = asf::denseInformation(g, index).inverse();
  asf::Marginals m;
  m.node.assign(g.size(), Eigen::Matrix3d::Zero());
  for (asf::NodeId i = 0; i < g.size(); ++i) {
    if (index[i] < 0) continue;
    m.node[i] = S.block<3, 3>(index[i], index[i]);
    for (asf::NodeId j = i + 1; j < g.size(); ++j)
      if (index[j] >= 0) m.cross[{i, j}] = S.block<3, 3>(index[i], index[j]);
  }
  return m;
}

const std::vector<asf::NodeId> kLong{0, 4, 5, 6, 7, 8, 9, 3}, kShort{0, 1, 2, 3};

TEST(PlannerExpectedUncertainty, AvoidsTheWeakSideOfALoop) {
  const asf::PoseGraph g = loop(0.5);
  const asf::Marginals m = denseMarginals(g);
  asf::PlanRequest req{&g, &m, nullptr, 0, 3};
  auto r = make()->plan(req);
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_EQ(r.nodes, kLong);
  EXPECT_EQ(r.criterion, "det(E[C])");
  // The reported cost is the library's evaluation of that path.
  const auto model = asf::planning::makePathModel(g, &m, r.nodes);
  asf::planning::CriterionOptions o;
  o.reloc.seed = 0;
  EXPECT_DOUBLE_EQ(
      r.cost,
      asf::planning::evaluatePath(asf::planning::Criterion::ExpectedUncertainty, model, o).cost);
  // Reverse direction too.
  req.start = 3;
  req.goal = 0;
  r = make({{"scalar", "trace"}})->plan(req);
  ASSERT_TRUE(r.found);
  EXPECT_EQ(r.nodes, std::vector<asf::NodeId>(kLong.rbegin(), kLong.rend()));
  EXPECT_EQ(r.criterion, "trace(E[C])");
}

TEST(PlannerExpectedUncertainty, EqualEdgesPreferTheShortSide) {
  const asf::PoseGraph g = loop(0.01);
  const asf::Marginals m = denseMarginals(g);
  const auto r = make()->plan(asf::PlanRequest{&g, &m, nullptr, 0, 3});
  ASSERT_TRUE(r.found) << r.reason;
  EXPECT_EQ(r.nodes, kShort);
}

TEST(PlannerExpectedUncertainty, RecognitionFileIsUsedAndChecked) {
  const auto dir = std::filesystem::temp_directory_path() / "asf_test_planner_eu";
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "p.txt").string(), bad = (dir / "bad.txt").string();
  // The long side is unrecognizable: with equal edges the short side wins more clearly, and
  // with p = 0 everywhere E[C] is pure odometry.
  std::ofstream(good) << "4 0\n5 0\n6 0\n7 0\n8 0\n9 0\n3 0\n1 0\n2 0\n";
  std::ofstream(bad) << "4 0\n5 zero\n";
  const asf::PoseGraph g = loop(0.5);
  const asf::Marginals m = denseMarginals(g);
  const auto r =
      make({{"p_recognition_file", good}})->plan(asf::PlanRequest{&g, &m, nullptr, 0, 3});
  ASSERT_TRUE(r.found);
  const auto model = asf::planning::makePathModel(g, &m, r.nodes);
  const auto odo = asf::planning::expectedCovariance(
      model, [](const asf::planning::RelocQuery&) { return 0.0; });
  EXPECT_NEAR(r.cost, odo.mean.determinant(), 1e-15);
  try {
    make({{"p_recognition_file", bad}});
    ADD_FAILURE() << "a bad recognition file was accepted";
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(bad + ":2"), std::string::npos) << e.what();
  }
}

TEST(PlannerExpectedUncertainty, NeedsMarginals) {
  const asf::PoseGraph g = loop(0.5);
  const auto r = make()->plan(asf::PlanRequest{&g, nullptr, nullptr, 0, 3});
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.reason.find("marginal"), std::string::npos) << r.reason;
}

}  // namespace
