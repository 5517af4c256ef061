#pragma once
// Private to backend_sparse_lm: the sparse inverse subset of a CHOLMOD supernodal factor,
// for the marginal covariances (sparse_se2_marginals.cpp).
#include <asf/errors.h>
#include <cholmod.h>

#include <Eigen/Dense>
#include <algorithm>
#include <vector>

namespace asf::sparse_lm::detail {

/// The sparse inverse subset of a supernodal LL^T factor: Sigma = (L L^T)^-1 on the pattern
/// of L, stored in L's own layout (one dense rows-by-columns block per supernode).
///
/// For a supernode with columns J and remaining rows R (L_JJ lower triangular, L_RJ below),
/// L^T Sigma = L^-1 (upper part zero, diagonal block L_JJ^-1) gives, with U = L_RJ L_JJ^-1,
///   Sigma_RJ = -Sigma_RR U,   Sigma_JJ = (L_JJ L_JJ^T)^-1 - U^T Sigma_RJ.
/// Sigma_RR lies in later supernodes and inside the pattern: the rows R of a supernode are a
/// clique of L's graph (the numeric factorization scatters L_RJ L_RJ^T there), so the
/// recursion, run from the last supernode to the first, never leaves the pattern.
class SparseInverse {
 public:
  explicit SparseInverse(const cholmod_factor* L) : L_(L) {
    if (!L->is_super || L->xtype != CHOLMOD_REAL)
      throw asf::Error("sparse_lm: internal error: expected a real supernodal factor");
    n_ = static_cast<int>(L->n);
    ns_ = static_cast<int>(L->nsuper);
    super_ = static_cast<const int*>(L->super);
    pi_ = static_cast<const int*>(L->pi);
    px_ = static_cast<const int*>(L->px);
    s_ = static_cast<const int*>(L->s);
    const int* perm = static_cast<const int*>(L->Perm);
    inv_perm_.resize(n_);
    for (int k = 0; k < n_; ++k) inv_perm_[perm[k]] = k;
    col2super_.resize(n_);
    for (int t = 0; t < ns_; ++t) {
      for (int c = super_[t]; c < super_[t + 1]; ++c) col2super_[c] = t;
      for (int p = pi_[t] + 1; p < pi_[t + 1]; ++p)
        if (s_[p] <= s_[p - 1])
          throw asf::Error("sparse_lm: internal error: unsorted supernode rows");
    }
    compute();
  }

  /// Sigma(a, b) for scalar indices of the original (unpermuted) matrix, or nullptr if the
  /// entry is outside the pattern of L.
  const double* entry(int a, int b) const {
    const int p = inv_perm_[a], q = inv_perm_[b];
    const int row = std::max(p, q), col = std::min(p, q);
    const int t = col2super_[col];
    const int nrows = pi_[t + 1] - pi_[t], ct = col - super_[t];
    const int* rows = s_ + pi_[t];
    const int* it = std::lower_bound(rows + ct, rows + nrows, row);
    if (it == rows + nrows || *it != row) return nullptr;
    return &x_[px_[t] + static_cast<std::size_t>(ct) * nrows + (it - rows)];
  }

  /// The 3x3 block of scalar rows 3i.., columns 3j..; false if outside the pattern.
  bool block(int i, int j, Eigen::Matrix3d& out) const {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        const double* v = entry(3 * i + r, 3 * j + c);
        if (!v) return false;
        out(r, c) = *v;
      }
    return true;
  }

 private:
  void compute() {
    const double* Lx = static_cast<const double*>(L_->x);
    x_.assign(L_->xsize, 0.0);
    for (int t = ns_ - 1; t >= 0; --t) {
      const int nc = super_[t + 1] - super_[t];
      const int nrows = pi_[t + 1] - pi_[t];
      const int nr = nrows - nc;
      const Eigen::Map<const Eigen::MatrixXd> Lt(Lx + px_[t], nrows, nc);
      const Eigen::MatrixXd Linv =
          Lt.topRows(nc).triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(nc, nc));
      Eigen::Map<Eigen::MatrixXd> St(x_.data() + px_[t], nrows, nc);
      if (nr == 0) {
        St = Linv.transpose() * Linv;
        continue;
      }
      const Eigen::MatrixXd U = Lt.bottomRows(nr) * Linv;
      const int* R = s_ + pi_[t] + nc;
      Eigen::MatrixXd Srr(nr, nr);
      for (int q = 0; q < nr; ++q) {
        const int col = R[q];
        const int u = col2super_[col];
        const int nrows_u = pi_[u + 1] - pi_[u], cu = col - super_[u];
        const int* rows_u = s_ + pi_[u];
        const double* vals = x_.data() + px_[u] + static_cast<std::size_t>(cu) * nrows_u;
        int pos = cu;  // rows_u[cu] == col
        Srr(q, q) = vals[pos];
        for (int p = q + 1; p < nr; ++p) {
          while (pos < nrows_u && rows_u[pos] < R[p]) ++pos;
          if (pos == nrows_u || rows_u[pos] != R[p])
            throw asf::Error("sparse_lm: internal error: supernode rows are not a clique");
          Srr(p, q) = Srr(q, p) = vals[pos];
        }
      }
      St.bottomRows(nr).noalias() = -Srr * U;
      St.topRows(nc) = Linv.transpose() * Linv;
      St.topRows(nc).noalias() -= U.transpose() * St.bottomRows(nr);
    }
  }

  const cholmod_factor* L_;
  int n_ = 0, ns_ = 0;
  const int *super_, *pi_, *px_, *s_;
  std::vector<int> inv_perm_, col2super_;
  std::vector<double> x_;
};

}  // namespace asf::sparse_lm::detail
