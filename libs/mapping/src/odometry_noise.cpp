#include <asf/mapping/odometry_noise.h>
#include <asf/params.h>
#include <mrpt/core/bits_math.h>
#include <cmath>

namespace asf::mapping {

using mrpt::poses::CPose2D;

OdometryNoiseModel OdometryNoiseModel::fromParams(const Params& p) {
  OdometryNoiseModel m;
  m.a1 = p.getDouble("odo_a1");
  m.a2 = p.getDouble("odo_a2");
  m.a3 = p.getDouble("odo_a3");
  m.a4 = p.getDouble("odo_a4");
  m.min_std_xy = p.getDouble("odo_min_std_xy");
  m.min_std_phi_deg = p.getDouble("odo_min_std_phi_deg");
  return m;
}

Eigen::Matrix3d OdometryNoiseModel::covariance(const CPose2D& delta) const {
  // MRPT's computeFromOdometry_modelGaussian, written out: it builds two heap-allocated PDFs
  // per call, which a live source pays at every scan. MRPT documents a2, a3 and the minimum
  // heading std in degrees but its formula uses them as radians (its own defaults are written
  // RAD2DEG(0.001), DEG2RAD(1.0), DEG2RAD(0.2)): convert our documented units the same way.
  // The same operations in the same order as MRPT, so the result is MRPT's to the last bit
  // (test_rawlog_io checks it against CActionRobotMovement2D).
  const double a2_rad = mrpt::RAD2DEG(a2), a3_rad = mrpt::DEG2RAD(a3);
  const double min_std_phi = mrpt::DEG2RAD(min_std_phi_deg);
  const double travelled = delta.norm(), turned = std::fabs(delta.phi());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  c(0, 0) = mrpt::square(min_std_xy + a1 * travelled + a2_rad * turned);
  c(1, 1) = mrpt::square(min_std_xy + a1 * travelled + a2_rad * turned);
  c(2, 2) = mrpt::square(min_std_phi + a3_rad * travelled + a4 * turned);
  // The increment's noise is along the half-angle heading: J rotates it by phi / 2 and adds
  // the heading's lever arm.
  const double cos_half = std::cos(delta.phi() / 2), sin_half = std::sin(delta.phi() / 2);
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> j = Eigen::Matrix3d::Zero();
  j(0, 0) = j(1, 1) = cos_half;
  j(0, 1) = -(j(1, 0) = sin_half);
  j(2, 2) = 1;
  j(0, 2) = -sin_half * delta.x() - cos_half * delta.y();
  j(1, 2) = cos_half * delta.x() - sin_half * delta.y();
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c_rm = c;
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> out = (j * c_rm * j.transpose()).eval();
  return out;
}

}  // namespace asf::mapping
