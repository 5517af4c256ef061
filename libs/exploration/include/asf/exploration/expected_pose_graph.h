#pragma once
/// \file expected_pose_graph.h
/// The pose graph a robot expects after driving a path, as a weighted graph, and its
/// D-optimality: the utility of the `dopt_frontier` policy (Placed and Castellanos, "A general
/// relationship between optimality criteria and connectivity indices for active graph-SLAM",
/// RA-L 2023). Each edge is weighted by the D-criterion of its information matrix,
/// w_j = det(Omega_j)^(1/3); the D-optimality of the whole graph's information is then
/// approximated by ||L_w||_0, the normalised weighted number of spanning trees
/// (graph::dOptimalitySparse; thesis ch. 5 ties the same Laplacian to the pose graph's
/// information, Theorem 5.2.1).
///
/// The path is "hallucinated" as the authors' controller does: new nodes along it, each joined
/// to the one before by an odometry edge, and a loop closure wherever an old node is near
/// enough for the front-end to close one. Expected edges start from the medians of the present
/// graph's own weights (odometry: consecutive nodes; loops: LoopClosure edges). With the map's
/// shares around each new node (AreaShares) they are scaled as in the authors' controller:
/// odometry by 1 + the unknown share (what the node will map), a loop by 1.5 x its age (id
/// difference over the graph's nodes) x the occupied share, and no loop where under 3 % of the
/// cells are occupied (nothing to match). Without them, the medians alone.
#include <asf/geometry.h>
#include <asf/graph/multigraph.h>
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

namespace asf::exploration {

/// D-criterion of one 3x3 information matrix: det^(1/3) (the geometric mean of its
/// eigenvalues); 0 when it is not positive definite.
double edgeDOptimality(const Eigen::Matrix3d& information);

struct ExpectedGraphOptions {
  double node_spacing = 0.5;  ///< a new node every this many metres of path (keyframes)
  double loop_radius = 2.0;   ///< an old node this near a new one closes a loop [m]
  int loop_skip_recent = 20;  ///< ... unless it is among the last this many nodes before it
};

/// Shares of the cells within a radius of a point that are unknown and occupied (the authors'
/// `cellInformation`): what an expected node there would see.
struct AreaShares {
  double unknown = 0, occupied = 0;
};
using AreaFn = std::function<AreaShares(const Point2&)>;

/// What a path is expected to add to the graph.
struct Expectation {
  double d_optimality = 0;  ///< ||L_w||_0 of the graph with the path's nodes and edges
  int nodes = 0;            ///< nodes added along the path
  int loops = 0;            ///< loop closures expected
};

class ExpectedPoseGraph {
 public:
  /// The present graph (node positions from its estimates). Its newest node is where the
  /// expected paths start from.
  ExpectedPoseGraph(const PoseGraph& g, const ExpectedGraphOptions& options);

  /// The graph after driving `path` (map-frame points from the robot to the goal): a node at
  /// every node_spacing metres of arc length and one at the end, an odometry edge from the
  /// newest node (or the previous new one) to each, and to each the nearest old node within
  /// loop_radius that is not among the loop_skip_recent nodes before it.
  /// `area` (optional): the map's shares around a point, for the authors' scaling above.
  Expectation afterPath(const std::vector<Point2>& path, const AreaFn& area = {}) const;

  /// ||L_w||_0 of the present graph.
  double present() const;
  double odometryWeight() const { return odometry_weight_; }
  double loopWeight() const { return loop_weight_; }
  const graph::Multigraph& graph() const { return base_; }

 private:
  int nearestOldNode(const Point2& p, int max_id) const;

  ExpectedGraphOptions options_;
  graph::Multigraph base_;  ///< Edge::information = w_j
  std::vector<Point2> positions_;
  double odometry_weight_ = 1, loop_weight_ = 1;
  /// Old nodes by square cell of side loop_radius.
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
  std::int64_t cellKey(const Point2& p, int dx = 0, int dy = 0) const;
};

}  // namespace asf::exploration
