#include <asf/mapping/coverage.h>
#include <asf/errors.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

namespace asf::mapping {

CoverageMeter::CoverageMeter(const WorldTruth& world, double unknown_band)
    : unknown_band_(unknown_band) {
  if (!world.grid) throw Error("coverage: the world has no grid");
  const auto& g = *world.grid;
  const int W = static_cast<int>(g.getSizeX()), H = static_cast<int>(g.getSizeY());
  const int sx = g.x2idx(world.map_origin.x()), sy = g.y2idx(world.map_origin.y());
  auto free = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < W && y < H && g.getCell(x, y) > 0.5f;
  };
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
  indexCells(4 * g.getResolution());
}

void CoverageMeter::indexCells(double bucket) {
  bucket_ = bucket;
  double x1 = bx0_ = cells_.front().x, y1 = by0_ = cells_.front().y;
  for (const Point2& p : cells_) {
    bx0_ = std::min(bx0_, p.x), by0_ = std::min(by0_, p.y);
    x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  bw_ = static_cast<int>((x1 - bx0_) / bucket_) + 1;
  bh_ = static_cast<int>((y1 - by0_) / bucket_) + 1;
  const auto bucketOf = [&](const Point2& p) {
    const int bx = std::min(bw_ - 1, static_cast<int>((p.x - bx0_) / bucket_));
    const int by = std::min(bh_ - 1, static_cast<int>((p.y - by0_) / bucket_));
    return static_cast<std::size_t>(by) * bw_ + bx;
  };
  first_.assign(static_cast<std::size_t>(bw_) * bh_ + 1, 0);  // counting sort by bucket
  for (const Point2& p : cells_) ++first_[bucketOf(p) + 1];
  for (std::size_t b = 1; b < first_.size(); ++b) first_[b] += first_[b - 1];
  std::vector<Point2> sorted(cells_.size());
  std::vector<std::size_t> next(first_.begin(), first_.end() - 1);
  for (const Point2& p : cells_) sorted[next[bucketOf(p)]++] = p;
  cells_ = std::move(sorted);
}

bool CoverageMeter::observed(const mrpt::maps::COccupancyGridMap2D& g, const Point2& p) const {
  const int x = g.x2idx(p.x), y = g.y2idx(p.y);
  if (x < 0 || y < 0 || x >= static_cast<int>(g.getSizeX()) || y >= static_cast<int>(g.getSizeY()))
    return false;
  return std::abs(g.getCell(x, y) - 0.5f) >= unknown_band_;
}

std::size_t CoverageMeter::observedCount(const mrpt::maps::COccupancyGridMap2D& g) const {
  std::size_t seen = 0;
  for (const Point2& p : cells_)
    if (observed(g, p)) ++seen;
  return seen;
}

template <class Count>
std::size_t CoverageMeter::inBox(const Box2& box, std::size_t& visited, Count count) const {
  if (cells_.empty() || box.empty()) return 0;
  const auto clampX = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - bx0_) / bucket_)), 0, bw_ - 1);
  };
  const auto clampY = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - by0_) / bucket_)), 0, bh_ - 1);
  };
  std::size_t n = 0;
  for (int by = clampY(box.min_y); by <= clampY(box.max_y); ++by)
    for (int bx = clampX(box.min_x); bx <= clampX(box.max_x); ++bx) {
      const std::size_t b = static_cast<std::size_t>(by) * bw_ + bx;
      for (std::size_t i = first_[b]; i < first_[b + 1]; ++i) {
        const Point2& p = cells_[i];
        if (p.x < box.min_x || p.x > box.max_x || p.y < box.min_y || p.y > box.max_y) continue;
        ++visited;
        if (count(i)) ++n;
      }
    }
  return n;
}

std::size_t CoverageMeter::observedIn(const mrpt::maps::COccupancyGridMap2D& grid, const Box2& box,
                                      std::size_t& visited) const {
  return inBox(box, visited, [&](std::size_t i) { return observed(grid, cells_[i]); });
}

bool CoverageMeter::GridIndex::fits(const mrpt::maps::COccupancyGridMap2D& g) const {
  return g.getXMin() == x_min && g.getYMin() == y_min && g.getResolution() == resolution &&
         g.getSizeX() == size_x && g.getSizeY() == size_y;
}

CoverageMeter::GridIndex CoverageMeter::indexFor(const mrpt::maps::COccupancyGridMap2D& g) const {
  GridIndex ix;
  ix.x_min = g.getXMin(), ix.y_min = g.getYMin(), ix.resolution = g.getResolution();
  ix.size_x = g.getSizeX(), ix.size_y = g.getSizeY();
  ix.cell.resize(cells_.size());
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    // The arithmetic of observed(): the same cell, or off the grid.
    const int x = g.x2idx(cells_[i].x), y = g.y2idx(cells_[i].y);
    const bool on =
        x >= 0 && y >= 0 && x < static_cast<int>(ix.size_x) && y < static_cast<int>(ix.size_y);
    ix.cell[i] = on ? static_cast<std::int32_t>(y * static_cast<int>(ix.size_x) + x) : -1;
  }
  return ix;
}

namespace {
using CellValue = mrpt::maps::COccupancyGridMap2D::cellType;

/// For every value a cell can store: free (p >= 0.5 + band, as float) and observed
/// (|p - 0.5| >= band, float against double), p = l2p(value): the comparisons of getCell()
/// and observed(), made once per value instead of an l2p call per cell (whole-grid recounts
/// after every rebuild of a long log's map).
class CellTable {
 public:
  explicit CellTable(double band) : flags_(std::size_t{1} << (8 * sizeof(CellValue))) {
    const float thr = 0.5f + static_cast<float>(band);
    for (long v = std::numeric_limits<CellValue>::min(); v <= std::numeric_limits<CellValue>::max();
         ++v) {
      const float p = mrpt::maps::COccupancyGridMap2D::l2p(static_cast<CellValue>(v));
      flags_[index(static_cast<CellValue>(v))] =
          static_cast<std::uint8_t>((p >= thr ? 1 : 0) | (std::abs(p - 0.5f) >= band ? 2 : 0));
    }
  }
  bool free(CellValue v) const { return flags_[index(v)] & 1; }
  bool observed(CellValue v) const { return flags_[index(v)] & 2; }

 private:
  static std::size_t index(CellValue v) {
    return static_cast<std::size_t>(static_cast<long>(v) - std::numeric_limits<CellValue>::min());
  }
  std::vector<std::uint8_t> flags_;
};

/// What each stored cell value says, in fixed point (bits * 2^32): 1 - its binary entropy,
/// 0 for an unknown cell. Sums over many cells are then exact, and a running total equals
/// a recount to the last bit.
class InformationTable {
 public:
  InformationTable() : i_(std::size_t{1} << (8 * sizeof(CellValue))) {
    for (long v = std::numeric_limits<CellValue>::min(); v <= std::numeric_limits<CellValue>::max();
         ++v) {
      const double p = mrpt::maps::COccupancyGridMap2D::l2p(static_cast<CellValue>(v));
      const double h = p <= 0 || p >= 1 ? 0 : -(p * std::log2(p) + (1 - p) * std::log2(1 - p));
      i_[index(static_cast<CellValue>(v))] = std::llround((1 - h) * kOne);
    }
  }
  static constexpr double kOne = 4294967296.0;  ///< 2^32: one bit
  std::int64_t operator()(CellValue v) const { return i_[index(v)]; }

 private:
  static std::size_t index(CellValue v) {
    return static_cast<std::size_t>(static_cast<long>(v) - std::numeric_limits<CellValue>::min());
  }
  std::vector<std::int64_t> i_;
};
const InformationTable& informationTable() {
  static const InformationTable table;
  return table;
}

/// The table of `band` (one per band and thread: runs of an experiment share no state).
const CellTable& cellTable(double band) {
  thread_local std::map<double, CellTable> tables;
  auto it = tables.find(band);
  if (it == tables.end()) it = tables.emplace(band, CellTable(band)).first;
  return it->second;
}

/// observed() on a cell of the buffer (the index of GridIndex::cell).
inline bool observedCell(const std::vector<CellValue>& raw, std::int32_t k, const CellTable& t) {
  return k >= 0 && t.observed(raw[static_cast<std::size_t>(k)]);
}
}  // namespace

std::size_t CoverageMeter::observedCount(const mrpt::maps::COccupancyGridMap2D& g,
                                         const GridIndex& index) const {
  const auto& raw = g.getRawMap();
  const CellTable& band = cellTable(unknown_band_);
  std::size_t seen = 0;
  for (const std::int32_t k : index.cell)
    if (observedCell(raw, k, band)) ++seen;
  return seen;
}

std::size_t CoverageMeter::observedIn(const mrpt::maps::COccupancyGridMap2D& g, const Box2& box,
                                      const GridIndex& index, std::size_t& visited) const {
  const auto& raw = g.getRawMap();
  const CellTable& band = cellTable(unknown_band_);
  return inBox(box, visited, [&](std::size_t i) { return observedCell(raw, index.cell[i], band); });
}

long CoverageMeter::observedChangeIn(const mrpt::maps::COccupancyGridMap2D& now,
                                     const mrpt::maps::COccupancyGridMap2D& before, const Box2& box,
                                     const GridIndex& index, std::size_t& visited) const {
  const auto& a = now.getRawMap();
  const auto& b = before.getRawMap();
  const CellTable& band = cellTable(unknown_band_);
  long change = 0;
  std::size_t cells = 0;
  inBox(box, cells, [&](std::size_t i) {
    const std::int32_t k = index.cell[i];
    if (k >= 0 && a[static_cast<std::size_t>(k)] != b[static_cast<std::size_t>(k)])
      change +=
          static_cast<long>(observedCell(a, k, band)) - static_cast<long>(observedCell(b, k, band));
    return false;
  });
  visited += 2 * cells;
  return change;
}

double CoverageMeter::coverage(const GridMap& map) const {
  if (!map.grid || cells_.empty()) return 0;
  return static_cast<double>(observedCount(*map.grid)) / cells_.size();
}

namespace {

/// What the area tracker counts over a range of cells: the free ones and their information
/// (InformationTable's fixed point).
struct CellSums {
  long free = 0;
  std::int64_t information = 0;
};

/// CellSums of `g` over the cells [x0, x1] x [y0, y1] (clamped to the grid); with `before`
/// (a grid of the same geometry) those of `g` minus those of `before`, in one pass that
/// reads only the cells whose stored values differ.
CellSums cellSums(const mrpt::maps::COccupancyGridMap2D& g,
                  const mrpt::maps::COccupancyGridMap2D* before, int x0, int x1, int y0, int y1,
                  double unknown_band) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, static_cast<int>(g.getSizeX()) - 1);
  y1 = std::min(y1, static_cast<int>(g.getSizeY()) - 1);
  const CellTable& t = cellTable(unknown_band);
  const InformationTable& info = informationTable();
  const std::size_t sx = g.getSizeX();
  CellSums sum;
  for (int y = y0; y <= y1; ++y) {
    const auto* a = g.getRawMap().data() + static_cast<std::size_t>(y) * sx;
    const auto* b =
        before ? before->getRawMap().data() + static_cast<std::size_t>(y) * sx : nullptr;
    for (int x = x0; x <= x1; ++x) {
      if (!b) {
        sum.free += t.free(a[x]);
        sum.information += info(a[x]);
      } else if (a[x] != b[x]) {
        sum.free += static_cast<long>(t.free(a[x])) - static_cast<long>(t.free(b[x]));
        sum.information += info(a[x]) - info(b[x]);
      }
    }
  }
  return sum;
}

CellSums allCells(const mrpt::maps::COccupancyGridMap2D& g, double unknown_band) {
  return cellSums(g, nullptr, 0, static_cast<int>(g.getSizeX()) - 1, 0,
                  static_cast<int>(g.getSizeY()) - 1, unknown_band);
}

}  // namespace

double mapInformationBits(const GridMap& map) {
  // The band does not change what a cell says, only whether it counts as free.
  return map.grid
             ? static_cast<double>(allCells(*map.grid, 0.02).information) / InformationTable::kOne
             : 0;
}

double mapEntropyBits(const GridMap& map) {
  if (!map.grid) return 0;
  const double cells = static_cast<double>(map.grid->getSizeX()) * map.grid->getSizeY();
  return cells - mapInformationBits(map);
}

double freeArea(const GridMap& map, double unknown_band) {
  if (!map.grid) return 0;
  const double r = map.grid->getResolution();
  return static_cast<double>(allCells(*map.grid, unknown_band).free) * r * r;
}

MapAreaTracker::MapAreaTracker(const CoverageMeter* meter, double unknown_band)
    : meter_(meter), band_(unknown_band) {}
MapAreaTracker::~MapAreaTracker() = default;
MapAreaTracker::MapAreaTracker(MapAreaTracker&&) noexcept = default;
MapAreaTracker& MapAreaTracker::operator=(MapAreaTracker&&) noexcept = default;

void MapAreaTracker::recount(const mrpt::maps::COccupancyGridMap2D& g) {
  ++recounts_;
  visited_ += static_cast<std::size_t>(g.getSizeX()) * g.getSizeY();
  const CellSums all = allCells(g, band_);
  free_cells_ = static_cast<std::size_t>(all.free);
  information_ = all.information;
  if (meter_) {
    observed_ = meter_->observedCount(g, indexFor(g));
    visited_ += meter_->reachableCells();
  }
  if (counted_)
    *counted_ = g;
  else
    counted_ = std::make_unique<mrpt::maps::COccupancyGridMap2D>(g);
}

bool MapAreaTracker::sameCells(const mrpt::maps::COccupancyGridMap2D& a,
                               const mrpt::maps::COccupancyGridMap2D& b) const {
  const double r = a.getResolution();
  if (r != b.getResolution()) return false;
  const auto whole = [&](double d) { return std::abs(d / r - std::round(d / r)) < 1e-3; };
  return whole(a.getXMin() - b.getXMin()) && whole(a.getYMin() - b.getYMin());
}

void MapAreaTracker::regrid(const mrpt::maps::COccupancyGridMap2D& g, int x0, int x1, int y0,
                            int y1) {
  using Grid = mrpt::maps::COccupancyGridMap2D;
  const Grid& old = *counted_;
  const double r = g.getResolution();
  // The same cells in the old grid: shifted by the whole number of cells between origins.
  const int dx = static_cast<int>(std::lround((g.getXMin() - old.getXMin()) / r));
  const int dy = static_cast<int>(std::lround((g.getYMin() - old.getYMin()) / r));
  auto now = std::make_unique<Grid>(g);
  const Grid::cellType unknown = Grid::p2l(0.5f);
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, static_cast<int>(g.getSizeX()) - 1);
  y1 = std::min(y1, static_cast<int>(g.getSizeY()) - 1);
  const int ow = static_cast<int>(old.getSizeX()), oh = static_cast<int>(old.getSizeY());
  for (int y = y0; y <= y1; ++y) {
    Grid::cellType* row = now->getRow(y);
    const int oy = y + dy;
    const Grid::cellType* orow = oy >= 0 && oy < oh ? old.getRow(oy) : nullptr;
    for (int x = x0; x <= x1; ++x) {
      const int ox = x + dx;
      row[x] = orow && ox >= 0 && ox < ow ? orow[ox] : unknown;
    }
  }
  counted_ = std::move(now);
}

void MapAreaTracker::update(const GridMap& map) {
  if (!map.grid) {
    counted_.reset();
    seen_ = nullptr;
    version_ = map.version;
    free_cells_ = observed_ = 0;
    information_ = 0;
    return;
  }
  if (counted_ && map.version == version_ && map.grid.get() == seen_) return;
  const auto& g = *map.grid;
  const bool trust_box = counted_ && map.version == version_ + 1 && !map.rebuilt &&
                         !map.changed.empty() && sameCells(*counted_, g);
  version_ = map.version;
  seen_ = map.grid.get();
  if (!trust_box) return recount(g);
  // Every cell whose value changed overlaps the box: grown by a cell, it holds their centres.
  const double r = g.getResolution();
  Box2 box = map.changed;
  box.min_x -= r, box.min_y -= r, box.max_x += r, box.max_y += r;
  const int x0 = std::max(g.x2idx(box.min_x), 0), y0 = std::max(g.y2idx(box.min_y), 0);
  const int x1 = std::min(g.x2idx(box.max_x), static_cast<int>(g.getSizeX()) - 1);
  const int y1 = std::min(g.y2idx(box.max_y), static_cast<int>(g.getSizeY()) - 1);
  if (x0 > x1 || y0 > y1) return;
  const bool same_geometry =
      g.getXMin() == counted_->getXMin() && g.getYMin() == counted_->getYMin() &&
      g.getSizeX() == counted_->getSizeX() && g.getSizeY() == counted_->getSizeY();
  if (!same_geometry) regrid(g, x0, x1, y0, y1);
  const mrpt::maps::COccupancyGridMap2D& before = *counted_;
  visited_ += 2 * static_cast<std::size_t>(x1 - x0 + 1) * (y1 - y0 + 1);
  const CellSums change = cellSums(g, &before, x0, x1, y0, y1, band_);
  free_cells_ = static_cast<std::size_t>(static_cast<long>(free_cells_) + change.free);
  information_ += change.information;
  if (meter_)
    observed_ =
        static_cast<std::size_t>(static_cast<long>(observed_) +
                                 meter_->observedChangeIn(g, before, box, indexFor(g), visited_));
  // What was counted now: the box's cells (everything else is unchanged).
  for (int y = y0; y <= y1; ++y)
    std::copy(g.getRow(y) + x0, g.getRow(y) + x1 + 1, counted_->getRow(y) + x0);
}

const CoverageMeter::GridIndex& MapAreaTracker::indexFor(const mrpt::maps::COccupancyGridMap2D& g) {
  if (!index_.fits(g)) index_ = meter_->indexFor(g);
  return index_;
}

double MapAreaTracker::freeArea() const {
  if (!counted_) return 0;
  const double r = counted_->getResolution();
  return static_cast<double>(free_cells_) * r * r;
}

double MapAreaTracker::informationBits() const {
  return counted_ ? static_cast<double>(information_) / InformationTable::kOne : 0;
}

double MapAreaTracker::coverage() const {
  if (!meter_ || !counted_ || meter_->reachableCells() == 0) return 0;
  return static_cast<double>(observed_) / meter_->reachableCells();
}

}  // namespace asf::mapping
