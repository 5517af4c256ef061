#pragma once
/// \file marginal_update.h
/// `incremental_marginals = updated`: the marginals of a growing graph from the last whole
/// factorization, updated for what was added since instead of factorizing again.
///
/// At the start of an epoch the whole graph G0 (nodes V0) was factorized at its poses and
/// all its marginals Sigma0 recovered. Since then nodes N and edges were added; B are the
/// nodes of V0 the new edges touch. The new edges involve only B and N, so (the Gaussian of
/// the linearized model):
/// - the marginal of S = B u N is exactly Lambda_S^-1, Lambda_S = [Sigma0_BB^-1 + A_BB, A_BN;
///   A_NB, A_NN] (G0's information on B after eliminating the rest of V0 is Sigma0_BB^-1; A
///   the new edges' J^T W J at the current poses);
/// - any other old node o keeps its conditional on B, so Sigma_oo = Sigma0_oo - Sigma0_oB K
///   Sigma0_Bo with K = Sigma0_BB^-1 (Sigma0_BB - Sigma_BB) Sigma0_BB^-1 (a Woodbury update;
///   the columns Sigma0_.B come from one solve with the kept factor per node of B).
/// So the blocks are those a new factorization at the epoch's linearization would give: the
/// same as exact marginals when nothing moved, to first order in the poses window solves
/// moved since. Each call costs the new columns' solves, a dense inverse of S and O(|V0|
/// rank(K)) for the old blocks; an epoch ends (the caller factorizes the whole graph) when S
/// or B outgrow their limits.
#include <asf/pose_graph.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "sparse_se2.h"

namespace asf::sparse_lm {

class MarginalUpdate {
 public:
  /// A new epoch: `m` are the marginals of `g` just computed by `whole.marginals(g, ...)`,
  /// whose factor must stay untouched while the epoch lasts.
  void start(const asf::PoseGraph& g, const asf::Marginals& m);
  void stop() { active_ = false; }
  bool active() const { return active_; }

  /// The marginals of `g`, which must be the epoch's graph plus nodes and edges (the same
  /// gauge and fixed nodes; poses may have moved). False, with `out` untouched, when S or B
  /// would exceed `max_nodes` / `max_touched` or a matrix is not positive definite: then the
  /// caller factorizes the whole graph.
  bool update(const asf::PoseGraph& g, SparseSe2& whole, const Options& o, std::size_t max_nodes,
              std::size_t max_touched, asf::Marginals& out);

  /// Nodes of the epoch's graph the new edges touch (B), in the order of the kept columns.
  const std::vector<asf::NodeId>& touched() const { return touched_; }

 private:
  /// Subtracts Sigma0_oB K Sigma0_Bo from each old free node's block.
  void downdateOld(const Eigen::MatrixXd& K, const std::vector<char>& held,
                   std::vector<Eigen::Matrix3d>& node) const;

  bool active_ = false;
  std::size_t nodes_ = 0, edges_ = 0;    ///< the epoch's graph
  std::vector<Eigen::Matrix3d> blocks_;  ///< its marginals Sigma0_ii
  std::vector<asf::NodeId> touched_;     ///< B
  Eigen::MatrixXd columns_;              ///< Sigma0_{V0, B}: 3 |V0| x 3 |B|
};

}  // namespace asf::sparse_lm
