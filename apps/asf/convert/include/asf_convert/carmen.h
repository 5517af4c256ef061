#pragma once
/// \file carmen.h
/// CARMEN text logs (.log / .clf, optionally .gz) -> observation-only MRPT rawlogs.
///
/// Lines used (fields separated by spaces; every message ends with
/// `ipc_timestamp ipc_hostname logger_timestamp`):
/// - `FLASER n r1..rn x y theta odom_x odom_y odom_theta ...`: front laser; x y theta is the
///   laser pose (the corrected pose in "corrected" logs), odom_* the robot's odometry;
/// - `ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode n r1..rn
///   m e1..em laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv fsd ssd turn_axis
///   ...`;
/// - `ODOM x y theta tv rv accel ...`;
/// - `PARAM name value ...`: robot_frontlaser_offset, robot_front_laser_max,
///   laser_front_laser_fov, laser_front_laser_resolution change how FLASER lines are read.
/// Other messages and `#` comments are skipped (counted per message name).
#include <asf/rawlog_io.h>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>

namespace asf::convert {

struct CarmenToRawlogOptions {
  std::string input;      ///< CARMEN log, ".gz" gunzipped
  std::string output;     ///< .rawlog or .rawlog.gz
  std::string gt_output;  ///< asf ground-truth file of the laser poses; empty: none

  enum class Odometry {
    Laser,      ///< the odometry pose carried by each laser line (odom_* / robot_*)
    OdomLines,  ///< the ODOM lines (those going back in time are dropped and counted)
    Synthetic,  ///< integrated noisy increments of the logged laser poses (see below)
  };
  Odometry odometry = Odometry::Laser;
  /// Synthetic: each increment d between consecutive logged robot poses gets Gaussian noise
  /// with covariance model.covariance(d), drawn from std::mt19937_64(seed); the odometry
  /// starts at the first logged pose.
  OdometryNoiseModel model;
  std::uint64_t seed = 1;

  /// FLASER field of view [deg]; 0: PARAM laser_front_laser_fov, else n times PARAM
  /// laser_front_laser_resolution (MRPT's rule), else 180.
  double fov_deg = 0;
  /// FLASER maximum range [m]; 0: PARAM robot_front_laser_max, else 80. Ranges outside
  /// (0, max) are invalid.
  double max_range = 0;
  bool skip_bad_lines = false;
  std::ostream* progress = nullptr;
};

struct CarmenToRawlogReport {
  std::size_t lines = 0, scans = 0, odometry = 0, gt_poses = 0;
  std::size_t bad_lines = 0, first_bad_line = 0;
  std::string first_bad_reason;
  /// Laser lines whose timestamp went back in time: raised to just after the previous one
  /// (log order is kept).
  std::size_t raised_timestamps = 0;
  std::size_t odom_dropped = 0;  ///< ODOM lines going back in time (OdomLines mode)
  std::string laser_message;     ///< FLASER or ROBOTLASER1 (the first one seen)
  double aperture_deg = 0;       ///< of the first scan
  std::size_t rays = 0;          ///< of the first scan
  std::map<std::string, std::size_t> ignored;  ///< message name -> lines skipped
  double wall_time_s = 0;
};

CarmenToRawlogReport carmenToRawlog(const CarmenToRawlogOptions& opt);

}  // namespace asf::convert
