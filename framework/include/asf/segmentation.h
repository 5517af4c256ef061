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

/// Turns a label image with provisional labels (any values > 0, 0 = no region) into a
/// Segmentation, the common last step of raster segmenters:
/// - regions smaller than `min_area` [m^2] are dropped (their cells become 0);
/// - ids are reused from `previous` (may be null) by largest overlap, greedily, each id at
///   most once; the others get fresh ids above `*max_issued` and every id of `previous`, and
///   `*max_issued` is updated (so an id is never reissued by the same segmenter);
/// - area, centroid and boundary (outer counter-clockwise, holes clockwise, through the
///   centres of the border cells) are computed per region; regions are sorted by id.
/// `labels` must have width * height entries; cells of one provisional label need not be
/// connected (a region's outer boundary is then that of its largest piece).
/// `boxes` (may be null) receives the cell bounding box of every region.
Segmentation regionsFromLabels(LabelImage labels, const Segmentation* previous,
                               RegionId* max_issued, std::uint64_t map_version,
                               double min_area = 0, RegionBoxes* boxes = nullptr);

/// The same result as regionsFromLabels(labels, &previous, max_issued, map_version,
/// min_area, &boxes), in time proportional to `window` and the regions with cells in it
/// rather than to the image, for an update that only changed the cells inside `window`.
/// Preconditions: outside `window`, `labels` holds exactly previous.labels (a provisional
/// label there is the previous region's id; fresh labels are not ids of `previous` and lie
/// inside the window), and `boxes` holds the cell boxes of previous' regions (as filled by
/// either function); on return it holds those of the result. When the rasters differ or a
/// box is missing, it falls back to regionsFromLabels.
Segmentation regionsFromLabelsInWindow(LabelImage labels, const Segmentation& previous,
                                       RegionBoxes& boxes, CellBox window,
                                       RegionId* max_issued, std::uint64_t map_version,
                                       double min_area = 0);

}  // namespace asf
