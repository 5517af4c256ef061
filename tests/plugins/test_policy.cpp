// Test plugins built by the test suite, one source compiled into several .so files with
// different macros: a good policy, and each way a plugin file can be broken.
#include <asf/errors.h>
#include <asf/policy.h>

#include <stdexcept>

namespace {

class TestPolicy : public asf::Policy {
 public:
  TestPolicy() {
#ifdef TEST_FACTORY_THROWS
    throw std::runtime_error("cannot open the device /dev/nowhere");
#endif
  }
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    fail_after_ = static_cast<int>(p.getInt("fail_after"));
    plan_home_ = p.getBool("plan_home");
  }
  asf::Decision decide(const asf::ExplorationState& s) override {
    if (fail_after_ < 0) return asf::Decision::done("nothing to explore in a test");
    if (calls_ >= fail_after_)
      throw asf::Error("test policy fails on purpose after " + std::to_string(fail_after_) +
                       " decisions");
    asf::Goal g;
    g.x = (calls_++ % 2 == 0) ? 1.0 : 0.0;  // back and forth, 1 m
    return asf::Decision::goTo(g, plan_home_ ? "test shuttle; " + askPlanner(s) : "test shuttle");
  }

 private:
  // The pipeline's planner as a policy sees it: the path from the newest node to node 0.
  static std::string askPlanner(const asf::ExplorationState& s) {
    if (!s.planner) return "planner: none";
    if (!s.graph || s.graph->size() < 2) return "planner: no graph yet";
    asf::PlanRequest req;
    req.graph = s.graph;
    req.marginals = s.marginals;
    req.map = s.map;
    req.start = static_cast<asf::NodeId>(s.graph->size() - 1);
    req.goal = 0;
    const asf::PlanResult r = s.planner->plan(req);
    if (!r.found) return "planner: no path: " + r.reason;
    return "planner: path of " + std::to_string(r.nodes.size()) + " nodes from node " +
           std::to_string(r.nodes.front()) + " to node " + std::to_string(r.nodes.back());
  }

  int fail_after_ = -1, calls_ = 0;
  bool plan_home_ = false;
};

const asf::KeySpec kKeys[] = {
    asf::keyInt("fail_after", "-1", "Shuttle for this many decisions, then throw (-1: say done at once)", -1,
                1000000),
    asf::keyBool("plan_home", "false",
                 "Ask the pipeline's planner for the path home at each decision (in the reason)"),
};

}  // namespace

#ifndef TEST_PLUGIN_NAME
#define TEST_PLUGIN_NAME "test_policy"
#endif

#if defined(TEST_NO_ENTRY_POINT)
// A shared library that is not a plugin: no asf_plugin_descriptor.
extern "C" int some_other_symbol() { return 42; }
#elif defined(TEST_WRONG_ABI)
extern "C" ASF_EXPORT const asf::PluginDescriptor* asf_plugin_descriptor() {
  static const asf::PluginDescriptor d{
      ASF_ABI_VERSION + 41, sizeof(asf::PluginDescriptor), TEST_PLUGIN_NAME,
      asf::PluginKind::Policy, "1.0.0", "built against another ABI",
      asf::ThreadSafety::ThreadCompatible, kKeys, std::size(kKeys),
      []() -> std::unique_ptr<asf::Plugin> { return std::make_unique<TestPolicy>(); }};
  return &d;
}
#else
ASF_PLUGIN(TestPolicy, asf::PluginKind::Policy, TEST_PLUGIN_NAME, "1.0.0",
           "Test policy: done at once, or shuttles 1 m and throws after fail_after decisions",
           asf::ThreadSafety::ThreadCompatible, kKeys)
#endif
