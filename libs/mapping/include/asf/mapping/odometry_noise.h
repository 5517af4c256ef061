#pragma once
/// \file odometry_noise.h
/// The covariance of an odometry increment, for logs and simulators that carry none.
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>

namespace asf {
class Params;
}  // namespace asf

namespace asf::mapping {

/// MRPT's Gaussian odometry model (CActionRobotMovement2D::TMotionModelOptions, mmGaussian):
/// the covariance of an odometry increment grows with the distance and angle travelled.
/// Units as in MRPT: a1 [m/m], a2 [m/deg], a3 [deg/m], a4 [deg/deg]; minimum stds in m, deg.
struct OdometryNoiseModel {
  double a1 = 0.01, a2 = 0.001, a3 = 1.0, a4 = 0.05;
  double min_std_xy = 0.01, min_std_phi_deg = 0.2;
  /// Covariance (x, y, phi) of the increment `delta`: MRPT's motion model, written out.
  Eigen::Matrix3d covariance(const mrpt::poses::CPose2D& delta) const;
  /// The model of a source's section: its keys odo_a1 .. odo_a4, odo_min_std_xy,
  /// odo_min_std_phi_deg (each source's key table documents them).
  static OdometryNoiseModel fromParams(const Params& p);
};

}  // namespace asf::mapping
