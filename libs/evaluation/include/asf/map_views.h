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

namespace asf {

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

/// The grid as a grey PNG (grey level = p(free), y up). Throws asf::Error when it cannot be
/// written; `map` must have a grid.
void writeGridPng(const std::string& file, const GridMap& map);

}  // namespace asf
