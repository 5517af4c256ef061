#pragma once
/// \file pose_graph.h
/// The SLAM pose graph (front-end writes, back-end optimizes) and its marginal covariances.
#include <Eigen/Core>
#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mrpt::obs {
class CObservation2DRangeScan;
}

namespace asf {

using NodeId = std::uint32_t;

struct PoseNode {
  NodeId id = 0;
  mrpt::poses::CPose2D pose;  ///< current estimate, map frame
  double timestamp = 0;
  /// Keyframe scan taken at this node (may be null).
  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> scan;
  std::optional<mrpt::poses::CPose2D> ground_truth;
};

enum class EdgeKind : std::uint8_t { Odometry = 0, ScanMatch = 1, LoopClosure = 2 };
const char* edgeKindName(EdgeKind k);

/// Relative pose measurement: pose(to) = pose(from) (+) mean. `information` is the inverse
/// covariance of PoseGraph::edgeError(e) (the g2o convention: its translation is expressed
/// in the frame of from (+) mean), ordering (x, y, phi).
struct PoseEdge {
  NodeId from = 0, to = 0;
  mrpt::poses::CPose2D mean;
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();
  EdgeKind kind = EdgeKind::Odometry;
};

/// Nodes are stored densely: node i has id i (ids are indices), which every plugin may rely on.
class PoseGraph {
 public:
  std::vector<PoseNode> nodes;
  std::vector<PoseEdge> edges;
  /// Nodes held fixed by the optimizer besides the gauge (g2o FIX lines).
  std::vector<NodeId> fixed;

  NodeId addNode(const mrpt::poses::CPose2D& pose, double timestamp = 0);
  void addEdge(const PoseEdge& e);  ///< throws asf::Error if an end is not a node
  std::size_t size() const { return nodes.size(); }
  bool empty() const { return nodes.empty(); }

  /// Error of one edge: log(mean^-1 (+) (from^-1 (+) to)) as (dx, dy, dphi).
  Eigen::Vector3d edgeError(const PoseEdge& e) const;
  /// Sum over edges of e^T Omega e (the g2o convention).
  double chi2() const;

  /// Incremented by whoever changes the graph (front-end adds, back-end moves poses);
  /// consumers compare it to know when to recompute.
  std::uint64_t revision = 0;
};

/// Marginal covariances recovered by a back-end. Blocks are 3x3 in (x, y, phi) and the
/// global frame, with the gauge fixed by the first node.
struct Marginals {
  std::vector<Eigen::Matrix3d> node;  ///< node[i] = Cov(x_i); empty if not computed
  /// Cross-covariance blocks Cov(x_i, x_j) for the requested pairs (i, j).
  std::map<std::pair<NodeId, NodeId>, Eigen::Matrix3d> cross;
  std::uint64_t graph_revision = 0;  ///< revision of the graph they belong to
  bool valid() const { return !node.empty(); }
};

/// g2o text format: VERTEX_SE2 id x y theta / EDGE_SE2 i j dx dy dth I11 I12 I13 I22 I23 I33
/// / FIX id. Node ids must be 0..n-1 (any order). A file without VERTEX lines gets its
/// initial guess by composing the odometry chain i -> i+1. Throws asf::InputError naming the
/// file and line (malformed line, unknown node, non positive-definite information).
PoseGraph readG2o(const std::string& path);
PoseGraph parseG2o(const std::string& text, const std::string& name = "<text>");
void writeG2o(const PoseGraph& g, const std::string& path);
std::string formatG2o(const PoseGraph& g);

/// a (+) b with first-order covariance propagation (additive x, y, phi; Ca in the frame a is
/// expressed in, Cb in a's frame): returns the composed pose, writes its covariance to out.
mrpt::poses::CPose2D composeWithCov(const mrpt::poses::CPose2D& a, const Eigen::Matrix3d& Ca,
                                    const mrpt::poses::CPose2D& b, const Eigen::Matrix3d& Cb,
                                    Eigen::Matrix3d& out);

/// Information of an edge with this `mean` (PoseEdge::information, g2o convention) from the
/// covariance `cov` of the mean as additive (x, y, phi) in the frame of `from`: the error's
/// translation is in the frame of from (+) mean, so Cov(e) = R^T cov R; `floor` is added to
/// Cov(e) to keep it invertible.
Eigen::Matrix3d edgeInformation(const mrpt::poses::CPose2D& mean, const Eigen::Matrix3d& cov,
                                const Eigen::Matrix3d& floor);

/// Throws asf::Error ("<who>: node i is not connected to node 0 (nor to a fixed node)...")
/// when some node has no chain of edges to node 0 or to a fixed node: its pose is not
/// determined by the graph, so neither is its covariance. Back-ends call it before solving.
void requireAnchored(const PoseGraph& g, const std::string& who);

/// Dense Gauss-Newton information matrix H = sum over edges of J^T Omega J at the current
/// estimate (analytic SE(2) Jacobians), over the free nodes: every node except node 0 (the
/// gauge) and g.fixed. `index` receives each node's first row in H (-1 for held nodes).
/// O((3n)^2) memory: for small graphs, baselines and test oracles.
Eigen::MatrixXd denseInformation(const PoseGraph& g, std::vector<int>& index);

}  // namespace asf
