#pragma once
/// \file se2_edge.h
/// Error and analytic Jacobians of one SE(2) relative-pose edge, shared by the SE(2)
/// back-ends (dense_gn, sparse_lm) and their tests. Header-only.
///
/// Poses are (x, y, theta) in the global frame; updates are additive on (x, y, theta).
/// With Ri, Rz the rotations of pose i and of the measurement z:
///   e_t     = Rz^T (Ri^T (t_j - t_i) - t_z)
///   e_theta = wrap(theta_j - theta_i - theta_z)
/// which is t2v(z^-1 (+) (x_i^-1 (+) x_j)), the convention of asf::PoseGraph::edgeError.
#include <Eigen/Core>

#include <cmath>

namespace asf::se2 {

/// a wrapped to [-pi, pi).
inline double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a < 0) a += 2 * M_PI;
  return a - M_PI;
}

struct EdgeLinearization {
  Eigen::Vector3d e;
  Eigen::Matrix3d Ji;  ///< d e / d x_i
  Eigen::Matrix3d Jj;  ///< d e / d x_j
};

inline Eigen::Vector3d edgeError(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                 const Eigen::Vector3d& z) {
  const double ci = std::cos(xi.z()), si = std::sin(xi.z());
  const double cz = std::cos(z.z()), sz = std::sin(z.z());
  const double dx = xj.x() - xi.x(), dy = xj.y() - xi.y();
  // Ri^T (t_j - t_i) - t_z
  const double ax = ci * dx + si * dy - z.x();
  const double ay = -si * dx + ci * dy - z.y();
  return {cz * ax + sz * ay, -sz * ax + cz * ay, wrapAngle(xj.z() - xi.z() - z.z())};
}

inline EdgeLinearization linearizeEdge(const Eigen::Vector3d& xi, const Eigen::Vector3d& xj,
                                       const Eigen::Vector3d& z) {
  EdgeLinearization L;
  L.e = edgeError(xi, xj, z);
  const double ci = std::cos(xi.z()), si = std::sin(xi.z());
  const double cz = std::cos(z.z()), sz = std::sin(z.z());
  const double dx = xj.x() - xi.x(), dy = xj.y() - xi.y();
  Eigen::Matrix2d RzT, RiT, dRiT;
  RzT << cz, sz, -sz, cz;
  RiT << ci, si, -si, ci;
  dRiT << -si, ci, -ci, -si;  // d(Ri^T)/d theta_i
  const Eigen::Matrix2d A = RzT * RiT;
  const Eigen::Vector2d dth = RzT * dRiT * Eigen::Vector2d(dx, dy);
  L.Ji.setZero();
  L.Ji.topLeftCorner<2, 2>() = -A;
  L.Ji.block<2, 1>(0, 2) = dth;
  L.Ji(2, 2) = -1;
  L.Jj.setZero();
  L.Jj.topLeftCorner<2, 2>() = A;
  L.Jj(2, 2) = 1;
  return L;
}

}  // namespace asf::se2
