#pragma once
/// \file loop_search.h
/// Loop-closure alignment for the icp_graph front-end, two ways. `icp`: ICP from the estimated
/// relative pose, then (if it passes the caller's gates) from perturbed guesses that must
/// converge to it. `correlative`: correlative scan matching
/// (correlative_matcher.h): the new keyframe's scan is searched over a window around the estimated
/// relative pose in a likelihood field of the candidate's submap, so a drifted estimate does not
/// decide what ICP converges to. Two cues come from the search: the best pose's score (how
/// much of the scan the submap explains) and the best score outside a disc around it (a
/// repetitive place, such as a corridor of identical doors, explains the scan about as well
/// elsewhere: ambiguous, refused). ICP then refines the best pose (the caller's gates).
#include <asf/pose_graph.h>
#include <mrpt/poses/CPose2D.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "correlative_matcher.h"
#include "scan_matcher.h"

namespace asf::icp_graph {

struct CorrelativeLoopOptions {
  double resolution = 0.1;     ///< likelihood grid cell [m]
  double sigma = 0.1;          ///< likelihood field std [m]
  double window_xy = 2.0;      ///< search +- this around the estimate [m]
  double window_phi = 0.35;    ///< search +- this around the estimate [rad]
  double min_score = 0.5;      ///< best pose's mean likelihood at least this
  double max_ambiguity = 0.9;  ///< best score outside the peak / best score at most this
  double peak_radius = 0.6;    ///< the peak: poses within this of the best [m]
  double max_range = 25.0;     ///< points farther from their scan's origin are left out [m]
};

struct CorrelativeLoopResult {
  bool ok = false;
  std::string why;               ///< why not, for the log
  mrpt::poses::CPose2D pose;     ///< the scan's frame in the submap's (when ok)
  double score = 0, second = 0;  ///< best score, best score outside the peak
};

/// Searches `cur` (robot frame of the new keyframe) in `ref` (frame of the candidate) around
/// `est`. Points of `ref` beyond max_range + window_xy of `est` cannot meet the scan and are
/// left out of the grid.
CorrelativeLoopResult correlativeLoopSearch(const Cloud& ref, const Cloud& cur,
                                            const mrpt::poses::CPose2D& est,
                                            const CorrelativeLoopOptions& o);

}  // namespace asf::icp_graph

namespace asf::icp_graph {

struct LoopSearchOptions {
  bool correlative = false;  ///< the correlative search, else ICP from perturbed guesses
  CorrelativeLoopOptions csm;
  IcpOptions icp;
  std::size_t min_points = 20;
  double perturb_xy = 0.3;    ///< icp: guesses shifted by +- this in x and y [m]
  double perturb_phi = 0.17;  ///< icp: guesses turned by +- this [rad]
  int min_agree = 4;          ///< icp: runs of the 7 that must converge to the best
};

/// The caller's quality gates for a loop alignment: empty when `m` passes, else why not.
using LoopGate = std::function<std::string(const MatchResult&)>;

/// The alignment of `cur` in the loop candidate's submap `ref` near the estimate `est`, or
/// nullopt with the reason in `why`; `how` says what found it.
/// icp: the ICP run from the estimate, if it passes `gate` (when given) and min_agree of the
/// 7 runs (it and the six perturbed guesses, tried in a fixed order) converge to it (within 2
/// inlier distances and 2 degrees). The cheap check comes first: an estimate's run that fails
/// the gate costs one ICP, not seven, and the perturbed guesses stop as soon as min_agree
/// agree or too few are left to reach it.
/// correlative: the search's best pose, unambiguous, refined by ICP, which must stay within
/// two grid cells and 2 degrees of it. The caller applies its quality gates to the result.
std::optional<MatchResult> loopAlignment(const Cloud& ref, const Cloud& cur,
                                         const mrpt::poses::CPose2D& est,
                                         const LoopSearchOptions& o, std::string& why,
                                         std::string& how, const LoopGate& gate = {});

/// A loop closure hypothesis: keyframe `to` seen from keyframe `from` (`mean`, its covariance
/// as additive x, y, phi in the frame of `from`).
struct LoopHypothesis {
  std::size_t from = 0, to = 0;
  mrpt::poses::CPose2D mean;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Identity();
};

/// Whether hypothesis `h` may confirm the held one (loop_confirm): another new keyframe and
/// another old keyframe, the two old keyframes at most `span` apart (0 = any). Far apart, the
/// cycle runs through a long chain of sequential edges whose covariance agrees with nearly
/// any offset, so it tests nothing.
bool mayConfirm(const LoopHypothesis& held, const LoopHypothesis& h, std::size_t span);

/// Pairwise consistency of two loop hypotheses a (ia -> ja) and b (ib -> jb) (Olson,
/// "Recognizing places using spectrally clustered local matches", RAS 2009, and the
/// consistency test of Latif et al.'s RRR): the cycle ia -a-> ja -> jb <-b- ib <- ia closes.
/// `ja_to_jb` and `ia_to_ib` are the relative poses between the two hypotheses' ends by the
/// trajectory (with covariances in the frame of ja and ia). Returns chi^2 of the cycle's
/// residual (3 dof) under the first-order covariance of both ways round.
double loopPairChi2(const LoopHypothesis& a, const LoopHypothesis& b,
                    const mrpt::poses::CPose2D& ia_to_ib, const Eigen::Matrix3d& C_i,
                    const mrpt::poses::CPose2D& ja_to_jb, const Eigen::Matrix3d& C_j);

/// Covariance of xi^-1 (+) xj (additive, frame of i) from global marginals Ci, Cj and the
/// cross-covariance Cij = Cov(xi, xj) (first order).
Eigen::Matrix3d relativeCov(const mrpt::poses::CPose2D& xi, const mrpt::poses::CPose2D& xj,
                            const Eigen::Matrix3d& Ci, const Eigen::Matrix3d& Cj,
                            const Eigen::Matrix3d& Cij);

}  // namespace asf::icp_graph

namespace asf::icp_graph {
struct CandidateGate {
  int skip_recent = 20;     ///< the last this many keyframes are not candidates
  double radius = 3;        ///< old keyframes within this distance are candidates [m]
  double gate_chi2 = 9.21;  ///< ... and those whose distance beyond it is this likely (2 dof)
  int max_candidates = 3;   ///< the nearest this many
  /// ... each at least this many keyframes from every nearer one taken (1: any two distinct):
  /// candidates a few keyframes apart search nearly the same reference.
  int min_gap = 1;
  /// Leave out keyframes already linked to the new one (linkedNear from the previous
  /// keyframe): their relative pose is constrained by scan matches already, so matching them
  /// again closes no loop (Karto's "near linked scans").
  bool skip_linked = false;
};

/// Keyframes reachable from `start` through edges of `g` whose both ends lie within `radius`
/// of `centre` (a flag per node; `start` itself is flagged when it is inside). Node `exclude`
/// is never entered (the new keyframe: its own edges were added by this keyframe).
std::vector<char> linkedNear(const asf::PoseGraph& g, asf::NodeId start,
                             const mrpt::poses::CPose2D& centre, double radius,
                             asf::NodeId exclude);

/// Loop candidates for the new keyframe j (previous keyframe `prev`), nearest first: old
/// keyframes with a scan within `radius` of j's estimate or, with the back-end's marginals
/// (`marg`, and `Cj` = Cov(x_j) propagated from x_prev), whose translation beyond the radius
/// has a Mahalanobis distance^2 below gate_chi2 under the relative covariance (with the cross
/// term Cov(x_i, x_prev) when the marginals hold it).
std::vector<asf::NodeId> loopCandidates(const asf::PoseGraph& g, asf::NodeId j, asf::NodeId prev,
                                        const asf::Marginals* marg,
                                        const std::optional<Eigen::Matrix3d>& Cj,
                                        const CandidateGate& o);
}  // namespace asf::icp_graph
