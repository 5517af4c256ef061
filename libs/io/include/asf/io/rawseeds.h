#pragma once
/// \file rawseeds.h
/// Rawseeds indoor datasets (Bicocca, Bovisa) <-> MRPT rawlogs.
///
/// Streams are CSV files `<dir>/<dataset>-<STREAM>.csv` or `.csv.bz2` (formats in
/// ../shared/docs/rawseeds-format.md):
/// - SICK_FRONT / SICK_REAR: `timestamp, N, angular offset [1/4 deg], R1..RN` (N = 181 over
///   180 degrees, right to left);
/// - ODOMETRY_XYT: `timestamp, rolling counter, ticks left, ticks right, X, Y, Theta`;
/// - GROUNDTRUTH: `timestamp, X, Y, Theta, C_xx .. C_tt` (13 fields); GT-extended:
///   `timestamp, X, Y, Theta`.
/// Timestamps are seconds.microseconds since 1970 (UTC).
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace asf::io {

/// Range limit of the SICK LMS 291 / LMS 200 (80 m in their cm mode). Readings outside
/// (0, kSickMaxRange) are marked invalid (the scanners report "no echo" beyond it).
constexpr double kSickMaxRange = 80.0;

/// The documented pose of a Rawseeds 2D laser on the robot (odometry frame: the middle of
/// the wheel axis, x forward): SICK_FRONT (0.08, 0, 0.45) m, SICK_REAR (-0.463, 0.001, 0.45)
/// m with yaw 180 deg. Throws asf::InputError for other streams (the Hokuyos are tilted and
/// have another line format).
mrpt::poses::CPose3D rawseedsLaserPose(const std::string& stream);

/// `<dir>/<dataset>-<stream>.csv`, or `.csv.bz2` when only that exists. Throws
/// asf::InputError naming both candidates when neither exists.
std::string findRawseedsStream(const std::string& dir, const std::string& dataset,
                               const std::string& stream);

struct RawseedsToRawlogOptions {
  std::string dir;
  std::string dataset;                         ///< e.g. "Bicocca_2009-02-25b"
  std::vector<std::string> lasers{"SICK_FRONT"};  ///< SICK_FRONT and/or SICK_REAR
  std::string output;                          ///< .rawlog, or .rawlog.gz (compressed)
  std::string gt_output;                       ///< asf ground-truth file; empty: none
  std::string gt_stream = "GROUNDTRUTH";       ///< or "GT-extended"
  /// Bad lines are skipped and counted instead of stopping with asf::InputError.
  bool skip_bad_lines = false;
  std::ostream* progress = nullptr;  ///< progress lines every ~2 s (null: silent)
};

struct StreamReport {
  std::string stream, file;
  std::size_t lines = 0;      ///< lines read (blank lines included)
  std::size_t records = 0;    ///< records converted
  std::size_t bad_lines = 0;  ///< skipped (only with skip_bad_lines)
  std::size_t first_bad_line = 0;
  std::string first_bad_reason;
  double t_first = 0, t_last = 0;  ///< seconds, of the converted records
};

struct RawseedsToRawlogReport {
  std::vector<StreamReport> streams;  ///< odometry, lasers, then ground truth
  std::size_t scans = 0, odometry = 0, gt_poses = 0;
  double wall_time_s = 0;
};

/// Merges the laser streams and ODOMETRY_XYT into one time-ordered observation-only rawlog
/// (CObservationOdometry per odometry line, before scans of the same time;
/// CObservation2DRangeScan per laser line, sensorLabel = stream name), and converts the
/// ground-truth stream to `gt_output`. A bad line (wrong field count, not a number, time
/// going backwards within its stream) throws asf::InputError "file:line: why" unless
/// skip_bad_lines.
RawseedsToRawlogReport rawseedsToRawlog(const RawseedsToRawlogOptions& opt);

/// Converts one ground-truth stream file (GROUNDTRUTH or GT-extended, plain or .bz2) into an
/// asf ground-truth file (`timestamp x y phi`). Times must increase strictly. Bad lines as in
/// rawseedsToRawlog.
StreamReport rawseedsGroundTruthToFile(const std::string& csv, const std::string& output,
                                       bool skip_bad_lines, std::ostream* progress = nullptr);

struct RawlogToRawseedsOptions {
  std::string rawlog;
  std::string gt_input;     ///< asf ground-truth file; empty: no GROUNDTRUTH stream
  std::string dir;          ///< created if missing
  std::string dataset;      ///< file name prefix
  std::string laser_label;  ///< which scans (RawlogReaderOptions::laser_label)
  bool bz2 = false;         ///< write .csv.bz2 instead of .csv
};

struct RawlogToRawseedsReport {
  std::size_t frames = 0, scans = 0, odometry_lines = 0, gt_lines = 0;
  std::vector<std::string> files;  ///< written, in order laser, odometry, ground truth
};

/// The inverse, to test the converter without the real streams: writes
/// `<dataset>-SICK_FRONT.csv` (one line per scan; invalid rays written as 0),
/// `<dataset>-ODOMETRY_XYT.csv` (the frames' odometry increments integrated from the
/// identity into X, Y, Theta; tick columns 0; rolling int16 counter) and, with gt_input,
/// `<dataset>-GROUNDTRUTH.csv` (covariance: diagonal 1e-6). Throws asf::InputError for a
/// scan that is not 181 rays over 180 degrees (naming the record).
RawlogToRawseedsReport rawlogToRawseeds(const RawlogToRawseedsOptions& opt);

}  // namespace asf::io
