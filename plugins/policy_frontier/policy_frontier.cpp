// policy_frontier: greedy nearest-frontier exploration (Yamauchi 1997) over the shared
// frontier core (policy_frontier_core): the robot goes to the frontier that is nearest along
// the free space it can drive.
#include <asf/frontier_search.h>

#include <cstdint>
#include <iomanip>
#include <sstream>

namespace {

class FrontierPolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    search_.configure(p, *this);
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    return search_.decide(s, [](const std::vector<asf::FrontierCandidate>& candidates,
                                const asf::mapping::Reachability&, const std::vector<std::uint8_t>&) {
      const asf::FrontierCandidate& best = candidates.front();  // nearest first
      std::ostringstream why;
      why << std::fixed << std::setprecision(2) << "nearest of " << candidates.size()
          << " frontiers: " << best.length << " m long, " << best.distance
          << " m away (frontier cell " << best.target.x << ", " << best.target.y << ")";
      return asf::FrontierChoice{0, why.str()};
    });
  }

 private:
  asf::FrontierSearch search_;
};

const asf::KeySpec kKeys[] = {
    asf::mapping::keyRobotRadius("0.2"), asf::mapping::keyOccupiedThreshold(),      asf::mapping::keyUnknownBand(),
    asf::keyMinFrontierSize(),  asf::keyFrontierGoalTolerance(),  asf::keySnapRadius(),
    asf::keyBlacklistRadius(),  asf::keyMaxFailuresPerFrontier(),
};

}  // namespace

ASF_PLUGIN(FrontierPolicy, asf::PluginKind::Policy, "frontier", "1.0.0",
           "Greedy nearest-frontier exploration (Yamauchi 1997): geodesic distances, "
           "blacklisting of failed frontiers",
           asf::ThreadSafety::ThreadCompatible, kKeys)
