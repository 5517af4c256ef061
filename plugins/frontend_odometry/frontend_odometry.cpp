// frontend_odometry: dead-reckoning pose graph. A keyframe node every keyframe_distance metres
// or keyframe_angle_deg degrees of accumulated odometry, joined to the previous keyframe by an
// odometry edge whose information is the inverse of the first-order propagated covariance.
#include <asf/errors.h>
#include <asf/frontend.h>
#include <asf/mapping/keyframe_tracker.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <cmath>

namespace {

constexpr double kDeg = M_PI / 180.0;

class OdometryFrontend final : public asf::Frontend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    kf_.setThresholds(p.getDouble("keyframe_distance"), p.getDouble("keyframe_angle_deg") * kDeg);
    const double sxy = p.getDouble("min_sigma_xy"), sphi = p.getDouble("min_sigma_phi");
    floor_ = Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
  }

  bool process(const asf::SensorFrame& f, asf::PoseGraph& g, const asf::Marginals&) override {
    switch (kf_.begin(f, g)) {
      case asf::mapping::KeyframeTracker::Begin::AddedRoot: return true;
      case asf::mapping::KeyframeTracker::Begin::Continued:
        MRPT_LOG_WARN_STREAM("graph not empty on the first frame: continuing from node "
                             << kf_.last());
        return false;
      case asf::mapping::KeyframeTracker::Begin::NotFirst: break;
    }
    if (!kf_.due()) return false;

    asf::PoseEdge e;
    e.from = kf_.last();
    e.mean = kf_.increment();
    // The increment's covariance is in the frame of `from`.
    e.information = asf::edgeInformation(e.mean, kf_.incrementCov(), floor_);
    e.kind = asf::EdgeKind::Odometry;
    mrpt::poses::CPose2D pose = g.nodes[e.from].pose + e.mean;
    pose.normalizePhi();
    e.to = kf_.addKeyframe(g, pose, f);
    g.addEdge(e);
    return true;
  }

  mrpt::poses::CPose2D currentPose(const asf::PoseGraph& g) const override {
    return kf_.currentPose(g);
  }

 private:
  asf::mapping::KeyframeTracker kf_{"odometry front-end"};
  Eigen::Matrix3d floor_ = Eigen::Matrix3d::Identity();
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
