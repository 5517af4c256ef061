#pragma once
/// \file topo_graph.h
/// Topological graph of regions: what exploration policies decide on.
#include <asf/geometry.h>
#include <asf/segmentation.h>

#include <vector>

namespace asf {

/// The node standing for all unexplored space (frontier edges end there).
constexpr RegionId kUnexplored = -1;

struct TopoNode {
  RegionId region = 0;  ///< region id, or kUnexplored
  Point2 centroid;
  double area = 0;
  bool visited = false;       ///< the robot has been inside
  int entrance_edge = -1;     ///< index of the edge of first entry, -1 if none
};

struct Traversal {
  bool forward = true;  ///< a -> b when true
  double time = 0;
};

struct TopoEdge {
  RegionId a = 0, b = 0;  ///< b == kUnexplored for frontier edges
  Point2 midpoint;        ///< middle of the shared border
  double width = 0;       ///< free width of the border, metres
  /// Cell centres along the border (a's side), map frame: where a goal for this edge can
  /// be placed. For a frontier edge, the cells of region a next to unknown space.
  std::vector<Point2> border;
  bool frontier() const { return b == kUnexplored; }
  std::vector<Traversal> traversals;
};

struct TopoGraph {
  std::vector<TopoNode> nodes;  ///< includes one node with region == kUnexplored
  std::vector<TopoEdge> edges;
  RegionId current = 0;  ///< region the robot is in (0: none)

  const TopoNode* node(RegionId r) const;
  TopoNode* node(RegionId r);
  /// Indices of edges incident to r.
  std::vector<int> incident(RegionId r) const;
  /// Number of traversals of edge e leaving region r.
  int outwardTraversals(int e, RegionId r) const;
};

}  // namespace asf
