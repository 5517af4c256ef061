#pragma once
/// \file reachability.h
/// Where the robot can drive on the estimated map, and how far each place is: geodesic
/// distances from the robot over known-free cells that keep the robot's radius from every
/// obstacle (8-connected Dijkstra, diagonal steps sqrt(2) cells). What exploration policies
/// use to pick the nearest goal and to avoid goals the robot cannot reach.
///
/// The robot may start closer than its radius to an obstacle (after a drift of the map):
/// cells within `robot_radius` of the start that are free are passable, so it can leave.
#include <asf/geometry.h>
#include <asf/grid_map.h>
#include <asf/key_spec.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

namespace asf {
class Params;
}  // namespace asf

namespace asf::mapping {

struct ReachabilityOptions {
  double robot_radius = 0.2;         ///< cells closer than this to an obstacle are lethal [m]
  double occupied_threshold = 0.65;  ///< p(occupied) above this is an obstacle
  double unknown_band = 0.02;        ///< |p - 0.5| below this is unknown (not passable)
};

/// The keys of a plugin that plans with Reachability, one definition for every policy:
/// robot_radius (each policy keeps its own default), occupied_threshold, unknown_band.
constexpr KeySpec keyRobotRadius(const char* def) {
  return keyDouble("robot_radius", def,
                   "Cells closer than this to an obstacle of the estimated map are not drivable "
                   "(the robot's radius and a margin for the map's blur) [m]",
                   0.0, 5.0);
}
constexpr KeySpec keyOccupiedThreshold() {
  return keyDouble("occupied_threshold", "0.65",
                   "A cell is an obstacle when p(occupied) exceeds this", 0.5, 1.0);
}
constexpr KeySpec keyUnknownBand() {
  return keyDouble("unknown_band", "0.02",
                   "A cell is unknown (not drivable; frontiers border it) when |p - 0.5| is "
                   "below this",
                   0.0, 0.5);
}
/// Reads those three keys; 0.5 + unknown_band reaching occupied_threshold fails naming
/// unknown_band (unknown cells would count as obstacles).
ReachabilityOptions reachabilityOptionsFrom(const Params& p);

/// Every cell of `grid` classified by cellStateOf (grid_map.h) under the thresholds of
/// `options` (row-major, getSizeX() per row), through a table over the
/// raw cell values (MRPT's cells are 8 or 16 bits): cheaper than a probability per cell.
std::vector<std::uint8_t> classifyCells(const mrpt::maps::COccupancyGridMap2D& grid,
                                        const ReachabilityOptions& options);

class Reachability {
 public:
  static constexpr double kUnreachable = std::numeric_limits<double>::infinity();

  /// Distances from `from` (map frame) over `map`. An empty or null grid gives a field
  /// where nothing is reachable.
  static Reachability compute(const GridMap& map, const Point2& from,
                              const ReachabilityOptions& options = {});

  /// Geodesic distance [m] from the start to the cell of p; kUnreachable if p is off the
  /// grid or not reachable.
  double distanceTo(const Point2& p) const;
  bool reachable(const Point2& p) const { return distanceTo(p) < kUnreachable; }

  /// The reachable cell centre nearest (Euclidean) to p within `radius` [m], if any; ties
  /// go to the smaller geodesic distance.
  std::optional<Point2> nearestReachable(const Point2& p, double radius) const;

  /// Among `candidates`, the index of the one with the smallest geodesic distance
  /// (each candidate may be moved to its nearest reachable cell within `snap_radius`);
  /// -1 if none is reachable. `snapped`, when given, receives the reachable point.
  int closest(const std::vector<Point2>& candidates, double snap_radius, Point2* snapped = nullptr,
              double* distance = nullptr) const;

  /// A shortest way from the start to p's cell: cell centres, the start's first and p's cell
  /// last, each 8-adjacent to the one before (back from p, each step to the neighbour whose
  /// distance plus the step is least: the Dijkstra predecessor). Empty if p is unreachable.
  std::vector<Point2> pathTo(const Point2& p) const;

  /// Grid geometry, for callers that scan cells (e.g. frontier detection).
  double resolution() const { return resolution_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// Cell centre of (cx, cy) in the map frame.
  Point2 cellCenter(int cx, int cy) const {
    return {origin_x_ + (cx + 0.5) * resolution_, origin_y_ + (cy + 0.5) * resolution_};
  }
  /// Distance of cell (cx, cy); kUnreachable outside the grid.
  double cellDistance(int cx, int cy) const;

 private:
  double resolution_ = 0.05, origin_x_ = 0, origin_y_ = 0;
  int width_ = 0, height_ = 0;
  std::vector<float> dist_;  ///< metres, row-major, +inf = unreachable
};

}  // namespace asf::mapping
