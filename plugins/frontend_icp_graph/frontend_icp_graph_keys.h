#pragma once
// The icp_graph front-end's INI keys: its ASF_PLUGIN table (frontend_icp_graph.cpp), in a file of
// its own for length. Included once, by frontend_icp_graph.cpp.
#include <asf/key_spec.h>

namespace {

const asf::KeySpec kKeys[] = {
    asf::keyDouble("keyframe_distance", "0.5",
                   "New node when the odometry since the last one exceeds this [m]", 1e-6, 1e6),
    asf::keyDouble("keyframe_angle_deg", "20",
                   "New node when the heading change since the last one exceeds this [deg]", 1e-6,
                   180),
    asf::keyDouble("min_sigma_xy", "1e-3",
                   "Its square is added to the x/y variances of odometry edges [m]", 1e-9, 1e3),
    asf::keyDouble("min_sigma_phi", "1e-4",
                   "Its square is added to the heading variance of odometry edges [rad]", 1e-9, 10),
    asf::keyInt("submap_keyframes", "3",
                "ICP reference: the scans of this many last keyframes, placed by the estimate", 1,
                100),
    asf::keyDouble("submap_radius", "0",
                   "Old keyframes within this distance of a new one join its ICP reference, "
                   "and an ICP edge from the nearest one is added when it passes the loop "
                   "gates on one guess (0: off) [m]",
                   0, 1e6),
    asf::keyInt("submap_nearby_keyframes", "5",
                "At most this many of those old keyframes, nearest first", 1, 1000),
    asf::keyEnum("icp_method", "mrpt_lm", "mrpt_lm|point_to_line",
                 "Coarse alignment before the point-to-line refinement: MRPT's CICP, or our "
                 "point-to-line Gauss-Newton (same keys; faster, worse on real logs: README)"),
    asf::keyInt("icp_max_iterations", "80",
                "CICP maxIterations; an alignment that uses them all is rejected", 1, 10000),
    asf::keyDouble("icp_threshold_dist", "0.75",
                   "CICP thresholdDist: initial correspondence distance [m]", 1e-3, 100),
    asf::keyDouble("icp_threshold_ang_deg", "0.15",
                   "CICP thresholdAng: correspondence distance added per metre of range [deg]", 0,
                   90),
    asf::keyDouble("icp_alfa", "0.5", "CICP ALFA: threshold shrink factor at convergence", 0.01,
                   0.99),
    asf::keyDouble("icp_smallest_threshold_dist", "0.05",
                   "CICP smallestThresholdDist: final correspondence distance [m]", 1e-4, 100),
    asf::keyInt("icp_decimation", "5", "CICP corresponding_points_decimation", 1, 1000),
    asf::keyBool("icp_robust", "false",
                 "Point-to-line refinement with a Cauchy kernel (IRLS, scale from the median "
                 "residual): far or mismatched points weigh less"),
    asf::keyDouble("icp_reference_cell", "0",
                   "The ICP references (sequential, revisit and loop) keep one point per "
                   "square of this side, the mean of its points (the scans of several "
                   "keyframes overlap); 0: all points [m]",
                   0, 10),
    asf::keyInt("icp_normal_neighbours", "8",
                "Reference normals: PCA of this many nearest points (more for noisier scans)", 3,
                1000),
    asf::keyDouble("icp_normal_radius", "0.3",
                   "Reference normals: only neighbours within this distance [m]", 1e-3, 100),
    asf::keyInt("icp_refine_iterations", "5",
                "Point-to-line Gauss-Newton steps after CICP (0: CICP's point-to-point result)", 0,
                100),
    asf::keyInt("icp_min_points", "20", "Fewer valid points in either scan: no ICP", 3, 1000000),
    asf::keyDouble("icp_min_goodness", "0.6",
                   "Reject an alignment whose CICP goodness (correspondence ratio) is lower", 0, 1),
    asf::keyEnum("icp_low_goodness", "odometry", "odometry|likelihood",
                 "A keyframe whose ICP alignment has too low a goodness (open space: far or "
                 "sparse walls): odometry = the odometry edge; likelihood = search the scan in "
                 "the submap's likelihood field over the odometry's uncertainty (the loop_csm_* "
                 "keys: score, ambiguity, peak), refine by ICP, keep it if it passes every other "
                 "gate"),
    asf::keyDouble("icp_inlier_dist", "0.1",
                   "A point within this of the reference is an inlier (residual statistics, "
                   "covariance) [m]",
                   1e-4, 10),
    asf::keyDouble("icp_sigma_floor", "0.005",
                   "Lower bound of the point noise std estimated from the residuals [m]", 1e-6, 1),
    asf::keyDouble("icp_cov_scale", "6",
                   "Multiplies the point-to-line ICP covariance (it ignores correlated errors "
                   "and is over-confident)",
                   1e-6, 1e6),
    asf::keyDouble("icp_min_sigma_xy", "0.005",
                   "Its square is added to the x/y variances of ICP edges [m]", 1e-9, 1e3),
    asf::keyDouble("icp_min_sigma_phi_deg", "0.1",
                   "Its square is added to the heading variance of ICP edges [deg]", 1e-9, 90),
    asf::keyDouble("icp_max_sigma_xy", "0.1",
                   "Reject an alignment whose translation std exceeds this in any direction "
                   "(degenerate scene) [m]",
                   1e-6, 1e3),
    asf::keyDouble("icp_max_sigma_phi_deg", "2", "Same for the heading std [deg]", 1e-6, 180),
    asf::keyDouble("icp_odometry_chi2", "36",
                   "Reject an alignment whose Mahalanobis distance^2 from the odometry "
                   "(odometry + ICP covariance) exceeds this (loose: odometry covariances "
                   "are often over-confident)",
                   0, 1e9),
    asf::keyBool("loop_closure", "true", "Search for loop closures"),
    asf::keyInt("loop_skip_recent", "20", "Loop candidates exclude the last this many keyframes", 1,
                1000000),
    asf::keyDouble("loop_radius", "3",
                   "Loop candidates: old keyframes within this distance of the new one [m]", 0,
                   1e6),
    asf::keyBool("loop_skip_linked", "true",
                 "Loop candidates leave out old keyframes linked to the previous keyframe "
                 "through edges between keyframes within loop_radius (a place the graph has "
                 "tied already: matching it again closes no loop; revisit edges keep tying "
                 "it)"),
    asf::keyDouble("loop_gate_chi2", "9.21",
                   "With valid marginals, also candidates whose distance beyond loop_radius has "
                   "a Mahalanobis distance^2 below this (2 dof; 9.21 = 99%)",
                   0, 1e9),
    asf::keyInt("loop_max_candidates", "3", "Candidates verified per keyframe (nearest first)", 1,
                1000),
    asf::keyInt("loop_candidate_gap", "1",
                "A candidate fewer than this many keyframes from a nearer one is skipped (its "
                "reference overlaps that one's; 2 loop_submap_half + 1: disjoint references)",
                1, 1000000),
    asf::keyInt("loop_max_per_keyframe", "1",
                "Loop edges accepted per keyframe at most (candidates are verified nearest first)",
                1, 1000),
    asf::keyInt("loop_submap_half", "1",
                "Loop reference: the candidate's scan plus this many keyframes each side", 0, 100),
    asf::keyEnum("loop_search", "icp", "icp|correlative",
                 "Loop verification: icp = ICP from the estimate, then (if it passes the "
                 "gates) up to 6 perturbed guesses that must converge to it; "
                 "correlative = correlative scan matching over a window (branch and bound), "
                 "refused when ambiguous, then ICP from its best pose"),
    asf::keyDouble("loop_csm_resolution", "0.1", "Correlative search: grid cell [m]", 0.005, 10),
    asf::keyDouble("loop_csm_sigma", "0.1", "Correlative search: likelihood field std [m]", 0.001,
                   10),
    asf::keyDouble("loop_csm_window_xy", "2", "Correlative search: +- this around the estimate [m]",
                   0, 100),
    asf::keyDouble("loop_csm_window_phi_deg", "20",
                   "Correlative search: +- this around the estimated heading [deg]", 0, 180),
    asf::keyDouble("loop_csm_sigmas", "3",
                   "Correlative search: the window covers this many standard deviations of the "
                   "relative pose (never less than the windows above)",
                   0, 100),
    asf::keyDouble("loop_csm_max_window_xy", "8",
                   "Correlative search: the translation window at most this [m]", 0, 1000),
    asf::keyDouble("loop_csm_min_score", "0.5",
                   "Correlative search: the best pose's mean point likelihood at least this", 0, 1),
    asf::keyDouble("loop_csm_max_ambiguity", "0.9",
                   "Correlative search: refused when a pose off the peak scores more than this "
                   "times the best (a repetitive place)",
                   0, 1),
    asf::keyDouble("loop_csm_peak_radius", "0.6",
                   "Correlative search: poses within this of the best are its peak [m]", 0, 100),
    asf::keyDouble("loop_csm_max_range", "25",
                   "Correlative search: points farther from the sensor are left out [m]", 0.1, 1e4),
    asf::keyBool("loop_confirm", "false",
                 "Hold a loop closure that passed every gate until another one, from another "
                 "keyframe within loop_confirm_window, closes a consistent cycle with it "
                 "(pairwise consistency); then add both"),
    asf::keyInt("loop_confirm_window", "10",
                "Keyframes a held loop closure waits for its confirmation", 1, 100000),
    asf::keyInt("loop_confirm_span", "0",
                "A loop closure is confirmed only by one whose older keyframe lies within this "
                "many keyframes of its own (both join the same two places); 0 = any",
                0, 100000000),
    asf::keyDouble("loop_confirm_chi2", "11.34",
                   "Two loop closures agree when the cycle they close has chi^2 below this "
                   "(3 dof; 11.34 = 99%)",
                   0, 1e9),
    asf::keyDouble("loop_perturb_xy", "0.3",
                   "Loop verification: initial guesses shifted by +-this in x and y [m]", 0, 100),
    asf::keyDouble("loop_perturb_phi_deg", "10",
                   "Loop verification: initial guesses turned by +-this [deg]", 0, 180),
    asf::keyInt("loop_min_agree", "4",
                "Of the 7 ICP runs (estimate and 6 perturbed guesses), at least this many must "
                "converge to the estimate's run, which must pass the loop gates first; the "
                "perturbed runs stop once this many agree or too few are left",
                1, 7),
    asf::keyDouble("loop_min_goodness", "0.6", "Loop ICP: minimum CICP goodness", 0, 1),
    asf::keyDouble("loop_min_inlier_ratio", "0.6",
                   "Loop ICP: minimum fraction of points within icp_inlier_dist", 0, 1),
    asf::keyDouble("loop_max_rmse", "0.05", "Loop ICP: maximum RMS residual of the inliers [m]", 0,
                   10),
    asf::keyDouble("loop_chi2", "11.34",
                   "Accept a loop edge only if its chi^2 against the current estimate "
                   "(relative + ICP covariance) is below this (3 dof; 11.34 = 99%)",
                   0, 1e9),
};

}  // namespace
