#pragma once
/// \file backend.h
/// `backend` plugins: optimize the pose graph and recover marginal covariances.
///
/// Contract:
/// - optimize() moves node poses only (never adds or removes), holds node 0 and
///   graph.fixed fixed, increments graph.revision if it moved anything, and never returns a
///   final chi2 above the initial one. An empty or single-node graph is a no-op. A graph
///   whose chi2 is not finite (poses or information too large, NaN) is an asf::Error saying
///   so: never a "converged" report with an infinite chi2.
/// - marginals() returns one symmetric positive semi-definite 3x3 block per node (node 0's
///   is zero: the gauge) and the requested cross blocks; nodes not connected to node 0 have
///   no defined covariance: asf::Error.
#include <asf/plugin.h>
#include <asf/pose_graph.h>

#include <string>
#include <utility>
#include <vector>

namespace asf {

struct OptimizeReport {
  double initial_chi2 = 0, final_chi2 = 0;
  int iterations = 0;
  bool converged = false;
  std::string message;  ///< why it stopped
};

class Backend : public Plugin {
 public:
  static constexpr PluginKind kStaticKind = PluginKind::Backend;
  PluginKind kind() const final { return kStaticKind; }
  ~Backend() override;

  virtual OptimizeReport optimize(PoseGraph& graph) = 0;
  virtual Marginals marginals(const PoseGraph& graph,
                              const std::vector<std::pair<NodeId, NodeId>>& cross = {}) = 0;
};

}  // namespace asf
