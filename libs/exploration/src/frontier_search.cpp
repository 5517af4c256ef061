// The frontier explorers' shared core (frontier_search.h): frontier cells are known-free cells
// next to unknown ones, clustered 8-connected; each frontier gets the goal of its cell nearest
// the robot along the free space it can drive (geodesic, robot radius kept); frontiers where
// navigation failed are blacklisted so the robot never loops on them.
#include <asf/exploration/frontier_search.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>

namespace asf::exploration {
namespace {

constexpr std::uint8_t kFree = kCellFree, kUnknown = kCellUnknown;

double dist2(const Point2& a, const Point2& b) {
  return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y);
}

Point2 cellCentre(const mapping::Reachability& reach, int cell) {
  return reach.cellCenter(cell % reach.width(), cell / reach.width());
}

}  // namespace

void FrontierSearch::configure(const Params& p, mrpt::system::COutputLogger& log) {
  log_ = &log;
  reach_ = mapping::reachabilityOptionsFrom(p);
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

Decision FrontierSearch::decide(const ExplorationState& s, const FrontierChooser& choose) {
  const Point2 robot{s.robot.x(), s.robot.y()};
  takeOutcome(s);

  const mrpt::maps::COccupancyGridMap2D* grid = s.map ? s.map->grid.get() : nullptr;
  if (!grid || grid->getSizeX() == 0 || grid->getSizeY() == 0) {
    reached_ = false;
    if (asked_without_map_) return Decision::done("no map after a first step ahead");
    // A short step gives the mapping stages their first scans to work with.
    asked_without_map_ = true;
    const double phi = s.robot.phi();
    return Decision::goTo(
        {robot.x + 0.5 * std::cos(phi), robot.y + 0.5 * std::sin(phi), goal_tolerance_},
        "no map yet: 0.5 m ahead");
  }

  const mapping::Reachability reach = mapping::Reachability::compute(*s.map, robot, reach_);
  const std::vector<std::uint8_t> cells = mapping::classifyCells(*grid, reach_);
  const std::vector<Frontier> frontiers =
      findFrontiers(cells, static_cast<int>(grid->getSizeX()), static_cast<int>(grid->getSizeY()));

  if (reached_) {
    // Reached, but the frontier is still there: the robot cannot see past it from there
    // (glass, out of range, a gap too small): a failure, or it would loop.
    reached_ = false;
    if (nearFrontierCell(frontiers, pending_target_, 1.5 * grid->getResolution(), reach))
      addFailure(pending_target_, "reached, still a frontier");
  }

  // A candidate within goal tolerance of the robot would be reached at once and change
  // nothing: it counts as a failure too, and the choice is made again.
  for (;;) {
    Rejected rejected;
    const std::vector<FrontierCandidate> found = candidates(frontiers, reach, robot, rejected);
    if (found.empty()) {
      std::ostringstream why;
      why << "no frontier left (" << rejected.blacklisted << " blacklisted, "
          << rejected.unreachable << " unreachable, " << rejected.too_small << " smaller than "
          << min_frontier_size_ << " m)";
      return Decision::done(why.str());
    }
    const FrontierChoice choice = choose(found, reach, cells);
    const FrontierCandidate& best = found.at(choice.index);
    if (dist2(best.goal, robot) <= goal_tolerance_ * goal_tolerance_) {
      addFailure(best.target, "frontier at the robot's position");
      continue;
    }
    pending_ = true;
    pending_target_ = best.target;
    pending_goal_ = best.goal;
    std::string why = choice.reason;
    if (rejected.blacklisted > 0)
      why += "; " + std::to_string(rejected.blacklisted) + " blacklisted";
    return Decision::goTo({best.goal.x, best.goal.y, goal_tolerance_}, why);
  }
}

void FrontierSearch::takeOutcome(const ExplorationState& s) {
  if (!pending_) return;
  pending_ = false;
  switch (s.last_status) {
    case NavStatus::Unreachable:
    case NavStatus::Blocked: {
      // The failure belongs to the frontier cell our goal served; if the host reports
      // another goal, blame that one.
      const Point2 reported{s.last_goal.x, s.last_goal.y};
      const bool ours = dist2(reported, pending_goal_) <= 1e-12;
      addFailure(ours ? pending_target_ : reported, navStatusName(s.last_status));
      break;
    }
    case NavStatus::Reached:
      reached_ = true;
      break;
    case NavStatus::Idle:
    case NavStatus::Moving:
      break;  // no outcome: nothing learnt
  }
}

void FrontierSearch::addFailure(const Point2& at, const std::string& why) {
  failures_.push_back(at);
  std::ostringstream msg;
  msg << "frontier goal failed (" << why << ") at (" << at.x << ", " << at.y << "): cells within "
      << blacklist_radius_ << " m are blacklisted";
  if (log_) log_->logStr(mrpt::system::LVL_WARN, msg.str());
}

std::vector<FrontierSearch::Frontier> FrontierSearch::findFrontiers(
    const std::vector<std::uint8_t>& state, int W, int H) const {
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

bool FrontierSearch::nearFrontierCell(const std::vector<Frontier>& frontiers, const Point2& p,
                                      double radius, const mapping::Reachability& reach) const {
  for (const Frontier& f : frontiers)
    for (const int c : f.cells)
      if (dist2(cellCentre(reach, c), p) <= radius * radius) return true;
  return false;
}

std::vector<FrontierCandidate> FrontierSearch::candidates(const std::vector<Frontier>& frontiers,
                                                          const mapping::Reachability& reach,
                                                          const Point2& robot,
                                                          Rejected& rejected) const {
  std::vector<FrontierCandidate> out;
  const double res = reach.resolution();
  const double bl2 = blacklist_radius_ * blacklist_radius_;
  std::vector<char> counted(failures_.size());
  for (const Frontier& f : frontiers) {
    const double length = f.cells.size() * res;
    if (length < min_frontier_size_) {
      ++rejected.too_small;
      continue;
    }
    // Failures near any of its cells count against this frontier.
    std::fill(counted.begin(), counted.end(), 0);
    int failures = 0;
    FrontierCandidate best;
    best.distance = mapping::Reachability::kUnreachable;
    bool any_allowed = false;
    for (const int c : f.cells) {
      const Point2 p = cellCentre(reach, c);
      bool blacklisted = false;
      for (std::size_t k = 0; k < failures_.size(); ++k)
        if (dist2(failures_[k], p) <= bl2) {
          blacklisted = true;
          if (!counted[k]) counted[k] = 1, ++failures;
        }
      if (blacklisted) continue;
      any_allowed = true;
      // The robot cannot stand on a frontier cell next to a wall: use the nearest cell it
      // can reach instead. A snapped goal is no nearer than the straight line allows (less a
      // cell for where the robot stands in its cell): skip the search when that cannot beat
      // the best cell so far.
      std::optional<Point2> goal;
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
    best.length = length;
    out.push_back(best);
  }
  std::sort(out.begin(), out.end(), [](const FrontierCandidate& a, const FrontierCandidate& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.cell < b.cell;
  });
  return out;
}

}  // namespace asf::exploration
