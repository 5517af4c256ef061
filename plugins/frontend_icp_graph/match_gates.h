#pragma once
/// \file match_gates.h
/// The icp_graph front-end's quality gates for an alignment (sequential: against the
/// odometry; loop and revisit: against the estimated relative pose) and the windows of its
/// correlative searches. Each gate returns an empty string when the alignment passes, else
/// why not (for the DEBUG log).
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <optional>
#include <string>

#include "scan_matcher.h"

namespace asf::icp_graph {

struct MatchGates {
  int max_iterations = 80;                           ///< CICP stopped here: not converged
  double min_goodness = 0.6;                         ///< sequential: CICP goodness at least this
  double max_sigma_xy = 0.1, max_sigma_phi = 0.035;  ///< std of every direction at most this
  double odometry_chi2 = 16;  ///< sequential: (ICP - odometry) Mahalanobis^2 at most this
  Eigen::Matrix3d odo_floor = Eigen::Matrix3d::Zero();  ///< added to odometry covariances
  Eigen::Matrix3d icp_floor = Eigen::Matrix3d::Zero();  ///< added to ICP covariances
  double loop_min_goodness = 0.6, loop_min_inliers = 0.6, loop_max_rmse = 0.05;
  double loop_chi2 = 11.34;  ///< loop: (ICP - estimate) Mahalanobis^2 at most this
};

/// Largest position std and the heading std of `C` within the gates' limits.
bool sigmasOk(const Eigen::Matrix3d& C, const MatchGates& g);

/// A sequential alignment `m` of a keyframe whose odometry increment is `odo` (covariance
/// `odo_cov`, floor not included): ran, converged, goodness >= `min_goodness`, well
/// conditioned, agreeing with the odometry.
std::string sequentialGateFailure(const MatchResult& m, const mrpt::poses::CPose2D& odo,
                                  const Eigen::Matrix3d& odo_cov, double min_goodness,
                                  const MatchGates& g);

/// A loop (or revisit) alignment `m` against the estimate `est` of the relative pose with
/// covariance `Crel`: goodness, inlier ratio, RMSE, conditioning, chi^2 against the estimate
/// (`chi2`, when given, receives it).
std::string loopGateFailure(const MatchResult& m, const mrpt::poses::CPose2D& est,
                            const std::optional<Eigen::Matrix3d>& Crel, const MatchGates& g,
                            double* chi2 = nullptr);

/// Half-widths of a correlative search covering `sigmas` standard deviations of a relative
/// pose with covariance `C` (its largest position std; its heading std), each clamped to
/// [min, max].
struct SearchWindow {
  double xy = 0, phi = 0;
};
SearchWindow windowCovering(const Eigen::Matrix3d& C, double sigmas, double min_xy, double max_xy,
                            double min_phi, double max_phi);

}  // namespace asf::icp_graph
