#pragma once
/// \file sensor_frame.h
/// One step of a robot's data: what a source produces.
#include <Eigen/Core>
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <optional>
#include <vector>

namespace mrpt::obs {
class CObservation;
class CObservation2DRangeScan;
}

namespace asf {

struct SensorFrame {
  /// Seconds (any epoch, increasing along a stream).
  double timestamp = 0;
  /// Odometry increment since the previous frame, in the robot frame of the previous frame.
  mrpt::poses::CPose2D odometry;
  /// Covariance of `odometry` (x, y, phi).
  Eigen::Matrix3d odometry_cov = Eigen::Matrix3d::Zero();
  /// The 2D laser scan of this step, or null when the step has none. Its sensorPose is the
  /// laser's pose on the robot.
  std::shared_ptr<const mrpt::obs::CObservation2DRangeScan> scan;
  /// Observations of this step for the 3D map (asf/mapping/map3d.h): point clouds, Velodyne scans,
  /// 3D range scans, tilted 2D scans. Each one's sensorPose is the sensor's pose on the
  /// robot. Empty for a robot without 3D sensors.
  std::vector<std::shared_ptr<const mrpt::obs::CObservation>> observations3d;
  /// True pose in the world frame, when the source knows it (simulators, logs with GT).
  std::optional<mrpt::poses::CPose2D> ground_truth;
};

}  // namespace asf
