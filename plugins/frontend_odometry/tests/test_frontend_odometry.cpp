// Tests of the odometry front-end: keyframing, edge means and information (analytic and
// Monte Carlo oracles), node payloads, currentPose.
#include <asf/errors.h>
#include <asf/frontend.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <random>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/frontend_odometry.so");
  return i;
}

asf::framework::PluginHandle<asf::Frontend> make(
    const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Frontend>(info());
  h->configure(asf::Params::fromSpecs("odometry", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

asf::SensorFrame frame(double x, double y, double phi, const Eigen::Matrix3d& cov, double t) {
  asf::SensorFrame f;
  f.odometry = mrpt::poses::CPose2D(x, y, phi);
  f.odometry_cov = cov;
  f.timestamp = t;
  return f;
}

/// Covariance of the edge's increment in the frame of `from` (additive x, y, phi): the
/// information weighs the g2o error, whose translation is in the frame of `to`.
Eigen::Matrix3d edgeCov(const asf::PoseEdge& e) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(e.mean.phi()), s = std::sin(e.mean.phi());
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R * e.information.inverse() * R.transpose();
}

TEST(FrontendOdometry, FirstFrameCreatesNodeZeroWithItsPayload) {
  auto fe = make();
  asf::PoseGraph g;
  asf::Marginals m;
  asf::SensorFrame f = frame(0.3, 0.1, 0.2, Eigen::Matrix3d::Identity(), 12.5);
  f.scan = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  f.ground_truth = mrpt::poses::CPose2D(4, 5, 1);
  EXPECT_TRUE(fe->process(f, g, m));
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g.revision, 1u);
  EXPECT_EQ(g.nodes[0].pose.x(), 0);  // the map frame is the first pose: odometry ignored
  EXPECT_EQ(g.nodes[0].pose.phi(), 0);
  EXPECT_EQ(g.nodes[0].timestamp, 12.5);
  EXPECT_EQ(g.nodes[0].scan, f.scan);
  ASSERT_TRUE(g.nodes[0].ground_truth);
  EXPECT_EQ(g.nodes[0].ground_truth->x(), 4);
  EXPECT_TRUE(g.edges.empty());
}

TEST(FrontendOdometry, StraightLineCovarianceMatchesTheClosedForm) {
  auto fe = make({{"keyframe_distance", "0.5"}, {"min_sigma_xy", "1e-9"},
                  {"min_sigma_phi", "1e-9"}});
  asf::PoseGraph g;
  asf::Marginals m;
  const double a = 1e-4, b = 4e-4, d = 0.12;
  const Eigen::Matrix3d cov = Eigen::Vector3d(a, a, b).asDiagonal();
  fe->process(frame(0, 0, 0, cov, 0), g, m);
  for (int k = 1; k <= 4; ++k) {
    EXPECT_FALSE(fe->process(frame(d, 0, 0, cov, k), g, m)) << k;  // 0.48 m: no keyframe
    EXPECT_EQ(g.revision, 1u);
  }
  asf::SensorFrame f5 = frame(d, 0, 0, cov, 5);
  f5.ground_truth = mrpt::poses::CPose2D(0.6, 0, 0);
  EXPECT_TRUE(fe->process(f5, g, m));
  ASSERT_EQ(g.size(), 2u);
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_EQ(g.revision, 2u);
  const asf::PoseEdge& e = g.edges[0];
  EXPECT_EQ(e.from, 0u);
  EXPECT_EQ(e.to, 1u);
  EXPECT_EQ(e.kind, asf::EdgeKind::Odometry);
  EXPECT_NEAR(e.mean.x(), 5 * d, 1e-12);
  EXPECT_NEAR(g.nodes[1].pose.x(), 5 * d, 1e-12);
  EXPECT_EQ(g.nodes[1].timestamp, 5);
  ASSERT_TRUE(g.nodes[1].ground_truth);
  // n steps of length d with cov diag(a, a, b):
  // xx = n a, phiphi = n b, yphi = d b n(n-1)/2, yy = n a + d^2 b (n-1) n (2n-1) / 6.
  const double n = 5;
  Eigen::Matrix3d expect;
  expect << n * a, 0, 0, 0, n * a + d * d * b * (n - 1) * n * (2 * n - 1) / 6,
      d * b * n * (n - 1) / 2, 0, d * b * n * (n - 1) / 2, n * b;
  EXPECT_TRUE(edgeCov(e).isApprox(expect, 1e-8)) << edgeCov(e) << "\nvs\n" << expect;
  EXPECT_TRUE(e.information.isApprox(e.information.transpose()));
}

TEST(FrontendOdometry, CurvedPathCovarianceMatchesMonteCarlo) {
  auto fe = make({{"keyframe_distance", "10"}, {"keyframe_angle_deg", "60"},
                  {"min_sigma_xy", "1e-9"}, {"min_sigma_phi", "1e-9"}});
  asf::PoseGraph g;
  asf::Marginals m;
  const mrpt::poses::CPose2D u(0.3, 0.05, 0.25);
  Eigen::Matrix3d cov;
  cov << 4e-4, 1e-4, 0, 1e-4, 2e-4, 5e-5, 0, 5e-5, 3e-4;
  fe->process(frame(0, 0, 0, cov, 0), g, m);
  int k = 0;
  while (g.size() < 2) fe->process(frame(u.x(), u.y(), u.phi(), cov, ++k), g, m);
  ASSERT_EQ(k, 5);  // 5 x 0.25 rad = 71.6 deg > 60
  const Eigen::Matrix3d P = edgeCov(g.edges[0]);

  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  const Eigen::Matrix3d Lc = cov.llt().matrixL();
  const int N = 40000;
  std::vector<Eigen::Vector3d> s(N);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < N; ++i) {
    mrpt::poses::CPose2D acc;
    for (int j = 0; j < k; ++j) {
      const Eigen::Vector3d nz = Lc * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
      acc = acc + mrpt::poses::CPose2D(u.x() + nz.x(), u.y() + nz.y(), u.phi() + nz.z());
    }
    s[i] = Eigen::Vector3d(acc.x(), acc.y(), acc.phi());
    mean += s[i] / N;
  }
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& v : s) C += (v - mean) * (v - mean).transpose() / (N - 1);
  EXPECT_NEAR(mean.x(), g.edges[0].mean.x(), 0.01);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(C(r, c), P(r, c), 0.05 * std::sqrt(P(r, r) * P(c, c)))
          << r << "," << c << "\nMC:\n" << C << "\npropagated:\n" << P;
}

TEST(FrontendOdometry, AngleThresholdMakesKeyframes) {
  auto fe = make({{"keyframe_angle_deg", "20"}});
  asf::PoseGraph g;
  asf::Marginals m;
  fe->process(frame(0, 0, 0, Eigen::Matrix3d::Zero(), 0), g, m);
  const double step = 6 * M_PI / 180;
  for (int k = 1; k <= 3; ++k)
    EXPECT_FALSE(fe->process(frame(0, 0, step, Eigen::Matrix3d::Zero(), k), g, m));
  EXPECT_TRUE(fe->process(frame(0, 0, step, Eigen::Matrix3d::Zero(), 4), g, m));
  ASSERT_EQ(g.size(), 2u);
  EXPECT_NEAR(g.nodes[1].pose.phi(), 4 * step, 1e-12);
}

TEST(FrontendOdometry, ZeroCovarianceGetsTheFloor) {
  auto fe = make({{"keyframe_distance", "0.5"}, {"min_sigma_xy", "0.002"},
                  {"min_sigma_phi", "0.0005"}});
  asf::PoseGraph g;
  asf::Marginals m;
  fe->process(frame(0, 0, 0, Eigen::Matrix3d::Zero(), 0), g, m);
  fe->process(frame(0.6, 0, 0, Eigen::Matrix3d::Zero(), 1), g, m);
  ASSERT_EQ(g.edges.size(), 1u);
  const Eigen::Matrix3d expect =
      Eigen::Vector3d(1 / 4e-6, 1 / 4e-6, 1 / 2.5e-7).asDiagonal();
  EXPECT_TRUE(g.edges[0].information.isApprox(expect, 1e-9)) << g.edges[0].information;
}

TEST(FrontendOdometry, CurrentPoseIsLastNodeComposedWithTheOdometrySince) {
  auto fe = make({{"keyframe_distance", "1.0"}});
  asf::PoseGraph g;
  asf::Marginals m;
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  EXPECT_EQ(fe->currentPose(g).x(), 0);
  fe->process(frame(0, 0, 0, cov, 0), g, m);
  fe->process(frame(0.7, 0, M_PI / 2, cov, 1), g, m);  // angle > 20 deg: node 1
  ASSERT_EQ(g.size(), 2u);
  fe->process(frame(0.2, 0.1, 0.1, cov, 2), g, m);
  EXPECT_EQ(g.size(), 2u);
  mrpt::poses::CPose2D expect = g.nodes[1].pose + mrpt::poses::CPose2D(0.2, 0.1, 0.1);
  auto p = fe->currentPose(g);
  EXPECT_NEAR(p.x(), expect.x(), 1e-12);
  EXPECT_NEAR(p.y(), expect.y(), 1e-12);
  EXPECT_NEAR(p.phi(), expect.phi(), 1e-12);
  // The back-end moves node 1: the current pose follows.
  g.nodes[1].pose = mrpt::poses::CPose2D(5, 5, 0);
  p = fe->currentPose(g);
  EXPECT_NEAR(p.x(), 5.2, 1e-12);
  EXPECT_NEAR(p.y(), 5.1, 1e-12);
  // ... and the next node is placed relative to the moved one.
  fe->process(frame(0.9, 0, 0, cov, 3), g, m);
  ASSERT_EQ(g.size(), 3u);
  const auto q = mrpt::poses::CPose2D(5, 5, 0) + g.edges[1].mean;
  EXPECT_NEAR(g.nodes[2].pose.x(), q.x(), 1e-12);
  EXPECT_NEAR(g.nodes[2].pose.y(), q.y(), 1e-12);
}

TEST(FrontendOdometry, FramesWithoutScansAndLongRuns) {
  auto fe = make();
  asf::PoseGraph g;
  asf::Marginals m;
  const Eigen::Matrix3d cov = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  mrpt::poses::CPose2D truth;
  for (int k = 0; k < 500; ++k) {
    const double phi = (k % 50 < 25) ? 0.02 : -0.03;
    const asf::SensorFrame f = frame(k ? 0.05 : 0, 0, k ? phi : 0, cov, k);
    if (k) truth = truth + f.odometry;
    fe->process(f, g, m);
  }
  // Dead reckoning: composing the edges reproduces the integrated odometry.
  mrpt::poses::CPose2D chain;
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    EXPECT_EQ(g.edges[i].from, i);
    EXPECT_EQ(g.edges[i].to, i + 1);
    chain = chain + g.edges[i].mean;
    EXPECT_FALSE(g.nodes[i + 1].scan);
    EXPECT_TRUE(g.edges[i].information.allFinite());
    EXPECT_GT(g.edges[i].information.determinant(), 0);
  }
  EXPECT_EQ(g.revision, g.size());
  const auto p = fe->currentPose(g);
  EXPECT_NEAR(p.x(), truth.x(), 1e-9);
  EXPECT_NEAR(p.y(), truth.y(), 1e-9);
  EXPECT_NEAR(std::remainder(p.phi() - truth.phi(), 2 * M_PI), 0, 1e-9);
  EXPECT_NEAR(chain.x(), g.nodes.back().pose.x(), 1e-9);
  EXPECT_GT(g.size(), 40u);  // 25 m driven, keyframes every 0.5 m
}

}  // namespace
