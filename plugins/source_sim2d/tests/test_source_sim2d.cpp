// Tests of the sim2d source: world loading, laser against analytic ranges, the odometry
// noise statistics, navigation on the estimated map, collisions, determinism, the recorded
// rawlog replaying the same stream, and the 2.5D world with its tilted laser.
#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <asf/io/rawlog_io.h>
#include <asf/framework/registry.h>
#include <asf/source.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <asf/navigation/grid_path.h>
#include "../sim2d_world.h"

namespace {

using mrpt::poses::CPose2D;
namespace fs = std::filesystem;
using KV = std::map<std::string, std::string>;

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/source_sim2d.so");
  return i;
}

asf::framework::PluginHandle<asf::Source> make(KV kv, std::uint64_t seed = 1,
                                               std::string out = "") {
  kv.emplace("record", out.empty() ? "false" : "true");
  auto h = asf::framework::Registry::create<asf::Source>(info());
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

// map_tiles: n x n copies, odd columns mirrored left-right and odd rows top-bottom, so a
// wall touching one side of the image meets itself across the seam.
TEST(Sim2dWorld, TiledImageMirrorsEveryOtherTile) {
  asf::sim2d::ImageWorldOptions o;
  o.file = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  o.resolution = 0.04;
  const auto one = asf::sim2d::World::fromImage(o);
  o.tiles = 3;
  const auto three = asf::sim2d::World::fromImage(o);
  const asf::Box2 b = three.bounds();
  EXPECT_NEAR(b.max_x - b.min_x, 60.0, 1e-3);
  EXPECT_NEAR(b.max_y - b.min_y, 60.0, 1e-3);
  EXPECT_EQ(three.wallCells(), 9 * one.wallCells());
  int checked = 0, walls = 0;
  for (double x = 0.02; x < 20; x += 0.52)
    for (double y = 0.02; y < 20; y += 0.52) {
      const bool v = one.occupiedAt(x, y);
      walls += v;
      ++checked;
      EXPECT_EQ(three.occupiedAt(x, y), v);               // tile (0, 0): as is
      EXPECT_EQ(three.occupiedAt(40 - x, y), v);          // (1, 0): mirrored in x
      EXPECT_EQ(three.occupiedAt(x, 40 - y), v);          // (0, 1): mirrored in y
      EXPECT_EQ(three.occupiedAt(40 - x, 40 - y), v);     // (1, 1): both
      EXPECT_EQ(three.occupiedAt(40 + x, 40 + y), v);     // (2, 2): as is again
    }
  EXPECT_GT(walls, checked / 10) << "the probe points see walls and free space";
  EXPECT_LT(walls, checked * 9 / 10);
  o.tiles = 0;
  EXPECT_THROW(asf::sim2d::World::fromImage(o), std::runtime_error);
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

  // Empty, cut and lying images are errors naming the file, without MRPT's call trace
  // (issue 20, item 7).
  std::ifstream in(ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png", std::ios::binary);
  const std::string png((std::istreambuf_iterator<char>(in)), {});
  ASSERT_GT(png.size(), 100u);
  std::string lying = png;  // IHDR width (bytes 16..19) says 2^30 px
  lying[16] = 0x40, lying[17] = lying[18] = lying[19] = 0;
  const std::string dir = ::testing::TempDir();
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"empty.png", ""},
                                    {"cut.png", png.substr(0, 60)},
                                    {"lying.png", lying}}) {
    o.file = dir + "/" + name;
    std::ofstream(o.file, std::ios::binary) << bytes;
    try {
      asf::sim2d::World::fromImage(o);
      ADD_FAILURE() << name << ": read without an error";
    } catch (const std::exception& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(o.file + ": ", 0), 0u) << name << ": " << msg;
      EXPECT_EQ(msg.find("MRPT exception"), std::string::npos) << name << ": " << msg;
    }
  }
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
  asf::mapping::OdometryNoiseModel model;
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
                     const asf::navigation::NavPlan& plan) {
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
  asf::navigation::NavOptions o;
  o.robot_radius = 0.2;
  const auto plan = asf::navigation::planPath(&g, {1, 1}, {5, 1}, 0.1, o);
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
  asf::navigation::NavOptions o;
  o.robot_radius = 0.2;
  const auto closed = wallMap(0, 0);
  EXPECT_FALSE(asf::navigation::planPath(&closed, {1, 1}, {5, 1}, 0.1, o).found);
  const auto narrow = wallMap(2.0, 2.3);  // 0.3 m gap, robot 0.4 m wide
  EXPECT_FALSE(asf::navigation::planPath(&narrow, {1, 1}, {5, 1}, 0.1, o).found);
  o.robot_radius = 0.1;
  EXPECT_TRUE(asf::navigation::planPath(&narrow, {1, 1}, {5, 1}, 0.1, o).found);
  const auto open = wallMap(2.5, 3.5);
  const auto in_wall = asf::navigation::planPath(&open, {1, 1}, {3.0, 1}, 0.05, o);
  EXPECT_FALSE(in_wall.found);
  EXPECT_NE(in_wall.reason.find("no free cell"), std::string::npos) << in_wall.reason;
}

TEST(Sim2dNav, UnknownSpaceBlockedOrCostly) {
  // Known free only left of x = 3; the goal lies in unknown space.
  mrpt::maps::COccupancyGridMap2D g(0, 6, 0, 4, 0.05);  // all 0.5 = unknown
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx)
      if (g.idx2x(cx) < 3) g.setCell(static_cast<int>(cx), static_cast<int>(cy), 1.0f);
  asf::navigation::NavOptions o;
  o.unknown_blocked = true;
  EXPECT_FALSE(asf::navigation::planPath(&g, {1, 2}, {5, 2}, 0.1, o).found);
  o.unknown_blocked = false;
  const auto plan = asf::navigation::planPath(&g, {1, 2}, {5, 2}, 0.1, o);
  ASSERT_TRUE(plan.found) << plan.reason;
  EXPECT_NEAR(plan.length, 4.0, 0.1);
  // No map at all: everything unknown, a straight line when costly.
  const auto none = asf::navigation::planPath(nullptr, {0, 0}, {3, 4}, 0.1, o);
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
  for (const auto& f : frames)
    EXPECT_GE(w.clearance(f.ground_truth->x(), f.ground_truth->y()), 0.25 - 0.04);
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

// A velocity-driven base (driveVelocity, what asf sim-robot's /cmd_vel gives it): exact
// unicycle arcs of the true pose, the base's limits, a wall that stops it, a goal taking over.
TEST(Sim2dSource, VelocityDrivesTheBaseWithinItsLimits) {
  // dt 0.1, step_length 0.05, turn_step 10 deg: at most 0.5 m/s and 100 deg/s.
  auto src = make({{"room_width", "8"}, {"room_height", "6"}, {"start_x", "1"},
                   {"start_y", "3"}, {"laser_rays", "10"}});
  const CPose2D start = *src->next()->ground_truth;
  ASSERT_TRUE(src->driveVelocity({0.3, 0}));
  CPose2D p = start;
  for (int i = 0; i < 10; ++i) p = *src->next()->ground_truth;
  EXPECT_NEAR(p.x() - start.x(), 0.3, 1e-9);  // 1 s at 0.3 m/s
  EXPECT_NEAR(p.y(), start.y(), 1e-9);
  // An arc: a quarter turn of radius 1 m in pi/2 / 0.5 = pi s (31.4 steps: 31 of them).
  ASSERT_TRUE(src->driveVelocity({0.5, 0.5}));
  const CPose2D a = p;
  for (int i = 0; i < 31; ++i) p = *src->next()->ground_truth;
  const double th = 31 * 0.1 * 0.5;
  EXPECT_NEAR(p.x(), a.x() + std::sin(th), 1e-6);
  EXPECT_NEAR(p.y(), a.y() + 1 - std::cos(th), 1e-6);
  EXPECT_NEAR(p.phi(), th, 1e-9);
  // Beyond the limits: clamped to 0.5 m/s and 100 deg/s; not a number: zero.
  ASSERT_TRUE(src->driveVelocity({0, -10}));
  const CPose2D b = *src->next()->ground_truth;
  EXPECT_NEAR(mrpt::math::wrapToPi(b.phi() - p.phi()), -10 * M_PI / 180, 1e-9);
  ASSERT_TRUE(src->driveVelocity({NAN, 0}));
  EXPECT_EQ(*src->next()->ground_truth, b);
  // Odometry reads the motion with noise; at rest exactly zero.
  EXPECT_EQ(src->next()->odometry, CPose2D());
  // Towards a wall: the base stops at it and stays clear of it.
  ASSERT_TRUE(src->driveVelocity({5, 0}));
  const auto w = asf::sim2d::World::room(8, 6, 0.04);
  double moved_at_end = 1;
  CPose2D prev = b;
  for (int i = 0; i < 200; ++i) {
    const CPose2D q = *src->next()->ground_truth;
    EXPECT_GE(w.clearance(q.x(), q.y()), 0.2 - 0.04);
    moved_at_end = std::hypot(q.x() - prev.x(), q.y() - prev.y());
    prev = q;
  }
  EXPECT_EQ(moved_at_end, 0);
  // A goal replaces the velocity: the robot drives to it (the estimate: the true pose).
  asf::NavigationContext ctx;
  ctx.robot_estimate = prev;
  asf::NavStatus st = src->navigate({4, 3, 0.1}, ctx);
  for (int i = 0; i < 3000 && st == asf::NavStatus::Moving; ++i) {
    prev = *src->next()->ground_truth;
    st = src->status();
  }
  EXPECT_EQ(st, asf::NavStatus::Reached);
  EXPECT_LT(std::hypot(prev.x() - 4, prev.y() - 3), 0.3);  // up to the odometry's drift
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
  for (std::size_t k = 0; !differs && k < a.size(); ++k)
    differs = !(a[k].odometry == c[k].odometry);
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
  asf::io::RawlogReaderOptions ro;
  ro.ground_truth_file = (dir / "sim2d.gt.txt").string();
  asf::io::RawlogReader reader((dir / "sim2d.rawlog").string(), ro);
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

// ------------------------------------------------------------------- 2.5D world, tilted laser

// Writes a binary PGM of w x h pixels with gray(col, row) (row 0 = top) and returns its path.
// CTest runs each test in its own process, in parallel, and they share this folder: the image
// is written under a name of this process and renamed, so no test ever reads a half-written one.
std::string writePgm(const std::string& name, int w, int h,
                     const std::function<int(int, int)>& gray) {
  const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "tests" / "sim2d_worlds";
  fs::create_directories(dir);
  const fs::path file = dir / name;
  const fs::path partial = dir / (name + ".part" + std::to_string(::getpid()));
  {
    std::ofstream out(partial, std::ios::binary);
    out << "P5\n" << w << " " << h << "\n255\n";
    for (int row = 0; row < h; ++row)
      for (int col = 0; col < w; ++col) out.put(static_cast<char>(gray(col, row)));
  }
  fs::rename(partial, file);
  return file.string();
}

// 6 m x 3 m at 0.02 m/px: a black (2 m) border wall two pixels thick, a low box (gray 100,
// 0.25 m) over x in [2.0, 2.4], y in [1.3, 1.7] and a tall pillar (gray 0, 2 m) over
// x in [4.0, 4.4], y in [0.2, 0.6].
constexpr double kRes = 0.02;
std::string lowBoxWorld() {
  static const std::string path = writePgm("lowbox.pgm", 300, 150, [](int col, int row) {
    const double x = (col + 0.5) * kRes, y = (150 - 1 - row + 0.5) * kRes;
    if (col < 2 || row < 2 || col >= 298 || row >= 148) return 0;
    if (x > 2.0 && x < 2.4 && y > 1.3 && y < 1.7) return 100;
    if (x > 4.0 && x < 4.4 && y > 0.2 && y < 0.6) return 0;
    return 255;
  });
  return path;
}

KV lowBoxKeys(double x, double y) {
  return {{"map_image", lowBoxWorld()},
          {"resolution", "0.02"},
          {"obstacle_heights", "0:2.0, 100:0.25"},
          {"start_x", std::to_string(x)},
          {"start_y", std::to_string(y)},
          {"range_sigma", "0"},
          {"tilted_laser", "true"}};
}

const mrpt::obs::CObservation2DRangeScan& tilted(const asf::SensorFrame& f) {
  EXPECT_EQ(f.observations3d.size(), 1u);
  auto s = std::dynamic_pointer_cast<const mrpt::obs::CObservation2DRangeScan>(
      f.observations3d.at(0));
  EXPECT_TRUE(s);
  return *s;
}

// The world points of the valid rays of a scan taken at the robot's true pose: the ray's end in
// the scan plane, through the scan's sensorPose and the robot pose.
std::vector<mrpt::math::TPoint3D> worldPoints(const mrpt::obs::CObservation2DRangeScan& s,
                                              const CPose2D& robot,
                                              std::vector<std::size_t>* index = nullptr) {
  const mrpt::poses::CPose3D sensor = mrpt::poses::CPose3D(robot) + s.sensorPose;
  std::vector<mrpt::math::TPoint3D> pts;
  for (std::size_t i = 0; i < s.getScanSize(); ++i) {
    if (!s.getScanRangeValidity(i)) continue;
    const double r = s.getScanRange(i), a = s.getScanAngle(i);
    mrpt::math::TPoint3D p;
    sensor.composePoint(r * std::cos(a), r * std::sin(a), 0, p.x, p.y, p.z);
    pts.push_back(p);
    if (index) index->push_back(i);
  }
  return pts;
}

TEST(Sim2dWorld, HeightClassesParse) {
  const auto c = asf::sim2d::parseHeightClasses(" 0:2.0, 100:0.25 ;200:1e-1");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[1].gray, 100);
  EXPECT_DOUBLE_EQ(c[1].height, 0.25);
  EXPECT_DOUBLE_EQ(c[2].height, 0.1);
  EXPECT_TRUE(asf::sim2d::parseHeightClasses("").empty());
  EXPECT_TRUE(asf::sim2d::parseHeightClasses("   ").empty());
  for (const char* bad : {"0=2", "300:1", "-1:1", "0:0", "0:-1", "0:abc", "0:1,0:2", "0:1,",
                          "a:1", "0:1:2", "0:nan", "0:inf", ":1", "0:", "128"})
    EXPECT_THROW(asf::sim2d::parseHeightClasses(bad), std::invalid_argument) << bad;
}

TEST(Sim2dWorld, ObstacleHeightIsTheNearestGrayClass) {
  // Top row: gray 0, 50, 80, 100, 200, 255; the bottom row is free.
  const int grays[6] = {0, 50, 80, 100, 200, 255};
  asf::sim2d::ImageWorldOptions o;
  o.file = writePgm("classes.pgm", 6, 2, [&](int col, int row) { return row ? 255 : grays[col]; });
  o.resolution = 1.0;
  o.pad_wall_px = 1;
  o.wall_height = 1.5;
  auto top = [](int col) { return col + 0.5; };  // x of pixel col; the top row is y in [1, 2]
  {
    const auto w = asf::sim2d::World::fromImage(o);  // no classes: every wall is wall_height
    for (int col = 0; col < 4; ++col) EXPECT_DOUBLE_EQ(w.heightAt(top(col), 1.5), 1.5) << col;
    EXPECT_EQ(w.heightAt(top(4), 1.5), 0.0);  // gray 200 is free (darkness 0.22 < 0.5)
    EXPECT_EQ(w.heightAt(top(0), 0.5), 0.0);
    EXPECT_DOUBLE_EQ(w.heightAt(-0.5, 0.5), 1.5);  // the padding frame
    EXPECT_EQ(w.heightAt(-50, 0.5), 0.0);           // outside the grid
    EXPECT_DOUBLE_EQ(w.maxHeight(), 1.5);
    EXPECT_EQ(w.cellsNotTallerThan(1.4), 0u);
    EXPECT_FALSE(w.gridTallerThan(1.4));
  }
  o.height_classes = asf::sim2d::parseHeightClasses("100:0.25, 0:2.0");
  const auto w = asf::sim2d::World::fromImage(o);
  EXPECT_DOUBLE_EQ(w.heightAt(top(0), 1.5), 2.0);
  EXPECT_DOUBLE_EQ(w.heightAt(top(1), 1.5), 2.0);   // 50: a tie, the darker class wins
  EXPECT_FLOAT_EQ(w.heightAt(top(2), 1.5), 0.25);   // 80: nearer to 100
  EXPECT_FLOAT_EQ(w.heightAt(top(3), 1.5), 0.25);
  EXPECT_EQ(w.heightAt(top(4), 1.5), 0.0);
  EXPECT_DOUBLE_EQ(w.heightAt(-0.5, 0.5), 1.5);  // the frame stays wall_height
  // Obstacles are obstacles whatever their height; the laser grid at 0.3 m drops the low ones.
  EXPECT_TRUE(w.occupiedAt(top(3), 1.5));
  EXPECT_EQ(w.cellsNotTallerThan(0.3), 2u);
  const auto g = w.gridTallerThan(0.3);
  ASSERT_TRUE(g);
  EXPECT_LT(g->getPos(top(1), 1.5), 0.5f);
  EXPECT_GT(g->getPos(top(2), 1.5), 0.5f);
  EXPECT_GT(g->getPos(top(3), 1.5), 0.5f);
  EXPECT_LT(w.grid().getPos(top(3), 1.5), 0.5f);
}

TEST(Sim2dTilted, PositivePitchLooksDown) {
  // MRPT's convention: CPose3D(x, y, z, yaw, pitch, roll), positive pitch = the x axis down.
  const mrpt::poses::CPose3D down(0, 0, 0.5, 0, 20 * M_PI / 180, 0);
  mrpt::math::TPoint3D p;
  down.composePoint(1, 0, 0, p.x, p.y, p.z);
  EXPECT_NEAR(p.z, 0.5 - std::sin(20 * M_PI / 180), 1e-12);
  // In a 20 m room with a 4 m range: looking down sees the floor, looking up sees nothing.
  const KV room{{"room_width", "20"}, {"room_height", "20"}, {"start_x", "10"},
                {"start_y", "10"},    {"range_sigma", "0"},  {"tilted_laser", "true"}};
  KV up = room;
  up["tilted_pitch_deg"] = "-20";
  const auto fd = make(room)->next(), fu = make(up)->next();
  // Looking down (defaults: 0.5 m, 20 deg, 4 m), ray a meets the floor at
  // 0.5 / (cos(a) sin(20 deg)) metres: within range for |a| < 68.6 deg.
  const auto& sd = tilted(*fd);
  std::size_t within = 0;
  for (std::size_t i = 0; i < sd.getScanSize(); ++i)
    within += 0.5 / (std::cos(sd.getScanAngle(i)) * std::sin(20 * M_PI / 180)) < 4 &&
              std::cos(sd.getScanAngle(i)) > 0;
  EXPECT_EQ(within, 137u);
  const auto down_pts = worldPoints(sd, *fd->ground_truth);
  EXPECT_EQ(down_pts.size(), within);
  for (const auto& q : down_pts) EXPECT_NEAR(q.z, 0, 1e-5);
  EXPECT_TRUE(worldPoints(tilted(*fu), *fu->ground_truth).empty());
}

TEST(Sim2dTilted, FlatFloorGivesPointsAtTheAnalyticDistance) {
  const double h = 0.5, pitch = 20 * M_PI / 180, phi = 30 * M_PI / 180;
  auto src = make({{"room_width", "20"}, {"room_height", "20"}, {"resolution", "0.05"},
                   {"start_x", "10"}, {"start_y", "10"}, {"start_phi_deg", "30"},
                   {"range_sigma", "0"}, {"tilted_laser", "true"}, {"tilted_x", "0.1"},
                   {"tilted_y", "0.05"}, {"tilted_z", "0.5"}, {"tilted_pitch_deg", "20"},
                   {"tilted_rays", "121"}, {"tilted_fov_deg", "120"}});
  const auto f = src->next();
  ASSERT_TRUE(f && f->scan && f->ground_truth);
  const auto& s = tilted(*f);
  EXPECT_EQ(s.sensorLabel, "TILTED_LASER");
  EXPECT_TRUE(s.rightToLeft);
  EXPECT_NEAR(s.sensorPose.pitch(), pitch, 1e-12);
  EXPECT_NEAR(s.sensorPose.z(), h, 1e-12);
  EXPECT_EQ(s.timestamp, f->scan->timestamp);
  ASSERT_EQ(s.getScanSize(), 121u);
  std::vector<std::size_t> idx;
  const auto pts = worldPoints(s, *f->ground_truth, &idx);
  ASSERT_EQ(pts.size(), 121u);  // +-60 deg: every ray meets the floor within 4 m
  // The sensor's ground position; the points lie on the floor on a line h / tan(pitch) ahead
  // of it (perpendicular to the heading), at lateral offset h tan(a) / sin(pitch).
  const double sx = 10 + 0.1 * std::cos(phi) - 0.05 * std::sin(phi);
  const double sy = 10 + 0.1 * std::sin(phi) + 0.05 * std::cos(phi);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double a = s.getScanAngle(idx[k]);
    const double ahead = (pts[k].x - sx) * std::cos(phi) + (pts[k].y - sy) * std::sin(phi);
    const double left = -(pts[k].x - sx) * std::sin(phi) + (pts[k].y - sy) * std::cos(phi);
    EXPECT_NEAR(pts[k].z, 0, 1e-5) << "ray " << idx[k];
    EXPECT_NEAR(ahead, h / std::tan(pitch), 1e-5) << "ray " << idx[k];
    EXPECT_NEAR(left, h * std::tan(a) / std::sin(pitch), 1e-5) << "ray " << idx[k];
  }
  // The 3D map's reading of the observation gives the same points.
  std::vector<Eigen::Vector3f> local;
  mrpt::poses::CPose3D on_robot;
  std::string why;
  ASSERT_TRUE(asf::mapping::Map3d::observationPoints(s, local, on_robot, &why)) << why;
  ASSERT_EQ(local.size(), pts.size());
  const mrpt::poses::CPose3D sensor = mrpt::poses::CPose3D(*f->ground_truth) + on_robot;
  for (std::size_t k = 0; k < local.size(); ++k) {
    mrpt::math::TPoint3D p;
    sensor.composePoint(local[k].x(), local[k].y(), local[k].z(), p.x, p.y, p.z);
    EXPECT_NEAR(p.z, 0, 1e-4);
    EXPECT_NEAR(p.x, pts[k].x, 1e-4);
  }
}

TEST(Sim2dTilted, LowBoxIsSeenOnlyByTheTiltedLaser) {
  // The robot at (1, 1.5) faces the low box 0.9 m ahead of the lasers (at x = 1.1).
  auto src = make(lowBoxKeys(1.0, 1.5));
  const auto f = src->next();
  ASSERT_TRUE(f && f->scan);
  // Horizontal laser at 0.3 m: the ray straight ahead reaches the far wall (x = 5.96), and
  // no ray ends at the box.
  ASSERT_EQ(f->scan->getScanSize(), 361u);
  EXPECT_NEAR(f->scan->getScanRange(180), 5.96 - 1.1, 0.03);
  for (const auto& p : worldPoints(*f->scan, *f->ground_truth))
    EXPECT_FALSE(p.x > 1.9 && p.x < 2.5 && p.y > 1.2 && p.y < 1.8) << p.x << " " << p.y;
  // It is MRPT's simulator on the world without the box (gray 100 is free at threshold 0.7).
  asf::sim2d::ImageWorldOptions o;
  o.file = lowBoxWorld();
  o.resolution = kRes;
  o.occupied_threshold = 0.7;
  const auto no_box = asf::sim2d::World::fromImage(o);
  EXPECT_EQ(no_box.heightAt(2.2, 1.5), 0.0);
  mrpt::obs::CObservation2DRangeScan expected = *f->scan;
  no_box.grid().laserScanSimulator(expected, *f->ground_truth, 0.5f, 361);
  for (std::size_t i = 0; i < 361; ++i) {
    ASSERT_TRUE(expected.getScanRangeValidity(i));
    ASSERT_EQ(f->scan->getScanRange(i), expected.getScanRange(i)) << "ray " << i;
  }

  // Tilted laser at 0.5 m, 20 deg down: the middle rays hit the box's face at x = 2.0 and
  // z = 0.5 - 0.9 tan(20 deg); every hit above the floor is on the box.
  std::vector<std::size_t> idx;
  const auto& t = tilted(*f);
  const auto pts = worldPoints(t, *f->ground_truth, &idx);
  const double tan20 = std::tan(20 * M_PI / 180);
  int on_box = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const auto& p = pts[k];
    if (p.z < 1e-5) continue;  // the floor
    // The rays near +-90 deg stay high enough to reach the border wall (x, y = 0.04, 5.96, 2.96).
    if (p.y > 2.96 - 1e-4 || p.y < 0.04 + 1e-4 || p.x < 0.04 + 1e-4 || p.x > 5.96 - 1e-4) {
      EXPECT_LE(p.z, 0.5 + 1e-5);
      continue;
    }
    ++on_box;
    EXPECT_TRUE(p.x > 2.0 - 1e-6 && p.x < 2.4 && p.y > 1.3 - 1e-6 && p.y < 1.7 + 1e-6)
        << "ray " << idx[k] << " at " << p.x << " " << p.y << " " << p.z;
    EXPECT_LE(p.z, 0.25 + 1e-5);
  }
  EXPECT_GT(on_box, 10);
  ASSERT_TRUE(t.getScanRangeValidity(90));
  mrpt::math::TPoint3D p;
  (mrpt::poses::CPose3D(*f->ground_truth) + t.sensorPose)
      .composePoint(t.getScanRange(90), 0, 0, p.x, p.y, p.z);
  EXPECT_NEAR(p.x, 2.0, 1e-4);
  EXPECT_NEAR(p.z, 0.5 - 0.9 * tan20, 1e-4);
}

TEST(Sim2dTilted, TallPillarIsSeenByBothLasers) {
  // The robot at (3, 0.4) faces the pillar's face at x = 4.0, 0.9 m ahead of the lasers.
  auto src = make(lowBoxKeys(3.0, 0.4));
  const auto f = src->next();
  EXPECT_NEAR(f->scan->getScanRange(180), 0.9, 0.03);
  const auto& t = tilted(*f);
  mrpt::math::TPoint3D p;
  (mrpt::poses::CPose3D(*f->ground_truth) + t.sensorPose)
      .composePoint(t.getScanRange(90), 0, 0, p.x, p.y, p.z);
  EXPECT_NEAR(p.x, 4.0, 1e-4);
  EXPECT_NEAR(p.z, 0.5 - 0.9 * std::tan(20 * M_PI / 180), 1e-4);
  // Raise the tilted laser to 2.4 m: its middle ray passes over the pillar's face (z = 2.07
  // at x = 4.0) and comes down onto its 2 m top 0.4 / tan(20 deg) = 1.10 m ahead (x = 4.2).
  KV kv = lowBoxKeys(3.0, 0.4);
  kv["tilted_z"] = "2.4";
  auto high = make(kv);
  const auto g = high->next();
  const auto& th = tilted(*g);
  (mrpt::poses::CPose3D(*g->ground_truth) + th.sensorPose)
      .composePoint(th.getScanRange(90), 0, 0, p.x, p.y, p.z);
  EXPECT_NEAR(p.z, 2.0, 1e-4);
  EXPECT_NEAR(p.x, 3.1 + 0.4 / std::tan(20 * M_PI / 180), 1e-4);
}

TEST(Sim2dTilted, RobotCannotDriveIntoALowBox) {
  // No map and a horizontal laser that does not see the box: the plan goes straight through
  // it, and the true world stops the robot.
  KV kv = lowBoxKeys(1.0, 1.5);
  kv["laser_rays"] = "31";
  auto src = make(kv);
  std::vector<asf::NavStatus> st;
  const auto frames = drive(*src, {{3.5, 1.5, 0.1}}, &st);
  ASSERT_EQ(st.size(), 1u);
  EXPECT_EQ(st[0], asf::NavStatus::Blocked);
  double max_x = 0;
  for (const auto& f : frames) {
    const double x = f.ground_truth->x(), y = f.ground_truth->y();
    const double dx = std::max({2.0 - x, 0.0, x - 2.4}), dy = std::max({1.3 - y, 0.0, y - 1.7});
    EXPECT_GE(std::hypot(dx, dy), 0.2 - kRes) << x << " " << y;
    max_x = std::max(max_x, x);
  }
  EXPECT_GT(max_x, 1.7);  // it did drive up to the box
}

TEST(Sim2dTilted, DefaultsScanTheTrueGridWithMrpt) {
  // The shipped cave with the defaults: every wall is 2 m tall, the horizontal laser is
  // MRPT's simulator on the true grid, and there is no tilted scan.
  const std::string cave = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  auto src = make({{"map_image", cave}, {"pad_wall_px", "1"}, {"start_x", "2"},
                   {"start_y", "2"}, {"laser_rays", "541"}, {"laser_fov_deg", "270"},
                   {"laser_max_range", "10"}, {"range_sigma", "0"}});
  asf::sim2d::ImageWorldOptions o;
  o.file = cave;
  o.pad_wall_px = 1;
  const auto w = asf::sim2d::World::fromImage(o);
  EXPECT_FALSE(w.gridTallerThan(0.3));
  EXPECT_DOUBLE_EQ(w.maxHeight(), 2.0);
  const auto f = src->next();
  EXPECT_TRUE(f->observations3d.empty());
  mrpt::obs::CObservation2DRangeScan expected = *f->scan;
  w.grid().laserScanSimulator(expected, *f->ground_truth, 0.5f, 541);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < 541; ++i) {
    ASSERT_EQ(f->scan->getScanRangeValidity(i), expected.getScanRangeValidity(i)) << "ray " << i;
    if (!expected.getScanRangeValidity(i)) continue;  // the source reads maxRange there
    ASSERT_EQ(f->scan->getScanRange(i), expected.getScanRange(i)) << "ray " << i;
    ++valid;
  }
  EXPECT_GT(valid, 300u);
}

TEST(Sim2dTilted, DeterministicAndIndependentOfTheOtherStreams) {
  KV on{{"laser_rays", "50"}, {"tilted_laser", "true"}, {"tilted_range_sigma", "0.02"},
        {"tilted_pitch_deg", "10"}};
  KV off = on;
  off["tilted_laser"] = "false";
  const std::vector<asf::Goal> goals{{5, 4, 0.1}, {2, 2, 0.1}};
  KV exact = on;
  exact["tilted_range_sigma"] = "0";
  const auto a = drive(*make(on, 3), goals), b = drive(*make(on, 3), goals),
             c = drive(*make(on, 4), goals), d = drive(*make(off, 3), goals),
             e = drive(*make(exact, 3), goals);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), d.size());
  ASSERT_EQ(a.size(), e.size());
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const auto &ta = tilted(a[k]), &tb = tilted(b[k]);
    for (std::size_t i = 0; i < ta.getScanSize(); ++i) {
      ASSERT_EQ(ta.getScanRange(i), tb.getScanRange(i));
      ASSERT_EQ(ta.getScanRangeValidity(i), tb.getScanRangeValidity(i));
    }
    if (k < c.size() && !c[k].observations3d.empty())
      differs |= tilted(c[k]).getScanRange(90) != ta.getScanRange(90);
    // Without the tilted laser: the same path, odometry and horizontal scans.
    EXPECT_TRUE(d[k].observations3d.empty());
    EXPECT_EQ(*d[k].ground_truth, *a[k].ground_truth);
    EXPECT_EQ(d[k].odometry, a[k].odometry);
    for (std::size_t i = 0; i < a[k].scan->getScanSize(); ++i)
      ASSERT_EQ(d[k].scan->getScanRange(i), a[k].scan->getScanRange(i));
  }
  EXPECT_TRUE(differs);
  // The noise: against the same run without it (same path), std 0.02 on the valid rays.
  double sum2 = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(*e[k].ground_truth, *a[k].ground_truth);
    const auto &ta = tilted(a[k]), &te = tilted(e[k]);
    for (std::size_t i = 0; i < ta.getScanSize(); ++i) {
      if (!ta.getScanRangeValidity(i) || !te.getScanRangeValidity(i)) continue;
      sum2 += std::pow(ta.getScanRange(i) - te.getScanRange(i), 2);
      ++n;
    }
  }
  ASSERT_GT(n, 1000u);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 0.002);
}

TEST(Sim2dTilted, ConfigErrorsNameTheKey) {
  KV kv = lowBoxKeys(1, 1.5);
  kv["obstacle_heights"] = "0:2.0, 128";
  const std::string e = configError(kv);
  EXPECT_NE(e.find("obstacle_heights"), std::string::npos) << e;
  EXPECT_NE(e.find("128"), std::string::npos) << e;
  kv["obstacle_heights"] = "0:2.0, 100:-0.25";
  EXPECT_NE(configError(kv).find("obstacle_heights"), std::string::npos);
}

TEST(Sim2dTilted, CaveScansSeeTheFloorAhead) {
  // The cave, 181 rays over 180 deg, 4 m, 20 deg down from 0.5 m: the floor is 1.37 m ahead,
  // so most rays return from almost every free pose (the time per scan: bench_sim2d).
  asf::sim2d::ImageWorldOptions o;
  o.file = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  o.pad_wall_px = 1;
  const auto w = asf::sim2d::World::fromImage(o);
  std::vector<CPose2D> poses;
  for (double x = 0.5; x < 19.5; x += 0.37)
    for (double y = 0.5; y < 19.5; y += 0.41)
      if (w.clearance(x, y) > 0.2) poses.push_back(CPose2D(x, y, x * y));
  ASSERT_GT(poses.size(), 500u);
  mrpt::obs::CObservation2DRangeScan t;
  t.aperture = static_cast<float>(M_PI);
  t.maxRange = 4;
  t.sensorPose = mrpt::poses::CPose3D(0.1, 0, 0.5, 0, 20 * M_PI / 180, 0);
  std::size_t valid = 0;
  for (const auto& p : poses) {
    w.simulateScan3D(t, p, 181);
    for (std::size_t i = 0; i < 181; ++i) valid += t.getScanRangeValidity(i);
  }
  EXPECT_GT(valid, 181 * poses.size() / 2);
}

TEST(Sim2dTilted, LowObstaclesDatasetHasItsClasses) {
  // datasets/low_obstacles: 8 m x 6 m, two rooms, boxes of 0.25 m (gray 64) and 0.2 m (112).
  asf::sim2d::ImageWorldOptions o;
  o.file = ASF_TEST_SOURCE_DIR "/datasets/low_obstacles/low_obstacles.png";
  o.height_classes = asf::sim2d::parseHeightClasses("0:2.0, 64:0.25, 112:0.2");
  const auto w = asf::sim2d::World::fromImage(o);
  const asf::Box2 b = w.bounds();
  EXPECT_NEAR(b.max_x - b.min_x, 8.0, 1e-4);
  EXPECT_NEAR(b.max_y - b.min_y, 6.0, 1e-4);
  EXPECT_DOUBLE_EQ(w.heightAt(0.05, 3.0), 2.0);   // outer wall
  EXPECT_DOUBLE_EQ(w.heightAt(4.0, 1.0), 2.0);    // the wall between the rooms
  EXPECT_EQ(w.heightAt(4.0, 3.0), 0.0);           // its door
  EXPECT_DOUBLE_EQ(w.heightAt(5.15, 4.65), 2.0);  // the pillar
  EXPECT_FLOAT_EQ(w.heightAt(2.2, 1.4), 0.25);    // boxes
  EXPECT_FLOAT_EQ(w.heightAt(5.75, 2.25), 0.25);
  EXPECT_FLOAT_EQ(w.heightAt(1.3, 4.35), 0.2);    // low boxes
  EXPECT_FLOAT_EQ(w.heightAt(6.75, 4.4), 0.2);
  EXPECT_FLOAT_EQ(w.heightAt(2.95, 2.95), 0.2);
  EXPECT_EQ(w.heightAt(1.0, 1.0), 0.0);           // the suggested start
  EXPECT_GT(w.clearance(1.0, 1.0), 0.3);
  // The pixels (centre inside) of the five boxes, all below a laser at 0.3 m.
  EXPECT_EQ(w.cellsNotTallerThan(0.3), 10u * 10 + 12u * 12 + 15u * 7 + 7u * 20 + 7u * 7);
  EXPECT_EQ(w.cellsNotTallerThan(0.2), 15u * 7 + 7u * 20 + 7u * 7);
}

TEST(Sim2dTilted, RecordedRawlogKeepsTheTiltedScans) {
  const fs::path dir = fs::path(ASF_TEST_BINARY_DIR) / "tests" / "sim2d_record_tilted";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<asf::SensorFrame> frames;
  {
    auto src = make({{"laser_rays", "91"}, {"laser_rate", "4"}, {"tilted_laser", "true"}}, 5,
                    dir.string());
    frames = drive(*src, {{6, 4, 0.1}});
  }
  asf::io::RawlogReaderOptions ro;
  ro.laser_label = "LASER";
  ro.observations3d = true;
  asf::io::RawlogReader reader((dir / "sim2d.rawlog").string(), ro);
  std::size_t k = 0, tilted_scans = 0;
  while (auto f = reader.next()) {
    ASSERT_LT(k, frames.size());
    const auto& o = frames[k++];
    ASSERT_EQ(f->observations3d.size(), o.observations3d.size()) << "frame " << k;
    EXPECT_EQ(o.observations3d.size(), o.scan ? 1u : 0u);  // with every horizontal scan
    if (o.observations3d.empty()) continue;
    ++tilted_scans;
    const auto &a = tilted(*f), &b = tilted(o);
    EXPECT_EQ(a.sensorLabel, "TILTED_LASER");
    EXPECT_EQ(a.sensorPose, b.sensorPose);
    ASSERT_EQ(a.getScanSize(), b.getScanSize());
    for (std::size_t i = 0; i < a.getScanSize(); ++i) {
      ASSERT_EQ(a.getScanRange(i), b.getScanRange(i));
      ASSERT_EQ(a.getScanRangeValidity(i), b.getScanRangeValidity(i));
    }
  }
  EXPECT_EQ(k, frames.size());
  EXPECT_GT(tilted_scans, 10u);
}

}  // namespace
