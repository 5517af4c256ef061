// nearest_region: an example exploration policy built outside the asf source tree.
//
// Goes to the centroid of the nearest unvisited region of the topological graph; when every
// region has been visited, to the midpoint of the nearest frontier edge (a border with
// unexplored space); Done when neither is left. Goals that came back Unreachable or Blocked
// are blacklisted, so the robot moves on instead of trying them forever.
#include <asf/policy.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

class NearestRegionPolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    tolerance_ = p.getDouble("tolerance");
    blacklist_radius_ = p.getDouble("blacklist_radius");
    frontiers_ = p.getBool("frontiers");
    // Types and ranges were checked against kKeys already; checks across keys would go here,
    // reported with p.fail("key", "why") (an asf::ConfigError naming the INI line).
    blacklist_.clear();
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    // Remember what failed last time.
    if (s.last_status == asf::NavStatus::Unreachable || s.last_status == asf::NavStatus::Blocked) {
      blacklist_.push_back(s.last_goal);
      MRPT_LOG_INFO_STREAM("blacklisted (" << s.last_goal.x << ", " << s.last_goal.y
                                           << "): " << asf::navStatusName(s.last_status));
    }
    const double rx = s.robot.x(), ry = s.robot.y();

    // 1. The nearest unvisited region.
    Candidate best;
    if (s.topo) {
      for (const asf::TopoNode& n : s.topo->nodes) {
        if (n.region <= 0 || n.visited) continue;  // kUnexplored, or already seen
        consider(best, n.centroid, rx, ry, "centroid of unvisited region " +
                                               std::to_string(n.region));
      }
    }
    // 2. Else the nearest frontier.
    if (!best.found && frontiers_ && s.topo) {
      for (const asf::TopoEdge& e : s.topo->edges) {
        if (!e.frontier()) continue;
        consider(best, e.midpoint, rx, ry,
                 "frontier of region " + std::to_string(e.a) + " to unexplored space");
      }
    }
    if (!best.found) {
      std::ostringstream why;
      why << "no unvisited region or frontier left";
      if (!blacklist_.empty()) why << " (" << blacklist_.size() << " goals failed)";
      return asf::Decision::done(why.str());
    }
    asf::Goal g;
    g.x = best.x;
    g.y = best.y;
    g.tolerance = tolerance_;
    std::ostringstream why;
    why << best.what << " at " << best.distance << " m";
    return asf::Decision::goTo(g, why.str());
  }

 private:
  struct Candidate {
    bool found = false;
    double x = 0, y = 0, distance = std::numeric_limits<double>::infinity();
    std::string what;
  };

  bool blacklisted(double x, double y) const {
    for (const asf::Goal& b : blacklist_)
      if (std::hypot(b.x - x, b.y - y) <= std::max(blacklist_radius_, 1e-9)) return true;
    return false;
  }

  void consider(Candidate& best, const asf::Point2& p, double rx, double ry,
                const std::string& what) const {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || blacklisted(p.x, p.y)) return;
    const double d = std::hypot(p.x - rx, p.y - ry);
    if (d < best.distance) best = {true, p.x, p.y, d, what};  // ties: the first one wins
  }

  double tolerance_ = 0.3;
  double blacklist_radius_ = 0.2;
  bool frontiers_ = true;
  std::vector<asf::Goal> blacklist_;
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("tolerance", "0.3", "Distance at which a goal counts as reached [m]", 0.01,
                   10.0),
    asf::keyDouble("blacklist_radius", "0.2",
                   "Candidates this close to a goal that failed are skipped [m]", 0.0, 100.0),
    asf::keyBool("frontiers", "true",
                 "Go to frontier edges once every region has been visited"),
};

}  // namespace

ASF_PLUGIN(NearestRegionPolicy, asf::PluginKind::Policy, "nearest_region", "1.0.0",
           "Nearest unvisited region, then nearest frontier; skips goals that failed",
           asf::ThreadSafety::ThreadCompatible, kKeys)
