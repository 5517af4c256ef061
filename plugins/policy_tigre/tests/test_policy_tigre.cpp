// Tests of the tigre policy on hand-made worlds: a fully known free grid cut into regions
// by a label image, the topological graph built by the framework's TopoBuilder, and a robot
// that teleports to each goal (the navigation is not under test here).
#include <asf/errors.h>
#include <asf/policy.h>
#include <asf/framework/registry.h>
#include <asf/mapping/topo_builder.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <functional>
#include <map>
#include <set>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/policy_tigre.so");
  return i;
}

asf::framework::PluginHandle<asf::Policy> make(const std::map<std::string, std::string>& kv = {},
                                               std::uint64_t seed = 7) {
  auto h = asf::framework::Registry::create<asf::Policy>(info());
  asf::PluginContext ctx;
  ctx.seed = seed;
  h->configure(
      asf::Params::fromSpecs("tigre", info()->descriptor->keys, info()->descriptor->num_keys, kv),
      ctx);
  return h;
}

/// A free, fully known W x H metre world whose regions are given by label(x, y) (0 = no
/// region, e.g. a wall cell, which is then also occupied in the grid), closed by a 0.3 m
/// outer wall (else its rim would border space never observed: frontier edges).
struct World {
  asf::GridMap map;
  asf::Segmentation seg;
  asf::mapping::TopoBuilder topo;
  double t = 0;

  World(double W, double H, const std::function<asf::RegionId(double, double)>& label,
        std::map<std::string, std::string> topo_keys = {}) {
    const double res = 0.1;
    const double rim = 0.3;
    auto grid =
        std::make_shared<mrpt::maps::COccupancyGridMap2D>(-rim, W + rim, -rim, H + rim, res);
    asf::LabelImage& L = seg.labels;
    L.width = static_cast<int>(grid->getSizeX());
    L.height = static_cast<int>(grid->getSizeY());
    L.resolution = res;
    L.origin_x = grid->getXMin();
    L.origin_y = grid->getYMin();
    L.labels.assign(static_cast<std::size_t>(L.width) * L.height, 0);
    std::map<asf::RegionId, std::pair<double, int>> sums_x, sums_y;
    for (int cy = 0; cy < L.height; ++cy)
      for (int cx = 0; cx < L.width; ++cx) {
        const double x = grid->idx2x(cx), y = grid->idx2y(cy);
        const bool inside = x > 0 && x < W && y > 0 && y < H;
        const asf::RegionId r = inside ? label(x, y) : 0;
        L.labels[static_cast<std::size_t>(cy) * L.width + cx] = r;
        grid->setCell(cx, cy, r > 0 ? 1.0f : 0.0f);
        if (r > 0) {
          sums_x[r].first += x;
          ++sums_x[r].second;
          sums_y[r].first += y;
        }
      }
    for (const auto& [r, sx] : sums_x) {
      asf::Region reg;
      reg.id = r;
      reg.area = sx.second * res * res;
      reg.centroid = {sx.first / sx.second, sums_y[r].first / sx.second};
      seg.regions.push_back(reg);
    }
    map.grid = grid;
    map.version = 1;
    topo.configure(asf::Params::fromSpecs("topology", keys(), nkeys(), topo_keys));
    topo.update(seg, map);
  }
  static const asf::KeySpec* keys() {
    std::size_t n;
    return asf::mapping::TopoBuilder::keys(n);
  }
  static std::size_t nkeys() {
    std::size_t n;
    asf::mapping::TopoBuilder::keys(n);
    return n;
  }
  void put(double x, double y) { topo.observeRobot(x, y, t += 1); }
};

struct Walked {
  std::vector<asf::Decision> decisions;
  std::vector<asf::RegionId> regions;  ///< region after each goal
  bool done = false;
};

/// Drives the policy until Done (or `max` decisions), teleporting the robot to each goal.
Walked drive(asf::Policy& p, World& w, double x, double y, int max = 200) {
  Walked run;
  w.put(x, y);
  asf::ExplorationState s;
  s.robot = mrpt::poses::CPose2D(x, y, 0);
  s.map = &w.map;
  s.segmentation = &w.seg;
  for (int i = 0; i < max; ++i) {
    s.topo = &w.topo.graph();
    const asf::Decision d = p.decide(s);
    run.decisions.push_back(d);
    if (d.type == asf::Decision::Type::Done) {
      run.done = true;
      break;
    }
    s.robot = mrpt::poses::CPose2D(d.goal.x, d.goal.y, 0);
    w.put(d.goal.x, d.goal.y);
    run.regions.push_back(w.topo.graph().current);
    s.last_status = asf::NavStatus::Reached;
    s.last_goal = d.goal;
  }
  return run;
}

/// The policy's view with the robot standing at (x, y) in `w`'s graph as it is now.
asf::ExplorationState standingAt(const World& w, double x, double y) {
  asf::ExplorationState s;
  s.topo = &w.topo.graph();
  s.robot = mrpt::poses::CPose2D(x, y, 0);
  s.map = &w.map;
  s.segmentation = &w.seg;
  return s;
}

// Rooms in a row, 3 m each, separated by 0.2 m walls with a 1 m door in the middle.
asf::RegionId rowOfRooms(double x, double y, int rooms) {
  const int i = static_cast<int>(x / 3.0);
  if (i >= rooms) return 0;
  const double in = x - 3.0 * i;
  if (in > 2.8 && i + 1 < rooms && !(y > 1.0 && y < 2.0)) return 0;  // wall, door at y in (1,2)
  return i + 1;
}

TEST(PolicyTigre, CorridorOfRoomsIsWalkedOutAndDoneWhenEveryEdgeIsTraversed) {
  World w(9.0, 3.0, [](double x, double y) { return rowOfRooms(x, y, 3); });
  ASSERT_EQ(w.topo.graph().edges.size(), 2u);  // 1-2, 2-3, no frontier (all known)
  auto p = make();
  const Walked r = drive(*p, w, 1.5, 1.5);
  ASSERT_TRUE(r.done);
  EXPECT_NE(r.decisions.back().reason.find("every edge traversed"), std::string::npos)
      << r.decisions.back().reason;
  EXPECT_EQ(r.decisions.back().reason.find("frontier"), std::string::npos)
      << r.decisions.back().reason;
  // Fraenkel-style stop: each edge once, no walk back.
  for (const auto& e : w.topo.graph().edges) EXPECT_EQ(e.traversals.size(), 1u);
  EXPECT_EQ(w.topo.graph().current, 3);
}

// A 2 x 2 block of rooms (1 bottom-left, 2 bottom-right, 3 top-right, 4 top-left) with doors
// between side neighbours only: a cycle of four edges.
asf::RegionId blockOfFour(double x, double y) {
  const bool right = x >= 3.0, top = y >= 3.0;
  const double ix = right ? x - 3.0 : x, iy = top ? y - 3.0 : y;
  // walls 0.2 m wide around the inner cross, doors 1 m wide in their middle
  const bool vwall = (x > 2.9 && x < 3.1) && !(iy > 1.0 && iy < 2.0);
  const bool hwall = (y > 2.9 && y < 3.1) && !(ix > 1.0 && ix < 2.0);
  if (vwall || hwall) return 0;
  if (x > 2.9 && x < 3.1 && y > 2.9 && y < 3.1) return 0;
  if (!right && !top) return 1;
  if (right && !top) return 2;
  if (right && top) return 3;
  return 4;
}

TEST(PolicyTigre, EveryEdgeOfACycleAtMostOnceEachWay) {
  World w(6.0, 6.0, blockOfFour);
  ASSERT_EQ(w.topo.graph().edges.size(), 4u);
  auto p = make();
  const Walked r = drive(*p, w, 1.5, 1.5);
  ASSERT_TRUE(r.done) << r.decisions.back().reason;
  for (const auto& e : w.topo.graph().edges) {
    EXPECT_GE(e.traversals.size(), 1u) << e.a << "-" << e.b;
    int fwd = 0, back = 0;
    for (const auto& t : e.traversals) (t.forward ? fwd : back)++;
    EXPECT_LE(fwd, 1) << e.a << "-" << e.b;
    EXPECT_LE(back, 1) << e.a << "-" << e.b;
  }
}

// next_goal = centre_new (the default): after the border, a region entered for the first
// time is walked into up to its centre (to see it), a region seen before only just inside.
TEST(PolicyTigre, CentreOnlyOfNewRegions) {
  World w(6.0, 6.0, blockOfFour);
  auto p = make();
  const Walked r = drive(*p, w, 1.5, 1.5);
  ASSERT_TRUE(r.done) << r.decisions.back().reason;
  std::set<asf::RegionId> visited{1};
  int centres = 0, entries = 0;
  for (std::size_t i = 0; i < r.regions.size(); ++i) {
    const std::string& why = r.decisions[i].reason;
    if (why.rfind("into region ", 0) == 0) {
      const asf::RegionId target = std::stoi(why.substr(12));
      const bool entry = why.find("(entry)") != std::string::npos;
      EXPECT_EQ(entry, visited.count(target) == 1) << why;
      (entry ? entries : centres)++;
    }
    visited.insert(r.regions[i]);
  }
  EXPECT_EQ(centres, 3) << "regions 2, 3, 4 entered for the first time";
  EXPECT_GE(entries, 1) << "closing the cycle re-enters region 1";
}

// Hand-made graph at one decision: region 2 entered from 1 (its entrance edge, the nearest),
// with an untraversed edge to unvisited region 3 farther away.
TEST(PolicyTigre, EntranceEdgeOnlyAsLastResort) {
  World w(9.0, 3.0, [](double x, double y) { return rowOfRooms(x, y, 3); });
  w.put(1.5, 1.5);
  w.put(3.3, 1.5);  // into region 2 through the door: entrance edge 1-2
  const asf::TopoGraph& g = w.topo.graph();
  ASSERT_EQ(g.current, 2);
  ASSERT_GE(g.node(2)->entrance_edge, 0);
  auto p = make();
  const asf::Decision d = p->decide(standingAt(w, 3.3, 1.5));
  ASSERT_EQ(d.type, asf::Decision::Type::GoTo) << d.reason;
  EXPECT_GT(d.goal.x, 5.0) << d.reason;  // the door 2-3 at x ~ 5.9, not 1-2 at x ~ 2.9
  EXPECT_NE(d.reason.find("edge 2-3"), std::string::npos) << d.reason;
}

// Back in region 1 after 1 -> 2 -> 1: Tarry's rule allows nothing here (1-2 was left by), while
// 2-3 is untraversed. asf relocates to it; relocate = false ends the exploration, as the
// thesis' Algorithm 4 does when the current region has no valid edge.
TEST(PolicyTigre, RelocatesToEdgesElsewhereUnlessSwitchedOff) {
  World w(9.0, 3.0, [](double x, double y) { return rowOfRooms(x, y, 3); });
  w.put(1.5, 1.5);
  w.put(3.3, 1.5);  // 1 -> 2
  w.put(1.5, 1.5);  // 2 -> 1
  const asf::TopoGraph& g = w.topo.graph();
  ASSERT_EQ(g.current, 1);
  const asf::ExplorationState s = standingAt(w, 1.5, 1.5);
  auto asf_rule = make();
  const asf::Decision moved = asf_rule->decide(s);
  ASSERT_EQ(moved.type, asf::Decision::Type::GoTo) << moved.reason;
  EXPECT_NE(moved.reason.find("relocating to edge 2-3"), std::string::npos) << moved.reason;
  auto thesis = make({{"relocate", "false"}});
  const asf::Decision ended = thesis->decide(s);
  ASSERT_EQ(ended.type, asf::Decision::Type::Done) << ended.reason;
  EXPECT_NE(ended.reason.find("1 untraversed elsewhere (relocate = false)"), std::string::npos)
      << ended.reason;
}

// Starting in the middle of three rooms, next to the door to room 1: both doors lead to
// unvisited rooms. ties = nearest takes the near door whatever the seed; ties = random (Tarry's
// own choice) takes each door for some seeds, and the same one for the same seed.
TEST(PolicyTigre, TiesGoToTheNearestOrAreDrawnFromTheSeed) {
  World w(9.0, 3.0, [](double x, double y) { return rowOfRooms(x, y, 3); });
  w.put(3.3, 1.5);
  const asf::TopoGraph& g = w.topo.graph();
  ASSERT_EQ(g.current, 2);
  const asf::ExplorationState s = standingAt(w, 3.3, 1.5);
  std::map<std::string, int> nearest, random;
  auto edgeOf = [](const asf::Decision& d) {
    const auto at = d.reason.find("edge ");
    return at == std::string::npos ? d.reason : d.reason.substr(at, 8);
  };
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    ++nearest[edgeOf(make({}, seed)->decide(s))];
    const std::string drawn = edgeOf(make({{"ties", "random"}}, seed)->decide(s));
    ++random[drawn];
    EXPECT_EQ(edgeOf(make({{"ties", "random"}}, seed)->decide(s)), drawn) << "seed " << seed;
  }
  EXPECT_EQ(nearest, (std::map<std::string, int>{{"edge 1-2", 24}}));
  ASSERT_EQ(random.size(), 2u);
  EXPECT_GT(random["edge 1-2"], 0);
  EXPECT_GT(random["edge 2-3"], 0);
}

// Region 5 (centre of a plus) after arriving from 1: edges to 2 (visited, far) and to 3
// (unvisited, near). TIGRE takes the loop-closing link; with loop_closing_first = false the
// nearest.
TEST(PolicyTigre, LoopClosingTieBreakPrefersVisitedRegions) {
  // Columns of 3 m: region 1 | region 5 | region 3 at the bottom row (y < 3) and region 2 on
  // top of all three (y >= 3.2), reached from 1 and 5 through doors.
  auto label = [](double x, double y) -> asf::RegionId {
    if (y >= 2.9 && y < 3.1) {  // horizontal wall with doors above 1 (x in 1..2) and 5 (x in 4..5)
      if ((x > 1.0 && x < 2.0) || (x > 4.0 && x < 5.0)) return y < 3.0 ? (x < 3 ? 1 : 5) : 2;
      return 0;
    }
    if (y >= 3.0) return 2;
    if (x > 2.9 && x < 3.1) return (y > 1.0 && y < 2.0) ? (x < 3.0 ? 1 : 5) : 0;
    if (x > 5.9 && x < 6.1) return (y > 1.0 && y < 2.0) ? (x < 6.0 ? 5 : 3) : 0;
    if (x < 3.0) return 1;
    if (x < 6.0) return 5;
    return 3;
  };
  auto run = [&](bool loop_first) {
    World w(7.0, 6.0, label);
    w.put(1.5, 1.5);
    w.put(1.5, 4.5);  // 1 -> 2
    w.put(1.5, 1.5);  // 2 -> 1
    w.put(3.3, 1.5);  // 1 -> 5, region 2 is visited
    const asf::TopoGraph& g = w.topo.graph();
    EXPECT_EQ(g.current, 5);
    auto p = make({{"loop_closing_first", loop_first ? "true" : "false"}});
    asf::ExplorationState s;
    s.topo = &g;
    s.robot = mrpt::poses::CPose2D(5.7, 1.5, 0);  // near the door to 3
    s.map = &w.map;
    s.segmentation = &w.seg;
    return p->decide(s);
  };
  const asf::Decision tigre = run(true);
  EXPECT_NE(tigre.reason.find("edge 2-5"), std::string::npos) << tigre.reason;
  EXPECT_NE(tigre.reason.find("link to visited region"), std::string::npos) << tigre.reason;
  const asf::Decision plain = run(false);
  EXPECT_NE(plain.reason.find("edge 3-5"), std::string::npos) << plain.reason;
}

TEST(PolicyTigre, FrontierEdgeGoalIsOnTheFrontierAndNotRetriedAfterReaching) {
  // One known room 3 x 3 whose right side opens onto unknown space (cells p = 0.5).
  World w(6.0, 3.0, [](double x, double) -> asf::RegionId { return x < 3.0 ? 1 : 0; });
  auto grid = std::const_pointer_cast<mrpt::maps::COccupancyGridMap2D>(w.map.grid);
  for (int cy = 0; cy < static_cast<int>(grid->getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(grid->getSizeX()); ++cx)
      if (grid->idx2x(cx) >= 3.0) grid->setCell(cx, cy, 0.5f);
  w.topo.update(w.seg, w.map);
  const asf::TopoGraph& g = w.topo.graph();
  ASSERT_EQ(g.edges.size(), 1u);
  ASSERT_TRUE(g.edges[0].frontier());
  w.put(1.0, 1.5);
  auto p = make();
  asf::ExplorationState s;
  s.topo = &g;
  s.robot = mrpt::poses::CPose2D(1.0, 1.5, 0);
  s.map = &w.map;
  s.segmentation = &w.seg;
  const asf::Decision d = p->decide(s);
  ASSERT_EQ(d.type, asf::Decision::Type::GoTo) << d.reason;
  EXPECT_GT(d.goal.x, 2.3);  // at the frontier (x ~ 2.95), kept off the walls
  EXPECT_NE(d.reason.find("frontier of region 1"), std::string::npos) << d.reason;
  // Reached, yet the frontier is still there (nothing more could be seen): the policy must
  // not send the robot to the same place forever.
  s.robot = mrpt::poses::CPose2D(d.goal.x, d.goal.y, 0);
  s.last_status = asf::NavStatus::Reached;
  s.last_goal = d.goal;
  std::set<std::pair<int, int>> goals;
  goals.insert({static_cast<int>(d.goal.x * 10), static_cast<int>(d.goal.y * 10)});
  int n = 0;
  for (; n < 50; ++n) {
    const asf::Decision e = p->decide(s);
    if (e.type == asf::Decision::Type::Done) {
      // The frontier is still in the map: the stop reason says so.
      EXPECT_NE(e.reason.find("; 1 frontier left, tried or out of reach"), std::string::npos)
          << e.reason;
      break;
    }
    EXPECT_TRUE(
        goals.insert({static_cast<int>(e.goal.x * 10), static_cast<int>(e.goal.y * 10)}).second)
        << "goal repeated: " << e.reason;
    s.robot = mrpt::poses::CPose2D(e.goal.x, e.goal.y, 0);
    s.last_goal = e.goal;
  }
  EXPECT_LT(n, 50);
}

TEST(PolicyTigre, WaitsForAMapThenGivesUp) {
  auto p = make({{"max_waits", "3"}});
  asf::TopoGraph empty;
  asf::ExplorationState s;
  s.topo = &empty;
  for (int i = 0; i < 3; ++i) {
    const asf::Decision d = p->decide(s);
    ASSERT_EQ(d.type, asf::Decision::Type::GoTo) << d.reason;
    EXPECT_NE(d.reason.find("waiting"), std::string::npos);
  }
  EXPECT_EQ(p->decide(s).type, asf::Decision::Type::Done);
}

/// A known room x < 3 m whose right side, H metres long, opens onto unknown space.
struct OpenRoom {
  World w;
  explicit OpenRoom(double H)
      : w(6.0, H, [](double x, double) -> asf::RegionId { return x < 3.0 ? 1 : 0; }),
        y0(std::min(1.0, H / 2)) {
    auto grid = std::const_pointer_cast<mrpt::maps::COccupancyGridMap2D>(w.map.grid);
    for (int cy = 0; cy < static_cast<int>(grid->getSizeY()); ++cy)
      for (int cx = 0; cx < static_cast<int>(grid->getSizeX()); ++cx)
        if (grid->idx2x(cx) >= 3.0) grid->setCell(cx, cy, 0.5f);
    w.topo.update(w.seg, w.map);
    w.put(1.0, y0);
  }
  const double y0;  ///< the robot's y: 1 m, or the middle of a narrower room
  /// Decisions while the navigation fails every goal, until Done or `max`.
  std::vector<asf::Decision> failEveryGoal(asf::Policy& p, int max) {
    asf::ExplorationState s;
    s.topo = &w.topo.graph();
    s.robot = mrpt::poses::CPose2D(1.0, y0, 0);
    s.map = &w.map;
    s.segmentation = &w.seg;
    std::vector<asf::Decision> out;
    for (int i = 0; i < max; ++i) {
      out.push_back(p.decide(s));
      if (out.back().type == asf::Decision::Type::Done) break;
      s.last_status = asf::NavStatus::Unreachable;
      s.last_goal = out.back().goal;
    }
    return out;
  }
};

// Two failed goals give up a narrow frontier but not a long one: each failure only rules out
// the frontier around its goal (blacklist_radius), so a 10 m frontier gets 2 failures per
// metre of it (max_edge_failures per 2 x 0.5 m), tried along its length, then given up.
TEST(PolicyTigre, ALongFrontierOutlastsTwoFailedGoals) {
  OpenRoom narrow(1.0);
  ASSERT_EQ(narrow.w.topo.graph().edges.size(), 1u);
  ASSERT_LT(narrow.w.topo.graph().edges[0].width, 2.0);
  auto p1 = make({{"max_edge_failures", "2"}});
  const auto n = narrow.failEveryGoal(*p1, 50);
  EXPECT_EQ(n.back().type, asf::Decision::Type::Done);
  EXPECT_LE(n.size(), 3u) << "a 1 m frontier: given up after two failures";

  OpenRoom wide(10.0);
  const asf::TopoGraph& g = wide.w.topo.graph();
  ASSERT_EQ(g.edges.size(), 1u);
  ASSERT_TRUE(g.edges[0].frontier());
  ASSERT_GT(g.edges[0].width, 9.0);
  auto p2 = make({{"max_edge_failures", "2"}});
  const auto d = wide.failEveryGoal(*p2, 100);
  ASSERT_GE(d.size(), 4u);
  for (std::size_t i = 0; i + 1 < d.size(); ++i) {
    ASSERT_EQ(d[i].type, asf::Decision::Type::GoTo) << i << ": " << d[i].reason;
    EXPECT_NE(d[i].reason.find("frontier of region 1"), std::string::npos) << d[i].reason;
  }
  // Along the frontier, up and away from the failures; done when it is used up.
  EXPECT_GT(d[2].goal.y, d[0].goal.y + 0.5);
  EXPECT_EQ(d.back().type, asf::Decision::Type::Done);
  EXPECT_LE(d.size(), 2 * 10 + 1u);
  EXPECT_GE(d.size(), 9u) << "goals along most of the 10 m";
}

TEST(PolicyTigre, UnreachableEdgeIsGivenUpAfterMaxFailures) {
  World w(9.0, 3.0, [](double x, double y) { return rowOfRooms(x, y, 3); });
  w.put(1.5, 1.5);
  auto p = make({{"max_edge_failures", "2"}, {"next_goal", "none"}});
  asf::ExplorationState s;
  s.topo = &w.topo.graph();
  s.robot = mrpt::poses::CPose2D(1.5, 1.5, 0);
  s.map = &w.map;
  s.segmentation = &w.seg;
  // The navigation fails for every goal: the policy must end, not loop.
  int n = 0;
  asf::Decision d;
  for (; n < 20; ++n) {
    d = p->decide(s);
    if (d.type == asf::Decision::Type::Done) break;
    s.last_status = asf::NavStatus::Unreachable;
    s.last_goal = d.goal;
  }
  EXPECT_LT(n, 20);
  EXPECT_EQ(d.type, asf::Decision::Type::Done);
}

}  // namespace

TEST(PolicyTigre, UnknownBandReachingTheObstacleThresholdIsAnError) {
  // Shared with the frontier policy (asf::mapping::reachabilityOptionsFrom): unknown cells must not
  // count as obstacles.
  try {
    make({{"occupied_threshold", "0.6"}, {"unknown_band", "0.1"}});
    FAIL() << "no error";
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown_band"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(make({{"occupied_threshold", "0.6"}, {"unknown_band", "0.05"}}));
}
