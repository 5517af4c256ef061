#pragma once
// Drawing of grids, regions and topological graphs with OpenCV (private to asf::evaluation):
// behind the run's map views (map_views.h) and the segmentation overlays.
#include <asf/segmentation.h>
#include <asf/topo_graph.h>

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace mrpt::maps {
class COccupancyGridMap2D;
}

namespace asf::evaluation::render {

/// Distinct, deterministic colour of a region id (BGR).
cv::Vec3b regionColour(RegionId id);

/// Grid as a BGR image, y up, and a map-point -> pixel function.
struct MapImage {
  cv::Mat img;
  double x0 = 0, y0 = 0, res = 1;
  cv::Point px(double x, double y) const {
    return {static_cast<int>((x - x0) / res), img.rows - 1 - static_cast<int>((y - y0) / res)};
  }
};

/// Grey levels = p(free).
MapImage renderGrid(const mrpt::maps::COccupancyGridMap2D& g);
/// Paints every labelled cell in its region's colour.
void drawRegions(MapImage& m, const LabelImage& labels);
/// Edges through their border midpoints (frontier edges red), region centroids as dots.
void drawTopology(MapImage& m, const TopoGraph& topo);
/// Region ids as text at the centroids.
void drawRegionIds(MapImage& m, const Segmentation& seg);

/// An SVG of `background` (embedded PNG) with the topological graph drawn as vectors on top:
/// region nodes (filled when visited, ringed when current) with their ids, edges through
/// their border midpoints labelled with their traversal counts, frontier edges in red, and
/// `path` (map frame) as a polyline. Pixel geometry is that of `m`.
std::string topologySvg(const MapImage& m, const cv::Mat& background, const TopoGraph& topo,
                        const std::vector<Point2>& path = {});

}  // namespace asf::evaluation::render
