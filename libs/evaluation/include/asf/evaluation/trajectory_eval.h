#pragma once
/// \file trajectory_eval.h
/// Trajectory accuracy against ground truth: absolute trajectory error (ATE) after the rigid
/// SE(2) alignment that minimises it, the measure SLAM papers and MRPT's tools report.
#include <asf/io/ground_truth.h>
#include <mrpt/poses/CPose2D.h>

#include <optional>
#include <string>
#include <vector>

namespace asf::evaluation {

struct TimedPose {
  double t = 0;
  mrpt::poses::CPose2D pose;
};

/// Rigid transform T (rotation + translation, no scale) minimising sum |T(a_i) - b_i|^2 over
/// the positions (closed form: 2D Kabsch/Umeyama). Needs at least one pair; with one pair (or
/// all a_i equal) the rotation is the identity.
mrpt::poses::CPose2D alignSE2(const std::vector<mrpt::poses::CPose2D>& a,
                              const std::vector<mrpt::poses::CPose2D>& b);

struct TrajectoryError {
  std::size_t poses = 0;      ///< estimated poses with a ground-truth match
  std::size_t unmatched = 0;  ///< estimated poses without one (outside the GT or in a gap)
  double ate_rmse_m = 0;      ///< sqrt(mean |T(est_i) - gt_i|^2)
  double ate_mean_m = 0, ate_max_m = 0;
  double rot_rmse_deg = 0;         ///< RMSE of the heading error after alignment
  mrpt::poses::CPose2D alignment;  ///< T: estimate frame -> ground-truth frame
  std::vector<double> errors_m;    ///< per matched pose, in estimate order
  std::vector<double> times;       ///< time of each matched pose (evaluateTrajectory only)
  bool aligned = true;
};

/// Pairs each estimated pose with the ground truth at its time (interpolateGroundTruth with
/// `max_gap`) and computes the ATE, after alignSE2 when `align` (else T = identity).
/// Throws asf::Error when no pose has a match.
TrajectoryError evaluateTrajectory(const std::vector<TimedPose>& estimate,
                                   const std::vector<io::GroundTruthPose>& ground_truth,
                                   double max_gap = 0.5, bool align = true);

/// Same with pairs already matched (estimate[i] <-> truth[i]).
TrajectoryError evaluateMatched(const std::vector<mrpt::poses::CPose2D>& estimate,
                                const std::vector<mrpt::poses::CPose2D>& truth, bool align = true);

/// Relative pose error (Sturm et al., IROS 2012; the relation-based error of Kuemmerle et al.,
/// Autonomous Robots 2009): for each i, E_i = (gt_i^-1 gt_{i+delta})^-1 (est_i^-1 est_{i+delta}),
/// the error of the estimated motion over `delta` poses. Independent of the global frame
/// (no alignment) and of drift accumulated before i: the local accuracy that ATE mixes with
/// the global one.
struct RelativePoseError {
  std::size_t pairs = 0;    ///< number of (i, i + delta) pairs
  double trans_rmse_m = 0;  ///< sqrt(mean |translation(E_i)|^2)
  double trans_max_m = 0;
  double rot_rmse_deg = 0;  ///< sqrt(mean angle(E_i)^2)
};
/// Pairs estimate[i] <-> truth[i]. Throws asf::Error when the sizes differ, delta is 0 or
/// there are fewer than delta + 1 poses.
RelativePoseError relativePoseError(const std::vector<mrpt::poses::CPose2D>& estimate,
                                    const std::vector<mrpt::poses::CPose2D>& truth,
                                    std::size_t delta = 1);

/// Reads an estimated trajectory: text lines `t x y phi [more columns ignored]` with absolute
/// times (asf's keyframes.txt, ground-truth files, MRPT's icp-slam log_estimated_path.txt).
/// '#' and '%' start comment lines.
/// Throws asf::InputError naming file:line.
std::vector<TimedPose> readTrajectory(const std::string& path);

}  // namespace asf::evaluation
