// policy_cpp_offline: the offline Chinese postman baseline of thesis ch. 6. It is given the
// whole map (the true world segmented once) and walks every edge of its topological graph
// by the shortest closed walk (route inspection).
#include <asf/exploration/route_policy.h>

namespace {

class CppOfflinePolicy final : public asf::exploration::RoutePolicy {
 public:
  CppOfflinePolicy() : RoutePolicy(Route::ChinesePostman) {}
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("goal_tolerance", "0.4", "A goal is reached within this distance [m]", 0.01,
                   5.0),
};

}  // namespace

ASF_PLUGIN(CppOfflinePolicy, asf::PluginKind::Policy, "cpp_offline", "1.0.0",
           "Offline baseline: the Chinese postman walk over the true world's topological graph",
           asf::ThreadSafety::ThreadCompatible, kKeys)
