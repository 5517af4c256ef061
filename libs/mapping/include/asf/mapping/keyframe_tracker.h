#pragma once
/// \file keyframe_tracker.h
/// The keyframe bookkeeping every pose-graph front-end needs: node 0 on the first frame (or
/// continue from a graph given non-empty), odometry accumulated with its covariance since the
/// last keyframe, the distance/turn test for a new keyframe, and the current pose estimate.
/// Front-ends decide what edge joins the new keyframe (odometry, ICP, ...).
#include <asf/pose_graph.h>
#include <asf/sensor_frame.h>

#include <string>

namespace asf::mapping {

class KeyframeTracker {
 public:
  /// `who` names the front-end in error messages.
  explicit KeyframeTracker(std::string who) : who_(std::move(who)) {}

  /// New keyframe when the accumulated odometry exceeds `distance` [m] or `angle` [rad].
  void setThresholds(double distance, double angle) {
    distance_ = distance;
    angle_ = angle;
  }

  enum class Begin {
    NotFirst,   ///< not the first frame: the caller processes it
    AddedRoot,  ///< first frame on an empty graph: node 0 added at the origin
    Continued,  ///< first frame on a non-empty graph: continuing from its last node
  };
  /// Call first for every frame. On the first one it starts the tracker (see Begin); on the
  /// others it checks that the graph still holds the last keyframe (throws asf::Error naming
  /// the front-end if it was replaced) and accumulates the frame's odometry.
  Begin begin(const SensorFrame& f, PoseGraph& g);

  /// The odometry since the last keyframe exceeds the thresholds times `factor`.
  bool due(double factor = 1) const;

  /// Adds the next keyframe node at `pose` (timestamp, scan, ground truth from `f`), bumps
  /// the graph revision and restarts the accumulation. The caller adds the joining edge.
  NodeId addKeyframe(PoseGraph& g, const mrpt::poses::CPose2D& pose, const SensorFrame& f);

  NodeId last() const { return last_; }
  /// Odometry since the last keyframe, in its frame, and the covariance of that increment.
  const mrpt::poses::CPose2D& increment() const { return acc_; }
  const Eigen::Matrix3d& incrementCov() const { return acc_cov_; }
  /// Last keyframe composed with the odometry since (the Frontend::currentPose contract).
  mrpt::poses::CPose2D currentPose(const PoseGraph& g) const;

 private:
  std::string who_;
  double distance_ = 0.5, angle_ = 0.349;
  bool started_ = false;
  NodeId last_ = 0;
  mrpt::poses::CPose2D acc_;
  Eigen::Matrix3d acc_cov_ = Eigen::Matrix3d::Zero();
};

}  // namespace asf::mapping
