// frontend_icp_graph: graph-SLAM front-end. Keyframes by travelled distance / rotation (as
// frontend_odometry); each new keyframe's scan is aligned by ICP (MRPT CICP, LM variant) to a
// local submap of the last keyframes, starting from odometry; the ICP result replaces the
// odometry edge when it passes a quality gate. Loop closures: old keyframes near the current
// estimate (distance radius, Mahalanobis with the back-end's marginals), verified by ICP from
// several initial guesses and a chi^2 test against the current estimate.
#include <asf/errors.h>
#include <asf/frontend.h>
#include <asf/mapping/keyframe_tracker.h>
#include <asf/pose_covariance.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "frontend_icp_graph_keys.h"
#include "loop_search.h"
#include "match_gates.h"
#include "scan_matcher.h"

namespace {

using asf::composeWithCov;
using asf::edgeCovarianceInFrom;
using asf::edgeInformation;
using asf::icp_graph::Cloud;
using asf::icp_graph::LoopHypothesis;
using asf::icp_graph::MatchResult;
using asf::icp_graph::poseDiff;
using asf::icp_graph::relativeCov;
using mrpt::poses::CPose2D;

constexpr double kDeg = M_PI / 180.0;

Eigen::Matrix3d diag3(double sxy, double sphi) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
}

class IcpGraphFrontend final : public asf::Frontend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    kf_.setThresholds(p.getDouble("keyframe_distance"), p.getDouble("keyframe_angle_deg") * kDeg);
    gates_.odo_floor = diag3(p.getDouble("min_sigma_xy"), p.getDouble("min_sigma_phi"));
    icp_.method = p.getString("icp_method") == "point_to_line"
                      ? asf::icp_graph::IcpMethod::PointToLine
                      : asf::icp_graph::IcpMethod::MrptLm;
    icp_.max_iterations = static_cast<int>(p.getInt("icp_max_iterations"));
    gates_.max_iterations = icp_.max_iterations;
    icp_.threshold_dist = p.getDouble("icp_threshold_dist");
    icp_.threshold_ang_deg = p.getDouble("icp_threshold_ang_deg");
    icp_.alfa = p.getDouble("icp_alfa");
    icp_.smallest_threshold_dist = p.getDouble("icp_smallest_threshold_dist");
    icp_.decimation = static_cast<int>(p.getInt("icp_decimation"));
    icp_.inlier_dist = p.getDouble("icp_inlier_dist");
    icp_.sigma_floor = p.getDouble("icp_sigma_floor");
    icp_.cov_scale = p.getDouble("icp_cov_scale");
    icp_.refine_iterations = static_cast<int>(p.getInt("icp_refine_iterations"));
    icp_.robust = p.getBool("icp_robust");
    normal_k_ = static_cast<std::size_t>(p.getInt("icp_normal_neighbours"));
    ref_cell_ = p.getDouble("icp_reference_cell");
    normal_radius_ = p.getDouble("icp_normal_radius");
    gates_.icp_floor =
        diag3(p.getDouble("icp_min_sigma_xy"), p.getDouble("icp_min_sigma_phi_deg") * kDeg);
    submap_ = static_cast<int>(p.getInt("submap_keyframes"));
    submap_radius_ = p.getDouble("submap_radius");
    submap_nearby_ = static_cast<int>(p.getInt("submap_nearby_keyframes"));
    min_points_ = static_cast<std::size_t>(p.getInt("icp_min_points"));
    gates_.min_goodness = p.getDouble("icp_min_goodness");
    likelihood_fallback_ = p.getString("icp_low_goodness") == "likelihood";
    gates_.max_sigma_xy = p.getDouble("icp_max_sigma_xy");
    gates_.max_sigma_phi = p.getDouble("icp_max_sigma_phi_deg") * kDeg;
    gates_.odometry_chi2 = p.getDouble("icp_odometry_chi2");
    loop_ = p.getBool("loop_closure");
    loop_skip_ = static_cast<int>(p.getInt("loop_skip_recent"));
    loop_radius_ = p.getDouble("loop_radius");
    loop_skip_linked_ = p.getBool("loop_skip_linked");
    loop_gate_ = p.getDouble("loop_gate_chi2");
    loop_max_cand_ = static_cast<int>(p.getInt("loop_max_candidates"));
    loop_cand_gap_ = static_cast<int>(p.getInt("loop_candidate_gap"));
    loop_max_accept_ = static_cast<int>(p.getInt("loop_max_per_keyframe"));
    loop_submap_ = static_cast<int>(p.getInt("loop_submap_half"));
    search_.perturb_xy = p.getDouble("loop_perturb_xy");
    search_.perturb_phi = p.getDouble("loop_perturb_phi_deg") * kDeg;
    search_.min_agree = static_cast<int>(p.getInt("loop_min_agree"));
    gates_.loop_min_goodness = p.getDouble("loop_min_goodness");
    gates_.loop_min_inliers = p.getDouble("loop_min_inlier_ratio");
    gates_.loop_max_rmse = p.getDouble("loop_max_rmse");
    gates_.loop_chi2 = p.getDouble("loop_chi2");
    search_.correlative = p.getString("loop_search") == "correlative";
    auto& csm_ = search_.csm;
    csm_.resolution = p.getDouble("loop_csm_resolution");
    csm_.sigma = p.getDouble("loop_csm_sigma");
    csm_.window_xy = p.getDouble("loop_csm_window_xy");
    csm_.window_phi = p.getDouble("loop_csm_window_phi_deg") * kDeg;
    csm_.min_score = p.getDouble("loop_csm_min_score");
    csm_.max_ambiguity = p.getDouble("loop_csm_max_ambiguity");
    csm_.peak_radius = p.getDouble("loop_csm_peak_radius");
    csm_.max_range = p.getDouble("loop_csm_max_range");
    csm_sigmas_ = p.getDouble("loop_csm_sigmas");
    confirm_ = p.getBool("loop_confirm");
    confirm_window_ = static_cast<int>(p.getInt("loop_confirm_window"));
    confirm_span_ = static_cast<std::size_t>(p.getInt("loop_confirm_span"));
    confirm_chi2_ = p.getDouble("loop_confirm_chi2");
    csm_max_window_xy_ = p.getDouble("loop_csm_max_window_xy");
    search_.icp = icp_;
    search_.min_points = min_points_;
    if (icp_.smallest_threshold_dist >= icp_.threshold_dist)
      p.fail("icp_smallest_threshold_dist", "must be below icp_threshold_dist");
  }

  bool process(const asf::SensorFrame& f, asf::PoseGraph& g,
               const asf::Marginals& marginals) override {
    switch (kf_.begin(f, g)) {
      case asf::mapping::KeyframeTracker::Begin::AddedRoot:
        nodeAdded(g, 0, f);
        return true;
      case asf::mapping::KeyframeTracker::Begin::Continued:
        MRPT_LOG_WARN_STREAM("graph not empty on the first frame: continuing from node "
                             << kf_.last());
        return false;
      case asf::mapping::KeyframeTracker::Begin::NotFirst:
        break;
    }
    if (!kf_.due()) return false;
    // Past the threshold on a frame without a scan: wait for one (a scan-less keyframe gets no
    // ICP), unless the robot has gone twice the threshold.
    if (!f.scan && !kf_.due(2)) return false;
    const CPose2D acc = kf_.increment();
    const Eigen::Matrix3d acc_cov = kf_.incrementCov();
    const asf::NodeId last = kf_.last();

    // The back-end's marginals describe this graph only if nothing changed since.
    const bool marg_ok = marginals.valid() && marginals.graph_revision == g.revision &&
                         marginals.node.size() == g.size();

    asf::PoseEdge e;
    e.from = last;
    e.mean = acc;
    e.kind = asf::EdgeKind::Odometry;
    Eigen::Matrix3d cov = acc_cov + gates_.odo_floor;  // additive, frame of `from`
    std::shared_ptr<const Cloud> cur;
    if (f.scan) {
      cur = std::make_shared<const Cloud>(Cloud::fromScan(*f.scan));
      matchToSubmap(g, last, *cur, acc, acc_cov, e, cov);
    }
    // `cov` already holds the floor of its kind.
    e.information = edgeInformation(e.mean, cov, Eigen::Matrix3d::Zero());
    CPose2D pose = g.nodes[last].pose + e.mean;
    pose.normalizePhi();
    const asf::NodeId prev = last;
    e.to = kf_.addKeyframe(g, pose, f);
    nodeAdded(g, e.to, f);
    clouds_[e.to] = cur;
    seq_edge_[e.to] = static_cast<long>(g.edges.size());
    g.addEdge(e);

    if (submap_radius_ > 0 && cur) {
      const asf::NodeId span = static_cast<asf::NodeId>(submap_) - 1;
      revisitEdge(g, e.to, prev >= span ? prev - span : 0);
    }
    if (loop_ && cur) {
      std::optional<Eigen::Matrix3d> Cj;
      if (marg_ok) {
        // Cov(x_new) from the last node's marginal and the new edge (first order).
        Eigen::Matrix3d C;
        composeWithCov(g.nodes[prev].pose, marginals.node[prev], e.mean, cov, C);
        Cj = C;
      }
      tryLoopClosure(g, e.to, prev, marg_ok ? &marginals : nullptr, Cj);
    }
    return true;
  }

  CPose2D currentPose(const asf::PoseGraph& g) const override { return kf_.currentPose(g); }

 private:
  /// Per-node state for a keyframe the tracker just added.
  void nodeAdded(const asf::PoseGraph& g, asf::NodeId id, const asf::SensorFrame& f) {
    clouds_.resize(g.size());
    seq_edge_.resize(g.size(), -1);
    if (id == 0 && f.scan) clouds_[0] = std::make_shared<const Cloud>(Cloud::fromScan(*f.scan));
  }

  /// The node's scan as a cloud in its robot frame (built on first use for nodes this
  /// front-end did not create), or null.
  std::shared_ptr<const Cloud> cloudOf(const asf::PoseGraph& g, asf::NodeId id) {
    if (clouds_.size() < g.size()) clouds_.resize(g.size()), seq_edge_.resize(g.size(), -1);
    if (!clouds_[id] && g.nodes[id].scan)
      clouds_[id] = std::make_shared<const Cloud>(Cloud::fromScan(*g.nodes[id].scan));
    return clouds_[id];
  }

  /// Scans of nodes [first, last] in the frame of node `frame`, placed by the current estimate.
  Cloud submap(const asf::PoseGraph& g, asf::NodeId frame, asf::NodeId first, asf::NodeId last) {
    Cloud out;
    out.setNormalNeighbourhood(normal_k_, normal_radius_);
    const CPose2D inv = CPose2D() - g.nodes[frame].pose;
    for (asf::NodeId k = first; k <= last && k < g.size(); ++k)
      if (auto c = cloudOf(g, k)) out.add(*c, inv + g.nodes[k].pose);
    return out;
  }

  /// Keyframes with a scan before `before` within submap_radius_ of `c`, nearest first, at
  /// most submap_nearby_ (the old keyframes of a place the robot is revisiting).
  std::vector<asf::NodeId> nearbyKeyframes(const asf::PoseGraph& g, const CPose2D& c,
                                           asf::NodeId before) const {
    std::vector<std::pair<double, asf::NodeId>> near;
    for (asf::NodeId k = 0; k < before && k < g.size(); ++k) {
      if (!g.nodes[k].scan) continue;
      const double d = std::hypot(g.nodes[k].pose.x() - c.x(), g.nodes[k].pose.y() - c.y());
      if (d <= submap_radius_) near.emplace_back(d, k);
    }
    std::sort(near.begin(), near.end());
    if (near.size() > static_cast<std::size_t>(submap_nearby_)) near.resize(submap_nearby_);
    std::vector<asf::NodeId> out;
    for (const auto& [d, k] : near) out.push_back(k);
    return out;
  }

  /// Adds the scans of `ids` to `out`, placed by the estimate in the frame of node `frame`.
  void addScans(const asf::PoseGraph& g, asf::NodeId frame, const std::vector<asf::NodeId>& ids,
                Cloud& out) {
    const CPose2D inv = CPose2D() - g.nodes[frame].pose;
    for (asf::NodeId k : ids)
      if (auto c = cloudOf(g, k)) out.add(*c, inv + g.nodes[k].pose);
  }

  /// Revisit edge: the new keyframe j matched against the old keyframes (before `first`, the
  /// start of the sequential submap) near it, in the frame of the nearest one, k. Added as an
  /// edge k -> j when the alignment is good and agrees with the chain estimate, so a revisited
  /// place is tied to its first visit at every keyframe, not only at verified loop closures.
  void revisitEdge(asf::PoseGraph& g, asf::NodeId j, asf::NodeId first) {
    const CPose2D& xj = g.nodes[j].pose;
    const std::vector<asf::NodeId> near = nearbyKeyframes(g, xj, first);
    if (near.empty()) return;
    const asf::NodeId k = near.front();
    Cloud ref;
    ref.setNormalNeighbourhood(normal_k_, normal_radius_);
    addScans(g, k, near, ref);
    ref.thin(ref_cell_);
    const CPose2D inv = CPose2D() - g.nodes[k].pose;
    const CPose2D est = inv + xj;
    const auto Crel = chainCov(g, k, j);
    if (!Crel) return;
    // The correlative search (loop_search = correlative) refuses an ambiguous place here too:
    // a revisit edge is a loop closure by another name.
    std::string why, how = "one ICP guess";
    const std::optional<MatchResult> found =
        search_.correlative
            ? asf::icp_graph::loopAlignment(ref, *clouds_[j], est, searchFor(Crel), why, how)
            : std::optional<MatchResult>(
                  asf::icp_graph::match(ref, *clouds_[j], est, icp_, min_points_));
    if (!found || !found->ran ||
        !asf::icp_graph::loopGateFailure(*found, est, Crel, gates_).empty())
      return;
    const MatchResult& m = *found;
    if (confirm_) {  // held like a loop closure until another agrees
      if (acceptLoop(g, {k, j, m.pose, m.cov + gates_.icp_floor}, "revisit, " + how)) ++n_revisits_;
      return;
    }
    asf::PoseEdge e;
    e.from = k;
    e.to = j;
    e.mean = m.pose;
    e.kind = asf::EdgeKind::ScanMatch;
    e.information = edgeInformation(m.pose, m.cov + gates_.icp_floor, Eigen::Matrix3d::Zero());
    g.addEdge(e);
    ++g.revision;
    ++n_revisits_;
  }

  /// The sequential match: the new keyframe's scan `cur` aligned by ICP, from the odometry
  /// `acc`, to the submap of the keyframes up to `last`. When it passes the gates (or the
  /// likelihood search takes over), `e` becomes a scan-match edge and `cov` its covariance;
  /// else both stay the odometry's.
  void matchToSubmap(const asf::PoseGraph& g, asf::NodeId last, const Cloud& cur,
                     const CPose2D& acc, const Eigen::Matrix3d& acc_cov, asf::PoseEdge& e,
                     Eigen::Matrix3d& cov) {
    const asf::NodeId span = static_cast<asf::NodeId>(submap_) - 1;
    Cloud ref = submap(g, last, last >= span ? last - span : 0, last);
    // Old keyframes near the predicted pose join the reference: the match then sees the
    // mapped surroundings, not only the last scans. (Uncorrected drift between old and
    // recent scans biases it; revisitEdge() gives the optimizer the direct constraint.)
    if (submap_radius_ > 0)
      addScans(g, last,
               nearbyKeyframes(g, g.nodes[last].pose + acc, last >= span ? last - span : 0), ref);
    ref.thin(ref_cell_);
    const MatchResult m = asf::icp_graph::match(ref, cur, acc, icp_, min_points_);
    std::string why =
        asf::icp_graph::sequentialGateFailure(m, acc, acc_cov, gates_.min_goodness, gates_);
    std::optional<MatchResult> used;
    if (why.empty())
      used = m;
    else if (likelihood_fallback_ && m.ran && m.goodness < gates_.min_goodness)
      used = likelihoodMatch(ref, cur, acc, acc_cov, why);
    if (used) {
      e.mean = used->pose;
      cov = used->cov + gates_.icp_floor;
      e.kind = asf::EdgeKind::ScanMatch;
      ++n_scan_match_;
    } else {
      ++n_fallback_;
      MRPT_LOG_DEBUG_STREAM("keyframe " << g.size() << ": odometry edge (" << why << ")");
    }
  }

  /// Open space (issue 25): far or sparse walls leave ICP few correspondences, so
  /// point-to-line goodness refuses alignments that are right. Such a keyframe is searched
  /// again as a scan-to-map likelihood: the correlative search over the odometry's uncertainty
  /// in the submap (refused when it explains too little of the scan or is ambiguous), refined
  /// by ICP, then held to every sequential gate but goodness. nullopt (and `why`) if it fails.
  std::optional<MatchResult> likelihoodMatch(const Cloud& ref, const Cloud& cur, const CPose2D& acc,
                                             const Eigen::Matrix3d& acc_cov, std::string& why) {
    asf::icp_graph::LoopSearchOptions o = search_;
    o.correlative = true;
    // The window covers loop_csm_sigmas standard deviations of the odometry (two cells and
    // two degrees at least, loop_csm_max_window_xy at most, as for loops): a pose the
    // odometry rules out is no rival to the best one.
    const auto w =
        asf::icp_graph::windowCovering(acc_cov + gates_.odo_floor, csm_sigmas_,
                                       2 * o.csm.resolution, csm_max_window_xy_, 2 * kDeg, M_PI);
    o.csm.window_xy = w.xy;
    o.csm.window_phi = w.phi;
    std::string searched, how;
    const auto r = asf::icp_graph::loopAlignment(ref, cur, acc, o, searched, how);
    const std::string failed =
        r ? asf::icp_graph::sequentialGateFailure(*r, acc, acc_cov, 0.0, gates_) : searched;
    if (failed.empty()) {
      MRPT_LOG_DEBUG_STREAM("keyframe " << kf_.last() + 1 << ": scan-to-map likelihood match ("
                                        << why << "; " << how << ")");
      return r;
    }
    why += "; likelihood search: " + failed;
    return std::nullopt;
  }

  /// Covariance of the relative pose i -> j from the chain of sequential edges (ignores loop
  /// closures, so it over-estimates after earlier closures); nullopt if the chain is unknown.
  std::optional<Eigen::Matrix3d> chainCov(const asf::PoseGraph& g, asf::NodeId i,
                                          asf::NodeId j) const {
    CPose2D acc;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (asf::NodeId k = i + 1; k <= j; ++k) {
      if (k >= seq_edge_.size() || seq_edge_[k] < 0) return std::nullopt;
      const asf::PoseEdge& e = g.edges[static_cast<std::size_t>(seq_edge_[k])];
      Eigen::Matrix3d out;
      acc = composeWithCov(acc, C, e.mean, edgeCovarianceInFrom(e), out);
      C = out;
    }
    return C;
  }

  /// The loop search options for a candidate whose relative pose has covariance `Crel`: the
  /// correlative window covers loop_csm_sigmas standard deviations of it (at least the
  /// configured window, at most loop_csm_max_window_xy), so the true pose of a drifted
  /// estimate is in view, and with it whatever else matches as well (ambiguity).
  asf::icp_graph::LoopSearchOptions searchFor(const std::optional<Eigen::Matrix3d>& Crel) const {
    asf::icp_graph::LoopSearchOptions o = search_;
    if (!o.correlative || !Crel) return o;
    const auto w = asf::icp_graph::windowCovering(*Crel, csm_sigmas_, o.csm.window_xy,
                                                  csm_max_window_xy_, o.csm.window_phi, M_PI);
    o.csm.window_xy = w.xy;
    o.csm.window_phi = w.phi;
    return o;
  }

  /// A loop hypothesis that passed every gate: added at once, or (loop_confirm) held until a
  /// later one, from another keyframe within loop_confirm_window, closes a consistent cycle
  /// with it; then both are added. Returns whether `h` was added.
  bool acceptLoop(asf::PoseGraph& g, const LoopHypothesis& h, const std::string& how) {
    if (!confirm_) {
      addLoopEdge(g, h, how);
      return true;
    }
    pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                  [&](const Pending& p) {
                                    return h.to - p.h.to >
                                           static_cast<std::size_t>(confirm_window_);
                                  }),
                   pending_.end());
    for (Pending& p : pending_) {
      if (!asf::icp_graph::mayConfirm(p.h, h, confirm_span_)) continue;
      const double chi2 = pairChi2(g, p.h, h);
      if (!(chi2 <= confirm_chi2_)) {
        MRPT_LOG_DEBUG_STREAM("loop candidate " << h.from << " -> " << h.to << " disagrees with "
                                                << p.h.from << " -> " << p.h.to << " (cycle chi2 "
                                                << chi2 << ")");
        continue;
      }
      std::ostringstream said;
      said << ", agrees with " << p.h.from << " -> " << p.h.to << " (cycle chi2 " << chi2 << ")";
      if (!p.added)
        addLoopEdge(g, p.h,
                    "confirmed by " + std::to_string(h.from) + " -> " + std::to_string(h.to));
      p.added = true;
      addLoopEdge(g, h, how + said.str());
      pending_.push_back({h, true});
      return true;
    }
    pending_.push_back({h, false});
    MRPT_LOG_DEBUG_STREAM("loop candidate " << h.from << " -> " << h.to << " held: " << how
                                            << "; waits for another loop that agrees");
    return false;
  }

  void addLoopEdge(asf::PoseGraph& g, const LoopHypothesis& h, const std::string& how) {
    asf::PoseEdge le;
    le.from = h.from;
    le.to = h.to;
    le.mean = h.mean;
    le.kind = asf::EdgeKind::LoopClosure;
    le.information = edgeInformation(h.mean, h.cov, Eigen::Matrix3d::Zero());
    g.addEdge(le);
    ++g.revision;
    ++n_loops_;
    MRPT_LOG_INFO_STREAM("loop closure " << h.from << " -> " << h.to << ": " << how << " ("
                                         << n_loops_ << " accepted, " << n_loop_rejects_
                                         << " rejected)");
  }

  /// chi^2 of the cycle two loop hypotheses close (loopPairChi2), with the trajectory between
  /// their ends from the estimate and the chain covariance; infinite if a chain is unknown.
  double pairChi2(const asf::PoseGraph& g, const LoopHypothesis& a, const LoopHypothesis& b) const {
    auto between = [&](asf::NodeId x, asf::NodeId y, Eigen::Matrix3d& C) -> std::optional<CPose2D> {
      C.setZero();
      if (x == y) return CPose2D();
      const asf::NodeId lo = std::min(x, y), hi = std::max(x, y);
      const auto Cc = chainCov(g, lo, hi);
      if (!Cc) return std::nullopt;
      const CPose2D p = CPose2D() - g.nodes[lo].pose + g.nodes[hi].pose;
      if (x < y) {
        C = *Cc;
        return p;
      }
      return asf::inverseWithCov(p, *Cc, C);
    };
    Eigen::Matrix3d Ci, Cj;
    const auto ri = between(a.from, b.from, Ci), rj = between(a.to, b.to, Cj);
    if (!ri || !rj) return std::numeric_limits<double>::infinity();
    return asf::icp_graph::loopPairChi2(a, b, *ri, Ci, *rj, Cj);
  }

  void tryLoopClosure(asf::PoseGraph& g, asf::NodeId j, asf::NodeId prev,
                      const asf::Marginals* marg, const std::optional<Eigen::Matrix3d>& Cj) {
    if (static_cast<long>(j) - loop_skip_ <= 0) return;
    const auto cur = clouds_[j];
    const CPose2D& xj = g.nodes[j].pose;
    asf::icp_graph::CandidateGate cg;
    cg.skip_recent = loop_skip_;
    cg.radius = loop_radius_;
    cg.gate_chi2 = loop_gate_;
    cg.max_candidates = loop_max_cand_;
    cg.min_gap = loop_cand_gap_;
    cg.skip_linked = loop_skip_linked_;
    const std::vector<asf::NodeId> cands = asf::icp_graph::loopCandidates(g, j, prev, marg, Cj, cg);

    int accepted = 0;
    for (const asf::NodeId i : cands) {
      const asf::NodeId first = i >= static_cast<asf::NodeId>(loop_submap_) ? i - loop_submap_ : 0;
      const asf::NodeId last = std::min<asf::NodeId>(
          i + loop_submap_,
          static_cast<asf::NodeId>(std::max<long>(0, static_cast<long>(j) - loop_skip_ - 1)));
      Cloud ref = submap(g, i, first, std::max(last, i));
      ref.thin(ref_cell_);
      const CPose2D est = CPose2D() - g.nodes[i].pose + xj;
      std::optional<Eigen::Matrix3d> Crel;
      if (marg && Cj && i < marg->node.size()) {
        Crel = relativeCov(g.nodes[i].pose, xj, marg->node[i], *Cj, Eigen::Matrix3d::Zero());
      } else {
        Crel = chainCov(g, i, j);
      }
      std::string how, searched;
      const asf::icp_graph::LoopGate gate = [&](const MatchResult& m) {
        return asf::icp_graph::loopGateFailure(m, est, Crel, gates_);
      };
      const std::optional<MatchResult> best =
          asf::icp_graph::loopAlignment(ref, *cur, est, searchFor(Crel), searched, how, gate);
      double chi2 = 0;
      const std::string failed =
          best ? asf::icp_graph::loopGateFailure(*best, est, Crel, gates_, &chi2) : searched;
      if (failed.empty()) {
        std::ostringstream said;
        said << "chi2 " << chi2 << ", inliers " << best->inlier_ratio << ", rmse " << best->rmse
             << ", " << how;
        if (acceptLoop(g, {i, j, best->pose, best->cov + gates_.icp_floor}, said.str()) &&
            ++accepted >= loop_max_accept_)
          return;
        continue;
      }
      ++n_loop_rejects_;
      MRPT_LOG_DEBUG_STREAM("loop candidate " << i << " -> " << j << " rejected: " << failed);
    }
  }

  // configuration
  asf::icp_graph::MatchGates gates_;  ///< completed in configure
  asf::icp_graph::IcpOptions icp_;
  int submap_ = 1, submap_nearby_ = 5;
  double submap_radius_ = 0;
  std::size_t normal_k_ = 8;
  double ref_cell_ = 0;
  double normal_radius_ = 0.3;
  std::size_t min_points_ = 20;
  bool likelihood_fallback_ = false;
  bool loop_ = true, loop_skip_linked_ = false;
  int loop_skip_ = 20, loop_max_cand_ = 3, loop_cand_gap_ = 1, loop_max_accept_ = 1,
      loop_submap_ = 1;
  double loop_radius_ = 3, loop_gate_ = 9.21;
  asf::icp_graph::LoopSearchOptions search_;  ///< loop alignment (completed in configure)
  double csm_sigmas_ = 3, csm_max_window_xy_ = 8;
  bool confirm_ = false;
  int confirm_window_ = 10;
  std::size_t confirm_span_ = 0;
  double confirm_chi2_ = 11.34;
  // state
  asf::mapping::KeyframeTracker kf_{"icp_graph front-end"};
  std::vector<std::shared_ptr<const Cloud>> clouds_;  ///< per node, robot frame
  std::vector<long> seq_edge_;  ///< per node: index of the edge from its predecessor, or -1
  struct Pending {
    LoopHypothesis h;
    bool added;  ///< confirmed (its edge is in the graph)
  };
  std::vector<Pending> pending_;  ///< loop hypotheses of the last loop_confirm_window keyframes
  long n_scan_match_ = 0, n_fallback_ = 0, n_loops_ = 0, n_loop_rejects_ = 0, n_revisits_ = 0;
};

}  // namespace

ASF_PLUGIN(
    IcpGraphFrontend, asf::PluginKind::Frontend, "icp_graph", "1.0.0",
    "Graph-SLAM front-end: keyframes joined by ICP (CICP LM) or odometry edges, ICP-verified "
    "loop closures",
    asf::ThreadSafety::ThreadCompatible, kKeys)
