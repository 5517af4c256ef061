// The path follower: its rule on single poses (analytic), and closed loop on an exact
// unicycle (the robot ends where the path ends, never far from it, in bounded time).
#include <asf/navigation/path_follower.h>
#include <gtest/gtest.h>

#include <cmath>

using asf::Point2;
using asf::navigation::FollowerOptions;
using asf::navigation::FollowState;
using asf::navigation::PathFollower;
using asf::navigation::Velocity;
using mrpt::poses::CPose2D;

namespace {

// Distance from p to the polyline start -> path.
double distanceToPath(const Point2& p, const Point2& start, const std::vector<Point2>& path) {
  double best = 1e300;
  Point2 a = start;
  for (const Point2& b : path) {
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    double s = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
    s = std::clamp(s, 0.0, 1.0);
    best = std::min(best, std::hypot(p.x - a.x - s * dx, p.y - a.y - s * dy));
    a = b;
  }
  return best;
}

// An exact unicycle arc of dt at v.
CPose2D drive(const CPose2D& p, const Velocity& v, double dt) {
  const double d = v.forward * dt, a = v.turn * dt;
  const CPose2D u = std::abs(a) < 1e-12 ? CPose2D(d, 0, 0)
                                        : CPose2D(d * std::sin(a) / a, d * (1 - std::cos(a)) / a, a);
  CPose2D q = p + u;
  q.normalizePhi();
  return q;
}

struct Outcome {
  FollowState state = FollowState::Following;
  CPose2D pose;
  double time = 0, worst_deviation = 0;
};

Outcome closedLoop(const std::vector<Point2>& path, CPose2D pose, const FollowerOptions& o,
                   double dt = 0.05, double limit = 120) {
  PathFollower f(o);
  const Point2 start{pose.x(), pose.y()};
  f.start(path, 0);
  Outcome out;
  for (double t = 0; t < limit && f.following(); t += dt) {
    const Velocity v = f.update(pose, t);
    EXPECT_LE(std::abs(v.forward), o.max_forward + 1e-12);
    EXPECT_LE(std::abs(v.turn), o.max_turn + 1e-12);
    EXPECT_GE(v.forward, 0);  // never backwards
    pose = drive(pose, v, dt);
    out.worst_deviation = std::max(out.worst_deviation, distanceToPath({pose.x(), pose.y()}, start, path));
    out.time = t;
  }
  out.state = f.state();
  out.pose = pose;
  return out;
}

}  // namespace

TEST(PathFollower, TurnsInPlaceTowardsAWaypointBehindOrBeside) {
  FollowerOptions o;
  PathFollower f(o);
  f.start({{0, 1}}, 0);
  const Velocity left = f.update(CPose2D(0, 0, 0), 0);
  EXPECT_EQ(left.forward, 0);
  EXPECT_DOUBLE_EQ(left.turn, o.max_turn);  // 2.5 * pi/2 > max_turn: clamped
  f.start({{0, -1}}, 0);
  const Velocity right = f.update(CPose2D(0, 0, 0), 0);
  EXPECT_EQ(right.forward, 0);
  EXPECT_DOUBLE_EQ(right.turn, -o.max_turn);
  // A small error above the tolerance: proportional.
  f.start({{std::cos(0.4), std::sin(0.4)}}, 0);
  const Velocity small = f.update(CPose2D(0, 0, 0), 0);
  EXPECT_EQ(small.forward, 0);
  EXPECT_NEAR(small.turn, o.turn_gain * 0.4, 1e-9);
}

TEST(PathFollower, DrivesAtFullSpeedAlongAStraightPathAndSlowsAtItsEnd) {
  FollowerOptions o;
  PathFollower f(o);
  f.start({{1, 0}, {2, 0}}, 0);
  const Velocity v = f.update(CPose2D(0, 0, 0), 0);
  EXPECT_DOUBLE_EQ(v.forward, o.max_forward);
  EXPECT_DOUBLE_EQ(v.turn, 0);
  EXPECT_DOUBLE_EQ(f.remaining(), 2.0);
  const Velocity end = f.update(CPose2D(1.75, 0, 0), 1);  // 0.25 m left: half speed
  EXPECT_NEAR(end.forward, o.max_forward * 0.25 / o.slow_down, 1e-12);
  EXPECT_TRUE(f.following());
  EXPECT_EQ(f.update(CPose2D(1.97, 0.01, 0), 2).forward, 0);
  EXPECT_EQ(f.state(), FollowState::Arrived);
  EXPECT_EQ(f.update(CPose2D(0, 0, 0), 3).turn, 0);  // arrived: no command any more
}

TEST(PathFollower, AWaypointTheRobotIsAlreadyBeyondIsPassed) {
  PathFollower f;
  f.start({{1, 0}, {2, 0}}, 0);
  // Beyond (1, 0) along the next segment, 0.5 m from it: steer for (2, 0), not back.
  const Velocity v = f.update(CPose2D(1.5, 0.1, 0), 0);
  EXPECT_GT(v.forward, 0);
  EXPECT_LT(v.turn, 0);
  EXPECT_NEAR(f.remaining(), std::hypot(0.5, 0.1), 1e-12);
}

TEST(PathFollower, AnEmptyPathIsArrivedAtOnce) {
  PathFollower f;
  f.start({}, 0);
  EXPECT_EQ(f.state(), FollowState::Arrived);
}

TEST(PathFollower, NoProgressForStuckTimeIsStuck) {
  FollowerOptions o;
  o.stuck_time = 5;
  PathFollower f(o);
  f.start({{3, 0}}, 10);
  const CPose2D wall(0, 0, 0);  // the robot does not move, whatever it is told
  for (double t = 10; t <= 15; t += 0.1) {
    f.update(wall, t);
    ASSERT_TRUE(f.following()) << t;
  }
  f.update(wall, 15.2);
  EXPECT_EQ(f.state(), FollowState::Stuck);
  EXPECT_EQ(f.update(wall, 16).forward, 0);
}

TEST(PathFollower, ALongerReplannedPathIsNotALackOfProgress) {
  FollowerOptions o;
  o.stuck_time = 5;
  PathFollower f(o);
  f.start({{4, 0}}, 0);
  f.update(CPose2D(0, 0, 0), 0);
  f.update(CPose2D(1, 0, 0), 4);  // progress at t = 4
  f.replace({{1, 3}, {4, 3}, {4, 0}});  // a detour: 9 m left instead of 3
  for (double t = 4; t < 9; t += 0.5) f.update(CPose2D(1, 0.2 * (t - 4), M_PI / 2), t);
  EXPECT_TRUE(f.following());  // 1 m up the detour by t = 9: progress on the new path
  f.update(CPose2D(1, 1, M_PI / 2), 9.5);
  EXPECT_TRUE(f.following());
  // Standing still on the detour: stuck stuck_time after the last progress, not after the replan.
  for (double t = 9.5; t < 16; t += 0.5) f.update(CPose2D(1, 1, M_PI / 2), t);
  EXPECT_EQ(f.state(), FollowState::Stuck);
}

TEST(PathFollower, ClosedLoopFollowsAnLShapedPathToItsEnd) {
  FollowerOptions o;
  std::vector<Point2> path;
  for (int i = 1; i <= 60; ++i) path.push_back({0.05 * i, 0});      // 3 m east, 5 cm cells
  for (int i = 1; i <= 40; ++i) path.push_back({3.0, 0.05 * i});    // then 2 m north
  const Outcome r = closedLoop(path, CPose2D(0, 0, M_PI), o);  // starting the wrong way round
  EXPECT_EQ(r.state, FollowState::Arrived);
  EXPECT_LT(std::hypot(r.pose.x() - 3.0, r.pose.y() - 2.0), o.arrival + 1e-9);
  EXPECT_LT(r.worst_deviation, 0.5 * o.lookahead);  // corners cut by less than the lookahead
  // 5 m at 0.5 m/s plus turning round (pi at max_turn) and a corner: well under twice that.
  EXPECT_LT(r.time, 2 * (5.0 / o.max_forward + M_PI / o.max_turn + 2));
}

TEST(PathFollower, ClosedLoopOnAZigZagOfDiagonalCells) {
  // An 8-connected A* path: alternating straight and diagonal steps.
  FollowerOptions o;
  std::vector<Point2> path;
  Point2 p{0, 0};
  for (int i = 0; i < 40; ++i) {
    p.x += 0.05;
    if (i % 2) p.y += 0.05;
    path.push_back(p);
  }
  for (double dt : {0.02, 0.1}) {  // a controller at 50 Hz and at 10 Hz
    const Outcome r = closedLoop(path, CPose2D(0, 0, 0), o, dt);
    EXPECT_EQ(r.state, FollowState::Arrived) << dt;
    EXPECT_LT(r.worst_deviation, 0.1) << dt;
  }
}
