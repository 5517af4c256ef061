// backend_dense_gn: Levenberg-Marquardt on SE(2) pose graphs with analytic Jacobians and
// dense normal equations. Small, exact and slow: the reference and test oracle for the sparse
// back-ends.
#include <asf/backend.h>
#include <asf/errors.h>
#include <asf/se2_edge.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace {

using asf::se2::linearizeEdge;
using Poses = std::vector<Eigen::Vector3d>;

class DenseGnBackend final : public asf::Backend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    max_iterations_ = static_cast<int>(p.getInt("max_iterations"));
    tolerance_ = p.getDouble("tolerance");
    max_nodes_ = static_cast<std::size_t>(p.getInt("max_nodes"));
    lambda_init_ = p.getDouble("lambda_init");
  }

  asf::OptimizeReport optimize(asf::PoseGraph& g) override {
    check(g, "optimize");
    asf::OptimizeReport r;
    Poses x = posesOf(g);
    r.initial_chi2 = r.final_chi2 = chi2(g, x);
    if (!std::isfinite(r.initial_chi2))
      throw asf::Error("dense_gn: the graph's chi2 is not finite (" +
                       std::to_string(r.initial_chi2) +
                       "): a pose, edge or information too large or not finite");
    const Layout L = layout(g);
    if (L.dim == 0 || g.edges.empty()) {
      r.converged = true;
      r.message = "nothing to optimize";
      return r;
    }
    double chi = r.initial_chi2;
    double lambda = lambda_init_;
    bool moved = false;
    r.message = "reached max_iterations";
    for (int it = 0; it < max_iterations_; ++it) {
      if (chi <= 0) {
        r.converged = true;
        r.message = "chi2 is zero";
        break;
      }
      ++r.iterations;
      Eigen::MatrixXd H;
      Eigen::VectorXd b;
      build(g, x, L, H, b);
      double chi_new = chi;
      Poses x_new;
      if (!dampedStep(g, x, L, H, b, chi, lambda, x_new, chi_new)) {
        r.converged = true;
        r.message = "no step decreases chi2 further (lambda " + std::to_string(lambda) + ")";
        break;
      }
      const double rel = (chi - chi_new) / chi;
      x.swap(x_new);
      chi = chi_new;
      moved = true;
      if (rel < tolerance_) {
        r.converged = true;
        r.message = "relative chi2 decrease below tolerance";
        break;
      }
    }
    if (moved) {
      for (std::size_t i = 0; i < x.size(); ++i)
        if (L.index[i] >= 0) g.nodes[i].pose = mrpt::poses::CPose2D(x[i].x(), x[i].y(), x[i].z());
      ++g.revision;
    }
    r.final_chi2 = chi;
    MRPT_LOG_DEBUG_STREAM("dense_gn: chi2 " << r.initial_chi2 << " -> " << r.final_chi2 << " in "
                                            << r.iterations << " iterations (" << r.message
                                            << ")");
    return r;
  }

  asf::Marginals marginals(const asf::PoseGraph& g,
                           const std::vector<std::pair<asf::NodeId, asf::NodeId>>& cross)
      override {
    check(g, "marginals");
    asf::Marginals m;
    m.graph_revision = g.revision;
    const std::size_t n = g.size();
    for (const auto& [i, j] : cross)
      if (i >= n || j >= n)
        throw asf::Error("dense_gn: cross-covariance requested for (" + std::to_string(i) + ", " +
                         std::to_string(j) + ") but the graph has " + std::to_string(n) +
                         " nodes");
    if (n == 0) return m;
    const Layout L = layout(g);
    asf::requireAnchored(g, "dense_gn");
    m.node.assign(n, Eigen::Matrix3d::Zero());
    Eigen::MatrixXd S;  // covariance of the free nodes
    if (L.dim > 0) {
      Eigen::MatrixXd H;
      Eigen::VectorXd b;
      build(g, posesOf(g), L, H, b);
      Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
      const double dmax = ldlt.vectorD().cwiseAbs().maxCoeff();
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * dmax))
        throw asf::Error("dense_gn: the information matrix is singular (degenerate edge "
                         "information?); no covariance defined");
      S = ldlt.solve(Eigen::MatrixXd::Identity(L.dim, L.dim));
      S = 0.5 * (S + S.transpose());
      for (std::size_t i = 0; i < n; ++i)
        if (L.index[i] >= 0) m.node[i] = S.block<3, 3>(L.index[i], L.index[i]);
    }
    for (const auto& [i, j] : cross) {
      Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
      if (L.index[i] >= 0 && L.index[j] >= 0) c = S.block<3, 3>(L.index[i], L.index[j]);
      m.cross[{i, j}] = c;
    }
    return m;
  }

 private:
  struct Layout {
    std::vector<int> index;  ///< node -> first row of its block, -1 for the gauge/fixed nodes
    int dim = 0;
  };

  void check(const asf::PoseGraph& g, const char* what) const {
    if (g.size() > max_nodes_)
      throw asf::Error("dense_gn: " + std::string(what) + " on " + std::to_string(g.size()) +
                       " nodes exceeds max_nodes = " + std::to_string(max_nodes_) +
                       " (dense normal equations cost O(n^2) memory and O(n^3) time); use a "
                       "sparse back-end for graphs this large");
    for (const auto& e : g.edges)
      if (e.from >= g.size() || e.to >= g.size())
        throw asf::Error("dense_gn: edge " + std::to_string(e.from) + " -> " +
                         std::to_string(e.to) + " names a node that does not exist");
    for (asf::NodeId f : g.fixed)
      if (f >= g.size())
        throw asf::Error("dense_gn: fixed node " + std::to_string(f) + " does not exist");
  }

  static Layout layout(const asf::PoseGraph& g) {
    Layout L;
    L.index.assign(g.size(), 0);
    if (!g.empty()) L.index[0] = -1;
    for (asf::NodeId f : g.fixed) L.index[f] = -1;
    for (auto& i : L.index)
      if (i == 0) {
        i = L.dim;
        L.dim += 3;
      }
    return L;
  }

  static Poses posesOf(const asf::PoseGraph& g) {
    Poses x(g.size());
    for (std::size_t i = 0; i < g.size(); ++i)
      x[i] = {g.nodes[i].pose.x(), g.nodes[i].pose.y(), g.nodes[i].pose.phi()};
    return x;
  }

  static double chi2(const asf::PoseGraph& g, const Poses& x) {
    double c = 0;
    for (const auto& e : g.edges) {
      const Eigen::Vector3d z(e.mean.x(), e.mean.y(), e.mean.phi());
      const Eigen::Vector3d r = asf::se2::edgeError(x[e.from], x[e.to], z);
      c += r.dot(e.information * r);
    }
    return c;
  }

  /// Damps the normal equations (H, b) at x (Marquardt scaling, tenfold more after each
  /// failure, at most 12 tries) until a step lowers chi2 below `chi`: then x_new, chi_new, a
  /// tenfold lower lambda, and true; false if none did.
  static bool dampedStep(const asf::PoseGraph& g, const Poses& x, const Layout& L,
                         const Eigen::MatrixXd& H, const Eigen::VectorXd& b, double chi,
                         double& lambda, Poses& x_new, double& chi_new) {
    Eigen::VectorXd D = H.diagonal().cwiseMax(1e-9 * std::max(1.0, H.diagonal().maxCoeff()));
    for (int attempt = 0; attempt < 12; ++attempt) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * D;
      Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
      if (ldlt.info() == Eigen::Success) {
        const Eigen::VectorXd dx = ldlt.solve(-b);
        if (dx.allFinite()) {
          x_new = x;
          for (std::size_t i = 0; i < x.size(); ++i) {
            if (L.index[i] < 0) continue;
            x_new[i] += dx.segment<3>(L.index[i]);
            x_new[i].z() = asf::se2::wrapAngle(x_new[i].z());
          }
          chi_new = chi2(g, x_new);
          if (chi_new < chi) {
            lambda /= 10;
            return true;
          }
        }
      }
      lambda = std::max(lambda * 10, 1e-9);
    }
    return false;
  }

  /// H = sum J^T Omega J, b = sum J^T Omega e over the free nodes.
  static void build(const asf::PoseGraph& g, const Poses& x, const Layout& L,
                    Eigen::MatrixXd& H, Eigen::VectorXd& b) {
    H.setZero(L.dim, L.dim);
    b.setZero(L.dim);
    for (const auto& e : g.edges) {
      const Eigen::Vector3d z(e.mean.x(), e.mean.y(), e.mean.phi());
      const auto lin = linearizeEdge(x[e.from], x[e.to], z);
      const int a = L.index[e.from], c = L.index[e.to];
      const Eigen::Matrix3d& W = e.information;
      if (a >= 0) {
        H.block<3, 3>(a, a) += lin.Ji.transpose() * W * lin.Ji;
        b.segment<3>(a) += lin.Ji.transpose() * W * lin.e;
      }
      if (c >= 0) {
        H.block<3, 3>(c, c) += lin.Jj.transpose() * W * lin.Jj;
        b.segment<3>(c) += lin.Jj.transpose() * W * lin.e;
      }
      if (a >= 0 && c >= 0) {
        const Eigen::Matrix3d Hac = lin.Ji.transpose() * W * lin.Jj;
        H.block<3, 3>(a, c) += Hac;
        H.block<3, 3>(c, a) += Hac.transpose();
      }
    }
  }

  int max_iterations_ = 50;
  double tolerance_ = 1e-9;
  std::size_t max_nodes_ = 1000;
  double lambda_init_ = 1e-4;
};

const asf::KeySpec kKeys[] = {
    asf::keyInt("max_iterations", "50", "Maximum Levenberg-Marquardt iterations", 1, 100000),
    asf::keyDouble("tolerance", "1e-9",
                   "Stop when an iteration decreases chi2 by less than this fraction", 0, 1),
    asf::keyInt("max_nodes", "1000",
                "Refuse larger graphs (dense: O(n^2) memory, O(n^3) time per iteration)", 1,
                100000),
    asf::keyDouble("lambda_init", "1e-4",
                   "Initial damping, relative to the diagonal of the normal matrix", 0, 1e10),
};

}  // namespace

ASF_PLUGIN(DenseGnBackend, asf::PluginKind::Backend, "dense_gn", "1.0.0",
           "Levenberg-Marquardt on SE(2) with dense normal equations (reference, small graphs)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
