// policy_frontier: greedy nearest-frontier exploration (Yamauchi 1997) over the shared
// frontier core (libs/exploration): the robot goes to the frontier that is nearest along
// the free space it can drive.
#include <asf/exploration/frontier_search.h>

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
    return search_.decide(s, [](const std::vector<asf::exploration::FrontierCandidate>& candidates,
                                const asf::mapping::Reachability&, const std::vector<std::uint8_t>&) {
      const asf::exploration::FrontierCandidate& best = candidates.front();  // nearest first
      std::ostringstream why;
      why << std::fixed << std::setprecision(2) << "nearest of " << candidates.size()
          << " frontiers: " << best.length << " m long, " << best.distance
          << " m away (frontier cell " << best.target.x << ", " << best.target.y << ")";
      return asf::exploration::FrontierChoice{0, why.str()};
    });
  }

 private:
  asf::exploration::FrontierSearch search_;
};

const asf::KeySpec kKeys[] = {
    asf::mapping::keyRobotRadius("0.2"), asf::mapping::keyOccupiedThreshold(),      asf::mapping::keyUnknownBand(),
    asf::exploration::keyMinFrontierSize(),  asf::exploration::keyFrontierGoalTolerance(),  asf::exploration::keySnapRadius(),
    asf::exploration::keyBlacklistRadius(),  asf::exploration::keyMaxFailuresPerFrontier(),
};

}  // namespace

ASF_PLUGIN(FrontierPolicy, asf::PluginKind::Policy, "frontier", "1.0.0",
           "Greedy nearest-frontier exploration (Yamauchi 1997): geodesic distances, "
           "blacklisting of failed frontiers",
           asf::ThreadSafety::ThreadCompatible, kKeys)
