// Covariances from the sparse_lm back-end's factor (see sparse_se2.h): the marginals (the sparse
// inverse subset; columns solved for cross blocks outside its pattern), columns of the inverse
// (for marginal_update.cpp) and the bound b^T H0^-1 b on the decrease of chi2.
#include "sparse_se2.h"

#include <asf/errors.h>
#include <asf/se2_edge.h>
#include <cholmod.h>

#include <Eigen/Dense>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sparse_inverse.h"
#include "sparse_problem.h"
#include "sparse_se2_impl.h"

namespace asf::sparse_lm {

using namespace detail;

using asf::NodeId;

std::optional<double> SparseSe2::Impl::decrementBound(const asf::PoseGraph& g, const Options& o) {
  if (!L || !factor_valid || S.free.size() > g.size()) return std::nullopt;
  const std::vector<char> held = Structure::heldNodes(g);
  for (std::size_t i = 0; i < S.free.size(); ++i)
    if ((S.free[i] < 0) != (held[i] != 0)) return std::nullopt;  // gauge or fixed set changed
  const SerialOpenMp serial(!o.cholmod_openmp);
  const Problem P(g, o);
  const Poses x = posesOf(g);
  const int known = static_cast<int>(S.free.size());
  std::vector<double> rhs(S.dim(), 0.0);  // J^T W e over the factor's free nodes
  for (const auto& e : P.edges) {
    const int a = e.from < known ? S.free[e.from] : -1, c = e.to < known ? S.free[e.to] : -1;
    if (a < 0 && c < 0) continue;
    const auto lin = asf::se2::linearizeEdge(x[e.from], x[e.to], e.z);
    const Eigen::Matrix3d W = robustWeight(e.kernel, o.robust_delta, lin.e.dot(e.W * lin.e)) * e.W;
    const Eigen::Vector3d We = W * lin.e;
    if (a >= 0 && a == c) {
      Eigen::Map<Eigen::Vector3d>(&rhs[3 * a]) += (lin.Ji + lin.Jj).transpose() * We;
      continue;
    }
    if (a >= 0) Eigen::Map<Eigen::Vector3d>(&rhs[3 * a]) += lin.Ji.transpose() * We;
    if (c >= 0) Eigen::Map<Eigen::Vector3d>(&rhs[3 * c]) += lin.Jj.transpose() * We;
  }
  const std::vector<double> h = solve(rhs, 1);
  double bound = 0;
  for (std::size_t k = 0; k < rhs.size(); ++k) bound += rhs[k] * h[k];
  return bound;
}

asf::Marginals SparseSe2::Impl::marginals(const asf::PoseGraph& g,
                                          const std::vector<std::pair<NodeId, NodeId>>& cross,
                                          const Options& o) {
  validate(g);
  const SerialOpenMp serial(!o.cholmod_openmp);
  last_cross_solved = 0;
  asf::Marginals m;
  m.graph_revision = g.revision;
  const std::size_t n = g.size();
  for (const auto& [i, j] : cross)
    if (i >= n || j >= n)
      throw asf::Error("sparse_lm: cross-covariance requested for (" + std::to_string(i) + ", " +
                       std::to_string(j) + ") but the graph has " + std::to_string(n) + " nodes");
  if (n == 0) return m;
  Structure S_new = Structure::of(g);
  asf::requireAnchored(g, "sparse_lm");
  m.node.assign(n, Eigen::Matrix3d::Zero());
  for (const auto& ij : cross) m.cross[ij] = Eigen::Matrix3d::Zero();
  if (S_new.nfree == 0) return m;

  prepare(std::move(S_new), o);
  const Problem P(g, o);
  linearize(P, posesOf(g), o);
  if (!factorize(H))
    throw asf::Error(
        "sparse_lm: the information matrix is not positive definite (degenerate "
        "edge information?); no covariance defined");
  std::unique_ptr<SparseInverse> inverse;
  {
    const Timer timer(counters.t_inverse);
    inverse = std::make_unique<SparseInverse>(L);
  }
  const SparseInverse& Sigma = *inverse;
  for (std::size_t i = 0; i < n; ++i) {
    const int f = S.free[i];
    if (f < 0) continue;
    Eigen::Matrix3d B;
    if (!Sigma.block(f, f, B))
      throw asf::Error("sparse_lm: internal error: diagonal block outside the factor");
    m.node[i] = 0.5 * (B + B.transpose());
  }

  // Cross blocks: from the sparse inverse when inside L's pattern (always the case for the
  // two ends of an edge), otherwise from columns of H^-1 solved with the factor.
  std::map<int, std::vector<std::pair<NodeId, NodeId>>> by_column;  // free col -> requests
  for (const auto& ij : cross) {
    const int fi = S.free[ij.first], fj = S.free[ij.second];
    if (fi < 0 || fj < 0) continue;  // a held node has no variance
    Eigen::Matrix3d B;
    if (Sigma.block(fi, fj, B))
      m.cross[ij] = B;
    else
      by_column[fj].push_back(ij);
  }
  std::vector<int> cols;
  for (const auto& [f, requests] : by_column) cols.push_back(f);
  const Eigen::MatrixXd X = columns(cols);
  std::size_t k = 0;
  for (const auto& [f, requests] : by_column) {
    for (const auto& ij : requests) {
      m.cross[ij] = X.block<3, 3>(3 * S.free[ij.first], 3 * k);
      ++last_cross_solved;
    }
    ++k;
  }
  return m;
}

Eigen::MatrixXd SparseSe2::covarianceColumns(const std::vector<NodeId>& nodes, const Options& o) {
  Impl& m = *impl_;
  const std::size_t known = factorNodes();
  std::vector<int> cols;
  for (NodeId v : nodes) {
    if (v >= known || m.S.free[v] < 0)
      throw asf::Error("sparse_lm: internal error: covariance column of a node outside the factor");
    cols.push_back(m.S.free[v]);
  }
  const SerialOpenMp serial(!o.cholmod_openmp);
  const Eigen::MatrixXd X = m.columns(cols);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3 * known, X.cols());
  for (std::size_t i = 0; i < known; ++i)
    if (m.S.free[i] >= 0) out.middleRows(3 * i, 3) = X.middleRows(3 * m.S.free[i], 3);
  return out;
}

}  // namespace asf::sparse_lm
