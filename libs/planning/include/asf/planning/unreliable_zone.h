#pragma once
/// \file unreliable_zone.h
/// The feature-void zone of thesis ch. 3.5.1 (Table 3.1): a region of a SLAM run in which
/// "every scan is ignored for all purposes" and the robot has only wheel odometry, with its
/// covariance multiplied by a factor (x10 or x100 in the thesis). Applied to the graph of a
/// run after the fact, with the log the run read:
/// - the zone's nodes lose their scans: no scan matching, no loop closure, no place
///   recognition there, and their scans are not part of the local maps other nodes are
///   recognized against (place_recognition.h);
/// - an edge between consecutive keyframes (i, i+1) with an end in the zone becomes the wheel
///   odometry between them (the log's increments composed, first-order covariance) with its
///   covariance times the factor;
/// - every other edge with an end in the zone (loop closures, revisits: scan matches) goes.
/// Zone membership is decided on the un-masked graph's poses (the run's map frame).
#include <asf/pose_graph.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace asf::planning {

/// An axis-aligned rectangle of the map frame [m].
struct Zone {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(const mrpt::poses::CPose2D& p) const {
    return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1;
  }
};

/// What a run's source log holds at each keyframe of the run.
struct KeyframeLog {
  /// scan[i]: the scan of the frame node i was made at (null if that frame had none).
  std::vector<std::shared_ptr<const mrpt::obs::CObservation2DRangeScan>> scan;
  /// odometry[i]: the wheel-odometry increment from node i-1 to node i in node i-1's frame
  /// (the frames' increments composed); odometry[0] is the identity.
  std::vector<mrpt::poses::CPose2D> odometry;
  /// odometry_cov[i]: its covariance (additive x, y, phi in node i-1's frame).
  std::vector<Eigen::Matrix3d> odometry_cov;
  std::size_t frames_read = 0;
};

/// Replays `rawlog` (the log the run read; `laser_label` as the run's source had it) and
/// matches each of `keyframe_times` (the nodes' timestamps in node order, increasing, as in a
/// run's keyframes.txt) to the frame with that timestamp (within `tolerance` s); composes
/// the frames' odometry increments between consecutive keyframes. Throws asf::InputError
/// naming the rawlog and the first node whose timestamp no frame has (the wrong log, or
/// times not increasing).
KeyframeLog readKeyframeLog(const std::string& rawlog, const std::vector<double>& keyframe_times,
                            const std::string& laser_label = "", double tolerance = 1e-6);

/// A run's graph (graph_file, g2o) with each node's scan from the log the run read:
/// keyframes_file (the run's keyframes.txt; empty: the one beside graph_file) gives the
/// nodes' times, readKeyframeLog the frames. `log` (optional) receives the log. Throws
/// asf::InputError naming the file that does not match (node counts, times).
PoseGraph readRunWithScans(const std::string& graph_file, std::string keyframes_file,
                           const std::string& rawlog, const std::string& laser_label,
                           KeyframeLog* log = nullptr);

/// Covariance of the edges the zone leaves between consecutive keyframes.
enum class ZoneCovariance {
  WheelOdometry,  ///< the log's wheel odometry (mean and covariance) x factor (the thesis)
  OdometryModel,  ///< the edge's own mean, MRPT's default motion model x factor (no log)
  Scaled,         ///< the edge's own mean and covariance x factor (an ICP-grade zone)
};

struct ZoneMaskOptions {
  double factor = 10;
  ZoneCovariance covariance = ZoneCovariance::WheelOdometry;
  /// Drop the non-consecutive edges with an end in the zone. Only false for the graph-only
  /// variants (OdometryModel, Scaled): a zone without scans has no loop closures.
  bool drop_loop_closures = true;
  /// Edges changed: true, those with an end in the zone; false, both ends (graph-only
  /// variants).
  bool touching = true;
};

struct ZoneMaskReport {
  std::size_t zone_nodes = 0;
  std::size_t scans_removed = 0;            ///< zone nodes that had a scan
  std::size_t edges_replaced = 0;           ///< consecutive edges made odometry (or scaled)
  std::size_t loop_closures_dropped = 0;    ///< non-consecutive edges removed
  std::size_t duplicate_edges_dropped = 0;  ///< second edges of a consecutive pair
};

/// `g` with the zone (in_zone[i] != 0 for its nodes) masked as the file comment says.
/// `log` is required for ZoneCovariance::WheelOdometry (throws asf::Error otherwise) and must
/// have one entry per node. Nodes keep their poses (re-optimize the result).
PoseGraph maskZone(const PoseGraph& g, const std::vector<char>& in_zone, const ZoneMaskOptions& o,
                   const KeyframeLog* log, ZoneMaskReport* report = nullptr);

}  // namespace asf::planning
