// Tests of the frontier policy on hand-made occupancy grids: geodesic choice, minimum size,
// blacklisting, Done, goals on reachable cells, the no-map step, loops avoided.
#include <asf/errors.h>
#include <asf/policy.h>
#include <asf/mapping/reachability.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

namespace {

constexpr double kRes = 0.05;
constexpr float kFree = 0.95f, kOccupied = 0.05f, kUnknown = 0.5f;  // p(free), MRPT
using Grid = mrpt::maps::COccupancyGridMap2D;
using Type = asf::Decision::Type;

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/policy_frontier.so");
  return i;
}

asf::framework::PluginHandle<asf::Policy> make(const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Policy>(info());
  h->configure(asf::Params::fromSpecs("frontier", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

/// Sets every cell whose centre is inside [x0, x1] x [y0, y1] to p_free.
void fill(Grid& g, double x0, double y0, double x1, double y1, float p_free) {
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx) {
      const double x = g.idx2x(cx), y = g.idx2y(cy);
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) g.setCell(cx, cy, p_free);
    }
}

/// A known room [0, 6] x [0, 4] (walls 0.1 m thick) split by a wall at x = 3 with a door at
/// y in [3.0, 3.8]; no unknown cell: add them per test.
std::shared_ptr<Grid> twoRooms() {
  auto g = std::make_shared<Grid>(0.0f, 6.0f, 0.0f, 4.0f, static_cast<float>(kRes));
  fill(*g, 0, 0, 6, 4, kOccupied);
  fill(*g, 0.1, 0.1, 5.9, 3.9, kFree);
  fill(*g, 2.95, 0, 3.05, 4, kOccupied);
  fill(*g, 2.95, 3.0, 3.05, 3.8, kFree);
  return g;
}

struct Driver {
  asf::Policy& p;
  asf::TopoGraph topo;
  asf::GridMap map;
  asf::ExplorationState s;
  Driver(asf::Policy& policy, std::shared_ptr<Grid> grid, double x, double y, double phi = 0)
      : p(policy) {
    s.topo = &topo;
    map.grid = std::move(grid);
    map.version = 1;
    s.map = map.grid ? &map : nullptr;
    s.robot = mrpt::poses::CPose2D(x, y, phi);
  }
  asf::Decision decide(asf::NavStatus last = asf::NavStatus::Idle) {
    s.last_status = last;
    const asf::Decision d = p.decide(s);
    if (d.type == Type::GoTo) s.last_goal = d.goal;
    return d;
  }
};

double dist(const asf::Goal& g, double x, double y) { return std::hypot(g.x - x, g.y - y); }

/// Distance from the goal to the nearest cell centre of box [x0, x1] x [y0, y1].
double distToBox(const asf::Goal& g, double x0, double y0, double x1, double y1) {
  const double dx = std::max({x0 - g.x, 0.0, g.x - x1}), dy = std::max({y0 - g.y, 0.0, g.y - y1});
  return std::hypot(dx, dy);
}

void expectReachable(const Driver& d, const asf::Decision& dec, double radius = 0.2) {
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  asf::mapping::ReachabilityOptions o;
  o.robot_radius = radius;
  const auto r = asf::mapping::Reachability::compute(d.map, {d.s.robot.x(), d.s.robot.y()}, o);
  EXPECT_TRUE(r.reachable({dec.goal.x, dec.goal.y}))
      << "goal (" << dec.goal.x << ", " << dec.goal.y << ") " << dec.reason;
}

TEST(PolicyFrontier, PicksTheGeodesicallyNearestFrontierNotTheEuclideanOne) {
  auto g = twoRooms();
  fill(*g, 3.5, 0.5, 4.0, 1.5, kUnknown);  // behind the wall: 1 m away, ~5 m to drive
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);  // same room: ~2 m away
  auto p = make();
  Driver d(*p, g, 2.5, 1.0);
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_LT(distToBox(dec.goal, 0.5, 2.5, 1.0, 3.0), 0.1) << dec.reason;
  EXPECT_GT(distToBox(dec.goal, 3.5, 0.5, 4.0, 1.5), 1.5) << dec.reason;
  EXPECT_DOUBLE_EQ(dec.goal.tolerance, 0.3);
  // The reason names the choice: how many frontiers, length and distance.
  EXPECT_NE(dec.reason.find("nearest of 2 frontiers"), std::string::npos) << dec.reason;
  EXPECT_NE(dec.reason.find("m long"), std::string::npos) << dec.reason;
  EXPECT_NE(dec.reason.find("m away"), std::string::npos) << dec.reason;
  expectReachable(d, dec);

  // Remove the wall between them: now the Euclidean nearest is also the nearest.
  fill(*g, 2.95, 0.1, 3.05, 3.0, kFree);
  auto p2 = make();
  Driver d2(*p2, g, 2.5, 1.0);
  const auto dec2 = d2.decide();
  ASSERT_EQ(dec2.type, Type::GoTo) << dec2.reason;
  EXPECT_LT(distToBox(dec2.goal, 3.5, 0.5, 4.0, 1.5), 0.1) << dec2.reason;
}

TEST(PolicyFrontier, GoalIsTheFrontierCellNearestTheRobotNotTheCentroid) {
  auto g = twoRooms();
  fill(*g, 0.5, 0.5, 2.5, 1.0, kUnknown);  // a long patch: its near end is at x = 2.5
  auto p = make();
  Driver d(*p, g, 2.5, 2.0);
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_GT(dec.goal.x, 2.2) << dec.reason;  // the centroid would be x = 1.5
  EXPECT_NEAR(dec.goal.y, 1.025, 0.06) << dec.reason;
}

TEST(PolicyFrontier, IgnoresFrontiersSmallerThanTheMinimumSize) {
  auto g = twoRooms();
  fill(*g, 2.0, 1.0, 2.1, 1.1, kUnknown);  // 2 x 2 cells: 8 frontier cells = 0.4 m
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);
  {
    auto p = make({{"min_frontier_size", "0.5"}});
    Driver d(*p, g, 2.5, 0.5);
    const auto dec = d.decide();
    ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
    EXPECT_LT(distToBox(dec.goal, 0.5, 2.5, 1.0, 3.0), 0.1) << dec.reason;
  }
  {
    auto p = make({{"min_frontier_size", "0.3"}});  // control: now the small one counts
    Driver d(*p, g, 2.5, 0.5);
    const auto dec = d.decide();
    ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
    EXPECT_LT(distToBox(dec.goal, 2.0, 1.0, 2.1, 1.1), 0.1) << dec.reason;
  }
  {
    // Only the small one left: Done, and the reason says why.
    auto g2 = twoRooms();
    fill(*g2, 2.0, 1.0, 2.1, 1.1, kUnknown);
    auto p = make();
    Driver d(*p, g2, 2.5, 0.5);
    const auto dec = d.decide();
    ASSERT_EQ(dec.type, Type::Done) << dec.reason;
    EXPECT_NE(dec.reason.find("1 smaller than"), std::string::npos) << dec.reason;
  }
}

TEST(PolicyFrontier, FailedFrontierIsBlacklistedAndTheNextOneChosen) {
  auto g = twoRooms();
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);  // near
  fill(*g, 4.5, 1.0, 5.0, 1.5, kUnknown);  // far, behind the wall
  auto p = make({{"max_failures_per_frontier", "1"}});
  Driver d(*p, g, 2.5, 1.0);
  auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_LT(distToBox(dec.goal, 0.5, 2.5, 1.0, 3.0), 0.1) << dec.reason;
  dec = d.decide(asf::NavStatus::Unreachable);
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_LT(distToBox(dec.goal, 4.5, 1.0, 5.0, 1.5), 0.1) << dec.reason;
  EXPECT_NE(dec.reason.find("1 blacklisted"), std::string::npos) << dec.reason;
  expectReachable(d, dec);
  dec = d.decide(asf::NavStatus::Blocked);
  ASSERT_EQ(dec.type, Type::Done) << dec.reason;
  EXPECT_EQ(dec.reason.find("no frontier left (2 blacklisted"), 0u) << dec.reason;
  // Done stays Done while the map is the same.
  EXPECT_EQ(d.decide(asf::NavStatus::Idle).type, Type::Done);
}

TEST(PolicyFrontier, AFrontierIsGivenUpAfterMaxFailures) {
  auto g = twoRooms();
  fill(*g, 0.5, 1.0, 2.5, 1.5, kUnknown);  // 2 m long patch: room for several goals
  fill(*g, 4.5, 1.0, 5.0, 1.5, kUnknown);  // the other one, far
  auto p = make({{"max_failures_per_frontier", "3"}, {"blacklist_radius", "0.3"}});
  Driver d(*p, g, 2.0, 2.5);
  std::vector<asf::Goal> near_goals;
  asf::Decision dec = d.decide();
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
    ASSERT_LT(distToBox(dec.goal, 0.5, 1.0, 2.5, 1.5), 0.1) << k << ": " << dec.reason;
    for (const asf::Goal& before : near_goals)
      EXPECT_GT(dist(dec.goal, before.x, before.y), 0.3) << "a blacklisted spot again";
    near_goals.push_back(dec.goal);
    dec = d.decide(asf::NavStatus::Unreachable);
  }
  // Three failures on the near frontier: it is given up although parts of it are left.
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_LT(distToBox(dec.goal, 4.5, 1.0, 5.0, 1.5), 0.1) << dec.reason;
}

TEST(PolicyFrontier, DoneWhenNoFrontierRemains) {
  auto p = make();
  Driver d(*p, twoRooms(), 2.5, 1.0);
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::Done) << dec.reason;
  EXPECT_EQ(dec.reason, "no frontier left (0 blacklisted, 0 unreachable, 0 smaller than 0.5 m)");
}

TEST(PolicyFrontier, FrontierBeyondANarrowDoorIsUnreachable) {
  auto g = twoRooms();
  fill(*g, 2.95, 3.0, 3.05, 3.8, kOccupied);
  fill(*g, 2.95, 3.0, 3.05, 3.3, kFree);  // a 0.3 m door: too narrow for radius 0.2
  fill(*g, 4.5, 1.0, 5.0, 1.5, kUnknown);
  auto p = make();
  Driver d(*p, g, 2.5, 1.0);
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::Done) << dec.reason;
  EXPECT_NE(dec.reason.find("1 unreachable"), std::string::npos) << dec.reason;
  // A thinner robot passes.
  auto thin = make({{"robot_radius", "0.1"}});
  Driver d2(*thin, g, 2.5, 1.0);
  EXPECT_EQ(d2.decide().type, Type::GoTo);
}

TEST(PolicyFrontier, GoalIsOnAReachableCellWhenTheFrontierHugsAWall) {
  auto g = twoRooms();
  // A 0.3 m gap in the outer wall opening onto unknown space: every frontier cell is
  // within the robot's radius of the wall, so the goal must be moved off the frontier.
  fill(*g, 5.9, 1.85, 6.0, 2.15, kUnknown);
  auto p = make({{"min_frontier_size", "0.2"}});
  Driver d(*p, g, 4.0, 1.0);
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  expectReachable(d, dec);
  // Moved off the frontier (its cells are the column x = 5.875) by at most snap_radius.
  EXPECT_LT(dec.goal.x, 5.85) << dec.reason;
  EXPECT_LE(distToBox(dec.goal, 5.875, 1.875, 5.875, 2.125), 0.5 + 1e-6) << dec.reason;
  // Reachability confirms the frontier cells themselves are not drivable.
  const auto r = asf::mapping::Reachability::compute(d.map, {4.0, 1.0}, {});
  for (const double y : {1.875, 1.925, 1.975, 2.025, 2.075, 2.125})
    EXPECT_FALSE(r.reachable({5.875, y})) << y;
}

TEST(PolicyFrontier, ReachingAFrontierThatStaysCountsAsAFailureNoEndlessLoop) {
  auto g = twoRooms();
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);
  fill(*g, 4.5, 1.0, 5.0, 1.5, kUnknown);
  auto p = make();
  Driver d(*p, g, 2.5, 1.0);
  asf::Decision dec = d.decide();
  // The map never changes (the robot sees nothing new): every goal is "reached" and the
  // robot moves there; the policy must run out of goals, never repeat one in a loop.
  int steps = 0;
  std::vector<asf::Goal> goals;
  while (dec.type == Type::GoTo && steps < 100) {
    for (const asf::Goal& before : goals)
      ASSERT_GT(dist(dec.goal, before.x, before.y), 1e-6) << "goal repeated: " << dec.reason;
    goals.push_back(dec.goal);
    expectReachable(d, dec);
    d.s.robot = mrpt::poses::CPose2D(dec.goal.x, dec.goal.y, 0);
    dec = d.decide(asf::NavStatus::Reached);
    ++steps;
  }
  ASSERT_EQ(dec.type, Type::Done) << dec.reason;
  EXPECT_NE(dec.reason.find("2 blacklisted"), std::string::npos) << dec.reason;
  EXPECT_LE(steps, 2 * 3 + 2);  // at most max_failures per frontier, plus slack
}

TEST(PolicyFrontier, RobotStandingOnAFrontierIsSentElsewhere) {
  auto g = twoRooms();
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);
  fill(*g, 4.5, 1.0, 5.0, 1.5, kUnknown);
  auto p = make();
  Driver d(*p, g, 1.2, 2.75);  // 0.175 m from the first patch's frontier
  const auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_GT(dist(dec.goal, 1.2, 2.75), 0.3) << dec.reason;
}

TEST(PolicyFrontier, NoMapGivesOneStepAheadThenDone) {
  auto p = make();
  Driver d(*p, nullptr, 1.0, 2.0, M_PI / 2);
  auto dec = d.decide();
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_NEAR(dec.goal.x, 1.0, 1e-9);
  EXPECT_NEAR(dec.goal.y, 2.5, 1e-9);
  EXPECT_NE(dec.reason.find("no map yet"), std::string::npos) << dec.reason;
  dec = d.decide(asf::NavStatus::Reached);
  EXPECT_EQ(dec.type, Type::Done) << dec.reason;
  EXPECT_FALSE(dec.reason.empty());
}

TEST(PolicyFrontier, FirstMapAfterTheStepIsExplored) {
  auto p = make();
  Driver d(*p, nullptr, 2.5, 1.0);
  ASSERT_EQ(d.decide().type, Type::GoTo);
  auto g = twoRooms();
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);
  d.map.grid = g;
  d.s.map = &d.map;
  const auto dec = d.decide(asf::NavStatus::Reached);
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  EXPECT_LT(distToBox(dec.goal, 0.5, 2.5, 1.0, 3.0), 0.1) << dec.reason;
}

TEST(PolicyFrontier, DecisionsAreDeterministic) {
  // Two identical patches nearly mirrored about the robot: every instance picks the same.
  auto g = twoRooms();
  fill(*g, 0.5, 1.0, 1.0, 1.5, kUnknown);
  fill(*g, 0.5, 2.5, 1.0, 3.0, kUnknown);
  asf::Goal first;
  for (int k = 0; k < 3; ++k) {
    auto p = make();
    Driver d(*p, g, 2.0, 2.0);
    const auto dec = d.decide();
    ASSERT_EQ(dec.type, Type::GoTo);
    if (k == 0) first = dec.goal;
    EXPECT_EQ(dec.goal.x, first.x);
    EXPECT_EQ(dec.goal.y, first.y);
  }
}

TEST(PolicyFrontier, SnapRadiusBelowRobotRadiusIsAConfigError) {
  try {
    make({{"robot_radius", "0.3"}, {"snap_radius", "0.2"}});
    FAIL() << "accepted snap_radius < robot_radius";
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("snap_radius"), std::string::npos) << e.what();
  }
}

// The cave (25 m square at 0.05 m) with everything farther than 5 m from the robot unknown:
// frontiers all around; prints the time of one decide().
TEST(PolicyFrontier, CaveDecisionIsReachable) {
  const std::string png = ASF_TEST_SOURCE_DIR "/datasets/cave/cave_filled.png";
  if (!std::filesystem::exists(png)) GTEST_SKIP() << png << " missing";
  auto g = std::make_shared<Grid>();
  ASSERT_TRUE(g->loadFromBitmapFile(png, 0.05f));
  asf::Point2 start{};
  for (unsigned cy = g->getSizeY() / 2; cy < g->getSizeY(); ++cy)
    if (g->getCell(g->getSizeX() / 2, cy) > 0.9f) {
      start = {g->idx2x(g->getSizeX() / 2), g->idx2y(cy) + 0.5};
      break;
    }
  for (unsigned cy = 0; cy < g->getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g->getSizeX(); ++cx)
      if (std::hypot(g->idx2x(cx) - start.x, g->idx2y(cy) - start.y) > 5.0)
        g->setCell(cx, cy, kUnknown);
  auto p = make();
  Driver d(*p, g, start.x, start.y);
  const int reps = 5;
  asf::Decision dec;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < reps; ++i) {
    auto fresh = make();
    Driver di(*fresh, g, start.x, start.y);
    dec = di.decide();
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
      reps;
  std::printf("frontier decide() on %ux%u cells: %.2f ms (%s)\n", g->getSizeX(), g->getSizeY(),
              ms, dec.reason.c_str());
  RecordProperty("decide_ms", std::to_string(ms));
  ASSERT_EQ(dec.type, Type::GoTo) << dec.reason;
  expectReachable(d, dec);
}

}  // namespace
