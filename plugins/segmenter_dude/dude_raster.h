#pragma once
// Raster steps of segmenter_dude around the decomposition (OpenCV label images, CV_32S;
// label 0 = no region; labels >= first_fresh are the ones an incremental update may change).
#include <opencv2/core.hpp>

namespace asf::dude::raster {

/// Every free cell gets a label: cells left out by the polygons (simplification, grown
/// obstacles, one-cell corridors) join the nearest labelled cell through free space (8-
/// neighbourhood BFS); free components with no labelled cell become regions of their own
/// (labels from *next_label) when they have at least `min_new_cells` cells, else stay 0.
/// Cells that are not free get 0.
void completeLabels(const cv::Mat& free, cv::Mat& labels, int* next_label, int min_new_cells = 0);

/// Regions below min_region_area [m^2] (labels >= first_fresh) join the neighbour they
/// share the longest border with.
void mergeSmallRegions(cv::Mat& labels, int next_label, double res, int first_fresh,
                       double min_region_area);

struct RoomLayerOptions {
  double merge_concavity = 1.0;   ///< [m]; 0: off
  double merge_min_border = 1.2;  ///< [m]
  double simplify_tolerance = 0.1;  ///< [m]
  double min_hole_extent = 2.5;   ///< [m]: a union with a wider hole stays apart
};

/// Room layer: neighbouring pieces whose union DuDe would not cut again are merged.
void mergeConvexNeighbours(cv::Mat& labels, int next_label, int first_fresh, double res,
                           const RoomLayerOptions& o);

}  // namespace asf::dude::raster
