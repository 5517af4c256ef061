/// \file policy_tests.cpp
/// Conformance tests of `policy` plugins (see policy.h), on small topological graphs.
#include <cmath>

#include "kit.h"
#include "synthetic.h"

namespace asf::conformance::detail {

using mrpt::poses::CPose2D;

namespace {

constexpr int kRetries = 50;

/// A topological graph with the map and robot pose that go with it.
struct World {
  TopoGraph topo;
  GridMap map;  ///< grid null: no map yet
  CPose2D robot;
  ExplorationState state() const {
    ExplorationState s;
    s.topo = &topo;
    s.robot = robot;
    s.map = map.grid ? &map : nullptr;
    s.graph = nullptr;
    s.time = 0;
    s.last_status = NavStatus::Idle;
    return s;
  }
};

World unexploredOnly() {
  World w;
  w.topo = makeTopoUnexploredOnly();
  return w;
}
World finished() {
  World w;
  w.topo = makeTopoFinished();
  w.map = makeTwoRoomsMap(true);
  w.robot = CPose2D(7, 2, 0);
  return w;
}
World withFrontiers() {
  World w;
  w.topo = makeTopoWithFrontiers();
  w.map = makeTwoRoomsMap(true);
  w.robot = CPose2D(2, 2, 0);
  return w;
}

testing::AssertionResult validDecision(const Decision& d) {
  if (d.type == Decision::Type::Done) {
    if (d.reason.empty()) return testing::AssertionFailure() << "Done without a reason";
    return testing::AssertionSuccess();
  }
  if (d.type != Decision::Type::GoTo)
    return testing::AssertionFailure() << "unknown decision type " << static_cast<int>(d.type);
  if (!(std::isfinite(d.goal.x) && std::isfinite(d.goal.y)))
    return testing::AssertionFailure() << "GoTo with a non-finite goal (" << d.goal.x << ", "
                                       << d.goal.y << ")";
  if (!(std::isfinite(d.goal.tolerance) && d.goal.tolerance >= 0))
    return testing::AssertionFailure() << "GoTo with tolerance " << d.goal.tolerance;
  return testing::AssertionSuccess();
}

bool sameGoal(const Goal& a, const Goal& b) {
  return std::hypot(a.x - b.x, a.y - b.y) <= 1e-6;
}

void record(Trace& tr, const std::string& l, const Decision& d) {
  tr.num(l + ".type", static_cast<int>(d.type));
  if (d.type != Decision::Type::GoTo) return;
  tr.num(l + ".x", d.goal.x);
  tr.num(l + ".y", d.goal.y);
  tr.num(l + ".tolerance", d.goal.tolerance);
}

}  // namespace

Trace standardRun(Policy& p) {
  Trace tr;
  const World a = unexploredOnly(), b = finished(), c = withFrontiers();
  record(tr, "unexplored_only", p.decide(a.state()));
  record(tr, "finished", p.decide(b.state()));
  ExplorationState s = c.state();
  Decision d = p.decide(s);
  record(tr, "frontiers", d);
  for (int k = 0; k < 10 && d.type == Decision::Type::GoTo; ++k) {
    s.last_status = NavStatus::Unreachable;
    s.last_goal = d.goal;
    s.time += 1;
    d = p.decide(s);
    record(tr, "after_unreachable[" + std::to_string(k) + "]", d);
  }
  return tr;
}

void registerPolicyTests(const InfoPtr& info) {
  using T = Policy;

  addTest<T>(info, "only_unexplored_node_gives_done_or_finite_goal", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const World w = unexploredOnly();
               EXPECT_TRUE(validDecision(h->decide(w.state())))
                   << "TopoGraph with only the kUnexplored node, no edges, no map";
             });

  addTest<T>(info, "finished_graph_gives_done_or_finite_goal", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const World w = finished();
               EXPECT_TRUE(validDecision(h->decide(w.state())))
                   << "every region visited, no frontier edge";
             });

  addTest<T>(info, "graph_with_frontiers_gives_done_or_finite_goal", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const World w = withFrontiers();
               EXPECT_TRUE(validDecision(h->decide(w.state())));
             });

  addTest<T>(info, "unreachable_goal_is_not_returned_forever", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const World w = withFrontiers();
               ExplorationState s = w.state();
               const Decision first = h->decide(s);
               ASSERT_TRUE(validDecision(first));
               if (first.type == Decision::Type::Done) return;  // nothing to retry
               for (int k = 0; k < kRetries; ++k) {
                 s.last_status = NavStatus::Unreachable;
                 s.last_goal = first.goal;
                 s.time += 1;
                 const Decision d = h->decide(s);
                 ASSERT_TRUE(validDecision(d)) << "after " << k + 1 << " Unreachable answers";
                 if (d.type == Decision::Type::Done || !sameGoal(d.goal, first.goal)) return;
               }
               ADD_FAILURE() << "decide() returned the goal (" << first.goal.x << ", "
                             << first.goal.y << ") " << kRetries + 1
                             << " times although it was reported Unreachable each time";
             });

  addTest<T>(info, "every_goal_reported_unreachable_eventually_done_or_new", Needs::Instance,
             [](KindTest<T>& t) {
               // Each new goal is reported Unreachable in turn: the policy must keep moving
               // on (a new goal or Done), never looping on one goal.
               auto h = t.make();
               const World w = withFrontiers();
               ExplorationState s = w.state();
               Decision d = h->decide(s);
               ASSERT_TRUE(validDecision(d));
               int same = 0;
               for (int k = 0; k < kRetries && d.type == Decision::Type::GoTo; ++k) {
                 s.last_status = NavStatus::Unreachable;
                 s.last_goal = d.goal;
                 s.time += 1;
                 const Decision next = h->decide(s);
                 ASSERT_TRUE(validDecision(next));
                 same = next.type == Decision::Type::GoTo && sameGoal(next.goal, d.goal)
                            ? same + 1
                            : 0;
                 ASSERT_LT(same, kRetries / 2)
                     << "decide() keeps returning (" << d.goal.x << ", " << d.goal.y
                     << ") although it was reported Unreachable";
                 d = next;
               }
             });
}

}  // namespace asf::conformance::detail
