#include <asf/errors.h>
#include <asf/mapping/keyframe_tracker.h>

#include <cmath>

namespace asf::mapping {

KeyframeTracker::Begin KeyframeTracker::begin(const SensorFrame& f, PoseGraph& g) {
  if (!started_) {
    started_ = true;
    acc_ = mrpt::poses::CPose2D();
    acc_cov_.setZero();
    if (g.empty()) {
      addKeyframe(g, mrpt::poses::CPose2D(), f);
      return Begin::AddedRoot;
    }
    // A graph given non-empty: continue from its last node (the robot stands there).
    last_ = static_cast<NodeId>(g.size() - 1);
    return Begin::Continued;
  }
  if (last_ >= g.size())
    throw Error(who_ + ": graph has " + std::to_string(g.size()) +
                " nodes but the last keyframe was node " + std::to_string(last_) +
                " (was the graph replaced?)");
  Eigen::Matrix3d out;
  acc_ = composeWithCov(acc_, acc_cov_, f.odometry, f.odometry_cov, out);
  acc_cov_ = out;
  return Begin::NotFirst;
}

bool KeyframeTracker::due(double factor) const {
  return std::hypot(acc_.x(), acc_.y()) > factor * distance_ ||
         std::abs(acc_.phi()) > factor * angle_;
}

NodeId KeyframeTracker::addKeyframe(PoseGraph& g, const mrpt::poses::CPose2D& pose,
                                    const SensorFrame& f) {
  const NodeId id = g.addNode(pose, f.timestamp);
  g.nodes[id].scan = f.scan;
  g.nodes[id].ground_truth = f.ground_truth;
  ++g.revision;
  last_ = id;
  acc_ = mrpt::poses::CPose2D();
  acc_cov_.setZero();
  return id;
}

mrpt::poses::CPose2D KeyframeTracker::currentPose(const PoseGraph& g) const {
  if (g.empty()) return acc_;
  const NodeId base = last_ < g.size() ? last_ : static_cast<NodeId>(g.size() - 1);
  mrpt::poses::CPose2D p = g.nodes[base].pose + acc_;
  p.normalizePhi();
  return p;
}

}  // namespace asf::mapping
