/// \file planner_tests.cpp
/// Conformance tests of `planner` plugins (see planner.h), on a small generated graph.
#include <cmath>
#include <set>
#include <sstream>

#include "kit.h"
#include "synthetic.h"

namespace asf::conformance::detail {

namespace {

struct Fixture {
  PoseGraph graph = makePlannerGraph();
  Marginals marginals = makePlannerMarginals(graph);
  std::set<std::pair<NodeId, NodeId>> adjacent;
  Fixture() {
    for (const auto& e : graph.edges) {
      adjacent.insert({e.from, e.to});
      adjacent.insert({e.to, e.from});
    }
  }
  PlanRequest request(NodeId s, NodeId g, bool with_marginals = true) const {
    PlanRequest r;
    r.graph = &graph;
    r.marginals = with_marginals ? &marginals : nullptr;
    r.start = s;
    r.goal = g;
    return r;
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

/// Pairs in one component (0..19 or 20..21): a path must exist.
const std::vector<std::pair<NodeId, NodeId>> kConnected = {
    {0, 19}, {19, 0}, {5, 12}, {3, 16}, {20, 21}, {0, 1}};

std::string showPath(const std::vector<NodeId>& p) {
  std::ostringstream os;
  for (std::size_t i = 0; i < p.size(); ++i) os << (i ? " " : "") << p[i];
  return "[" + os.str() + "]";
}

void checkPath(const Fixture& f, const PlanResult& r, NodeId s, NodeId g) {
  ASSERT_TRUE(r.found) << "no path found from " << s << " to " << g << " (reason: '" << r.reason
                       << "') although both are in one component";
  ASSERT_FALSE(r.nodes.empty()) << "found = true with an empty path";
  EXPECT_EQ(r.nodes.front(), s) << "path " << showPath(r.nodes) << " does not start at " << s;
  EXPECT_EQ(r.nodes.back(), g) << "path " << showPath(r.nodes) << " does not end at " << g;
  for (std::size_t i = 0; i + 1 < r.nodes.size(); ++i)
    EXPECT_EQ(f.adjacent.count({r.nodes[i], r.nodes[i + 1]}), 1u)
        << "path " << showPath(r.nodes) << ": no edge joins " << r.nodes[i] << " and "
        << r.nodes[i + 1];
  EXPECT_TRUE(std::isfinite(r.cost)) << "cost " << r.cost << " is not finite";
}

}  // namespace

Trace standardRun(Planner& p) {
  Trace tr;
  const Fixture& f = fixture();
  auto record = [&](const std::string& l, const PlanResult& r) {
    tr.num(l + ".found", r.found);
    tr.num(l + ".cost", r.cost);
    tr.text(l + ".criterion", r.criterion);
    tr.num(l + ".length", static_cast<double>(r.nodes.size()));
    for (NodeId n : r.nodes) tr.num(l + ".node", n);
  };
  for (const auto& [s, g] : kConnected)
    record("plan(" + std::to_string(s) + "," + std::to_string(g) + ")", p.plan(f.request(s, g)));
  record("plan(0,20)", p.plan(f.request(0, 20)));
  record("plan(7,7)", p.plan(f.request(7, 7)));
  return tr;
}

void registerPlannerTests(const InfoPtr& info) {
  using T = Planner;

  addTest<T>(info, "start_equal_goal_gives_one_node_path", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    const Fixture& f = fixture();
    for (NodeId n : {NodeId{0}, NodeId{7}, NodeId{21}}) {
      const PlanResult r = h->plan(f.request(n, n));
      EXPECT_TRUE(r.found) << "start == goal == " << n << " not found: " << r.reason;
      EXPECT_EQ(r.nodes, std::vector<NodeId>{n}) << "start == goal must give the one-node path";
    }
  });

  addTest<T>(info, "found_paths_join_start_to_goal_along_edges", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const Fixture& f = fixture();
               for (const auto& [s, g] : kConnected) {
                 SCOPED_TRACE("plan " + std::to_string(s) + " -> " + std::to_string(g));
                 checkPath(f, h->plan(f.request(s, g)), s, g);
               }
             });

  addTest<T>(info, "null_marginals_raise_no_exception", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    const Fixture& f = fixture();
    const PlanResult r = h->plan(f.request(0, 19, false));
    if (r.found) {
      checkPath(f, r, 0, 19);
    } else {
      EXPECT_FALSE(r.reason.empty()) << "found = false needs a reason";
    }
  });

  addTest<T>(info, "disconnected_goal_gives_not_found_with_reason", Needs::Instance,
             [](KindTest<T>& t) {
               auto h = t.make();
               const Fixture& f = fixture();
               for (auto [s, g] : {std::pair<NodeId, NodeId>{0, 20}, {21, 5}}) {
                 const PlanResult r = h->plan(f.request(s, g));
                 EXPECT_FALSE(r.found) << s << " -> " << g << " lie in different components, "
                                       << "yet a path was found: " << showPath(r.nodes);
                 EXPECT_FALSE(r.reason.empty()) << "found = false needs a reason";
               }
             });

  addTest<T>(info, "out_of_range_ids_give_not_found", Needs::Instance, [](KindTest<T>& t) {
    auto h = t.make();
    const Fixture& f = fixture();
    const NodeId n = static_cast<NodeId>(f.graph.size());
    for (auto [s, g] : {std::pair<NodeId, NodeId>{0, n}, {n + 5, 0}, {n, n}, {0, 4000000000u}}) {
      const PlanResult r = h->plan(f.request(s, g));
      EXPECT_FALSE(r.found) << "plan " << s << " -> " << g << " on a graph of " << n
                            << " nodes was found";
      EXPECT_FALSE(r.reason.empty()) << "found = false needs a reason";
    }
  });
}

}  // namespace asf::conformance::detail
