#pragma once
// Room segmentation on the generalized Voronoi graph of free space (after Thrun 1998 and
// Bormann et al., ICRA 2016), on a raster free-space mask. Units are cells here; the plugin
// converts its metric keys with the map resolution.
#include <opencv2/core.hpp>
#include <vector>

namespace asf::voronoi {

struct Options {
  double robot_radius = 6;          ///< opening radius [cells]; 0: no opening
  double prune_length = 10;         ///< dead-end branches shorter than this are removed [cells]
  int neighborhood = 30;            ///< half window along the graph for clearance minima [cells]
  double min_rise = 0;              ///< clearance rise factor on both sides of a critical point
  double min_cut_angle = 2.0;       ///< min angle between the two basis points [rad]
  double max_cut_length = 1e9;      ///< cut lines longer than this are not drawn [cells]
  double max_furniture_area = 0;    ///< no cuts to obstacles smaller than this [cells]; 0: off
  double min_room_area = 600;       ///< smaller regions merge into a neighbour [cells]
  double max_merge_area = 5000;     ///< regions below this may merge by shared border [cells]
  double merge_border_ratio = 0.2;  ///< shared border / perimeter that triggers that merge
};

/// What one run found (for logs and tests).
struct Stats {
  int skeleton_cells = 0;
  int critical_points = 0;  ///< clearance minima on the graph
  int cuts = 0;             ///< cut lines drawn (minima with basis points on opposite sides)
  int components = 0;       ///< regions after cutting, before merging
  int regions = 0;          ///< regions returned
  // Geometry, in the input's pixel coordinates (for pictures and tests).
  cv::Mat skeleton;                     ///< CV_8U, 1 = graph cell after pruning
  std::vector<cv::Point> critical;      ///< the critical points
  std::vector<cv::Vec4i> cut_lines;     ///< x1 y1 x2 y2 of the cut lines drawn
};

/// \param free CV_8U, non-zero = free cell.
/// \return CV_32S of the same size: 0 = no region, 1..n = regions (every free cell connected
///         to a region gets one).
cv::Mat segmentFreeSpace(const cv::Mat& free, const Options& options, Stats* stats = nullptr);

}  // namespace asf::voronoi
