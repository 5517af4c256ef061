// Quality gates and search windows of the icp_graph front-end (match_gates.h).
#include "match_gates.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace asf::icp_graph {

bool sigmasOk(const Eigen::Matrix3d& C, const MatchGates& g) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
  return es.eigenvalues()(1) <= g.max_sigma_xy * g.max_sigma_xy &&
         C(2, 2) <= g.max_sigma_phi * g.max_sigma_phi;
}

std::string sequentialGateFailure(const MatchResult& m, const mrpt::poses::CPose2D& odo,
                                  const Eigen::Matrix3d& odo_cov, double min_goodness,
                                  const MatchGates& g) {
  if (!m.ran) return m.reason.empty() ? "no alignment" : m.reason;
  std::ostringstream os;
  if (static_cast<int>(m.iterations) >= g.max_iterations)
    os << "ICP did not converge in " << m.iterations << " iterations";
  else if (m.goodness < min_goodness)
    os << "goodness " << m.goodness << " < " << min_goodness;
  else if (!sigmasOk(m.cov, g))
    os << "ill-conditioned alignment (sigmas " << std::sqrt(m.cov(0, 0)) << ", "
       << std::sqrt(m.cov(1, 1)) << ", " << std::sqrt(m.cov(2, 2)) << ")";
  else {
    const Eigen::Vector3d d = poseDiff(m.pose, odo);
    const Eigen::Matrix3d C = odo_cov + g.odo_floor + m.cov + g.icp_floor;
    const double chi2 = d.dot(C.ldlt().solve(d));
    if (!(chi2 <= g.odometry_chi2)) os << "disagrees with odometry: chi2 " << chi2;
  }
  return os.str();
}

std::string loopGateFailure(const MatchResult& m, const mrpt::poses::CPose2D& est,
                            const std::optional<Eigen::Matrix3d>& Crel, const MatchGates& g,
                            double* chi2) {
  std::ostringstream why;
  if (m.goodness < g.loop_min_goodness)
    why << "goodness " << m.goodness;
  else if (m.inlier_ratio < g.loop_min_inliers)
    why << "inlier ratio " << m.inlier_ratio;
  else if (m.rmse > g.loop_max_rmse)
    why << "rmse " << m.rmse;
  else if (!sigmasOk(m.cov, g))
    why << "ill-conditioned alignment";
  else if (!Crel)
    why << "no covariance for the relative pose";
  else {
    const Eigen::Vector3d d = poseDiff(m.pose, est);
    const double c = d.dot((*Crel + m.cov + g.icp_floor).ldlt().solve(d));
    if (chi2) *chi2 = c;
    if (!(c <= g.loop_chi2)) why << "chi2 " << c << " > " << g.loop_chi2;
  }
  return why.str();
}

SearchWindow windowCovering(const Eigen::Matrix3d& C, double sigmas, double min_xy, double max_xy,
                            double min_phi, double max_phi) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
  const double sxy = std::sqrt(std::max(0.0, es.eigenvalues()(1)));
  const double sphi = std::sqrt(std::max(0.0, C(2, 2)));
  return {std::clamp(sigmas * sxy, min_xy, std::max(min_xy, max_xy)),
          std::clamp(sigmas * sphi, min_phi, std::max(min_phi, max_phi))};
}

}  // namespace asf::icp_graph
