#pragma once
/// \file scan_matcher.h
/// Scan matching for the icp_graph front-end: point clouds from 2D scans, MRPT's CICP
/// (Levenberg-Marquardt variant) for the alignment, a point-to-line refinement on a kd-tree
/// cached with the reference cloud, and our own residual statistics and point-to-line
/// covariance at the solution (CICP's LM covariance is the inverse of its damped Gauss-Newton
/// matrix of kernelized squared distances, not a covariance in metres).
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::obs {
class CObservation2DRangeScan;
}
namespace mrpt::maps {
class CSimplePointsMap;
}

namespace asf::icp_graph {

/// Points of one or more scans in one frame, with a normal per point where the
/// neighbourhood is line-like (computed per point on first use, for a reference cloud). The
/// kd-tree over the points (and MRPT's point map, for CICP) is built on first use and kept
/// until points are added, so every match against the same reference shares it.
class Cloud {
 public:
  Cloud();
  ~Cloud();
  Cloud(Cloud&&) noexcept;
  Cloud& operator=(Cloud&&) noexcept;
  Cloud(const Cloud&) = delete;
  Cloud& operator=(const Cloud&) = delete;

  /// The valid returns of `scan`, in the robot frame (the scan's sensorPose applied).
  static Cloud fromScan(const mrpt::obs::CObservation2DRangeScan& scan);
  /// The points (x[i], y[i]) in this cloud's frame.
  static Cloud fromPoints(const std::vector<float>& x, const std::vector<float>& y);
  /// Adds `other`'s points moved by `pose` (other's frame expressed in this one).
  void add(const Cloud& other, const mrpt::poses::CPose2D& pose);

  /// Replaces the points in each square of side `cell` (a grid aligned with this frame's
  /// origin) by their mean, in the order the squares first occur (a voxel-grid filter);
  /// cell <= 0: all points kept.
  void thin(double cell);
  std::size_t size() const;
  /// The points as MRPT's point map (built on first use), for CICP.
  const mrpt::maps::CSimplePointsMap& map() const;
  /// Index of the point nearest to (x, y) and its squared distance (size() must be > 0).
  std::size_t nearest(float x, float y, float& d2) const;
  const std::vector<float>& xs() const { return x_; }
  const std::vector<float>& ys() const { return y_; }

  /// Unit normal of point i, or (0, 0) when its neighbourhood is not line-like.
  Eigen::Vector2d normal(std::size_t i) const;
  /// Normals from a PCA of the k nearest points within `radius` (noisier scans need more).
  void setNormalNeighbourhood(std::size_t k, double radius) {
    normal_k_ = k;
    normal_radius_ = radius;
    normals_ok_ = false;
  }

 private:
  struct Index;  // nanoflann's kd-tree, kept out of this header
  Eigen::Vector2d computeNormal(std::size_t i) const;
  const Index& index() const;
  void dropCaches();
  std::vector<float> x_, y_;
  mutable std::unique_ptr<mrpt::maps::CSimplePointsMap> map_;
  mutable std::unique_ptr<Index> index_;
  mutable std::vector<Eigen::Vector2d> normals_;
  mutable std::vector<char> normal_done_;
  mutable bool normals_ok_ = false;
  std::size_t normal_k_ = 8;
  double normal_radius_ = 0.3;
};

/// The coarse alignment before the point-to-line refinement: MRPT's CICP (Levenberg-Marquardt
/// on point-to-point distances), or our own Gauss-Newton on point-to-line residuals with the
/// same shrinking correspondence distance (thresholds, decimation, goodness as CICP's).
enum class IcpMethod { MrptLm, PointToLine };

struct IcpOptions {
  IcpMethod method = IcpMethod::MrptLm;
  int max_iterations = 80;
  double threshold_dist = 0.75;     ///< initial correspondence distance [m]
  double threshold_ang_deg = 0.15;  ///< extra distance per metre of range [deg]
  double alfa = 0.5;                ///< threshold shrink factor at convergence
  double smallest_threshold_dist = 0.05;
  int decimation = 5;          ///< CICP corresponding_points_decimation
  double inlier_dist = 0.1;    ///< residual statistics: a point within this is an inlier
  double sigma_floor = 0.005;  ///< lower bound of the point noise std [m]
  double cov_scale = 1.0;      ///< multiplies the point-to-line covariance
  int refine_iterations = 5;   ///< point-to-line Gauss-Newton steps after CICP
  bool robust = false;         ///< Cauchy-weighted refinement (IRLS), scale from MAD
};

struct MatchResult {
  bool ran = false;           ///< false: a cloud had too few points (see reason)
  mrpt::poses::CPose2D pose;  ///< pose of the current cloud's frame in the reference's
  /// Covariance of `pose` as additive (x, y, phi) in the reference frame: sigma^2 H^-1 of the
  /// point-to-line (point-to-point where no normal) residuals at the solution, x cov_scale.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();
  /// What CICP returned (for diagnostics; zero with IcpMethod::PointToLine).
  Eigen::Matrix3d cicp_cov = Eigen::Matrix3d::Zero();
  double goodness = 0;        ///< correspondence ratio at the final threshold (as CICP's)
  unsigned iterations = 0;    ///< iterations of the coarse alignment
  double inlier_ratio = 0;    ///< fraction of current points within inlier_dist
  double rmse = 0;            ///< RMS point-to-line residual of the inliers [m]
  std::size_t residuals = 0;  ///< residual rows used for the covariance
  std::string reason;
};

/// Aligns `cur` to `ref` starting from `guess` (cur's frame in ref's). Needs at least
/// `min_points` points in each cloud (else ran = false).
MatchResult match(const Cloud& ref, const Cloud& cur, const mrpt::poses::CPose2D& guess,
                  const IcpOptions& o, std::size_t min_points = 10);

/// (a - b) with the angle wrapped.
Eigen::Vector3d poseDiff(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b);

}  // namespace asf::icp_graph
