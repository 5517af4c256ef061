#include <asf/params.h>
#include <asf/mapping/reachability.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>

namespace asf::mapping {

ReachabilityOptions reachabilityOptionsFrom(const Params& p) {
  ReachabilityOptions o;
  o.robot_radius = p.getDouble("robot_radius");
  o.occupied_threshold = p.getDouble("occupied_threshold");
  o.unknown_band = p.getDouble("unknown_band");
  if (0.5 + o.unknown_band >= o.occupied_threshold)
    p.fail("unknown_band", "0.5 + unknown_band must stay below occupied_threshold (" +
                               p.getString("occupied_threshold") +
                               "), else unknown cells would count as obstacles");
  return o;
}

namespace {
constexpr std::uint8_t kFree = kCellFree, kUnknown = kCellUnknown, kOccupied = kCellOccupied;
}  // namespace

std::vector<std::uint8_t> classifyCells(const mrpt::maps::COccupancyGridMap2D& grid,
                                        const ReachabilityOptions& o) {
  using CellT = mrpt::maps::COccupancyGridMap2D::cellType;
  using CellU = mrpt::maps::COccupancyGridMap2D::cellTypeUnsigned;
  constexpr std::size_t kValues = std::size_t{1} << (8 * sizeof(CellT));
  std::vector<std::uint8_t> class_of(kValues);
  for (std::size_t u = 0; u < kValues; ++u) {
    const double p_free = mrpt::maps::COccupancyGridMap2D::l2p(
        static_cast<CellT>(static_cast<CellU>(u)));  // MRPT stores p(free)
    class_of[u] = cellStateOf(p_free, o.occupied_threshold, o.unknown_band);
  }
  const int W = static_cast<int>(grid.getSizeX()), H = static_cast<int>(grid.getSizeY());
  std::vector<std::uint8_t> state(static_cast<std::size_t>(W) * H);
  for (int y = 0; y < H; ++y) {
    const CellT* cells = grid.getRow(y);
    std::uint8_t* row = &state[static_cast<std::size_t>(y) * W];
    for (int x = 0; x < W; ++x) row[x] = class_of[static_cast<CellU>(cells[x])];
  }
  return state;
}

namespace {

/// A box of grid cells, inclusive.
struct CellBox {
  int x0, y0, x1, y1;
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
};

/// Only the box of known cells (plus the robot's footprint around the start cell) can hold
/// passable cells: the rest of the grid, often most of it (MapBuilder grows it with
/// margins), is unknown.
CellBox knownBox(const std::vector<std::uint8_t>& all, int W, int H, int sx, int sy, int foot) {
  int bx0 = W, by0 = H, bx1 = -1, by1 = -1;
  for (int y = 0; y < H; ++y) {
    const std::uint8_t* row = &all[static_cast<std::size_t>(y) * W];
    int first = -1, last = -1;
    for (int x = 0; x < W; ++x)
      if (row[x] != kUnknown) {
        if (first < 0) first = x;
        last = x;
      }
    if (first < 0) continue;
    bx0 = std::min(bx0, first);
    bx1 = std::max(bx1, last);
    by0 = std::min(by0, y);
    by1 = std::max(by1, y);
  }
  return {std::max(0, std::min(bx0, sx - foot)), std::max(0, std::min(by0, sy - foot)),
          std::min(W - 1, std::max(bx1, sx + foot)), std::min(H - 1, std::max(by1, sy + foot))};
}

/// The passable cells of box `b`, padded by one non-passable cell (so neighbour steps need no
/// bounds checks): free cells whose clearance keeps the robot's radius, and the cells under
/// the robot at `from`.
std::vector<std::uint8_t> passableCells(const std::vector<std::uint8_t>& all, int W,
                                        const CellBox& b, double origin_x, double origin_y,
                                        double res, const Point2& from,
                                        const ReachabilityOptions& o) {
  const int BW = b.width(), BH = b.height();
  cv::Mat1b not_obstacle(BH, BW);
  bool any_obstacle = false;
  for (int y = 0; y < BH; ++y) {
    const std::uint8_t* cells = &all[static_cast<std::size_t>(y + b.y0) * W + b.x0];
    std::uint8_t* mask_row = not_obstacle[y];
    for (int x = 0; x < BW; ++x) {
      mask_row[x] = cells[x] == kOccupied ? 0 : 255;
      any_obstacle |= cells[x] == kOccupied;
    }
  }
  // Clearance of a cell = distance from its centre to the nearest obstacle cell's edge
  // (centre distance minus half a cell), as the sim2d navigator measures it, so a cell
  // passable here is not lethal there. Outside the box there are no obstacles, so the
  // transform of the box is exact.
  cv::Mat1f centre_dist;
  if (any_obstacle)
    cv::distanceTransform(not_obstacle, centre_dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const float min_centre_dist = static_cast<float>(o.robot_radius / res + 0.5);
  const int PW = BW + 2, PH = BH + 2;
  std::vector<std::uint8_t> passable(static_cast<std::size_t>(PW) * PH, 0);
  const double r2 = o.robot_radius * o.robot_radius;
  for (int y = 0; y < BH; ++y) {
    const float* dist_row = any_obstacle ? centre_dist[y] : nullptr;
    const std::uint8_t* cells = &all[static_cast<std::size_t>(y + b.y0) * W + b.x0];
    for (int x = 0; x < BW; ++x) {
      const double sdx = origin_x + (x + b.x0 + 0.5) * res - from.x;
      const double sdy = origin_y + (y + b.y0 + 0.5) * res - from.y;
      const bool under_robot = sdx * sdx + sdy * sdy <= r2;
      const std::uint8_t st = cells[x];
      // The robot's own footprint is free even where the sensor has not seen it (behind a
      // 270-degree laser at the start): unknown cells under it are passable.
      if (st == kOccupied || (st == kUnknown && !under_robot)) continue;
      // Escape rule: cells under the robot stay passable even within the radius of an
      // obstacle, so a robot that drifted close to a wall can leave.
      const bool ok = !dist_row || dist_row[x] >= min_centre_dist || under_robot;
      passable[static_cast<std::size_t>(y + 1) * PW + (x + 1)] = ok;
    }
  }
  return passable;
}

/// Dijkstra in cell units over a padded passable raster `PW` wide, with buckets one cell
/// wide: every step costs >= 1, so no cell in the current bucket can improve another one
/// there and the result is exact, in linear time (three buckets in a ring cover steps of 1
/// and sqrt(2)).
std::vector<float> bucketDijkstra(const std::vector<std::uint8_t>& passable, int PW, int start) {
  std::vector<float> d(passable.size(), std::numeric_limits<float>::infinity());
  std::vector<std::uint8_t> settled(passable.size(), 0);
  std::vector<int> bucket[3];
  for (auto& b : bucket) b.reserve(1024);
  d[start] = 0;
  bucket[0].push_back(start);
  const int kOrtho[4] = {1, -1, PW, -PW};
  const int kDiag[4][3] = {{PW + 1, 1, PW},
                           {PW - 1, -1, PW},
                           {-PW + 1, 1, -PW},
                           {-PW - 1, -1, -PW}};  // step, and the two cells it passes
  const float kSqrt2 = static_cast<float>(M_SQRT2);
  int empty_in_a_row = 0;
  for (int k = 0; empty_in_a_row < 3; ++k) {
    std::vector<int>& cur = bucket[k % 3];
    if (cur.empty()) {
      ++empty_in_a_row;
      continue;
    }
    empty_in_a_row = 0;
    for (std::size_t i = 0; i < cur.size(); ++i) {
      const int c = cur[i];
      if (settled[c] || static_cast<int>(d[c]) != k) continue;  // stale entry
      settled[c] = 1;
      const float dc = d[c];
      for (const int step : kOrtho) {
        const int nb = c + step;
        if (!passable[nb] || dc + 1.f >= d[nb]) continue;
        d[nb] = dc + 1.f;
        bucket[static_cast<int>(d[nb]) % 3].push_back(nb);
      }
      for (const auto& diag : kDiag) {
        const int nb = c + diag[0];
        // No corner cutting past cells the robot may not occupy.
        if (!passable[nb] || !passable[c + diag[1]] || !passable[c + diag[2]] ||
            dc + kSqrt2 >= d[nb])
          continue;
        d[nb] = dc + kSqrt2;
        bucket[static_cast<int>(d[nb]) % 3].push_back(nb);
      }
    }
    cur.clear();
  }
  return d;
}

}  // namespace

Reachability Reachability::compute(const GridMap& map, const Point2& from,
                                   const ReachabilityOptions& o) {
  Reachability r;
  const mrpt::maps::COccupancyGridMap2D* grid = map.grid.get();
  if (!grid || grid->getSizeX() == 0 || grid->getSizeY() == 0) return r;
  r.resolution_ = grid->getResolution();
  r.origin_x_ = grid->getXMin();
  r.origin_y_ = grid->getYMin();
  r.width_ = static_cast<int>(grid->getSizeX());
  r.height_ = static_cast<int>(grid->getSizeY());
  const int W = r.width_, H = r.height_;
  const double res = r.resolution_;
  r.dist_.assign(static_cast<std::size_t>(W) * H, std::numeric_limits<float>::infinity());

  const int sx = static_cast<int>(std::floor((from.x - r.origin_x_) / res));
  const int sy = static_cast<int>(std::floor((from.y - r.origin_y_) / res));
  if (sx < 0 || sy < 0 || sx >= W || sy >= H) return r;  // start off the map: nothing known

  const std::vector<std::uint8_t> all = classifyCells(*grid, o);
  const int foot = static_cast<int>(std::ceil(o.robot_radius / res)) + 1;
  const CellBox b = knownBox(all, W, H, sx, sy, foot);
  const int PW = b.width() + 2;
  const std::vector<float> d =
      bucketDijkstra(passableCells(all, W, b, r.origin_x_, r.origin_y_, res, from, o), PW,
                     (sy - b.y0 + 1) * PW + (sx - b.x0 + 1));
  const float to_metres = static_cast<float>(res);
  for (int y = 0; y < b.height(); ++y)
    for (int x = 0; x < b.width(); ++x) {
      const float v = d[static_cast<std::size_t>(y + 1) * PW + (x + 1)];
      if (v < std::numeric_limits<float>::infinity())
        r.dist_[static_cast<std::size_t>(y + b.y0) * W + (x + b.x0)] = v * to_metres;
    }
  return r;
}

double Reachability::cellDistance(int cx, int cy) const {
  if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) return kUnreachable;
  return dist_[static_cast<std::size_t>(cy) * width_ + cx];
}

double Reachability::distanceTo(const Point2& p) const {
  if (width_ == 0) return kUnreachable;
  return cellDistance(static_cast<int>(std::floor((p.x - origin_x_) / resolution_)),
                      static_cast<int>(std::floor((p.y - origin_y_) / resolution_)));
}

std::optional<Point2> Reachability::nearestReachable(const Point2& p, double radius) const {
  if (width_ == 0) return std::nullopt;
  const int px = static_cast<int>(std::floor((p.x - origin_x_) / resolution_));
  const int py = static_cast<int>(std::floor((p.y - origin_y_) / resolution_));
  // p's own cell counts even when its centre is farther than a tiny radius; when p is that
  // centre (border and frontier cells are), no other cell can be nearer.
  if (cellDistance(px, py) < kUnreachable) {
    const Point2 c = cellCenter(px, py);
    if (radius < 0.5 * resolution_ || std::hypot(c.x - p.x, c.y - p.y) <= 1e-3 * resolution_)
      return c;
  }
  const int span = static_cast<int>(std::ceil(std::max(radius, 0.0) / resolution_)) + 1;
  const double r2 = radius * radius;
  double best_d2 = std::numeric_limits<double>::infinity(), best_geo = kUnreachable;
  int bx = -1, by = -1;
  for (int cy = std::max(0, py - span); cy <= std::min(height_ - 1, py + span); ++cy)
    for (int cx = std::max(0, px - span); cx <= std::min(width_ - 1, px + span); ++cx) {
      const double geo = dist_[static_cast<std::size_t>(cy) * width_ + cx];
      if (!(geo < kUnreachable)) continue;
      const Point2 c = cellCenter(cx, cy);
      const double d2 = (c.x - p.x) * (c.x - p.x) + (c.y - p.y) * (c.y - p.y);
      const bool own = cx == px && cy == py;
      if (d2 > r2 && !own) continue;
      // Distances equal to a micrometre are ties (cell centres come from MRPT's float
      // resolution); the row-major scan keeps the smaller cell index on a full tie.
      const bool tie = std::abs(std::sqrt(d2) - std::sqrt(best_d2)) <= 1e-6;
      if ((d2 < best_d2 && !tie) || (tie && geo < best_geo)) {
        best_d2 = d2;
        best_geo = geo;
        bx = cx;
        by = cy;
      }
    }
  if (bx < 0) return std::nullopt;
  return cellCenter(bx, by);
}

std::vector<Point2> Reachability::pathTo(const Point2& p) const {
  if (!reachable(p)) return {};
  int cx = static_cast<int>(std::floor((p.x - origin_x_) / resolution_));
  int cy = static_cast<int>(std::floor((p.y - origin_y_) / resolution_));
  std::vector<Point2> back{cellCenter(cx, cy)};
  // Each step goes to a strictly nearer cell, so the walk ends, at the start (distance 0):
  // every other reachable cell has its predecessor among its neighbours.
  for (double d = cellDistance(cx, cy); d > 0;) {
    int bx = -1, by = -1;
    double best = std::numeric_limits<double>::infinity(), best_d = d;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const double dn = cellDistance(cx + dx, cy + dy);
        if (!(dn < d)) continue;
        // No corner cutting, as in the search: both cells a diagonal step passes are open.
        if (dx != 0 && dy != 0 &&
            !(cellDistance(cx + dx, cy) < kUnreachable && cellDistance(cx, cy + dy) < kUnreachable))
          continue;
        const double through = dn + ((dx != 0 && dy != 0) ? std::sqrt(2.0) : 1.0) * resolution_;
        if (through < best) best = through, best_d = dn, bx = cx + dx, by = cy + dy;
      }
    if (bx < 0) break;  // float rounding left no nearer neighbour: stop where we are
    cx = bx, cy = by, d = best_d;
    back.push_back(cellCenter(cx, cy));
  }
  return {back.rbegin(), back.rend()};
}

int Reachability::closest(const std::vector<Point2>& candidates, double snap_radius,
                          Point2* snapped, double* distance) const {
  int best = -1;
  double best_dist = kUnreachable;
  Point2 best_point;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const std::optional<Point2> q = nearestReachable(candidates[i], snap_radius);
    if (!q) continue;
    const double dq = distanceTo(*q);
    if (dq < best_dist) {
      best_dist = dq;
      best = static_cast<int>(i);
      best_point = *q;
    }
  }
  if (best >= 0) {
    if (snapped) *snapped = best_point;
    if (distance) *distance = best_dist;
  }
  return best;
}

}  // namespace asf::mapping
