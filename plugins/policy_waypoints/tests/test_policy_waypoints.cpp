// Tests of the waypoints policy: order, skipping, looping, errors.
#include <asf/errors.h>
#include <asf/policy.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include <map>

namespace {

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/policy_waypoints.so");
  return i;
}

asf::framework::PluginHandle<asf::Policy> make(const std::map<std::string, std::string>& kv) {
  auto h = asf::framework::Registry::create<asf::Policy>(info());
  h->configure(asf::Params::fromSpecs("waypoints", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

struct Driver {
  asf::Policy& p;
  asf::TopoGraph topo;
  asf::ExplorationState s;
  explicit Driver(asf::Policy& policy) : p(policy) { s.topo = &topo; }
  asf::Decision decide(asf::NavStatus last) {
    s.last_status = last;
    const asf::Decision d = p.decide(s);
    if (d.type == asf::Decision::Type::GoTo) s.last_goal = d.goal;
    return d;
  }
};

void expectGoTo(const asf::Decision& d, double x, double y) {
  ASSERT_EQ(d.type, asf::Decision::Type::GoTo) << d.reason;
  EXPECT_DOUBLE_EQ(d.goal.x, x);
  EXPECT_DOUBLE_EQ(d.goal.y, y);
}

TEST(PolicyWaypoints, NoWaypointsIsDone) {
  auto p = make({});
  Driver d(*p);
  const auto r = d.decide(asf::NavStatus::Idle);
  EXPECT_EQ(r.type, asf::Decision::Type::Done);
  EXPECT_EQ(r.reason, "no waypoints");
}

TEST(PolicyWaypoints, VisitsInOrderAndSkipsFailures) {
  auto p = make({{"waypoints", "1 2; 3.5, -4 ;5 6;"}, {"tolerance", "0.25"}});
  Driver d(*p);
  auto r = d.decide(asf::NavStatus::Idle);
  expectGoTo(r, 1, 2);
  EXPECT_DOUBLE_EQ(r.goal.tolerance, 0.25);
  EXPECT_NE(r.reason.find("1 of 3"), std::string::npos) << r.reason;
  expectGoTo(d.decide(asf::NavStatus::Moving), 1, 2);  // no outcome yet: same goal
  expectGoTo(d.decide(asf::NavStatus::Reached), 3.5, -4);
  expectGoTo(d.decide(asf::NavStatus::Blocked), 5, 6);  // skipped 2nd
  r = d.decide(asf::NavStatus::Reached);
  EXPECT_EQ(r.type, asf::Decision::Type::Done);
  EXPECT_EQ(r.reason, "visited 2 of 3 waypoints (1 skipped)");
  EXPECT_EQ(d.decide(asf::NavStatus::Idle).type, asf::Decision::Type::Done);
}

TEST(PolicyWaypoints, UnreachableGoalsAreNeverRepeatedForever) {
  auto p = make({{"waypoints", "1 1; 2 2"}});
  Driver d(*p);
  expectGoTo(d.decide(asf::NavStatus::Idle), 1, 1);
  expectGoTo(d.decide(asf::NavStatus::Unreachable), 2, 2);
  const auto r = d.decide(asf::NavStatus::Unreachable);
  EXPECT_EQ(r.type, asf::Decision::Type::Done);
  EXPECT_EQ(r.reason, "visited 0 of 2 waypoints (2 skipped)");
}

TEST(PolicyWaypoints, LoopStartsOverAndStopsWhenNothingIsReachable) {
  auto p = make({{"waypoints", "1 1; 2 2"}, {"loop", "true"}});
  Driver d(*p);
  expectGoTo(d.decide(asf::NavStatus::Idle), 1, 1);
  expectGoTo(d.decide(asf::NavStatus::Reached), 2, 2);
  expectGoTo(d.decide(asf::NavStatus::Reached), 1, 1);
  expectGoTo(d.decide(asf::NavStatus::Blocked), 2, 2);
  expectGoTo(d.decide(asf::NavStatus::Reached), 1, 1);  // one reached in that round
  expectGoTo(d.decide(asf::NavStatus::Blocked), 2, 2);
  const auto r = d.decide(asf::NavStatus::Unreachable);
  EXPECT_EQ(r.type, asf::Decision::Type::Done);
  EXPECT_NE(r.reason.find("no waypoint reached in a full round"), std::string::npos)
      << r.reason;
}

TEST(PolicyWaypoints, BadWaypointTextIsAConfigError) {
  for (const char* text : {"1 2; 3", "1 2; 3 x", "1 2 3", "nan 1"}) {
    try {
      make({{"waypoints", text}});
      FAIL() << "accepted '" << text << "'";
    } catch (const asf::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("waypoint"), std::string::npos) << e.what();
    }
  }
  try {
    make({{"waypoints", "1 2; 3 x"}});
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("waypoint 2"), std::string::npos) << e.what();
  }
}

}  // namespace
