#include <asf/navigation/grid_path.h>

#include <asf/grid_map.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <queue>

namespace asf::navigation {

namespace {

constexpr std::uint8_t kFree = kCellFree, kUnknown = kCellUnknown, kOccupied = kCellOccupied;

struct Grid {
  double x0 = 0, y0 = 0, res = 0.05;
  int nx = 0, ny = 0;
  std::vector<std::uint8_t> state;
  std::vector<float> factor;  // step cost factor; +inf = lethal
  int idx(int i, int j) const { return j * nx + i; }
  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < nx && j < ny; }
  int col(double x) const { return static_cast<int>(std::floor((x - x0) / res)); }
  int row(double y) const { return static_cast<int>(std::floor((y - y0) / res)); }
  Point2 centre(int i, int j) const { return {x0 + (i + 0.5) * res, y0 + (j + 0.5) * res}; }
};

/// The step cost factor of every cell: lethal on obstacles and within the robot's radius of
/// them (except on the way out for a robot that is already that close), rising through the
/// inflation margin, times unknown_cost on unknown cells.
void setCostFactors(Grid& g, const Point2& start, const NavOptions& o) {
  // Clearance: distance to the nearest obstacle cell (occupied, and unknown if blocked).
  cv::Mat1b free_mask(g.ny, g.nx);
  int ox0 = g.nx, oy0 = g.ny, ox1 = -1, oy1 = -1;  // the obstacles' bounding box
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::uint8_t s = g.state[g.idx(i, j)];
      const bool obstacle = s == kOccupied || (o.unknown_blocked && s == kUnknown);
      free_mask(j, i) = obstacle ? 0 : 255;
      if (obstacle)
        ox0 = std::min(ox0, i), ox1 = std::max(ox1, i), oy0 = std::min(oy0, j),
        oy1 = std::max(oy1, j);
    }
  const bool any_obstacle = ox1 >= 0;
  // The distance transform only where a clearance can matter: around the obstacles, by
  // more than the inflation zone plus a robot radius (the escape test compares with the
  // start's clearance only for cells within a radius of the start and of an obstacle). Every
  // obstacle is inside, so the distances there are those of the whole grid; outside, every
  // cell is farther than the zone from any obstacle.
  const int grow =
      static_cast<int>(std::ceil((2 * o.robot_radius + o.inflation_margin) / g.res)) + 2;
  const cv::Rect near = any_obstacle ? cv::Rect(ox0 - grow, oy0 - grow, ox1 - ox0 + 1 + 2 * grow,
                                                oy1 - oy0 + 1 + 2 * grow) &
                                           cv::Rect(0, 0, g.nx, g.ny)
                                     : cv::Rect();
  cv::Mat1f dist;
  if (any_obstacle)
    cv::distanceTransform(free_mask(near), dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);

  // A robot that ended up closer than its radius to an obstacle may leave, but only through
  // cells no closer to obstacles than where it stands.
  const auto clearanceAt = [&](int i, int j) {
    if (!near.contains(cv::Point(i, j))) return 1e9;
    return std::max(0.0, dist(j - near.y, i - near.x) * g.res - 0.5 * g.res);
  };
  const int si = g.col(start.x), sj = g.row(start.y);
  const double start_clear = g.inside(si, sj) ? clearanceAt(si, sj) : 0.0;
  g.factor.assign(g.state.size(), 1.f);
  const double inf = std::numeric_limits<float>::infinity();
  const auto unknown_factor = static_cast<float>(1.0 * o.unknown_cost);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const int k = g.idx(i, j);
      if (!near.contains(cv::Point(i, j))) {  // no obstacle near: only unknown space costs
        if (g.state[k] == kUnknown) g.factor[k] = unknown_factor;
        continue;
      }
      const bool obstacle = free_mask(j, i) == 0;
      const double clear = clearanceAt(i, j);
      // Only cells within the radius of an obstacle need the escape test (and its hypot).
      const auto escape = [&] {
        const Point2 c = g.centre(i, j);
        return (i == si && j == sj) ||
               (std::hypot(c.x - start.x, c.y - start.y) <= o.robot_radius && clear >= start_clear);
      };
      double f = 1.0;
      if (obstacle || (clear < o.robot_radius && !escape())) {
        f = inf;
      } else {
        if (g.state[k] == kUnknown) f *= o.unknown_cost;
        const double zone = o.robot_radius + o.inflation_margin;
        if (o.inflation_margin > 0 && clear < zone)
          f *= 1.0 + 2.0 * (zone - std::max(clear, o.robot_radius)) / o.inflation_margin;
      }
      g.factor[k] = static_cast<float>(f);
    }
}

Grid buildGrid(const mrpt::maps::COccupancyGridMap2D* map, const Point2& start, const Point2& goal,
               double tolerance, const NavOptions& o, const std::vector<Point2>& obstacles) {
  Grid g;
  g.res = map ? map->getResolution() : o.default_resolution;
  Box2 box;
  if (map) {
    box.extend(map->getXMin(), map->getYMin());
    box.extend(map->getXMax(), map->getYMax());
  }
  box.extend(start.x - o.border, start.y - o.border);
  box.extend(start.x + o.border, start.y + o.border);
  const double gb = o.border + tolerance;
  box.extend(goal.x - gb, goal.y - gb);
  box.extend(goal.x + gb, goal.y + gb);
  g.x0 = box.min_x;
  g.y0 = box.min_y;
  g.nx = static_cast<int>(std::ceil((box.max_x - box.min_x) / g.res)) + 1;
  g.ny = static_cast<int>(std::ceil((box.max_y - box.min_y) / g.res)) + 1;
  g.state.assign(static_cast<std::size_t>(g.nx) * g.ny, kUnknown);
  if (map) {
    const int mx = static_cast<int>(map->getSizeX()), my = static_cast<int>(map->getSizeY());
    // The map cell under each column and row centre, computed once (a cell centre's map
    // index depends only on its column, resp. row).
    std::vector<int> map_col(g.nx), map_row(g.ny);
    for (int i = 0; i < g.nx; ++i) map_col[i] = map->x2idx(g.centre(i, 0).x);
    for (int j = 0; j < g.ny; ++j) map_row[j] = map->y2idx(g.centre(0, j).y);
    // A cell's state is a function of its stored log-odds: tabulated once per plan.
    using Raw = mrpt::maps::COccupancyGridMap2D::cellType;
    using RawBits = mrpt::maps::COccupancyGridMap2D::cellTypeUnsigned;
    std::vector<std::uint8_t> state_of(std::size_t{1} << (8 * sizeof(Raw)));
    for (std::size_t b = 0; b < state_of.size(); ++b) {
      const Raw raw = static_cast<Raw>(static_cast<RawBits>(b));
      const double p_free = mrpt::maps::COccupancyGridMap2D::l2p(raw);  // MRPT stores p(free)
      state_of[b] = cellStateOf(p_free, o.occupied_threshold, o.unknown_band);
    }
    const Raw* raw = map->getRawMap().data();
    for (int j = 0; j < g.ny; ++j) {
      const int cy = map_row[j];
      if (cy < 0 || cy >= my) continue;
      const Raw* row = raw + static_cast<std::size_t>(cy) * mx;
      for (int i = 0; i < g.nx; ++i) {
        const int cx = map_col[i];
        if (cx < 0 || cx >= mx) continue;
        g.state[g.idx(i, j)] = state_of[static_cast<RawBits>(row[cx])];
      }
    }
  }

  for (const Point2& q : obstacles) {
    const int i = g.col(q.x), j = g.row(q.y);
    if (g.inside(i, j)) g.state[g.idx(i, j)] = kOccupied;
  }

  setCostFactors(g, start, o);
  return g;
}

// Largest cost factor met on the straight segment a-b (sampled at half a cell), +inf if it
// touches a lethal cell.
float segmentMaxFactor(const Grid& g, const Point2& a, const Point2& b) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * g.res))));
  float worst = 0;
  for (int s = 0; s <= n; ++s) {
    const double t = static_cast<double>(s) / n;
    const int i = g.col(a.x + t * (b.x - a.x)), j = g.row(a.y + t * (b.y - a.y));
    if (!g.inside(i, j)) return std::numeric_limits<float>::infinity();
    worst = std::max(worst, g.factor[g.idx(i, j)]);
  }
  return worst;
}

/// Targets: non-lethal cells whose centre lies within the tolerance of the goal (and the
/// goal's own cell); empty when there is none.
std::vector<char> goalTargets(const Grid& g, const Point2& goal, double tolerance) {
  std::vector<char> target(g.state.size(), 0);
  bool any_target = false;
  const int span = static_cast<int>(std::ceil(tolerance / g.res)) + 1;
  const int gi = g.col(goal.x), gj = g.row(goal.y);
  for (int j = gj - span; j <= gj + span; ++j)
    for (int i = gi - span; i <= gi + span; ++i) {
      if (!g.inside(i, j) || !std::isfinite(g.factor[g.idx(i, j)])) continue;
      const Point2 c = g.centre(i, j);
      if (std::hypot(c.x - goal.x, c.y - goal.y) <= tolerance || (i == gi && j == gj)) {
        target[g.idx(i, j)] = 1;
        any_target = true;
      }
    }
  if (!any_target) target.clear();
  return target;
}

/// A* from cell (si, sj) to the first target cell; `parent` links the path. The target
/// reached, or -1.
int aStar(const Grid& g, int si, int sj, const std::vector<char>& target, const Point2& goal,
          double tolerance, std::vector<int>& parent, std::size_t& expanded) {
  const auto h = [&](int i, int j) {
    const Point2 c = g.centre(i, j);
    return std::max(0.0, std::hypot(c.x - goal.x, c.y - goal.y) - tolerance);
  };
  const int s = g.idx(si, sj);
  std::vector<double> cost(g.state.size(), std::numeric_limits<double>::infinity());
  parent.assign(g.state.size(), -1);
  std::vector<char> closed(g.state.size(), 0);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  cost[s] = 0;
  open.push({h(si, sj), s});
  static const int kDi[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int kDj[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const int k = open.top().second;
    open.pop();
    if (closed[k]) continue;
    closed[k] = 1;
    ++expanded;
    if (target[k]) return k;
    const int i = k % g.nx, j = k / g.nx;
    for (int d = 0; d < 8; ++d) {
      const int ni = i + kDi[d], nj = j + kDj[d];
      if (!g.inside(ni, nj)) continue;
      const int nk = g.idx(ni, nj);
      if (closed[nk] || !std::isfinite(g.factor[nk])) continue;
      // No corner cutting past lethal cells.
      if (d >= 4 &&
          (!std::isfinite(g.factor[g.idx(ni, j)]) || !std::isfinite(g.factor[g.idx(i, nj)])))
        continue;
      const double step = (d >= 4 ? M_SQRT2 : 1.0) * g.res;
      const double fk = std::isfinite(g.factor[k]) ? g.factor[k] : 1.0;  // start may be lethal
      const double c = cost[k] + step * 0.5 * (fk + g.factor[nk]);
      if (c < cost[nk]) {
        cost[nk] = c;
        parent[nk] = k;
        open.push({c + h(ni, nj), nk});
      }
    }
  }
  return -1;
}

/// String pulling: jump to the farthest cell reachable in a straight line without meeting
/// a costlier cell than the grid path itself does.
void pullString(const Grid& g, const std::vector<Point2>& cells, NavPlan& plan) {
  std::size_t a = 0;
  while (a + 1 < cells.size()) {
    float path_max = 0;
    std::size_t best = a + 1;
    // Stops at the first cell not reachable in a straight line: linear in the path length
    // (a full scan for the farthest visible cell would be quadratic).
    for (std::size_t b = a + 1; b < cells.size(); ++b) {
      path_max = std::max(path_max, segmentMaxFactor(g, cells[b - 1], cells[b]));
      if (segmentMaxFactor(g, cells[a], cells[b]) > path_max) break;
      best = b;
    }
    plan.waypoints.push_back(cells[best]);
    plan.length += std::hypot(cells[best].x - cells[a].x, cells[best].y - cells[a].y);
    a = best;
  }
}

}  // namespace

NavPlan planPath(const mrpt::maps::COccupancyGridMap2D* map, const Point2& start,
                 const Point2& goal, double tolerance, const NavOptions& o,
                 const std::vector<Point2>& obstacles) {
  NavPlan plan;
  const Grid g = buildGrid(map, start, goal, tolerance, o, obstacles);
  const std::vector<char> target = goalTargets(g, goal, tolerance);
  if (target.empty()) {
    plan.reason = "no free cell within " + std::to_string(tolerance) +
                  " m of the goal (obstacle, inflation or blocked unknown space)";
    return plan;
  }
  std::vector<int> parent;
  const int reached =
      aStar(g, g.col(start.x), g.row(start.y), target, goal, tolerance, parent, plan.expanded);
  if (reached < 0) {
    plan.reason = "no collision-free path on the navigation grid";
    return plan;
  }
  std::vector<Point2> cells;
  for (int k = reached; k != -1; k = parent[k]) cells.push_back(g.centre(k % g.nx, k / g.nx));
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  // End exactly at the goal when its own cell is free (A* stops at the first cell within
  // the tolerance, which may be a neighbour of it).
  const int gi = g.col(goal.x), gj = g.row(goal.y);
  if (g.inside(gi, gj) && std::isfinite(g.factor[g.idx(gi, gj)])) {
    if (cells.size() > 1 && std::isfinite(segmentMaxFactor(g, cells[cells.size() - 2], goal)))
      cells.back() = goal;
    else
      cells.push_back(goal);
  }
  pullString(g, cells, plan);
  plan.found = true;
  return plan;
}

std::vector<Point2> scanEndpoints(const mrpt::obs::CObservation2DRangeScan& scan,
                                  const mrpt::poses::CPose2D& robot) {
  std::vector<Point2> pts;
  const mrpt::poses::CPose2D laser = robot + mrpt::poses::CPose2D(scan.sensorPose);
  for (std::size_t i = 0; i < scan.getScanSize(); ++i) {
    if (!scan.getScanRangeValidity(i)) continue;
    const double r = scan.getScanRange(i), a = scan.getScanAngle(i);
    double gx = 0, gy = 0;
    laser.composePoint(r * std::cos(a), r * std::sin(a), gx, gy);
    pts.push_back({gx, gy});
  }
  return pts;
}

}  // namespace asf::navigation
