// Tests of the sim2d source: world loading, laser against analytic ranges, the odometry
// noise statistics, navigation on the estimated map, collisions, determinism, and the
// recorded rawlog replaying the same stream.
#include <asf/errors.h>
#include <asf/rawlog_io.h>
#include <asf/registry.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "../sim2d_nav.h"
#include "../sim2d_world.h"

namespace {

using mrpt::poses::CPose2D;
namespace fs = std::filesystem;
using KV = std::map<std::string, std::string>;

std::shared_ptr<const asf::PluginInfo> info() {
  static auto i = asf::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_sim2d.so");
  return i;
}

asf::PluginHandle<asf::Source> make(KV kv, std::uint64_t seed = 1, std::string out = "") {
  kv.emplace("record", out.empty() ? "false" : "true");
  auto h = asf::Registry::create<asf::Source>(info());
  h->setMinLoggingLevel(mrpt::system::LVL_ERROR);
  asf::PluginContext ctx;
  ctx.seed = seed;
  ctx.output_dir = out;
  h->configure(asf::Params::fromSpecs("sim2d", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               ctx);
  return h;
}

std::string configError(const KV& kv) {
  try {
    make(kv);
  } catch (const asf::ConfigError& e) {
    return e.what();
  }
  return "(no ConfigError)";
}

// Distance from (x, y) along angle a to the boundary of [0, w] x [0, h], from inside.
double rectRange(double x, double y, double a, double w, double h) {
  double best = 1e9;
  const double c = std::cos(a), s = std::sin(a);
  if (c > 1e-12) best = std::min(best, (w - x) / c);
  if (c < -1e-12) best = std::min(best, -x / c);
  if (s > 1e-12) best = std::min(best, (h - y) / s);
  if (s < -1e-12) best = std::min(best, -y / s);
  return best;
}

// Drives to each goal in turn (navigating with the source's own odometry as the estimate,
// no map), returning every frame; stops a goal when it is no longer Moving. Goals are given
// in the world frame; the map frame (odometry) starts at the true start pose, heading 0.
std::vector<asf::SensorFrame> drive(asf::Source& src, const std::vector<asf::Goal>& goals,
                                    std::vector<asf::NavStatus>* outcomes = nullptr) {
  std::vector<asf::SensorFrame> frames;
  CPose2D odo;
  frames.push_back(*src.next());
  const CPose2D start = *frames.front().ground_truth;
  for (const auto& g : goals) {
    asf::NavigationContext ctx;
    ctx.robot_estimate = odo;
    asf::Goal local = g;
    local.x -= start.x();
    local.y -= start.y();
    asf::NavStatus st = src.navigate(local, ctx);
    while (st == asf::NavStatus::Moving) {
      auto f = src.next();
      if (!f) break;
      odo = odo + f->odometry;
      frames.push_back(*f);
      st = src.status();
    }
    if (outcomes) outcomes->push_back(st);
  }
  return frames;
}

// ------------------------------------------------------------------------------ world

TEST(Sim2dWorld, RoomHasWallsExactlyOnItsBoundary) {
  const auto w = asf::sim2d::World::room(4.0, 3.0, 0.05);
  EXPECT_FALSE(w.occupiedAt(0.02, 1.0));
  EXPECT_TRUE(w.occupiedAt(-0.02, 1.0));
  EXPECT_TRUE(w.occupiedAt(4.02, 1.0));
  EXPECT_TRUE(w.occupiedAt(2.0, 3.02));
  EXPECT_TRUE(w.occupiedAt(50, 50));  // outside the grid
  // Clearance to the nearest wall surface, within half a cell of the exact value.
  EXPECT_NEAR(w.clearance(1.0, 1.5), 1.0, 0.05);
  EXPECT_NEAR(w.clearance(2.0, 0.5), 0.5, 0.05);
  EXPECT_EQ(w.clearance(-0.02, 1.0), 0.0);
  EXPECT_TRUE(w.sweepCollides({1, 1}, {3.95, 1}, 0.2));
  EXPECT_FALSE(w.sweepCollides({1, 1}, {3.5, 1}, 0.2));
}

TEST(Sim2dWorld, CaveImageIsTwentyMetresWithPaddedWall) {
  asf::sim2d::ImageWorldOptions o;
  o.file = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  o.resolution = 0.04;
  o.pad_wall_px = 1;
  const auto w = asf::sim2d::World::fromImage(o);
  const asf::Box2 b = w.bounds();
  EXPECT_NEAR(b.max_x - b.min_x, 20.08, 1e-3);
  EXPECT_NEAR(b.max_y - b.min_y, 20.08, 1e-3);
  EXPECT_NEAR(b.min_x, -0.04, 1e-4);
  // The padding frame is wall, the open lower-left area is free, the big block in the
  // lower right (pixels ~390..500, rows ~410..500 from the top) is wall.
  EXPECT_TRUE(w.occupiedAt(-0.02, 10));
  EXPECT_FALSE(w.occupiedAt(2, 2));
  EXPECT_TRUE(w.occupiedAt(18, 1.5));
  // The image's top row is y = 20 - res: the upper-left block (pixels ~60..150, rows
  // ~0..50) is near the top.
  EXPECT_TRUE(w.occupiedAt(4.0, 19.2));
  EXPECT_FALSE(w.occupiedAt(1.0, 19.2));

  o.file = ASF_TEST_SOURCE_DIR "/datasets/cave/no_such_map.png";
  EXPECT_THROW(asf::sim2d::World::fromImage(o), std::runtime_error);
}

// ------------------------------------------------------------------------------ laser

TEST(Sim2dLaser, RangesMatchTheRoomGeometry) {
  // Robot at (2, 1.5) heading 30 deg, laser 0.1 m ahead, full circle, no noise.
  auto src = make({{"room_width", "5"}, {"room_height", "3"}, {"resolution", "0.01"},
                   {"start_x", "2"}, {"start_y", "1.5"}, {"start_phi_deg", "30"},
                   {"laser_rays", "360"}, {"laser_fov_deg", "360"}, {"laser_max_range", "20"},
                   {"range_sigma", "0"}, {"sensor_x", "0.1"}});
  const auto f = src->next();
  ASSERT_TRUE(f && f->scan);
  const auto& s = *f->scan;
  ASSERT_EQ(s.getScanSize(), 360u);
  const double phi = 30 * M_PI / 180;
  const double lx = 2 + 0.1 * std::cos(phi), ly = 1.5 + 0.1 * std::sin(phi);
  double worst = 0;
  for (std::size_t i = 0; i < s.getScanSize(); ++i) {
    ASSERT_TRUE(s.getScanRangeValidity(i)) << "ray " << i;
    const double expected = rectRange(lx, ly, phi + s.getScanAngle(i), 5, 3);
    worst = std::max(worst, std::abs(s.getScanRange(i) - expected));
  }
  // MRPT marches rays in steps of under a cell: expect errors of a couple of cells at most.
  EXPECT_LT(worst, 0.03);
  EXPECT_EQ(s.sensorPose.x(), 0.1);
  ASSERT_TRUE(f->ground_truth);
  EXPECT_DOUBLE_EQ(f->ground_truth->x(), 2);
}

TEST(Sim2dLaser, NoiseAndMaxRange) {
  // A 4 m range in a 20 m room: only the near wall is seen; the rest are invalid rays.
  auto src = make({{"room_width", "20"}, {"room_height", "20"}, {"resolution", "0.02"},
                   {"start_x", "1"}, {"start_y", "10"}, {"start_phi_deg", "180"},
                   {"laser_rays", "181"}, {"laser_max_range", "4"}, {"range_sigma", "0.05"},
                   {"sensor_x", "0"}});
  const auto s = src->next()->scan;
  // The ray straight ahead (index 90) sees the wall at 1 m with noise; the side rays see
  // nothing within 4 m.
  EXPECT_TRUE(s->getScanRangeValidity(90));
  EXPECT_NEAR(s->getScanRange(90), 1.0, 0.25);
  EXPECT_FALSE(s->getScanRangeValidity(0));
  EXPECT_FLOAT_EQ(s->getScanRange(0), 4.0f);
  // The noise: residuals of the rays hitting the near wall have a std near 0.05.
  double sum2 = 0;
  int n = 0;
  for (std::size_t i = 0; i < s->getScanSize(); ++i) {
    if (!s->getScanRangeValidity(i)) continue;
    const double a = M_PI + s->getScanAngle(i);
    const double r = 1.0 / std::abs(std::cos(a));
    sum2 += std::pow(s->getScanRange(i) - r, 2);
    ++n;
  }
  ASSERT_GT(n, 60);
  const double sd = std::sqrt(sum2 / n);
  EXPECT_GT(sd, 0.035);
  EXPECT_LT(sd, 0.07);
}

TEST(Sim2dLaser, RateSkipsScansBetweenPeriods) {
  auto src = make({{"dt", "0.05"}, {"laser_rate", "5"}});
  int scans = 0;
  for (int k = 0; k < 40; ++k) scans += src->next()->scan != nullptr;  // 2 s of time
  EXPECT_EQ(scans, 10);
}

// -------------------------------------------------------------------------- odometry

TEST(Sim2dOdometry, NoiseMatchesTheMotionModel) {
  // Back and forth along a 16 m corridor: thousands of straight 0.05 m steps and turns.
  const KV kv{{"room_width", "18"}, {"room_height", "12"}, {"start_x", "1"},
              {"start_y", "6"},      {"laser_rays", "2"},    {"odo_a1", "0.05"},
              {"odo_a3", "1.0"},     {"odo_a4", "0.02"},     {"odo_min_std_xy", "0.002"},
              {"odo_min_std_phi_deg", "0.1"}};
  auto src = make(kv, 7);
  std::vector<asf::Goal> goals;
  for (int k = 0; k < 4; ++k) {
    goals.push_back({17, 6, 0.1});
    goals.push_back({1, 6, 0.1});
  }
  const auto frames = drive(*src, goals);
  asf::OdometryNoiseModel model;
  model.a1 = 0.05, model.a2 = 0.001, model.a3 = 1.0, model.a4 = 0.02;
  model.min_std_xy = 0.002, model.min_std_phi_deg = 0.1;

  // Normalized errors e_i / sigma_i of the forward steps (true increment (0.05, 0, 0)):
  // mean 0, variance 1 per component if the noise follows the model.
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum2 = Eigen::Vector3d::Zero();
  int n = 0, rest = 0;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const CPose2D truth = *frames[k].ground_truth - *frames[k - 1].ground_truth;
    if (truth.norm() < 1e-12 && std::abs(truth.phi()) < 1e-12) {
      // At rest odometry reads exactly zero.
      EXPECT_EQ(frames[k].odometry.norm(), 0.0);
      ++rest;
      continue;
    }
    const Eigen::Matrix3d C = model.covariance(truth);
    const Eigen::Vector3d e(frames[k].odometry.x() - truth.x(),
                            frames[k].odometry.y() - truth.y(),
                            mrpt::math::wrapToPi(frames[k].odometry.phi() - truth.phi()));
    // Reported covariance: the model at the reading.
    EXPECT_TRUE(frames[k].odometry_cov.isApprox(model.covariance(frames[k].odometry), 1e-9));
    const Eigen::Vector3d z = e.array() / C.diagonal().array().sqrt();
    sum += z;
    sum2 += z.cwiseProduct(z);
    ++n;
  }
  ASSERT_GT(n, 2000) << rest << " steps at rest";
  const Eigen::Vector3d mean = sum / n, var = sum2 / n - mean.cwiseProduct(mean);
  for (int c = 0; c < 3; ++c) {
    // 5-sigma sampling bounds: mean ~ N(0, 1/n), variance ~ N(1, 2/n).
    EXPECT_LT(std::abs(mean[c]), 5 / std::sqrt(n)) << "component " << c;
    EXPECT_LT(std::abs(var[c] - 1), 5 * std::sqrt(2.0 / n)) << "component " << c;
  }
}

// -------------------------------------------------------------------------- navigation

mrpt::maps::COccupancyGridMap2D wallMap(double gap_from, double gap_to) {
  // 6 x 4 m, all free, with a wall at x in [2.9, 3.1] except the gap (y range).
  mrpt::maps::COccupancyGridMap2D g(0, 6, 0, 4, 0.05);
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx) {
      const double x = g.idx2x(cx), y = g.idx2y(cy);
      const bool wall = x > 2.9 && x < 3.1 && !(y > gap_from && y < gap_to);
      g.setCell(static_cast<int>(cx), static_cast<int>(cy), wall ? 0.0f : 1.0f);
    }
  return g;
}

// Minimum over the plan's segments of the distance of sample points to wall cells.
double planClearance(const mrpt::maps::COccupancyGridMap2D& g, asf::Point2 from,
                     const asf::sim2d::NavPlan& plan) {
  double worst = 1e9;
  for (const auto& w : plan.waypoints) {
    for (int s = 0; s <= 50; ++s) {
      const double x = from.x + (w.x - from.x) * s / 50.0, y = from.y + (w.y - from.y) * s / 50.0;
      for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
        for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
          if (g.getCell(static_cast<int>(cx), static_cast<int>(cy)) < 0.5f)
            worst = std::min(worst, std::hypot(g.idx2x(cx) - x, g.idx2y(cy) - y) - 0.025);
    }
    from = w;
  }
  return worst;
}

TEST(Sim2dNav, PathGoesThroughTheGapAndKeepsClear) {
  const auto g = wallMap(2.5, 3.5);
  asf::sim2d::NavOptions o;
  o.robot_radius = 0.2;
  const auto plan = asf::sim2d::planPath(&g, {1, 1}, {5, 1}, 0.1, o);
  ASSERT_TRUE(plan.found) << plan.reason;
  // It must detour through the gap: longer than the straight 4 m, and some waypoint up in
  // the gap.
  EXPECT_GT(plan.length, 5.0);
  bool through_gap = false;
  for (const auto& w : plan.waypoints) through_gap |= w.y > 2.4 && w.y < 3.6;
  EXPECT_TRUE(through_gap);
  EXPECT_GE(planClearance(g, {1, 1}, plan), 0.2 - 1e-6);
  EXPECT_NEAR(plan.waypoints.back().x, 5, 1e-9);
  EXPECT_NEAR(plan.waypoints.back().y, 1, 1e-9);
}

TEST(Sim2dNav, UnreachableWhenClosedOrTooNarrowOrInsideAWall) {
  asf::sim2d::NavOptions o;
  o.robot_radius = 0.2;
  const auto closed = wallMap(0, 0);
  EXPECT_FALSE(asf::sim2d::planPath(&closed, {1, 1}, {5, 1}, 0.1, o).found);
  const auto narrow = wallMap(2.0, 2.3);  // 0.3 m gap, robot 0.4 m wide
  EXPECT_FALSE(asf::sim2d::planPath(&narrow, {1, 1}, {5, 1}, 0.1, o).found);
  o.robot_radius = 0.1;
  EXPECT_TRUE(asf::sim2d::planPath(&narrow, {1, 1}, {5, 1}, 0.1, o).found);
  const auto open = wallMap(2.5, 3.5);
  const auto in_wall = asf::sim2d::planPath(&open, {1, 1}, {3.0, 1}, 0.05, o);
  EXPECT_FALSE(in_wall.found);
  EXPECT_NE(in_wall.reason.find("no free cell"), std::string::npos) << in_wall.reason;
}

TEST(Sim2dNav, UnknownSpaceBlockedOrCostly) {
  // Known free only left of x = 3; the goal lies in unknown space.
  mrpt::maps::COccupancyGridMap2D g(0, 6, 0, 4, 0.05);  // all 0.5 = unknown
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
      if (g.idx2x(cx) < 3) g.setCell(static_cast<int>(cx), static_cast<int>(cy), 1.0f);
  asf::sim2d::NavOptions o;
  o.unknown_blocked = true;
  EXPECT_FALSE(asf::sim2d::planPath(&g, {1, 2}, {5, 2}, 0.1, o).found);
  o.unknown_blocked = false;
  const auto plan = asf::sim2d::planPath(&g, {1, 2}, {5, 2}, 0.1, o);
  ASSERT_TRUE(plan.found) << plan.reason;
  EXPECT_NEAR(plan.length, 4.0, 0.1);
  // No map at all: everything unknown, a straight line when costly.
  const auto none = asf::sim2d::planPath(nullptr, {0, 0}, {3, 4}, 0.1, o);
  ASSERT_TRUE(none.found);
  EXPECT_NEAR(none.length, 5.0, 0.1);
}

TEST(Sim2dSource, ReachesGoalsInTheRoom) {
  auto src = make({{"room_width", "8"}, {"room_height", "6"}, {"start_x", "1"},
                   {"start_y", "1"}, {"laser_rays", "10"}});
  std::vector<asf::NavStatus> st;
  const auto frames = drive(*src, {{6, 5, 0.1}, {1, 5, 0.1}, {1, 1, 0.1}}, &st);
  ASSERT_EQ(st.size(), 3u);
  for (auto s : st) EXPECT_EQ(s, asf::NavStatus::Reached);
  // The robot followed its odometry: the true end pose is near the last goal, up to the
  // drift over ~15 m.
  const CPose2D end = *frames.back().ground_truth;
  EXPECT_LT(std::hypot(end.x() - 1, end.y() - 1), 0.6);
  // Unreachable goals are reported at once.
  asf::NavigationContext ctx;
  EXPECT_EQ(src->navigate({NAN, 1, 0.1}, ctx), asf::NavStatus::Unreachable);
}

TEST(Sim2dSource, WallsStopTheRobot) {
  // No map: the plan goes straight through unknown space, into the room's right wall.
  auto src = make({{"room_width", "4"}, {"room_height", "3"}, {"start_x", "1"},
                   {"start_y", "1.5"}, {"laser_rays", "10"}, {"robot_radius", "0.25"},
                   {"odo_a4", "0.01"}});
  std::vector<asf::NavStatus> st;
  const auto frames = drive(*src, {{6, 1.5, 0.1}}, &st);
  ASSERT_EQ(st.size(), 1u);
  EXPECT_EQ(st[0], asf::NavStatus::Blocked);
  const auto w = asf::sim2d::World::room(4, 3, 0.04);
  for (const auto& f : frames) EXPECT_GE(w.clearance(f.ground_truth->x(), f.ground_truth->y()), 0.25 - 0.04);
  EXPECT_GT(frames.back().ground_truth->x(), 3.5);  // it did drive up to the wall

  // Recovery: the next goal (world (1, 1.5), the start) starts by backing away from the
  // wall (recovery_backup 0.15 m = three 0.05 m steps), then the robot gets there.
  asf::NavigationContext ctx;
  CPose2D odo;
  for (const auto& f : frames) odo = odo + f.odometry;
  ctx.robot_estimate = odo;
  ASSERT_EQ(src->navigate({0, 0, 0.1}, ctx), asf::NavStatus::Moving);
  std::vector<double> forward;
  asf::NavStatus s = asf::NavStatus::Moving;
  CPose2D prev = *frames.back().ground_truth;
  for (int k = 0; k < 2000 && s == asf::NavStatus::Moving; ++k) {
    const CPose2D now = *src->next()->ground_truth;
    forward.push_back((now - prev).x());  // in the robot's frame
    prev = now;
    s = src->status();
  }
  EXPECT_EQ(s, asf::NavStatus::Reached);
  ASSERT_GE(forward.size(), 3u);
  EXPECT_NEAR(forward[0], -0.05, 1e-9);
  EXPECT_NEAR(forward[2], -0.05, 1e-9);
}

TEST(Sim2dSource, DeterministicForASeed) {
  const KV kv{{"laser_rays", "50"}};
  const std::vector<asf::Goal> goals{{5, 4, 0.1}, {2, 2, 0.1}};
  const auto a = drive(*make(kv, 3), goals), b = drive(*make(kv, 3), goals),
             c = drive(*make(kv, 4), goals);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].odometry, b[k].odometry);
    for (std::size_t i = 0; i < a[k].scan->getScanSize(); ++i)
      ASSERT_EQ(a[k].scan->getScanRange(i), b[k].scan->getScanRange(i));
  }
  // The laser draws from its own stream: another laser leaves the path unchanged.
  const auto d = drive(*make({{"laser_rays", "7"}, {"range_sigma", "0.2"}}, 3), goals);
  ASSERT_EQ(d.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(*d[k].ground_truth, *a[k].ground_truth);
  bool differs = a.size() != c.size();
  for (std::size_t k = 0; !differs && k < a.size(); ++k) differs = !(a[k].odometry == c[k].odometry);
  EXPECT_TRUE(differs);
}

TEST(Sim2dSource, RecordedRawlogReplaysTheSameStream) {
  const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "tests" / "sim2d_record";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<asf::SensorFrame> frames;
  {
    auto src = make({{"laser_rays", "91"}, {"laser_rate", "4"}}, 5, dir.string());
    frames = drive(*src, {{6, 4, 0.1}, {2, 1.5, 0.1}});
  }  // closing the source closes the files
  asf::RawlogReaderOptions ro;
  ro.ground_truth_file = (dir / "sim2d.gt.txt").string();
  asf::RawlogReader reader((dir / "sim2d.rawlog").string(), ro);
  std::size_t k = 0, scans = 0;
  while (auto f = reader.next()) {
    ASSERT_LT(k, frames.size());
    const auto& o = frames[k++];
    EXPECT_EQ(f->timestamp, o.timestamp);
    EXPECT_EQ(f->odometry, o.odometry);
    EXPECT_TRUE(f->odometry_cov.isApprox(o.odometry_cov, 1e-12));
    ASSERT_TRUE(f->ground_truth);
    EXPECT_NEAR(f->ground_truth->x(), o.ground_truth->x(), 1e-8);
    EXPECT_NEAR(mrpt::math::wrapToPi(f->ground_truth->phi() - o.ground_truth->phi()), 0, 1e-8);
    ASSERT_EQ(f->scan != nullptr, o.scan != nullptr) << "frame " << k;
    if (!o.scan) continue;
    ++scans;
    ASSERT_EQ(f->scan->getScanSize(), o.scan->getScanSize());
    for (std::size_t i = 0; i < o.scan->getScanSize(); ++i) {
      ASSERT_EQ(f->scan->getScanRange(i), o.scan->getScanRange(i));
      ASSERT_EQ(f->scan->getScanRangeValidity(i), o.scan->getScanRangeValidity(i));
    }
  }
  EXPECT_EQ(k, frames.size());
  EXPECT_GT(scans, 10u);
  EXPECT_LT(scans, frames.size());  // laser_rate 4 Hz with 10 Hz steps
}

TEST(Sim2dSource, ConfigErrorsNameTheKey) {
  EXPECT_NE(configError({{"start_x", "0.05"}}).find("start_x"), std::string::npos);
  EXPECT_NE(configError({{"start_x", "100"}}).find("start_x"), std::string::npos);
  const std::string e = configError({{"map_image", "/nonexistent/map.png"}});
  EXPECT_NE(e.find("map_image"), std::string::npos) << e;
  EXPECT_NE(e.find("/nonexistent/map.png"), std::string::npos) << e;
}

}  // namespace
