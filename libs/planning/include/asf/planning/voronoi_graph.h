#pragma once
/// \file voronoi_graph.h
/// The generalized Voronoi graph (GVG) of the free space of an occupancy grid, as a raster
/// skeleton (the free cells farther than a clearance from non-free cells, thinned by
/// Guo-Hall's parallel thinning (OpenCV ximgproc), whose end points keep the dead-end
/// corridors, then corner spurs pruned), and the *virtual
/// edges* it gives a pose graph in a partially explored map (thesis section 3.6): pairs of
/// pose-graph nodes that the GVG joins through free space but the pose graph does not join
/// directly (two corridors seen but never driven between, a shortcut through a room).
///
/// Conventions: grid cells (cx, cy) with cy up (MRPT), index cy * width + cx; metres in the
/// map frame. Everything here is deterministic.
#include <asf/grid_map.h>
#include <asf/mapping/odometry_noise.h>
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace asf::planning {

struct GvgOptions {
  /// A cell is free when p(free) > this (MRPT getCell); unknown (0.5) and occupied are not.
  double free_threshold = 0.65;
  /// Robot clearance [m]: the GVG lives in free cells whose centre is farther than this
  /// from the centre of every non-free cell (and from the grid's border), so no GVG path
  /// passes a gap narrower than about 2 x clearance.
  double clearance = 0.2;
};

/// Corner spurs: thinning grows a branch into every convex corner of the free space (a
/// room's corners, the corners closing a dead-end corridor); a dead-end branch whose end lies
/// within 1.5 x the junction's clearance of its junction is such a spur and is removed
/// (repeatedly). A real dead-end corridor reaches farther.
///
/// The GVG of a grid: its skeleton cells and, for reading, the graph they form (vertices:
/// clusters of skeleton cells whose skeleton degree is not 2 -- junctions and dead ends --
/// edges: the chains of degree-2 cells between them; a closed loop without a junction is
/// one edge from a vertex on it to itself).
struct Gvg {
  int width = 0, height = 0;
  double resolution = 0, origin_x = 0,
         origin_y = 0;                 ///< cell (cx, cy) centre: origin + (c + 0.5) res
  std::vector<std::uint8_t> skeleton;  ///< width * height, 1 = GVG cell
  std::size_t skeleton_cells = 0;
  struct Vertex {
    Eigen::Vector2d position;  ///< mean of its cells' centres [m]
    int degree = 0;            ///< number of chain ends at it (edges, a loop counting twice)
    std::vector<int> cells;
  };
  struct Edge {
    int a = 0, b = 0;        ///< vertex indices
    double length = 0;       ///< along the cells, centre to centre [m]
    std::vector<int> cells;  ///< from a's cell to b's cell
  };
  std::vector<Vertex> vertices;
  std::vector<Edge> edges;
  std::size_t junctions() const;  ///< vertices of degree >= 3
  std::size_t ends() const;       ///< vertices of degree 1
  Eigen::Vector2d cellCentre(int index) const;
};

/// Throws asf::Error when the map has no grid or options are out of range.
Gvg computeGvg(const GridMap& map, const GvgOptions& o = {});

// ---------------------------------------------------------------------------------------

struct VirtualEdgeOptions {
  GvgOptions gvg;
  /// A pose-graph node attaches to the GVG cell nearest to it along free cells (geodesic,
  /// 8-connected, so never through a wall), if that is at most this far [m].
  double attach_radius = 1.0;
  /// A pair joined by the GVG becomes a virtual edge only when the pose graph has no edge
  /// between them and no path (metres between estimates) of at most detour x the virtual
  /// edge's length: the virtual edge is then a real shortcut.
  double detour = 1.5;
  /// The virtual edges' odometry covariance: `odometry` of the motion, times this.
  mapping::OdometryNoiseModel odometry;
  double covariance_scale = 1.0;
  /// > 0: the drive is ceil(length / odometry_step) equal increments (the turn spread over
  /// them), each with `odometry`'s covariance, composed to first order; 0: one increment.
  double odometry_step = 0;
};

/// An edge the GVG adds to the pose graph (not a measurement: the robot would drive it by
/// odometry alone).
struct VirtualEdge {
  NodeId a = 0, b = 0;  ///< a < b
  /// Length of the drive a -> b through free space [m]: a's attach leg + the GVG path between
  /// the two attach cells + b's attach leg.
  double length = 0;
  double skeleton_length = 0;  ///< the GVG part of it [m]
  /// Covariance (x, y, phi) of the motion a -> b in a's frame (the PathModel convention):
  /// covariance_scale x odometry.covariance(CPose2D(length, 0, dphi)) -- driving `length`
  /// straight ahead and turning by dphi, b's heading in a's frame -- rotated so that the
  /// forward axis points at b. covariance_ba: the same for b -> a, in b's frame.
  Eigen::Matrix3d covariance_ab = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d covariance_ba = Eigen::Matrix3d::Zero();
};

struct VirtualEdges {
  Gvg gvg;
  /// Per pose-graph node: the GVG cell it attaches to (-1: none within attach_radius, or
  /// outside the grid) and the geodesic length of that leg [m].
  std::vector<int> attach_cell;
  std::vector<double> attach_distance;
  std::size_t attached = 0;
  /// Candidate pairs the GVG joined (before the edge/detour filter).
  std::size_t candidates = 0;
  /// Sorted by (a, b), one per pair.
  std::vector<VirtualEdge> edges;
};

/// The virtual edges of `g` on `map`'s GVG. Nodes attached to the same GVG cell are one
/// port, represented by its node with the shortest attach leg (ties: smallest id); the
/// ports split the GVG into regions (multi-source shortest paths along the skeleton) and
/// ports whose regions touch are joined (the GVG path between them, shortest in those two
/// regions); every other node of a port is joined to its representative. Each joined pair
/// passing VirtualEdgeOptions::detour becomes a VirtualEdge. Throws asf::Error for a map
/// without grid or bad options.
VirtualEdges computeVirtualEdges(const PoseGraph& g, const GridMap& map,
                                 const VirtualEdgeOptions& o = {});

}  // namespace asf::planning
