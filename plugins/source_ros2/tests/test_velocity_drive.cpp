// drive = cmd_vel without DDS (velocity_drive.h): a goal planned on a map with a wall, followed
// by commands a simulated unicycle executes in the odometry frame (map -> odom not the
// identity), the outcome held back until the run has seen it, halts and failures.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include "../velocity_drive.h"

using asf::NavStatus;
using asf::ros2live::VelocityDrive;
using asf::ros2live::VelocityDriveOptions;
using mrpt::poses::CPose2D;

namespace {

// 6 x 4 m, free, a wall at x in [2.9, 3.1] except for a gap at y in [2.5, 3.5].
std::shared_ptr<mrpt::maps::COccupancyGridMap2D> wallMap() {
  auto g = std::make_shared<mrpt::maps::COccupancyGridMap2D>(0, 6, 0, 4, 0.05);
  for (unsigned cy = 0; cy < g->getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g->getSizeX(); ++cx) {
      const double x = g->idx2x(cx), y = g->idx2y(cy);
      const bool wall = x > 2.9 && x < 3.1 && !(y > 2.5 && y < 3.5);
      g->setCell(static_cast<int>(cx), static_cast<int>(cy), wall ? 0.0f : 1.0f);
    }
  return g;
}

struct Robot {
  std::vector<asf::navigation::Velocity> sent;
  VelocityDrive drive;
  explicit Robot(VelocityDriveOptions o = {})
      : drive(o, [this](const asf::navigation::Velocity& v) { sent.push_back(v); }) {}
};

CPose2D arc(const CPose2D& p, const asf::navigation::Velocity& v, double dt) {
  const double d = v.forward * dt, a = v.turn * dt;
  const CPose2D u = std::abs(a) < 1e-12 ? CPose2D(d, 0, 0)
                                        : CPose2D(d * std::sin(a) / a, d * (1 - std::cos(a)) / a, a);
  return p + u;
}

}  // namespace

TEST(VelocityDrive, FollowsAPlanThroughTheGapInTheOdometryFrame) {
  Robot r;
  const auto map = wallMap();
  // The odometry frame is rotated and shifted against the map: map = map_to_odom (+) odom.
  const CPose2D map_to_odom(2.0, -1.0, 0.7);
  CPose2D odom = (CPose2D() - map_to_odom) + CPose2D(1, 1, 0);  // the robot at map (1, 1)
  VelocityDrive::View v{map, map_to_odom + odom, odom, {}, 0};
  ASSERT_EQ(r.drive.navigate({5, 1, 0.1}, v), NavStatus::Moving);
  // Distance from the robot's centre to the wall's two blocks.
  auto clearance = [](const CPose2D& m) {
    auto box = [&](double y0, double y1) {
      const double dx = std::max({2.9 - m.x(), 0.0, m.x() - 3.1});
      const double dy = std::max({y0 - m.y(), 0.0, m.y() - y1});
      return std::hypot(dx, dy);
    };
    return std::min(box(0, 2.5), box(3.5, 4));
  };
  double t = 0, worst = 1e9;
  for (; t < 100 && r.drive.status(t) == NavStatus::Moving; t += 0.05) {
    const std::size_t before = r.sent.size();
    r.drive.odometry(odom, t);
    ASSERT_EQ(r.sent.size(), before + 1);  // one command per odometry message
    odom = arc(odom, r.sent.back(), 0.05);
    const CPose2D m = map_to_odom + odom;
    worst = std::min(worst, clearance(m));
  }
  EXPECT_EQ(r.drive.status(t), NavStatus::Reached) << r.drive.why();
  const CPose2D end = map_to_odom + odom;
  EXPECT_LT(std::hypot(end.x() - 5, end.y() - 1), 0.1);
  EXPECT_GT(worst, 0.2 - 0.03);  // through the gap, keeping the robot's radius (to a cell)
  EXPECT_EQ(r.sent.back().forward, 0);  // the last command stops the robot
  EXPECT_EQ(r.sent.back().turn, 0);
}

TEST(VelocityDrive, TheOutcomeWaitsForTheRunToSeeIt) {
  Robot r;
  VelocityDrive::View v{wallMap(), CPose2D(1, 1, 0), CPose2D(1, 1, 0), {}, 10};
  ASSERT_EQ(r.drive.navigate({1.3, 1, 0.1}, v), NavStatus::Moving);
  r.drive.odometry(CPose2D(1.29, 1, 0), 12.0);  // arrived at robot time 12
  EXPECT_EQ(r.drive.status(11.9), NavStatus::Moving);  // the run is at a frame of 11.9 s
  EXPECT_EQ(r.drive.status(12.0), NavStatus::Reached);
}

TEST(VelocityDrive, UnreachableGoalsAndGoalsAlreadyReached) {
  Robot r;
  VelocityDrive::View v{wallMap(), CPose2D(1, 1, 0), CPose2D(), {}, 0};
  EXPECT_EQ(r.drive.navigate({3.0, 1.0, 0.05}, v), NavStatus::Unreachable);  // in the wall
  EXPECT_NE(r.drive.why(), "");
  EXPECT_EQ(r.drive.status(0), NavStatus::Unreachable);  // until the next goal: the policy learns
  EXPECT_EQ(r.drive.navigate({1.05, 1, 0.1}, v), NavStatus::Reached);
  EXPECT_EQ(r.drive.status(0), NavStatus::Reached);
  EXPECT_EQ(r.drive.navigate({NAN, 1, 0.1}, v), NavStatus::Unreachable);
  EXPECT_TRUE(r.sent.empty());
}

TEST(VelocityDrive, ARobotThatDoesNotMoveIsBlockedAfterStuckTime) {
  VelocityDriveOptions o;
  o.follow.stuck_time = 3;
  Robot r(o);
  VelocityDrive::View v{wallMap(), CPose2D(1, 1, 0), CPose2D(1, 1, 0), {}, 0};
  ASSERT_EQ(r.drive.navigate({2, 1, 0.1}, v), NavStatus::Moving);
  for (double t = 0; t < 3; t += 0.1) r.drive.odometry(CPose2D(1, 1, 0), t);
  EXPECT_EQ(r.drive.status(3), NavStatus::Moving);
  r.drive.odometry(CPose2D(1, 1, 0), 3.2);
  EXPECT_EQ(r.drive.status(3.2), NavStatus::Blocked);
  EXPECT_NE(r.drive.why().find("stuck"), std::string::npos);
}

TEST(VelocityDrive, GoalTimeoutAndHalt) {
  VelocityDriveOptions o;
  o.goal_timeout = 1;
  Robot r(o);
  VelocityDrive::View v{wallMap(), CPose2D(1, 1, 0), CPose2D(1, 1, 0), {}, 0};
  ASSERT_EQ(r.drive.navigate({2, 1, 0.1}, v), NavStatus::Moving);
  r.drive.odometry(CPose2D(1.1, 1, 0), 0.5);
  EXPECT_GT(r.sent.back().forward, 0);
  r.drive.odometry(CPose2D(1.2, 1, 0), 1.5);
  EXPECT_EQ(r.drive.status(2), NavStatus::Blocked);
  ASSERT_EQ(r.drive.navigate({2, 1, 0.1}, v), NavStatus::Moving);
  r.drive.odometry(CPose2D(1.1, 1, 0), 0.5);
  r.drive.halt();
  EXPECT_EQ(r.sent.back().forward, 0);
  EXPECT_EQ(r.drive.status(5), NavStatus::Idle);
  const std::size_t n = r.sent.size();
  r.drive.odometry(CPose2D(1.1, 1, 0), 0.6);  // halted: no more commands
  EXPECT_EQ(r.sent.size(), n);
}

TEST(VelocityDrive, AReplanOnANewMapThatClosesThePathBlocksTheGoal) {
  VelocityDriveOptions o;
  o.replan_period = 1;
  Robot r(o);
  VelocityDrive::View v{wallMap(), CPose2D(1, 1, 0), CPose2D(1, 1, 0), {}, 0};
  ASSERT_EQ(r.drive.navigate({5, 1, 0.1}, v), NavStatus::Moving);
  auto closed = std::make_shared<mrpt::maps::COccupancyGridMap2D>(*v.map);
  for (unsigned cy = 0; cy < closed->getSizeY(); ++cy)
    closed->setCell(static_cast<int>(closed->x2idx(3.0)), static_cast<int>(cy), 0.0f);
  v.map = closed;
  v.time = 0.5;
  r.drive.observe(v);  // not due yet
  EXPECT_EQ(r.drive.status(0.5), NavStatus::Moving);
  v.time = 1.0;
  r.drive.observe(v);
  EXPECT_EQ(r.drive.status(1.0), NavStatus::Blocked);
  EXPECT_NE(r.drive.why().find("no path"), std::string::npos);
}
