#pragma once
/// \file coverage.h
/// How much of the world an exploration has mapped: the share of the reachable free area of
/// the true world that the estimated map has observed. Reachable = free cells of the world
/// connected (4-neighbours) to the robot's start; observed = the estimated map's cell at the
/// same place (mapped through the known map-frame origin) is no longer unknown. Drift of the
/// estimate moves cells by its error, so 100% needs the map to be right too.
#include <asf/grid_map.h>
#include <asf/source.h>

#include <vector>

namespace asf {

class CoverageMeter {
 public:
  /// `world` must hold a grid; cells with p(free) > 0.5 are free. The start is the map
  /// frame's origin. Throws asf::Error when the start is not on a free cell.
  explicit CoverageMeter(const WorldTruth& world, double unknown_band = 0.02);

  double reachableArea() const { return reachable_area_; }  ///< m^2
  /// Fraction in [0, 1] of the reachable cells observed in `map` (0 without a grid).
  double coverage(const GridMap& map) const;

 private:
  std::vector<Point2> cells_;  ///< reachable world cells, map frame
  double reachable_area_ = 0, unknown_band_ = 0.02;
};

/// Free area [m^2] of an estimated map: cells with p(free) >= 0.5 + unknown_band.
double freeArea(const GridMap& map, double unknown_band = 0.02);

}  // namespace asf
