#pragma once
/// \file frontier_search.h
/// The frontier explorers' shared core: frontiers on the estimated occupancy grid, a goal per
/// frontier on a cell the robot can reach, and the failures that blacklist frontiers. How a
/// candidate is chosen is the policy's: `frontier` takes the nearest, `dopt_frontier` the
/// one whose expected pose graph is D-optimal. Behaviour and keys: policy_frontier/README.md.
#include <asf/key_spec.h>
#include <asf/policy.h>
#include <asf/mapping/reachability.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace asf::exploration {

/// The keys every frontier policy reads (besides keyRobotRadius, keyOccupiedThreshold and
/// keyUnknownBand of reachability.h), each defined once here.
constexpr KeySpec keyMinFrontierSize() {
  return keyDouble("min_frontier_size", "0.5",
                   "Frontiers shorter than this are ignored (length = cells x resolution) [m]", 0,
                   1000);
}
constexpr KeySpec keyFrontierGoalTolerance() {
  return keyDouble("goal_tolerance", "0.3", "Goal tolerance sent with every goal [m]", 0.01, 10);
}
constexpr KeySpec keySnapRadius() {
  return keyDouble("snap_radius", "0.5",
                   "A frontier cell the robot cannot stand on gets the nearest reachable cell "
                   "within this distance as its goal (>= robot_radius) [m]",
                   0, 10);
}
constexpr KeySpec keyBlacklistRadius() {
  return keyDouble("blacklist_radius", "0.5",
                   "Frontier cells within this distance of a failed goal's frontier cell are "
                   "not chosen again [m]",
                   0.01, 100);
}
constexpr KeySpec keyMaxFailuresPerFrontier() {
  return keyInt("max_failures_per_frontier", "3",
                "A frontier with this many failures near it is given up as a whole", 1, 1000);
}

/// The best goal of one frontier.
struct FrontierCandidate {
  int cell = -1;        ///< frontier cell the goal serves (row-major index)
  Point2 target;        ///< that cell's centre
  Point2 goal;          ///< reachable cell centre the robot is sent to
  double distance = 0;  ///< geodesic distance of the goal [m]
  double length = 0;    ///< the frontier's length (cells x resolution) [m]
};

/// What a policy's choice returns: the index of the chosen candidate and the reason's text.
struct FrontierChoice {
  std::size_t index = 0;
  std::string reason;
};
/// Chooses among candidates sorted nearest first (ties: smaller cell index), never empty,
/// given the decision's reachability field and its cells classified (classifyCells: the
/// grid's cells row-major, free / unknown / occupied), which the search made anyway.
using FrontierChooser = std::function<FrontierChoice(
    const std::vector<FrontierCandidate>&, const mapping::Reachability&, const std::vector<std::uint8_t>&)>;

class FrontierSearch {
 public:
  /// Reads the keys above and the reachability keys; ConfigError naming snap_radius when it
  /// is below robot_radius. Forgets every failure. Failures are logged as warnings to `log`
  /// (the policy plugin), which must outlive this object.
  void configure(const Params& p, mrpt::system::COutputLogger& log);

  /// One decision: the first step before any map, failures learnt from the last goal, the
  /// candidates, `choose`, and the goal sent (a chosen goal within goal_tolerance of the robot
  /// is a failure: the choice is made again). Done with the counts of the frontiers not
  /// taken when no candidate is left.
  Decision decide(const ExplorationState& s, const FrontierChooser& choose);

  double goalTolerance() const { return goal_tolerance_; }

 private:
  struct Frontier {
    std::vector<int> cells;  ///< row-major indices, ascending
  };
  struct Rejected {
    int too_small = 0, blacklisted = 0, unreachable = 0;
  };

  void takeOutcome(const ExplorationState& s);
  void addFailure(const Point2& at, const std::string& why);
  /// `state`: the grid's cells classified, W x H row-major.
  std::vector<Frontier> findFrontiers(const std::vector<std::uint8_t>& state, int W, int H) const;
  bool nearFrontierCell(const std::vector<Frontier>& frontiers, const Point2& p, double radius,
                        const mapping::Reachability& reach) const;
  std::vector<FrontierCandidate> candidates(const std::vector<Frontier>& frontiers,
                                            const mapping::Reachability& reach, const Point2& robot,
                                            Rejected& rejected) const;

  mrpt::system::COutputLogger* log_ = nullptr;
  mapping::ReachabilityOptions reach_;
  double min_frontier_size_ = 0.5, goal_tolerance_ = 0.3, snap_radius_ = 0.5;
  double blacklist_radius_ = 0.5;
  int max_failures_ = 3;

  std::vector<Point2> failures_;  ///< frontier cells whose goal failed, map frame
  bool pending_ = false;          ///< a frontier goal was sent, outcome not read yet
  bool reached_ = false;          ///< ... and it was reached (checked on the new map)
  Point2 pending_target_, pending_goal_;
  bool asked_without_map_ = false;
};

}  // namespace asf::exploration
