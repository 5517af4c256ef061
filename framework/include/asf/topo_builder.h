#pragma once
/// \file topo_builder.h
/// Framework service: topological graph from a Segmentation and the map, with the robot's
/// traversal history. Regions that share a free border at least `min_border_width` wide are
/// joined; a region bordering unknown space over at least `min_frontier_width` gets an edge
/// to the kUnexplored node.
#include <asf/grid_map.h>
#include <asf/key_spec.h>
#include <asf/params.h>
#include <asf/segmentation.h>
#include <asf/topo_graph.h>

namespace asf {

class TopoBuilder {
 public:
  static const KeySpec* keys(std::size_t& n);  ///< the [topology] section
  void configure(const Params& p);

  /// Recomputes nodes and edges from a new segmentation; traversal history, visited flags
  /// and entrance edges carry over for region ids that persist.
  void update(const Segmentation& seg, const GridMap& map);
  /// Records the robot at (x, y) at time t: updates the current region, and a traversal
  /// when it moved into a neighbouring region.
  void observeRobot(double x, double y, double t);
  const TopoGraph& graph() const { return graph_; }

 private:
  double min_border_width_ = 0.3, min_frontier_width_ = 0.5, unknown_band_ = 0.02;
  Segmentation seg_;
  TopoGraph graph_;
};

}  // namespace asf
