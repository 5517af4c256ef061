// policy_frontier: greedy nearest-frontier exploration (Yamauchi 1997). Frontier cells are
// known-free cells next to unknown ones; the robot goes to the frontier that is nearest
// along the free space it can drive (geodesic, robot radius kept), and frontiers where
// navigation failed are blacklisted so the robot never loops on them.
#include <asf/policy.h>
#include <asf/reachability.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr std::uint8_t kFree = asf::kCellFree, kUnknown = asf::kCellUnknown;

/// A frontier: 8-connected frontier cells (row-major indices, ascending).
struct Frontier {
  std::vector<int> cells;
};

/// The best goal found for one frontier.
struct Candidate {
  int frontier = -1;
  int cell = -1;           ///< frontier cell the goal serves (row-major index)
  asf::Point2 target;      ///< that cell's centre
  asf::Point2 goal;        ///< reachable cell centre the robot is sent to
  double distance = 0;     ///< geodesic distance of the goal [m]
};

/// Counts of frontiers that were not candidates, for Done's reason.
struct Rejected {
  int too_small = 0, blacklisted = 0, unreachable = 0;
};

double dist2(const asf::Point2& a, const asf::Point2& b) {
  return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y);
}

class FrontierPolicy final : public asf::Policy {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    reach_ = asf::reachabilityOptionsFrom(p);
    min_frontier_size_ = p.getDouble("min_frontier_size");
    goal_tolerance_ = p.getDouble("goal_tolerance");
    snap_radius_ = p.getDouble("snap_radius");
    blacklist_radius_ = p.getDouble("blacklist_radius");
    max_failures_ = static_cast<int>(p.getInt("max_failures_per_frontier"));
    if (snap_radius_ < reach_.robot_radius)
      p.fail("snap_radius", "must be >= robot_radius (" + std::to_string(reach_.robot_radius) +
                                "): a frontier along a wall lies within the robot's radius "
                                "of it and could never get a goal");
    failures_.clear();
    pending_ = reached_ = asked_without_map_ = false;
  }

  asf::Decision decide(const asf::ExplorationState& s) override {
    const asf::Point2 robot{s.robot.x(), s.robot.y()};
    takeOutcome(s);

    const mrpt::maps::COccupancyGridMap2D* grid = s.map ? s.map->grid.get() : nullptr;
    if (!grid || grid->getSizeX() == 0 || grid->getSizeY() == 0) {
      reached_ = false;
      if (asked_without_map_) return asf::Decision::done("no map after a first step ahead");
      // A short step gives the mapping stages their first scans to work with.
      asked_without_map_ = true;
      const double phi = s.robot.phi();
      return asf::Decision::goTo({robot.x + 0.5 * std::cos(phi), robot.y + 0.5 * std::sin(phi),
                                  goal_tolerance_},
                                 "no map yet: 0.5 m ahead");
    }

    const asf::Reachability reach = asf::Reachability::compute(*s.map, robot, reach_);
    const std::vector<Frontier> frontiers = findFrontiers(*grid);
    const int W = static_cast<int>(grid->getSizeX());
    const auto centre = [&](int cell) { return reach.cellCenter(cell % W, cell / W); };

    if (reached_) {
      // Reached, but the frontier is still there: the robot cannot see past it from
      // there (glass, out of range, a gap too small): a failure, or it would loop.
      reached_ = false;
      if (nearFrontierCell(frontiers, pending_target_, 1.5 * grid->getResolution(), centre))
        addFailure(pending_target_, "reached, still a frontier");
    }

    // A candidate within goal tolerance of the robot would be reached at once and change
    // nothing: it counts as a failure too, and the choice is made again.
    for (;;) {
      Rejected rejected;
      std::vector<Candidate> candidates =
          bestPerFrontier(frontiers, reach, robot, centre, rejected);
      if (candidates.empty()) {
        std::ostringstream why;
        why << "no frontier left (" << rejected.blacklisted << " blacklisted, "
            << rejected.unreachable << " unreachable, " << rejected.too_small
            << " smaller than " << min_frontier_size_ << " m)";
        return asf::Decision::done(why.str());
      }
      std::sort(candidates.begin(), candidates.end(),
                [](const Candidate& a, const Candidate& b) {
                  return a.distance != b.distance ? a.distance < b.distance : a.cell < b.cell;
                });
      const Candidate& best = candidates.front();
      if (dist2(best.goal, robot) <= goal_tolerance_ * goal_tolerance_) {
        addFailure(best.target, "frontier at the robot's position");
        continue;
      }
      pending_ = true;
      pending_target_ = best.target;
      pending_goal_ = best.goal;
      const double length = frontiers[best.frontier].cells.size() * grid->getResolution();
      std::ostringstream why;
      why << std::fixed << std::setprecision(2) << "nearest of " << candidates.size()
          << " frontiers: " << length << " m long, " << best.distance
          << " m away (frontier cell " << best.target.x << ", " << best.target.y << ")";
      if (rejected.blacklisted > 0) why << "; " << rejected.blacklisted << " blacklisted";
      return asf::Decision::goTo({best.goal.x, best.goal.y, goal_tolerance_}, why.str());
    }
  }

 private:
  /// Reads the outcome of the goal this policy sent last.
  void takeOutcome(const asf::ExplorationState& s) {
    if (!pending_) return;
    pending_ = false;
    switch (s.last_status) {
      case asf::NavStatus::Unreachable:
      case asf::NavStatus::Blocked: {
        // The failure belongs to the frontier cell our goal served; if the host reports
        // another goal, blame that one.
        const asf::Point2 reported{s.last_goal.x, s.last_goal.y};
        const bool ours = dist2(reported, pending_goal_) <= 1e-12;
        addFailure(ours ? pending_target_ : reported, asf::navStatusName(s.last_status));
        break;
      }
      case asf::NavStatus::Reached: reached_ = true; break;
      case asf::NavStatus::Idle:
      case asf::NavStatus::Moving: break;  // no outcome: nothing learnt
    }
  }

  void addFailure(const asf::Point2& at, const std::string& why) {
    failures_.push_back(at);
    MRPT_LOG_WARN_STREAM("frontier goal failed (" << why << ") at (" << at.x << ", " << at.y
                                                  << "): cells within " << blacklist_radius_
                                                  << " m are blacklisted");
  }

  /// Frontier cells (known free, 4-adjacent to unknown or to the grid's edge, beyond which
  /// nothing is known) clustered 8-connected, in row-major order of their first cell.
  std::vector<Frontier> findFrontiers(const mrpt::maps::COccupancyGridMap2D& grid) const {
    const int W = static_cast<int>(grid.getSizeX()), H = static_cast<int>(grid.getSizeY());
    const std::vector<std::uint8_t> state = asf::classifyCells(grid, reach_);
    const auto unknownAt = [&](int x, int y) {
      return x < 0 || y < 0 || x >= W || y >= H ||
             state[static_cast<std::size_t>(y) * W + x] == kUnknown;
    };
    std::vector<std::uint8_t> frontier(state.size(), 0);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (state[static_cast<std::size_t>(y) * W + x] == kFree &&
            (unknownAt(x - 1, y) || unknownAt(x + 1, y) || unknownAt(x, y - 1) ||
             unknownAt(x, y + 1)))
          frontier[static_cast<std::size_t>(y) * W + x] = 1;

    std::vector<Frontier> out;
    std::vector<int> stack;
    for (int start = 0; start < W * H; ++start) {
      if (frontier[start] != 1) continue;
      Frontier f;
      frontier[start] = 2;
      stack.assign(1, start);
      while (!stack.empty()) {
        const int c = stack.back();
        stack.pop_back();
        f.cells.push_back(c);
        const int cx = c % W, cy = c / W;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = cx + dx, ny = cy + dy;
            if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
            const int n = ny * W + nx;
            if (frontier[n] != 1) continue;
            frontier[n] = 2;
            stack.push_back(n);
          }
      }
      std::sort(f.cells.begin(), f.cells.end());
      out.push_back(std::move(f));
    }
    return out;
  }

  template <class CentreFn>
  bool nearFrontierCell(const std::vector<Frontier>& frontiers, const asf::Point2& p,
                        double radius, const CentreFn& centre) const {
    for (const Frontier& f : frontiers)
      for (const int c : f.cells)
        if (dist2(centre(c), p) <= radius * radius) return true;
    return false;
  }

  /// For each frontier that is long enough and not given up on, its cell with the nearest
  /// reachable goal (cells in a blacklisted disk are skipped).
  template <class CentreFn>
  std::vector<Candidate> bestPerFrontier(const std::vector<Frontier>& frontiers,
                                         const asf::Reachability& reach,
                                         const asf::Point2& robot, const CentreFn& centre,
                                         Rejected& rejected) const {
    std::vector<Candidate> out;
    const double res = reach.resolution();
    const double bl2 = blacklist_radius_ * blacklist_radius_;
    std::vector<char> counted(failures_.size());
    for (std::size_t fi = 0; fi < frontiers.size(); ++fi) {
      const Frontier& f = frontiers[fi];
      if (f.cells.size() * res < min_frontier_size_) {
        ++rejected.too_small;
        continue;
      }
      // Failures near any of its cells count against this frontier.
      std::fill(counted.begin(), counted.end(), 0);
      int failures = 0;
      Candidate best;
      best.distance = asf::Reachability::kUnreachable;
      bool any_allowed = false;
      for (const int c : f.cells) {
        const asf::Point2 p = centre(c);
        bool blacklisted = false;
        for (std::size_t k = 0; k < failures_.size(); ++k)
          if (dist2(failures_[k], p) <= bl2) {
            blacklisted = true;
            if (!counted[k]) counted[k] = 1, ++failures;
          }
        if (blacklisted) continue;
        any_allowed = true;
        // The robot cannot stand on a frontier cell next to a wall: use the nearest cell
        // it can reach instead. A snapped goal is no nearer than the straight line allows
        // (less a cell for where the robot stands in its cell): skip the search when that
        // cannot beat the best cell so far.
        std::optional<asf::Point2> goal;
        if (reach.reachable(p))
          goal = p;
        else if (std::sqrt(dist2(p, robot)) - snap_radius_ - res < best.distance)
          goal = reach.nearestReachable(p, snap_radius_);
        if (!goal) continue;
        const double d = reach.distanceTo(*goal);
        if (d < best.distance) {  // cells ascend: ties keep the smaller index
          best.distance = d;
          best.cell = c;
          best.target = p;
          best.goal = *goal;
        }
      }
      if (failures >= max_failures_ || !any_allowed) {
        ++rejected.blacklisted;
        continue;
      }
      if (best.cell < 0) {
        ++rejected.unreachable;
        continue;
      }
      best.frontier = static_cast<int>(fi);
      out.push_back(best);
    }
    return out;
  }

  asf::ReachabilityOptions reach_;
  double min_frontier_size_ = 0.5, goal_tolerance_ = 0.3, snap_radius_ = 0.5;
  double blacklist_radius_ = 0.5;
  int max_failures_ = 3;

  std::vector<asf::Point2> failures_;  ///< frontier cells whose goal failed, map frame
  bool pending_ = false;               ///< a frontier goal was sent, outcome not read yet
  bool reached_ = false;               ///< ... and it was reached (checked on the new map)
  asf::Point2 pending_target_, pending_goal_;
  bool asked_without_map_ = false;
};

const asf::KeySpec kKeys[] = {
    asf::keyRobotRadius("0.2"),
    asf::keyOccupiedThreshold(),
    asf::keyUnknownBand(),
    asf::keyDouble("min_frontier_size", "0.5",
                   "Frontiers shorter than this are ignored (length = cells x resolution) [m]",
                   0, 1000),
    asf::keyDouble("goal_tolerance", "0.3", "Goal tolerance sent with every goal [m]", 0.01,
                   10),
    asf::keyDouble("snap_radius", "0.5",
                   "A frontier cell the robot cannot stand on gets the nearest reachable cell "
                   "within this distance as its goal (>= robot_radius) [m]",
                   0, 10),
    asf::keyDouble("blacklist_radius", "0.5",
                   "Frontier cells within this distance of a failed goal's frontier cell are "
                   "not chosen again [m]",
                   0.01, 100),
    asf::keyInt("max_failures_per_frontier", "3",
                "A frontier with this many failures near it is given up as a whole", 1, 1000),
};

}  // namespace

ASF_PLUGIN(FrontierPolicy, asf::PluginKind::Policy, "frontier", "1.0.0",
           "Greedy nearest-frontier exploration (Yamauchi 1997): geodesic distances, "
           "blacklisting of failed frontiers",
           asf::ThreadSafety::ThreadCompatible, kKeys)
