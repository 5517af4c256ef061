#include <asf/coverage.h>
#include <asf/errors.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>

namespace asf {

CoverageMeter::CoverageMeter(const WorldTruth& world, double unknown_band)
    : unknown_band_(unknown_band) {
  if (!world.grid) throw Error("coverage: the world has no grid");
  const auto& g = *world.grid;
  const int W = static_cast<int>(g.getSizeX()), H = static_cast<int>(g.getSizeY());
  const int sx = g.x2idx(world.map_origin.x()), sy = g.y2idx(world.map_origin.y());
  auto free = [&](int x, int y) { return x >= 0 && y >= 0 && x < W && y < H && g.getCell(x, y) > 0.5f; };
  if (!free(sx, sy))
    throw Error("coverage: the robot's start (" + std::to_string(world.map_origin.x()) + ", " +
                std::to_string(world.map_origin.y()) + ") is not on a free cell of the world");
  std::vector<char> seen(static_cast<std::size_t>(W) * H, 0);
  std::vector<int> stack{sy * W + sx};
  seen[stack.back()] = 1;
  const mrpt::poses::CPose2D inv = -world.map_origin;  // world -> map frame
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const int x = i % W, y = i / W;
    double mx, my;
    inv.composePoint(g.idx2x(x), g.idx2y(y), mx, my);
    cells_.push_back({mx, my});
    const int nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& d : nb) {
      const int nx = x + d[0], ny = y + d[1];
      if (!free(nx, ny) || seen[ny * W + nx]) continue;
      seen[ny * W + nx] = 1;
      stack.push_back(ny * W + nx);
    }
  }
  reachable_area_ = cells_.size() * g.getResolution() * g.getResolution();
}

double CoverageMeter::coverage(const GridMap& map) const {
  if (!map.grid || cells_.empty()) return 0;
  const auto& g = *map.grid;
  std::size_t seen = 0;
  for (const Point2& p : cells_) {
    const int x = g.x2idx(p.x), y = g.y2idx(p.y);
    if (x < 0 || y < 0 || x >= static_cast<int>(g.getSizeX()) || y >= static_cast<int>(g.getSizeY()))
      continue;
    if (std::abs(g.getCell(x, y) - 0.5f) >= unknown_band_) ++seen;
  }
  return static_cast<double>(seen) / cells_.size();
}

double freeArea(const GridMap& map, double unknown_band) {
  if (!map.grid) return 0;
  const auto& g = *map.grid;
  std::size_t n = 0;
  const float thr = 0.5f + static_cast<float>(unknown_band);
  for (unsigned y = 0; y < g.getSizeY(); ++y)
    for (unsigned x = 0; x < g.getSizeX(); ++x)
      if (g.getCell(x, y) >= thr) ++n;
  return n * g.getResolution() * g.getResolution();
}

}  // namespace asf
