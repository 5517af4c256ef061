// policy_tsp_offline: the offline TSP baseline of thesis ch. 6. It is given the
// whole map (the true world segmented once) and visits every region of its topological graph
// by the shortest closed walk that visits them all (TSP on the graph).
#include <asf/exploration/route_policy.h>

namespace {

class TspOfflinePolicy final : public asf::exploration::RoutePolicy {
 public:
  TspOfflinePolicy() : RoutePolicy(Route::Tsp) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("goal_tolerance", "0.4", "A goal is reached within this distance [m]", 0.01,
                   5.0),
};

}  // namespace

ASF_PLUGIN(TspOfflinePolicy, asf::PluginKind::Policy, "tsp_offline", "1.0.0",
           "Offline baseline: the TSP walk (every region) over the true world's topological graph",
           asf::ThreadSafety::ThreadCompatible, kKeys)
