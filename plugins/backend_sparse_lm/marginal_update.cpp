// Marginals updated from the last whole factorization: see marginal_update.h.
#include "marginal_update.h"

#include <asf/se2_edge.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "sparse_problem.h"

namespace asf::sparse_lm {

using asf::NodeId;

namespace {

/// Adds the information J^T W J of P's edges at g's poses to Lambda, where the rows of node v
/// start at pos[v] (-1: not in Lambda).
void addEdgeInformation(const asf::PoseGraph& g, const detail::Problem& P,
                        const std::vector<int>& pos, const Options& o, Eigen::MatrixXd& Lambda) {
  auto pose = [&](int v) -> Eigen::Vector3d {
    const auto& p = g.nodes[v].pose;
    return {p.x(), p.y(), p.phi()};
  };
  for (const auto& e : P.edges) {
    const auto lin = asf::se2::linearizeEdge(pose(e.from), pose(e.to), e.z);
    const Eigen::Matrix3d W = robustWeight(e.kernel, o.robust_delta, lin.e.dot(e.W * lin.e)) * e.W;
    const int a = pos[e.from], c = pos[e.to];
    if (e.from == e.to) {
      if (a < 0) continue;
      const Eigen::Matrix3d J = lin.Ji + lin.Jj;
      Lambda.block<3, 3>(a, a) += J.transpose() * W * J;
      continue;
    }
    if (a >= 0) Lambda.block<3, 3>(a, a) += lin.Ji.transpose() * W * lin.Ji;
    if (c >= 0) Lambda.block<3, 3>(c, c) += lin.Jj.transpose() * W * lin.Jj;
    if (a >= 0 && c >= 0) {
      const Eigen::Matrix3d off = lin.Ji.transpose() * W * lin.Jj;
      Lambda.block<3, 3>(a, c) += off;
      Lambda.block<3, 3>(c, a) += off.transpose();
    }
  }
}

}  // namespace

void MarginalUpdate::start(const asf::PoseGraph& g, const asf::Marginals& m) {
  active_ = m.node.size() == g.size();
  nodes_ = g.size();
  edges_ = g.edges.size();
  blocks_ = m.node;
  touched_.clear();
  columns_.resize(3 * nodes_, 0);
}

bool MarginalUpdate::update(const asf::PoseGraph& g, SparseSe2& whole, const Options& o,
                            std::size_t max_nodes, std::size_t max_touched, asf::Marginals& out) {
  if (!active_ || g.size() < nodes_ || g.edges.size() < edges_) return false;
  const std::vector<char> held = detail::Structure::heldNodes(g);
  std::vector<std::size_t> added(g.edges.size() - edges_);
  for (std::size_t k = 0; k < added.size(); ++k) added[k] = edges_ + k;
  const detail::Problem P(g, added, o);

  // B grows over the epoch; the columns of its nodes are solved once each.
  std::vector<NodeId> missing;
  for (const auto& e : P.edges)
    for (const int v : {e.from, e.to})
      if (static_cast<std::size_t>(v) < nodes_ && !held[v] &&
          std::find(touched_.begin(), touched_.end(), v) == touched_.end() &&
          std::find(missing.begin(), missing.end(), v) == missing.end())
        missing.push_back(static_cast<NodeId>(v));
  std::vector<NodeId> fresh;  // N: the free nodes added since the epoch
  for (std::size_t v = nodes_; v < g.size(); ++v)
    if (!held[v]) fresh.push_back(static_cast<NodeId>(v));
  const std::size_t nb = touched_.size() + missing.size();
  if (nb > max_touched || nb + fresh.size() > max_nodes) return false;
  if (!missing.empty()) {
    if (whole.factorNodes() != nodes_) return false;  // the kept factor is gone
    const Eigen::MatrixXd X = whole.covarianceColumns(missing, o);
    columns_.conservativeResize(Eigen::NoChange, 3 * nb);
    columns_.rightCols(X.cols()) = X;
    touched_.insert(touched_.end(), missing.begin(), missing.end());
  }

  // Lambda_S over S = B then N.
  const int sb = static_cast<int>(3 * nb), dim = sb + static_cast<int>(3 * fresh.size());
  std::vector<int> pos(g.size(), -1);
  for (std::size_t i = 0; i < nb; ++i) pos[touched_[i]] = static_cast<int>(3 * i);
  for (std::size_t k = 0; k < fresh.size(); ++k) pos[fresh[k]] = sb + static_cast<int>(3 * k);
  Eigen::MatrixXd S0(sb, sb);
  for (std::size_t i = 0; i < nb; ++i)
    S0.middleRows(3 * i, 3) = columns_.middleRows(3 * touched_[i], 3);
  S0 = 0.5 * (S0 + S0.transpose()).eval();
  const Eigen::LLT<Eigen::MatrixXd> s0(S0);
  if (s0.info() != Eigen::Success) return false;
  const Eigen::MatrixXd S0inv = s0.solve(Eigen::MatrixXd::Identity(sb, sb));
  Eigen::MatrixXd Lambda = Eigen::MatrixXd::Zero(dim, dim);
  Lambda.topLeftCorner(sb, sb) = S0inv;
  addEdgeInformation(g, P, pos, o, Lambda);
  const Eigen::LLT<Eigen::MatrixXd> lambda(Lambda);
  if (lambda.info() != Eigen::Success) return false;
  const Eigen::MatrixXd Sigma = lambda.solve(Eigen::MatrixXd::Identity(dim, dim));

  out.node = blocks_;  // the new nodes' blocks are set below, held ones stay zero
  out.node.resize(g.size(), Eigen::Matrix3d::Zero());
  if (nb > 0) {
    const Eigen::MatrixXd K = S0inv * (S0 - Sigma.topLeftCorner(sb, sb)) * S0inv;
    downdateOld(0.5 * (K + K.transpose()), held, out.node);
  }
  for (std::size_t v = 0; v < g.size(); ++v)
    if (pos[v] >= 0) out.node[v] = Sigma.block<3, 3>(pos[v], pos[v]);
  for (auto& b : out.node) b = 0.5 * (b + b.transpose()).eval();
  out.cross.clear();
  out.graph_revision = g.revision;
  return true;
}

void MarginalUpdate::downdateOld(const Eigen::MatrixXd& K, const std::vector<char>& held,
                                 std::vector<Eigen::Matrix3d>& node) const {
  // Sigma0_oo - Sigma0_oB K Sigma0_Bo with K = R R^T from K's eigenvectors: its rank is that
  // of the information the new edges add to B, usually far below 3 |B|.
  const int sb = static_cast<int>(K.rows());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K);
  const Eigen::VectorXd& ev = eig.eigenvalues();  // ascending
  const double floor = 1e-12 * std::max(ev(sb - 1), 0.0);
  int r = 0;
  while (r < sb && ev(sb - 1 - r) > floor) ++r;
  Eigen::MatrixXd R = eig.eigenvectors().rightCols(r);
  for (int k = 0; k < r; ++k) R.col(k) *= std::sqrt(ev(sb - r + k));
  const Eigen::MatrixXd Q = columns_ * R;  // 3 |V0| x r
  for (std::size_t i = 0; i < nodes_; ++i) {
    if (held[i]) continue;
    const auto q = Q.middleRows(3 * i, 3);
    node[i] -= q * q.transpose();
  }
}

}  // namespace asf::sparse_lm
