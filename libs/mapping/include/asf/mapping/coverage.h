#pragma once
/// \file coverage.h
/// How much of the world an exploration has mapped: the share of the reachable free area of
/// the true world that the estimated map has observed. Reachable = free cells of the world
/// connected (4-neighbours) to the robot's start; observed = the estimated map's cell at the
/// same place (mapped through the known map-frame origin) is no longer unknown. Drift of the
/// estimate moves cells by its error, so 100% needs the map to be right too.
#include <asf/grid_map.h>
#include <asf/source.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace asf::mapping {

class CoverageMeter {
 public:
  /// `world` must hold a grid; cells with p(free) > 0.5 are free. The start is the map
  /// frame's origin. Throws asf::Error when the start is not on a free cell.
  explicit CoverageMeter(const WorldTruth& world, double unknown_band = 0.02);

  double reachableArea() const { return reachable_area_; }  ///< m^2
  /// Fraction in [0, 1] of the reachable cells observed in `map` (0 without a grid).
  double coverage(const GridMap& map) const;
  /// Reachable cells observed in `grid` among those whose centre lies in `box` (map frame);
  /// visits only the cells in the box (a bucket index), `visited` counts them.
  std::size_t observedIn(const mrpt::maps::COccupancyGridMap2D& grid, const Box2& box,
                         std::size_t& visited) const;
  /// Reachable cells observed in `grid` (all of them: coverage() times reachableCells()).
  std::size_t observedCount(const mrpt::maps::COccupancyGridMap2D& grid) const;
  std::size_t reachableCells() const { return cells_.size(); }

  /// Where each reachable cell falls in grids of `grid`'s geometry (origin, resolution,
  /// size): its index in the grid's cell buffer, or -1 off the grid. Computed once per
  /// geometry by a caller that counts many versions of a growing map (MapAreaTracker); the
  /// overloads below then read the cells without the coordinate arithmetic.
  struct GridIndex {
    double x_min = 0, y_min = 0, resolution = 0;
    unsigned size_x = 0, size_y = 0;
    std::vector<std::int32_t> cell;  ///< per reachable cell, in this meter's order
    bool fits(const mrpt::maps::COccupancyGridMap2D& grid) const;
  };
  GridIndex indexFor(const mrpt::maps::COccupancyGridMap2D& grid) const;
  /// As observedCount(grid) and observedIn(grid, box, visited), with `index` made for a grid
  /// of the same geometry (index.fits(grid)); the same counts.
  std::size_t observedCount(const mrpt::maps::COccupancyGridMap2D& grid,
                            const GridIndex& index) const;
  std::size_t observedIn(const mrpt::maps::COccupancyGridMap2D& grid, const Box2& box,
                         const GridIndex& index, std::size_t& visited) const;
  /// observedIn(now, box, index) - observedIn(before, box, index) for two grids of the
  /// index's geometry, in one pass that compares only the cells whose stored values differ.
  long observedChangeIn(const mrpt::maps::COccupancyGridMap2D& now,
                        const mrpt::maps::COccupancyGridMap2D& before, const Box2& box,
                        const GridIndex& index, std::size_t& visited) const;

 private:
  void indexCells(double bucket);
  bool observed(const mrpt::maps::COccupancyGridMap2D& g, const Point2& p) const;
  /// observedIn's walk over the buckets under `box`: count(i) for each cell i inside it.
  template <class Count>
  std::size_t inBox(const Box2& box, std::size_t& visited, Count count) const;

  std::vector<Point2> cells_;  ///< reachable world cells, map frame, sorted by bucket
  /// Bucket index over cells_: bucket (bx, by) of side `bucket_` holds
  /// cells_[first_[b] .. first_[b + 1]).
  std::vector<std::size_t> first_;
  double bucket_ = 1, bx0_ = 0, by0_ = 0;
  int bw_ = 0, bh_ = 0;
  double reachable_area_ = 0, unknown_band_ = 0.02;
};

/// Free area and coverage of a map that grows version by version, kept up to date in
/// O(cells in GridMap::changed) per version instead of a scan of the whole grid (on a
/// 25-million-cell map the scan dominated a run). The result equals the full recount
/// (freeArea, CoverageMeter::coverage) after every update. It recounts everything when it
/// cannot trust the change box: the first map, a version that does not follow the last one
/// seen, an empty box ("says nothing"), a rebuild, a grid of another resolution or whose
/// cells moved. It keeps its own copy of the cells it counted (updated inside each box), not
/// the published grid: a publisher may then change its grid in place (MapBuilder).
class MapAreaTracker {
 public:
  /// `meter`: the coverage reference (may be null: coverage() is then 0); kept by pointer.
  explicit MapAreaTracker(const CoverageMeter* meter = nullptr, double unknown_band = 0.02);
  ~MapAreaTracker();
  MapAreaTracker(MapAreaTracker&&) noexcept;
  MapAreaTracker& operator=(MapAreaTracker&&) noexcept;
  /// Brings the counts up to `map` (a no-op for the version already seen).
  void update(const GridMap& map);
  double freeArea() const;                               ///< m^2, as asf::mapping::freeArea(map)
  double coverage() const;                               ///< as CoverageMeter::coverage(map)
  double informationBits() const;                        ///< as mapInformationBits(map), exactly
  std::size_t cellsVisited() const { return visited_; }  ///< grid cells read, all updates
  std::size_t recounts() const { return recounts_; }     ///< updates that read everything

 private:
  void recount(const mrpt::maps::COccupancyGridMap2D& g);
  bool sameCells(const mrpt::maps::COccupancyGridMap2D& a,
                 const mrpt::maps::COccupancyGridMap2D& b) const;
  /// counted_ in g's geometry (g grew): g's cells outside `cells` (unchanged since counted_),
  /// counted_'s inside (unknown where counted_ had none).
  void regrid(const mrpt::maps::COccupancyGridMap2D& g, int x0, int x1, int y0, int y1);

  /// The meter's cells in the current grid's geometry (rebuilt when the grid grows).
  const CoverageMeter::GridIndex& indexFor(const mrpt::maps::COccupancyGridMap2D& g);

  const CoverageMeter* meter_;
  CoverageMeter::GridIndex index_;
  double band_;
  std::unique_ptr<mrpt::maps::COccupancyGridMap2D> counted_;  ///< the cells counted
  const void* seen_ = nullptr;  ///< the grid object of the version counted (identity only)
  std::uint64_t version_ = 0;
  std::size_t free_cells_ = 0, observed_ = 0, visited_ = 0, recounts_ = 0;
  std::int64_t information_ = 0;  ///< of counted_, bits * 2^32 (mapInformationBits' fixed point)
};

/// What an occupancy grid says, in bits: the sum over its cells of 1 - h(p), h the binary
/// entropy -p log2 p - (1 - p) log2(1 - p) of the cell's occupancy; an unknown cell adds 0,
/// a certain one 1. So the entropy of the map over any fixed region R that holds the grid
/// (the measure of map uncertainty active SLAM papers plot) is cells(R) - information, and
/// that holds while the grid grows: a run's timeseries gives the entropy over its final
/// grid as that grid's cells minus each row's information. Each cell's term is rounded to
/// 2^-32 bit, so sums are exact. Reads the whole grid: a run keeps it with MapAreaTracker.
double mapInformationBits(const GridMap& map);
/// The entropy over the grid itself: its cells minus mapInformationBits (unknown: 1 bit).
double mapEntropyBits(const GridMap& map);

/// Free area [m^2] of an estimated map: cells with p(free) >= 0.5 + unknown_band. Reads the
/// whole grid: a run keeps it with MapAreaTracker.
double freeArea(const GridMap& map, double unknown_band = 0.02);

}  // namespace asf::mapping
