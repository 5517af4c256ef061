// Reachability: geodesic distances over known-free cells that keep the robot's radius from
// obstacles. Analytic cases on hand-made MRPT grids.
#include <asf/mapping/reachability.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <chrono>
#include <cmath>
#include <filesystem>

namespace {

constexpr double kRes = 0.05;
constexpr float kFree = 0.95f, kOccupied = 0.05f, kUnknown = 0.5f;  // p(free), MRPT

using Grid = mrpt::maps::COccupancyGridMap2D;

/// A grid over [0, w] x [0, h], every cell unknown.
std::shared_ptr<Grid> unknownGrid(double w, double h) {
  return std::make_shared<Grid>(0.0f, static_cast<float>(w), 0.0f, static_cast<float>(h),
                                static_cast<float>(kRes));
}

/// Sets every cell whose centre is inside [x0, x1] x [y0, y1] to p_free.
void fill(Grid& g, double x0, double y0, double x1, double y1, float p_free) {
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx) {
      const double x = g.idx2x(cx), y = g.idx2y(cy);
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) g.setCell(cx, cy, p_free);
    }
}

asf::GridMap wrap(std::shared_ptr<Grid> g) {
  asf::GridMap m;
  m.grid = std::move(g);
  m.version = 1;
  return m;
}

double octile(double dx, double dy) {
  dx = std::abs(dx);
  dy = std::abs(dy);
  return std::max(dx, dy) + (M_SQRT2 - 1) * std::min(dx, dy);
}

/// A room [0, w] x [0, h] of known free space closed by a wall 0.1 m thick.
std::shared_ptr<Grid> room(double w, double h) {
  auto g = unknownGrid(w, h);
  fill(*g, 0, 0, w, h, kOccupied);
  fill(*g, 0.1, 0.1, w - 0.1, h - 0.1, kFree);
  return g;
}

TEST(Reachability, NullOrEmptyGridReachesNothing) {
  asf::GridMap none;
  const auto r = asf::mapping::Reachability::compute(none, {0, 0});
  EXPECT_FALSE(r.reachable({0, 0}));
  EXPECT_EQ(r.distanceTo({0, 0}), asf::mapping::Reachability::kUnreachable);
  EXPECT_FALSE(r.nearestReachable({0, 0}, 1.0).has_value());
  EXPECT_EQ(r.closest({{0, 0}, {1, 1}}, 1.0), -1);
  EXPECT_EQ(r.width(), 0);
  EXPECT_EQ(r.cellDistance(0, 0), asf::mapping::Reachability::kUnreachable);

  // (MRPT cannot make a grid of zero cells.) A grid of unknown cells: only the robot's
  // footprint (cells within robot_radius of it, which it occupies) is reachable.
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.2;
  const asf::Point2 at{1.01, 1.01};
  const auto u = asf::mapping::Reachability::compute(wrap(unknownGrid(2, 2)), at, o);
  EXPECT_EQ(u.distanceTo(at), 0.0);
  for (int cy = 0; cy < u.height(); ++cy)
    for (int cx = 0; cx < u.width(); ++cx) {
      const asf::Point2 c = u.cellCenter(cx, cy);
      const bool under_robot = std::hypot(c.x - at.x, c.y - at.y) <= o.robot_radius;
      EXPECT_EQ(u.cellDistance(cx, cy) < 1e9, under_robot) << cx << "," << cy;
    }
  EXPECT_FALSE(u.reachable({1.3, 1.0}));
}

TEST(Reachability, StartOffTheGridReachesNothing) {
  auto g = unknownGrid(2, 2);
  fill(*g, 0, 0, 2, 2, kFree);
  const auto r = asf::mapping::Reachability::compute(wrap(g), {-1, 1});
  EXPECT_FALSE(r.reachable({1, 1}));
  EXPECT_FALSE(r.reachable({-1, 1}));
  // From inside the same grid is reachable everywhere (the control).
  EXPECT_TRUE(asf::mapping::Reachability::compute(wrap(g), {0.5, 1}).reachable({1.5, 1}));
}

TEST(Reachability, OpenFreeSpaceIsOctileDistanceBetweenEuclideanAndOctile) {
  // No obstacle at all: the 8-connected geodesic from the start cell is the octile distance
  // between cell centres, which is at least the Euclidean distance.
  auto g = unknownGrid(4, 3);
  fill(*g, 0, 0, 4, 3, kFree);
  const asf::Point2 start{1.03, 0.98};
  const auto r = asf::mapping::Reachability::compute(wrap(g), start);
  EXPECT_EQ(r.width(), 80);
  EXPECT_EQ(r.height(), 60);
  EXPECT_NEAR(r.resolution(), kRes, 1e-6);
  const int sx = static_cast<int>(std::floor(start.x / kRes));
  const int sy = static_cast<int>(std::floor(start.y / kRes));
  EXPECT_EQ(r.cellDistance(sx, sy), 0.0);
  const asf::Point2 s = r.cellCenter(sx, sy);
  for (int cy = 0; cy < r.height(); ++cy)
    for (int cx = 0; cx < r.width(); ++cx) {
      const asf::Point2 c = r.cellCenter(cx, cy);
      const double d = r.cellDistance(cx, cy);
      const double oct = octile(c.x - s.x, c.y - s.y);
      ASSERT_NEAR(d, oct, 1e-4) << cx << "," << cy;
      ASSERT_GE(d, std::hypot(c.x - s.x, c.y - s.y) - 1e-4);
      ASSERT_DOUBLE_EQ(r.distanceTo(c), d);
    }
  EXPECT_FALSE(r.reachable({4.1, 1}));  // off the grid
}

TEST(Reachability, RoomKeepsTheRobotRadiusFromWalls) {
  auto g = room(4, 3);
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.2;
  const asf::Point2 start{2, 1.5};
  const auto r = asf::mapping::Reachability::compute(wrap(g), start, o);
  // Wall inner face at 0.1: centres 0.3 m + half a cell... Cell centres at >= 0.2 m from the
  // wall's edge are passable, closer ones are not.
  EXPECT_TRUE(r.reachable({0.325, 1.5}));   // centre 0.225 from the face
  EXPECT_FALSE(r.reachable({0.275, 1.5}));  // centre 0.175 from the face
  EXPECT_FALSE(r.reachable({0.05, 1.5}));   // the wall itself
  // Inside a convex room the geodesic stays between Euclidean and octile.
  for (const asf::Point2 p : {asf::Point2{0.4, 0.4}, {3.6, 2.6}, {3.0, 1.0}, {1.0, 2.3}}) {
    ASSERT_TRUE(r.reachable(p)) << p.x << "," << p.y;
    const double d = r.distanceTo(p);
    EXPECT_GE(d, std::hypot(p.x - start.x, p.y - start.y) - kRes * 1.5);
    EXPECT_LE(d, octile(p.x - start.x, p.y - start.y) + kRes * 1.5);
  }
  // A bigger radius shrinks the free space further.
  o.robot_radius = 0.5;
  const auto big = asf::mapping::Reachability::compute(wrap(g), start, o);
  EXPECT_FALSE(big.reachable({0.4, 0.4}));
  EXPECT_TRUE(big.reachable({0.7, 1.5}));
}

/// A room 6 x 4 m split by a wall at x in [2.95, 3.05] with a door [3.0, 3.0 + door].
std::shared_ptr<Grid> roomWithDoor(double door) {
  auto g = room(6, 4);
  fill(*g, 2.95, 0, 3.05, 4, kOccupied);
  if (door > 0) fill(*g, 2.95, 3.0, 3.05, 3.0 + door, kFree);
  return g;
}

TEST(Reachability, DoorNarrowerThanTheRobotBlocksWiderDoorIsGoneAround) {
  const asf::Point2 start{1, 1}, goal{5, 1};
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.2;
  // 0.3 m < 2 * radius: the other side is unreachable although free and connected.
  const auto narrow = asf::mapping::Reachability::compute(wrap(roomWithDoor(0.3)), start, o);
  EXPECT_TRUE(narrow.reachable({2, 1}));
  EXPECT_FALSE(narrow.reachable(goal));
  EXPECT_FALSE(narrow.reachable({4, 3.2}));
  // The same door is fine for a thinner robot.
  o.robot_radius = 0.1;
  EXPECT_TRUE(asf::mapping::Reachability::compute(wrap(roomWithDoor(0.3)), start, o).reachable(goal));

  o.robot_radius = 0.2;
  const auto wide = asf::mapping::Reachability::compute(wrap(roomWithDoor(0.8)), start, o);
  ASSERT_TRUE(wide.reachable(goal));
  // The path must cross the wall line inside the door, y in [3.2, 3.6] once the radius is
  // kept from the jambs: at least the broken line through (3, 3.2).
  const double through_door = 2 * std::hypot(2.0, 2.2);
  const double d = wide.distanceTo(goal);
  EXPECT_GE(d, through_door - 2 * kRes);
  EXPECT_LE(d, through_door * 1.0824 + 4 * kRes);  // octile stretch of a straight line
  EXPECT_GT(d, 4.0 + 1.0);                         // far longer than straight across
}

TEST(Reachability, PathToFollowsTheDistanceFieldThroughTheDoor) {
  const asf::Point2 start{1, 1}, goal{5, 1};
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.2;
  const auto r = asf::mapping::Reachability::compute(wrap(roomWithDoor(0.8)), start, o);
  const std::vector<asf::Point2> path = r.pathTo(goal);
  ASSERT_GE(path.size(), 2u);
  EXPECT_LE(std::hypot(path.front().x - start.x, path.front().y - start.y), kRes);
  EXPECT_LE(std::hypot(path.back().x - goal.x, path.back().y - goal.y), kRes);
  EXPECT_NEAR(r.distanceTo(path.front()), 0, 1e-9);
  double length = 0;
  bool through_door = false;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double step = std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
    EXPECT_LE(step, M_SQRT2 * kRes + 1e-6) << "step " << i << " is not to a neighbour";
    EXPECT_GT(r.distanceTo(path[i]), r.distanceTo(path[i - 1])) << "step " << i;
    EXPECT_TRUE(r.reachable(path[i]));
    length += step;
    if (std::abs(path[i].x - 3) < 0.06) through_door = through_door || path[i].y > 3.15;
  }
  // A shortest path: its length is the field's distance (float metres, ~1e-6 per step).
  EXPECT_NEAR(length, r.distanceTo(goal), 1e-3);
  EXPECT_TRUE(through_door);
  // Nothing to follow to an unreachable place or off the grid.
  EXPECT_TRUE(r.pathTo({50, 50}).empty());
  EXPECT_TRUE(asf::mapping::Reachability::compute(wrap(roomWithDoor(0.3)), start, o).pathTo(goal).empty());
}

TEST(Reachability, UnknownCellsBlock) {
  auto g = unknownGrid(6, 2);
  fill(*g, 0, 0, 2.5, 2, kFree);
  fill(*g, 3.5, 0, 6, 2, kFree);  // [2.5, 3.5] stays unknown
  const auto r = asf::mapping::Reachability::compute(wrap(g), {1, 1});
  EXPECT_TRUE(r.reachable({2.4, 1}));
  EXPECT_FALSE(r.reachable({3.0, 1}));
  EXPECT_FALSE(r.reachable({5, 1}));
  // Control: the same band known free joins both sides.
  fill(*g, 2.5, 0, 3.5, 2, kFree);
  EXPECT_NEAR(asf::mapping::Reachability::compute(wrap(g), {1, 1}).distanceTo({5, 1}), 4.0, kRes);
  // Nearly unknown (inside unknown_band) also blocks; just outside it does not. (MRPT
  // stores 0.53 as 0.531.)
  fill(*g, 2.5, 0, 3.5, 2, 0.53f);
  asf::mapping::ReachabilityOptions o;
  o.unknown_band = 0.04;
  EXPECT_FALSE(asf::mapping::Reachability::compute(wrap(g), {1, 1}, o).reachable({5, 1}));
  o.unknown_band = 0.02;
  EXPECT_TRUE(asf::mapping::Reachability::compute(wrap(g), {1, 1}, o).reachable({5, 1}));
}

TEST(Reachability, OccupiedThresholdDecidesWhatIsAnObstacle) {
  auto g = unknownGrid(6, 2);
  fill(*g, 0, 0, 6, 2, kFree);
  fill(*g, 2.9, 0, 3.1, 2, 0.3f);  // p(occupied) = 0.7
  asf::mapping::ReachabilityOptions o;
  o.occupied_threshold = 0.65;
  EXPECT_FALSE(asf::mapping::Reachability::compute(wrap(g), {1, 1}, o).reachable({5, 1}));
  o.occupied_threshold = 0.75;  // now the band is free, if a little doubtful
  EXPECT_TRUE(asf::mapping::Reachability::compute(wrap(g), {1, 1}, o).reachable({5, 1}));
}

TEST(Reachability, StartInsideTheRadiusOfAWallCanLeave) {
  auto g = room(4, 3);
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.3;
  // 0.07 m from the wall's face at x = 0.1: every cell around the start is lethal.
  const asf::Point2 start{0.175, 1.5};
  const auto r = asf::mapping::Reachability::compute(wrap(g), start, o);
  EXPECT_EQ(r.distanceTo(start), 0.0);
  EXPECT_TRUE(r.reachable({0.225, 1.5}));  // inside the escape disk
  EXPECT_TRUE(r.reachable({2, 1.5}));
  EXPECT_NEAR(r.distanceTo({2.025, 1.525}), 1.85, kRes);
  // Elsewhere the same clearance stays lethal: the exception is local to the start.
  EXPECT_FALSE(r.reachable({0.175, 0.6}));
  EXPECT_FALSE(r.reachable({0.05, 1.5}));  // never into the wall
}

TEST(Reachability, NearestReachableSnapsToTheClosestReachableCell) {
  auto g = room(4, 3);
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.2;
  const auto r = asf::mapping::Reachability::compute(wrap(g), {2, 1.5}, o);
  // A point in the left wall: the nearest reachable cell centres are at x = 0.325.
  const auto q = r.nearestReachable({0.05, 1.51}, 0.5);
  ASSERT_TRUE(q.has_value());
  EXPECT_NEAR(q->x, 0.325, 1e-6);
  EXPECT_NEAR(q->y, 1.525, 1e-6);
  EXPECT_TRUE(r.reachable(*q));
  EXPECT_FALSE(r.nearestReachable({0.05, 1.51}, 0.2).has_value());  // too far to snap
  // A reachable point snaps to its own cell centre.
  const auto own = r.nearestReachable({1.01, 1.01}, 0.3);
  ASSERT_TRUE(own.has_value());
  EXPECT_NEAR(own->x, 1.025, 1e-6);
  EXPECT_NEAR(own->y, 1.025, 1e-6);
  const auto own0 = r.nearestReachable({1.01, 1.01}, 0.0);
  ASSERT_TRUE(own0.has_value());
  EXPECT_NEAR(own0->x, 1.025, 1e-6);
}

TEST(Reachability, NearestReachableTieGoesToTheSmallerGeodesicDistance) {
  // A thin wall at x = 2 with free space on both sides; the point in the wall is equally
  // far from the first free cells on either side, but only the left side is near the start.
  auto g = unknownGrid(4, 2);
  fill(*g, 0, 0, 4, 2, kFree);
  fill(*g, 1.95, 0, 2.05, 1.8, kOccupied);  // wall with a way round at the top
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = 0.0;
  for (const double sx : {1.0, 3.0}) {
    const auto r = asf::mapping::Reachability::compute(wrap(g), {sx, 0.5}, o);
    ASSERT_TRUE(r.reachable({4 - sx, 0.5}));  // round the wall
    const auto q = r.nearestReachable({2.0, 0.525}, 0.2);
    ASSERT_TRUE(q.has_value());
    EXPECT_NEAR(q->x, sx < 2 ? 1.925 : 2.075, 1e-6) << "start x " << sx;
  }
}

TEST(Reachability, ClosestIsGeodesicNotEuclidean) {
  const auto r = asf::mapping::Reachability::compute(wrap(roomWithDoor(0.8)), {2.5, 1}, {});
  // A is 1 m away through the wall (3.5, 1), B 2.5 m away on the same side.
  const std::vector<asf::Point2> candidates{{3.5, 1}, {0.5, 2.5}, {-5, -5}};
  asf::Point2 snapped;
  double dist = -1;
  EXPECT_EQ(r.closest(candidates, 0.3, &snapped, &dist), 1);
  EXPECT_TRUE(r.reachable(snapped));
  EXPECT_DOUBLE_EQ(dist, r.distanceTo(snapped));
  EXPECT_LT(dist, r.distanceTo({3.5, 1}));
  // A candidate in the wall is snapped to a reachable cell within the radius.
  const std::vector<asf::Point2> in_wall{{3.0, 1.0}};
  EXPECT_EQ(r.closest(in_wall, 0.1), -1);  // wall plus radius: nothing within 0.1 m
  ASSERT_EQ(r.closest(in_wall, 0.5, &snapped, &dist), 0);
  EXPECT_LT(snapped.x, 3.0);  // the start's side of the wall
  EXPECT_TRUE(r.reachable(snapped));
  EXPECT_EQ(r.closest({}, 1.0), -1);
  EXPECT_EQ(r.closest({{-5, -5}}, 1.0), -1);
}

// The cave map (fully known): a Bellman check of the whole field, and the time it takes.
TEST(Reachability, CaveFieldIsConsistent) {
  const std::string png = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  if (!std::filesystem::exists(png)) GTEST_SKIP() << png << " missing";
  auto g = std::make_shared<Grid>();
  ASSERT_TRUE(g->loadFromBitmapFile(png, 0.05f));
  const asf::GridMap map = wrap(g);
  // Start at the freest cell, found with a first field from anywhere free.
  asf::Point2 start{};
  for (unsigned cy = g->getSizeY() / 2; cy < g->getSizeY(); ++cy)
    if (g->getCell(g->getSizeX() / 2, cy) > 0.9f) {
      start = {g->idx2x(g->getSizeX() / 2), g->idx2y(cy)};
      break;
    }
  asf::mapping::ReachabilityOptions o;
  const auto t0 = std::chrono::steady_clock::now();
  const int reps = 10;
  asf::mapping::Reachability r;
  for (int i = 0; i < reps; ++i) r = asf::mapping::Reachability::compute(map, start, o);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
      reps;
  RecordProperty("compute_ms", std::to_string(ms));
  std::printf("Reachability::compute on %dx%d cells: %.2f ms\n", r.width(), r.height(), ms);

  int reachable = 0;
  const double res = r.resolution();
  for (int cy = 0; cy < r.height(); ++cy)
    for (int cx = 0; cx < r.width(); ++cx) {
      const double d = r.cellDistance(cx, cy);
      if (!(d < asf::mapping::Reachability::kUnreachable)) continue;
      ++reachable;
      bool has_parent = d == 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!dx && !dy) continue;
          const double dn = r.cellDistance(cx + dx, cy + dy);
          if (!(dn < asf::mapping::Reachability::kUnreachable)) continue;
          const double step = (dx && dy ? M_SQRT2 : 1.0) * res;
          if (!dx || !dy) {
            ASSERT_LE(d, dn + step + 1e-4) << cx << "," << cy;  // no shortcut
          }
          if (std::abs(dn + step - d) < 1e-4) has_parent = true;
        }
      ASSERT_TRUE(has_parent) << cx << "," << cy << " d=" << d;
    }
  EXPECT_GT(reachable, 10000);
}

}  // namespace
