#pragma once
/// \file incremental_se2.h
/// `sparse_lm`'s incremental mode: a growing pose graph solved in a window around what is
/// new, the whole graph only when a bound says the window's answer is not good enough.
///
/// After each call the graph as this object left it is remembered. When the next graph only
/// adds nodes and edges to it (nothing else moved or changed), the new nodes, the ends of the
/// new edges and everything within `hops` edges of them, plus every node added since the
/// last factorization of the whole graph, are optimized with all other nodes held. Then the
/// gradient b of the whole graph's cost is non-zero only on nodes of that last factorization
/// H0, and b^T H0^-1 b bounds what a Gauss-Newton step on the whole graph would still lower
/// chi2 by (SparseSe2::decrementBound). Above `gap` (or with a window larger than
/// `max_window` nodes, or no factor yet) the whole graph is solved as the plain back-end
/// does. So the estimate is at most `gap` in chi2 above the optimum of the Gauss-Newton
/// model, i.e. within sqrt(gap) standard deviations of it along any direction
/// ((x - x*)^T H (x - x*) <= gap).
///
/// Marginals (`marginals`): Exact (the default) factorizes the whole graph at its poses at
/// every call. Updated: after window solves, the last whole factorization's blocks updated
/// for the information added since (marginal_update.h): the blocks that factorization's
/// linearization gives, a new one only when the update outgrows its limits. Propagated:
/// after window solves the last exact blocks are kept and each newer node's block is
/// propagated along one of its edges to older nodes (first order; the edge giving the
/// smallest trace): upper bounds in the positive semi-definite order of what a new
/// computation would give (information only grows; to first order in the poses that moved),
/// at the cost of one 3x3 composition per new node instead of a factorization. All three are
/// exact after a solve of the whole graph, or when cross blocks are asked for.
#include <asf/backend.h>
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "marginal_update.h"
#include "sparse_se2.h"

namespace asf::sparse_lm {

enum class MarginalsMode { Exact, Updated, Propagated };

struct IncrementalOptions {
  bool enabled = false;
  double gap = 0.5;              ///< chi2 a whole-graph step may still gain, at most
  int hops = 3;                  ///< window: edges away from the new nodes and edge ends
  std::size_t max_window = 300;  ///< larger windows: solve the whole graph instead
  MarginalsMode marginals = MarginalsMode::Exact;
  /// Updated marginals: a new whole factorization once the new nodes plus the old nodes new
  /// edges touch exceed `update_max_nodes`, or those old nodes `update_max_touched`.
  std::size_t update_max_nodes = 32, update_max_touched = 8;
};

struct IncrementalCounters {
  long window_solves = 0;    ///< calls answered by a window solve
  long whole_solves = 0;     ///< calls that solved the whole graph
  long bound_exceeded = 0;   ///< ... of which after a window solve whose bound was above gap
  long exact_marginals = 0;  ///< marginals() from a factorization of the whole graph
  long propagated_marginals = 0;
  long updated_marginals = 0;  ///< marginals() updated from the last whole factorization
  double last_bound = -1;      ///< the last decrement bound computed (-1: none)
  std::string last_path;       ///< how the last optimize() was answered, for the log
};

class IncrementalSe2 {
 public:
  asf::OptimizeReport optimize(asf::PoseGraph& g, const Options& o, const IncrementalOptions& io);
  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross,
                           const Options& o, const IncrementalOptions& io);

  const IncrementalCounters& counters() const { return counters_; }
  /// The solver of the whole graph (its counters, its last symbolic analysis).
  const SparseSe2& whole() const { return whole_; }

 private:
  /// True if g is the graph this object last returned plus nodes and edges.
  bool extendsLast(const asf::PoseGraph& g) const;
  /// Records g's edges (appended when g extends the last graph, else from scratch).
  void syncEdges(const asf::PoseGraph& g, bool extends);
  /// Records g's poses as this object leaves them.
  void rememberPoses(const asf::PoseGraph& g);
  std::vector<asf::NodeId> window(const asf::PoseGraph& g, std::size_t old_nodes,
                                  std::size_t old_edges, std::size_t factor_nodes, int hops) const;
  asf::OptimizeReport solveWhole(asf::PoseGraph& g, const Options& o, const IncrementalOptions& io,
                                 const std::string& why);
  bool propagate(const asf::PoseGraph& g);

  SparseSe2 whole_, window_;
  IncrementalCounters counters_;

  struct EdgeCopy {
    asf::NodeId from, to;
    double x, y, phi;
    Eigen::Matrix3d information;
  };
  bool have_ = false;
  std::vector<Eigen::Vector3d> poses_;  ///< node poses as last returned
  std::vector<EdgeCopy> edges_;
  std::vector<asf::NodeId> fixed_;
  double cost_ = 0;  ///< the objective (chi2, or the robust cost) at the remembered poses
  std::vector<std::vector<std::size_t>> incident_;  ///< node -> indices of its edges
  /// Whole-graph factor current with the remembered poses (set by a whole solve, cleared by a
  /// window solve): marginals() may then use it.
  bool last_whole_ = false;
  asf::Marginals marg_;    ///< the last marginals returned (exact or propagated)
  MarginalUpdate update_;  ///< active from an exact marginals() until whole_ factorizes again
};

}  // namespace asf::sparse_lm
