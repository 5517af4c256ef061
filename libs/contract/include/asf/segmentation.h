#pragma once
/// \file segmentation.h
/// Regions of free space produced by a segmenter.
#include <asf/geometry.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace asf {

using RegionId = std::int32_t;  ///< > 0 for regions; 0 = no region

struct Region {
  RegionId id = 0;  ///< stable across incremental updates where the region did not change
  Polygon outer;    ///< boundary, metres, counter-clockwise
  std::vector<Polygon> holes;
  double area = 0;  ///< m^2 (free cells x cell area)
  Point2 centroid;  ///< of the region's cells
};

/// Label image aligned with the grid: cell (cx, cy) covers
/// [origin_x + cx*resolution, +resolution) x [origin_y + cy*resolution, +resolution).
struct LabelImage {
  int width = 0, height = 0;
  double resolution = 0, origin_x = 0, origin_y = 0;
  std::vector<RegionId> labels;  ///< row-major, cy * width + cx

  RegionId at(int cx, int cy) const { return labels[static_cast<std::size_t>(cy) * width + cx]; }
  /// Label of the cell containing map point (x, y); 0 outside the image.
  RegionId atPoint(double x, double y) const;
};

/// Rectangle of cells [x, x + width) x [y, y + height) of a LabelImage.
struct CellBox {
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
};

/// Cell bounding box of every region of a segmentation, by id (all of its cells, not only
/// the piece its outline describes).
using RegionBoxes = std::unordered_map<RegionId, CellBox>;

struct Segmentation {
  std::vector<Region> regions;
  LabelImage labels;
  std::uint64_t map_version = 0;  ///< version of the GridMap it was computed from
  /// How the segmenter computed it, for the run's statistics: Full (the whole map),
  /// Incremental (only the part touching the change, thesis Algorithm 3), or Unknown (the
  /// segmenter does not say).
  enum class Mode : std::uint8_t { Unknown, Full, Incremental };
  Mode mode = Mode::Unknown;
  /// Cells whose input (free / not free) changed since the segmenter's previous call; the
  /// number of cells of the map when there was no comparable previous call; -1: not known.
  std::int64_t changed_cells = -1;
  const Region* find(RegionId id) const;
};

}  // namespace asf
