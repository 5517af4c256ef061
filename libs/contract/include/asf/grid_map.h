#pragma once
/// \file grid_map.h
/// The occupancy grid built from the pose graph (a framework service, see map_builder.h).
#include <asf/geometry.h>

#include <cmath>
#include <cstdint>
#include <memory>

namespace mrpt::maps {
class COccupancyGridMap2D;
}

namespace asf {

struct GridMap {
  /// The grid (MRPT). MRPT's convention: getCell()/getPos() return the probability that
  /// the cell is FREE (1 = free, 0 = occupied, 0.5 = unknown). A version a consumer keeps
  /// (holds this shared_ptr) is never modified: the publisher copies before changing it. A
  /// version no one keeps may be changed in place for the next one, so a raw pointer or
  /// reference is valid during the call that handed it over only, and the same object may
  /// carry several versions: compare `version`, not pointers.
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> grid;
  /// Incremented on every change; 0 = no map yet.
  std::uint64_t version = 0;
  /// Map-frame box of what changed since version-1 (whole map after a rebuild). It must
  /// cover every cell whose value changed: an incremental segmenter given version k after
  /// version k-1 reads the grid only inside it (dude); an empty box says nothing.
  Box2 changed;
  /// True when known structure moved (loop closure -> rebuild), not only new cells.
  bool rebuilt = false;
};

/// What a cell of an occupancy grid is for driving, the one definition the policies'
/// reachability (reachability.h) and the simulator's navigation use: an obstacle when
/// p(occupied) = 1 - p(free) exceeds `occupied_threshold`, unknown (not known to be free;
/// frontiers border it) when |p(free) - 0.5| is below `unknown_band`, free otherwise.
enum CellState : std::uint8_t { kCellFree = 0, kCellUnknown = 1, kCellOccupied = 2 };
inline CellState cellStateOf(double p_free, double occupied_threshold, double unknown_band) {
  if (1.0 - p_free > occupied_threshold) return kCellOccupied;
  if (std::abs(p_free - 0.5) < unknown_band) return kCellUnknown;
  return kCellFree;
}

}  // namespace asf
