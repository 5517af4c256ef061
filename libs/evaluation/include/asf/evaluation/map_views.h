#pragma once
/// \file map_views.h
/// The pictures of a run's map: map.png (the grid, the path, the keyframes), regions.png (the
/// regions, the path, the topological graph), topology.svg (the graph as vectors over the
/// regions), and a grid alone as a grey image.
#include <asf/grid_map.h>
#include <asf/pose_graph.h>
#include <asf/segmentation.h>
#include <asf/topo_graph.h>
#include <mrpt/poses/CPose2D.h>

#include <string>
#include <vector>

namespace asf::evaluation {

/// Writes PREFIXmap.png and, when `seg` has labels, PREFIXregions.png and
/// PREFIXtopology.svg; nothing without a grid. Throws asf::Error when a file cannot be
/// written.
void writeMapViews(const std::string& prefix, const PoseGraph& graph, const GridMap& map,
                   const Segmentation& seg, const TopoGraph& topo,
                   const std::vector<mrpt::poses::CPose2D>& path);

/// One frame of a run's timeline (report.html): the regions (or the bare grid without a
/// segmentation), the topological graph, the path so far, the robot and its goal, scaled
/// down so that its longer side is at most `max_side` pixels, written as a PNG to `file`.
/// Nothing without a grid. Throws asf::Error when it cannot be written.
void writeTimelineFrame(const std::string& file, const GridMap& map, const Segmentation& seg,
                        const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                        const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side);

/// A picture in memory: 8-bit blue, green, red per pixel, rows top to bottom.
struct ViewImage {
  int width = 0, height = 0;
  std::vector<unsigned char> bgr;  ///< width * height * 3
};

/// What the live view (`asf run --gui`) shows: the timeline frame's picture (regions, the
/// topological graph, the path, the robot and its goal) with the pose graph over it: its
/// edges (loop closures in magenta) and nodes, at most `max_side` pixels. Empty without a
/// grid.
ViewImage renderLiveView(const GridMap& map, const Segmentation& seg, const TopoGraph& topo,
                         const PoseGraph& graph, const std::vector<mrpt::poses::CPose2D>& path,
                         const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side);
/// Writes a ViewImage as a PNG (asf::Error when it cannot).
void writeViewPng(const std::string& file, const ViewImage& image);

/// The grid as a grey PNG (grey level = p(free), y up). Throws asf::Error when it cannot be
/// written; `map` must have a grid.
void writeGridPng(const std::string& file, const GridMap& map);

}  // namespace asf::evaluation
