#include <asf/mapping/odometry_noise.h>
#include <asf/params.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/obs/CActionRobotMovement2D.h>

namespace asf::mapping {

using mrpt::obs::CActionRobotMovement2D;
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
  CActionRobotMovement2D::TMotionModelOptions o;
  o.modelSelection = CActionRobotMovement2D::mmGaussian;
  // MRPT documents these fields in degrees but its formula uses them with radians (its own
  // defaults are written RAD2DEG(0.001), DEG2RAD(1.0), DEG2RAD(0.2)): convert our documented
  // units the same way.
  o.gaussianModel.a1 = a1;
  o.gaussianModel.a2 = mrpt::RAD2DEG(a2);  // m/deg -> m/rad
  o.gaussianModel.a3 = mrpt::DEG2RAD(a3);  // deg/m -> rad/m
  o.gaussianModel.a4 = a4;                 // deg/deg == rad/rad
  o.gaussianModel.minStdXY = min_std_xy;
  o.gaussianModel.minStdPHI = mrpt::DEG2RAD(min_std_phi_deg);
  CActionRobotMovement2D act;
  act.computeFromOdometry(delta, o);
  mrpt::math::CMatrixDouble33 cov;
  CPose2D mean;
  act.poseChange->getCovarianceAndMean(cov, mean);
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) out(r, k) = cov(r, k);
  return out;
}

}  // namespace asf::mapping
