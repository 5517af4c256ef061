#pragma once
/// \file map3d_from_log.h
/// What `asf map3d` does, as a library: every 3D observation of a rawlog inserted into an
/// asf::mapping::Map3d at the robot pose of its time (integrated odometry of the log, or a ground
/// truth), with counts, skips and timings.
#include <asf/mapping/map3d.h>
#include <asf/io/rawlog_io.h>
#include <mrpt/poses/CPose3D.h>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace asf::studies {

struct Map3dFromLogOptions {
  /// Robot poses from this ground truth instead of odometry (observations outside it are
  /// skipped); empty: odometry.
  std::vector<io::GroundTruthPose> ground_truth;
  /// Replaces the sensorPose of point clouds, Velodyne and 3D range scans (logs that store
  /// the identity); 2D laser scans keep theirs.
  std::optional<mrpt::poses::CPose3D> sensor_pose;
};

struct Map3dFromLogReport {
  std::size_t records = 0, observations = 0, points = 0;
  std::map<std::string, std::size_t> inserted_by_class;  ///< MRPT class -> observations
  std::map<std::string, std::size_t> skipped;            ///< reason -> observations
  std::map<std::string, std::string> sensor_poses;       ///< label -> pose on the robot used
  double read_s = 0, extract_s = 0, insert_s = 0;
  /// Why reading stopped early (a cut or corrupt record); empty when the log was read to
  /// its end. What was inserted before it stays in the map.
  std::string error;
};

/// Inserts `rawlog` (either layout, gz or not) into `map`. `progress` (may be empty) gets a
/// line every 2 s. Throws InputError when the file cannot be opened; a bad record ends the
/// reading with Map3dFromLogReport::error set.
Map3dFromLogReport insertRawlog3d(const std::string& rawlog, const Map3dFromLogOptions& o,
                                  mapping::Map3d& map,
                                  const std::function<void(const std::string&)>& progress);

}  // namespace asf::studies
