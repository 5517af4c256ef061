// The feature-void zone of thesis Table 3.1 (unreliable_zone.h): the keyframes'
// scans and wheel odometry read back from a run's log (hand-composed
// covariances), and the masking that removes exactly the zone's scans, makes
// its consecutive links wheel odometry x factor and drops its other links.
#include <asf/errors.h>
#include <asf/io/rawlog_io.h>
#include <asf/sensor_frame.h>
#include <asf/planning/unreliable_zone.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;

std::shared_ptr<mrpt::obs::CObservation2DRangeScan> scanOf(float range) {
  auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  s->aperture = static_cast<float>(M_PI);
  s->maxRange = 10;
  s->resizeScan(5);
  for (std::size_t i = 0; i < 5; ++i) s->setScanRange(i, range), s->setScanRangeValidity(i, true);
  return s;
}

/// 10 frames at t = 100 + i: each moves 1 m straight ahead with covariance
/// diag(a, a, c); frame i has a scan of range i + 1 when i is even.
constexpr double kA = 0.01, kC = 0.001;

std::string writeLog(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("asf_test_zone_" + name + ".rawlog");
  asf::io::RawlogWriter w(p.string());
  for (int i = 0; i < 10; ++i) {
    asf::SensorFrame f;
    f.timestamp = 100 + i;
    if (i > 0) {
      f.odometry = mrpt::poses::CPose2D(1, 0, 0);
      f.odometry_cov = Eigen::Vector3d(kA, kA, kC).asDiagonal();
    }
    if (i % 2 == 0) f.scan = scanOf(static_cast<float>(i + 1));
    w.write(f);
  }
  return p.string();
}

TEST(UnreliableZone, KeyframeLogComposesTheWheelOdometryBetweenKeyframes) {
  const std::string log = writeLog("compose");
  const asf::planning::KeyframeLog k = asf::planning::readKeyframeLog(log, {100, 102, 103, 107});
  ASSERT_EQ(k.scan.size(), 4u);
  // The scans of frames 0, 2 (even), none at 3 or 7.
  ASSERT_TRUE(k.scan[0] && k.scan[1]);
  EXPECT_FLOAT_EQ(k.scan[0]->getScanRange(0), 1.0f);
  EXPECT_FLOAT_EQ(k.scan[1]->getScanRange(0), 3.0f);
  EXPECT_FALSE(k.scan[2]);
  EXPECT_FALSE(k.scan[3]);
  // Node 1 is two straight 1 m steps after node 0: x = 2. First order, the
  // heading's variance of the first step moves the second step's end sideways
  // by 1 m per radian: var(y) = a + a + c, cov(y, phi) = c, var(phi) = 2c.
  EXPECT_NEAR(k.odometry[1].x(), 2, 1e-12);
  EXPECT_NEAR(k.odometry[1].y(), 0, 1e-12);
  const Eigen::Matrix3d& C = k.odometry_cov[1];
  EXPECT_NEAR(C(0, 0), 2 * kA, 1e-12);
  EXPECT_NEAR(C(1, 1), 2 * kA + kC, 1e-12);
  EXPECT_NEAR(C(1, 2), kC, 1e-12);
  EXPECT_NEAR(C(2, 2), 2 * kC, 1e-12);
  EXPECT_NEAR(C(0, 1), 0, 1e-12);
  // One step: the frame's own increment and covariance.
  EXPECT_NEAR(k.odometry[2].x(), 1, 1e-12);
  EXPECT_NEAR(k.odometry_cov[2](1, 1), kA, 1e-12);
  // Four steps: var(y) = 4a + c (1 + 4 + 9) -- the lever arms 1, 2, 3 m of the
  // first three headings.
  EXPECT_NEAR(k.odometry[3].x(), 4, 1e-12);
  EXPECT_NEAR(k.odometry_cov[3](1, 1), 4 * kA + kC * (1 + 4 + 9), 1e-12);
  EXPECT_TRUE(k.odometry[0] == mrpt::poses::CPose2D());
}

TEST(UnreliableZone, KeyframeLogNamesTheLogAndTheNodeWithoutAFrame) {
  const std::string log = writeLog("missing");
  try {
    asf::planning::readKeyframeLog(log, {100, 102, 102.5, 104});
    FAIL() << "a keyframe time the log does not have was accepted";
  } catch (const asf::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(log), std::string::npos) << m;
    EXPECT_NE(m.find("node 2"), std::string::npos) << m;
  }
  EXPECT_THROW(asf::planning::readKeyframeLog(log, {100, 120}), asf::InputError) << "past the log's end";
}

/// Six nodes on a line, a scan each, the log's odometry 1 m per keyframe;
/// edges: scan matches 0-1 ... 4-5, a second match 2-3, a revisit 2-4 and a
/// loop closure 1-4 (around the zone 2-3 of the tests).
asf::PoseGraph lineGraph() {
  asf::PoseGraph g;
  for (int i = 0; i < 6; ++i) {
    g.addNode(mrpt::poses::CPose2D(i, 0, 0), i);
    g.nodes[i].scan = scanOf(static_cast<float>(i + 1));
  }
  auto edge = [&](asf::NodeId a, asf::NodeId b, asf::EdgeKind kind) {
    asf::PoseEdge e;
    e.from = a;
    e.to = b;
    e.mean = mrpt::poses::CPose2D(static_cast<double>(b) - a, 0, 0);
    e.information = Eigen::Vector3d(1e4, 1e4, 1e5).asDiagonal();
    e.kind = kind;
    g.addEdge(e);
  };
  for (asf::NodeId i = 0; i < 5; ++i) edge(i, i + 1, asf::EdgeKind::ScanMatch);
  edge(2, 3, asf::EdgeKind::ScanMatch);
  edge(2, 4, asf::EdgeKind::ScanMatch);
  edge(1, 4, asf::EdgeKind::LoopClosure);
  return g;
}

asf::planning::KeyframeLog lineLog() {
  asf::planning::KeyframeLog k;
  for (int i = 0; i < 6; ++i) {
    k.scan.push_back(nullptr);
    // Odometry that disagrees with the scan matches (1.1 m, drifting left), so
    // that the test sees which one an edge carries.
    k.odometry.emplace_back(i ? 1.1 : 0, i ? 0.05 : 0, 0);
    k.odometry_cov.push_back(Eigen::Vector3d(0.02, 0.03, 0.004).asDiagonal());
  }
  return k;
}

TEST(UnreliableZone, MaskRemovesExactlyTheZonesScansAndMakesItsLinksWheelOdometry) {
  const asf::PoseGraph g = lineGraph();
  const asf::planning::KeyframeLog log = lineLog();
  const std::vector<char> in_zone{0, 0, 1, 1, 0, 0};
  asf::planning::ZoneMaskOptions o;
  o.factor = 10;
  asf::planning::ZoneMaskReport r;
  const asf::PoseGraph m = asf::planning::maskZone(g, in_zone, o, &log, &r);
  ASSERT_EQ(m.size(), 6u);
  for (asf::NodeId v = 0; v < 6; ++v) {
    if (in_zone[v])
      EXPECT_FALSE(m.nodes[v].scan) << "node " << v << " is in the zone: its scan is ignored";
    else
      EXPECT_EQ(m.nodes[v].scan, g.nodes[v].scan) << "node " << v << " keeps its own scan";
    EXPECT_TRUE(m.nodes[v].pose == g.nodes[v].pose);
  }
  EXPECT_EQ(r.zone_nodes, 2u);
  EXPECT_EQ(r.scans_removed, 2u);
  EXPECT_EQ(r.edges_replaced, 3u);  // 1-2, 2-3, 3-4
  EXPECT_EQ(r.loop_closures_dropped,
            1u);  // 2-4, a revisit; 1-4 joins two nodes outside
  EXPECT_EQ(r.duplicate_edges_dropped, 1u);
  ASSERT_EQ(m.edges.size(), 6u);
  for (const asf::PoseEdge& e : m.edges) {
    const bool zone = in_zone[e.from] || in_zone[e.to];
    if (e.kind == asf::EdgeKind::LoopClosure) {
      EXPECT_TRUE(e.from == 1 && e.to == 4) << "the loop closure around the zone stays";
      continue;
    }
    ASSERT_EQ(e.to, e.from + 1) << "only consecutive links touch the zone";
    if (!zone) {
      EXPECT_EQ(e.kind, asf::EdgeKind::ScanMatch);
      EXPECT_NEAR(e.mean.x(), 1, 1e-12) << "outside the zone the scan match stays";
      EXPECT_NEAR(e.information(0, 0), 1e4, 1e-6);
      continue;
    }
    EXPECT_EQ(e.kind, asf::EdgeKind::Odometry) << e.from << "-" << e.to;
    EXPECT_NEAR(e.mean.x(), 1.1, 1e-12);
    EXPECT_NEAR(e.mean.y(), 0.05, 1e-12);
    // The information is (10 Sigma)^-1 rotated into the error's frame: the mean
    // turns by 0, so it is diagonal, 1 / (10 x variance) (the 1e-12 floor is
    // far below).
    EXPECT_NEAR(e.information(0, 0), 1 / 0.2, 1e-6);
    EXPECT_NEAR(e.information(1, 1), 1 / 0.3, 1e-6);
    EXPECT_NEAR(e.information(2, 2), 1 / 0.04, 1e-6);
    EXPECT_NEAR(e.information(0, 1), 0, 1e-9);
  }
}

TEST(UnreliableZone, GraphOnlyVariantsKeepTheEdgesMeans) {
  const asf::PoseGraph g = lineGraph();
  const std::vector<char> in_zone{0, 0, 1, 1, 0, 0};
  asf::planning::ZoneMaskOptions o;
  o.factor = 100;
  o.covariance = asf::planning::ZoneCovariance::Scaled;
  o.drop_loop_closures = false;
  asf::planning::ZoneMaskReport r;
  const asf::PoseGraph m = asf::planning::maskZone(g, in_zone, o, nullptr, &r);
  EXPECT_EQ(m.edges.size(), g.edges.size()) << "nothing dropped";
  EXPECT_EQ(r.edges_replaced, 5u);  // 1-2, 2-3 twice, 3-4, 2-4
  for (std::size_t i = 0; i < g.edges.size(); ++i) {
    const bool zone = in_zone[g.edges[i].from] || in_zone[g.edges[i].to];
    EXPECT_TRUE(m.edges[i].mean == g.edges[i].mean);
    EXPECT_NEAR(m.edges[i].information(0, 0), zone ? 100 : 1e4, 1e-9) << i;
  }
  // Inside only: an edge needs both ends in the zone.
  o.touching = false;
  asf::planning::maskZone(g, in_zone, o, nullptr, &r);
  EXPECT_EQ(r.edges_replaced, 2u);  // 2-3 twice
  // Wheel odometry without the log is a programming error, not a silent
  // fallback.
  o.covariance = asf::planning::ZoneCovariance::WheelOdometry;
  EXPECT_THROW(asf::planning::maskZone(g, in_zone, o, nullptr), asf::Error);
}

}  // namespace
