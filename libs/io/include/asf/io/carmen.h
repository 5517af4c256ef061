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
#include <asf/io/rawlog_io.h>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace asf::io {

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
  mapping::OdometryNoiseModel model;
  std::uint64_t seed = 1;

  /// FLASER field of view [deg]; 0: PARAM laser_front_laser_fov, else n times PARAM
  /// laser_front_laser_resolution (MRPT's rule; n - 1 times, the span of rays that far
  /// apart, measured no better on freiburg-079: docs/DATASETS.md), else 180. The PARAM
  /// angles are in degrees (CARMEN's laser module); a fov of at most 2 pi (e.g. csail's
  /// 3.14159) is implausible in degrees: read as radians, with a warning.
  double fov_deg = 0;
  /// FLASER maximum range [m]; 0: PARAM robot_front_laser_max, else 80. Ranges outside
  /// (0, max) are invalid.
  double max_range = 0;

  /// Where the scans' timestamps come from. Real corrected logs have all scans stamped alike
  /// (csail, orebro: precision lost), negative or wrapped stamps (infinite-corridor).
  enum class Timestamps {
    Auto,   ///< Log when the log's laser stamps are usable (see below), else Order
    Log,    ///< the ipc_timestamp of each laser line; a bad one is a bad line
    Order,  ///< the log's order: scan i at (i + 1) * scan_period_s
  };
  /// Auto reads the log twice: its laser stamps are usable when every one is a time in
  /// seconds (>= 0) and at most 10% of them are not after the one before (those are raised
  /// to 1 us after it, as in Log; intel-corrected has 4 of 910).
  Timestamps timestamps = Timestamps::Auto;
  /// Order: seconds between scans; 0: the median step between the log's increasing laser
  /// stamps when at least half of the steps increase, else 1 s.
  double scan_period_s = 0;
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
  std::size_t odom_dropped = 0;                ///< ODOM lines going back in time (OdomLines mode)
  std::string laser_message;                   ///< FLASER or ROBOTLASER1 (the first one seen)
  double aperture_deg = 0;                     ///< of the first scan
  std::size_t rays = 0;                        ///< of the first scan
  std::map<std::string, std::size_t> ignored;  ///< message name -> lines skipped

  /// The log's laser stamps (surveyed when timestamps is Auto or Order): how many are not a
  /// time in seconds, how many are not after the one before.
  std::size_t stamps_bad = 0, stamps_not_increasing = 0;
  bool stamped_by_order = false;  ///< the scans were stamped from the log's order
  double scan_period_s = 0;       ///< the step used then
  /// What the converter decided about a questionable input (file:line: what and why).
  std::vector<std::string> warnings;
  double wall_time_s = 0;
};

CarmenToRawlogReport carmenToRawlog(const CarmenToRawlogOptions& opt);

}  // namespace asf::io
