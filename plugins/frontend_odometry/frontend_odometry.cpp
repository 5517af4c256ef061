// frontend_odometry: dead-reckoning pose graph. A keyframe node every keyframe_distance metres
// or keyframe_angle_deg degrees of accumulated odometry, joined to the previous keyframe by an
// odometry edge whose information is the inverse of the first-order propagated covariance.
#include <asf/errors.h>
#include <asf/frontend.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <cmath>

namespace {

constexpr double kDeg = M_PI / 180.0;

class OdometryFrontend final : public asf::Frontend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    kf_dist_ = p.getDouble("keyframe_distance");
    kf_angle_ = p.getDouble("keyframe_angle_deg") * kDeg;
    const double sxy = p.getDouble("min_sigma_xy"), sphi = p.getDouble("min_sigma_phi");
    floor_ = Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
  }

  bool process(const asf::SensorFrame& f, asf::PoseGraph& g, const asf::Marginals&) override {
    if (!started_) {
      started_ = true;
      acc_ = mrpt::poses::CPose2D();
      acc_cov_.setZero();
      if (g.empty()) {
        addNode(g, mrpt::poses::CPose2D(), f);
        return true;
      }
      // A graph given non-empty: continue from its last node (the robot stands there).
      last_ = static_cast<asf::NodeId>(g.size() - 1);
      MRPT_LOG_WARN_STREAM("graph not empty on the first frame: continuing from node " << last_);
      return false;
    }
    if (last_ >= g.size())
      throw asf::Error("odometry front-end: graph has " + std::to_string(g.size()) +
                       " nodes but the last keyframe was node " + std::to_string(last_) +
                       " (was the graph replaced?)");
    accumulate(f.odometry, f.odometry_cov);
    if (std::hypot(acc_.x(), acc_.y()) <= kf_dist_ && std::abs(acc_.phi()) <= kf_angle_)
      return false;

    asf::PoseEdge e;
    e.from = last_;
    e.mean = acc_;
    // acc_cov_ is the covariance of the increment in the frame of `from`.
    e.information = asf::edgeInformation(acc_, acc_cov_, floor_);
    e.kind = asf::EdgeKind::Odometry;
    mrpt::poses::CPose2D pose = g.nodes[last_].pose + acc_;
    pose.normalizePhi();
    e.to = addNode(g, pose, f);
    g.addEdge(e);
    acc_ = mrpt::poses::CPose2D();
    acc_cov_.setZero();
    return true;
  }

  mrpt::poses::CPose2D currentPose(const asf::PoseGraph& g) const override {
    if (g.empty()) return acc_;
    const asf::NodeId base = last_ < g.size() ? last_ : static_cast<asf::NodeId>(g.size() - 1);
    mrpt::poses::CPose2D p = g.nodes[base].pose + acc_;
    p.normalizePhi();
    return p;
  }

 private:
  asf::NodeId addNode(asf::PoseGraph& g, const mrpt::poses::CPose2D& pose,
                      const asf::SensorFrame& f) {
    const asf::NodeId id = g.addNode(pose, f.timestamp);
    g.nodes[id].scan = f.scan;
    g.nodes[id].ground_truth = f.ground_truth;
    ++g.revision;
    last_ = id;
    return id;
  }

  void accumulate(const mrpt::poses::CPose2D& u, const Eigen::Matrix3d& cov_u) {
    Eigen::Matrix3d out;
    acc_ = asf::composeWithCov(acc_, acc_cov_, u, cov_u, out);
    acc_cov_ = out;
  }

  double kf_dist_ = 0.5, kf_angle_ = 20 * kDeg;
  Eigen::Matrix3d floor_ = Eigen::Matrix3d::Identity();
  bool started_ = false;
  asf::NodeId last_ = 0;
  mrpt::poses::CPose2D acc_;
  Eigen::Matrix3d acc_cov_ = Eigen::Matrix3d::Zero();
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("keyframe_distance", "0.5",
                   "New node when the odometry since the last one exceeds this [m]", 1e-6, 1e6),
    asf::keyDouble("keyframe_angle_deg", "20",
                   "New node when the heading change since the last one exceeds this [deg]",
                   1e-6, 180),
    asf::keyDouble("min_sigma_xy", "1e-3",
                   "Its square is added to the x/y variances of every edge (keeps the "
                   "information finite) [m]",
                   1e-9, 1e3),
    asf::keyDouble("min_sigma_phi", "1e-4",
                   "Its square is added to the heading variance of every edge [rad]", 1e-9, 10),
};

}  // namespace

ASF_PLUGIN(OdometryFrontend, asf::PluginKind::Frontend, "odometry", "1.0.0",
           "Dead-reckoning pose graph: keyframes joined by propagated odometry edges",
           asf::ThreadSafety::ThreadCompatible, kKeys)
