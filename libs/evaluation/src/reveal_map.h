#pragma once
// The next map of a step-by-step reveal (ExplorationSimulator, RasterDiskReveal).
#include <asf/grid_map.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <memory>
#include <vector>

namespace asf::evaluation::detail {

/// Publishes into `map` (version + 1, not rebuilt) a copy of `grid` (published grids never
/// change; a fresh W x H grid of unknown cells when null) in which the image pixels
/// `revealed` (index row * W + col, row 0 on top) are set free (1) where free(index), else
/// occupied (0). `grid` becomes the copy.
template <class IsFree>
void publishReveal(std::shared_ptr<mrpt::maps::COccupancyGridMap2D>& grid, GridMap& map, int W,
                   int H, double res, const std::vector<int>& revealed, IsFree free,
                   const Box2& changed) {
  using Grid = mrpt::maps::COccupancyGridMap2D;
  auto g = grid ? std::make_shared<Grid>(*grid) : nullptr;
  if (!g) {
    g = std::make_shared<Grid>(0.f, static_cast<float>(W * res), 0.f, static_cast<float>(H * res),
                               static_cast<float>(res));
    g->fill(0.5f);
  }
  for (int i : revealed) g->setCell(i % W, H - 1 - i / W, free(i) ? 1.0f : 0.0f);
  grid = g;
  map.grid = g;
  ++map.version;
  map.changed = changed;
  map.rebuilt = false;
}

}  // namespace asf::evaluation::detail
