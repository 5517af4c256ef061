// frontend_icp_graph: graph-SLAM front-end. Keyframes by travelled distance / rotation (as
// frontend_odometry); each new keyframe's scan is aligned by ICP (MRPT CICP, LM variant) to a
// local submap of the last keyframes, starting from odometry; the ICP result replaces the
// odometry edge when it passes a quality gate. Loop closures: old keyframes near the current
// estimate (distance radius, Mahalanobis with the back-end's marginals), verified by ICP from
// several initial guesses and a chi^2 test against the current estimate.
#include <asf/errors.h>
#include <asf/frontend.h>
#include <asf/keyframe_tracker.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "scan_matcher.h"

namespace {

using asf::icp_graph::Cloud;
using asf::composeWithCov;
using asf::edgeInformation;
using asf::icp_graph::MatchResult;
using asf::icp_graph::poseDiff;
using mrpt::poses::CPose2D;

constexpr double kDeg = M_PI / 180.0;

Eigen::Matrix3d diag3(double sxy, double sphi) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, sphi * sphi).asDiagonal();
}

/// Covariance of an edge's mean as additive (x, y, phi) in the frame of `from`, recovered from
/// its information (inverse of edgeInformation without the floor).
Eigen::Matrix3d edgeCovInFrom(const asf::PoseEdge& e) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(e.mean.phi()), s = std::sin(e.mean.phi());
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R * e.information.inverse() * R.transpose();
}

class IcpGraphFrontend final : public asf::Frontend {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    kf_.setThresholds(p.getDouble("keyframe_distance"), p.getDouble("keyframe_angle_deg") * kDeg);
    odo_floor_ = diag3(p.getDouble("min_sigma_xy"), p.getDouble("min_sigma_phi"));
    icp_.max_iterations = static_cast<int>(p.getInt("icp_max_iterations"));
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
    normal_radius_ = p.getDouble("icp_normal_radius");
    icp_floor_ = diag3(p.getDouble("icp_min_sigma_xy"), p.getDouble("icp_min_sigma_phi_deg") * kDeg);
    submap_ = static_cast<int>(p.getInt("submap_keyframes"));
    submap_radius_ = p.getDouble("submap_radius");
    submap_nearby_ = static_cast<int>(p.getInt("submap_nearby_keyframes"));
    min_points_ = static_cast<std::size_t>(p.getInt("icp_min_points"));
    min_goodness_ = p.getDouble("icp_min_goodness");
    max_sigma_xy_ = p.getDouble("icp_max_sigma_xy");
    max_sigma_phi_ = p.getDouble("icp_max_sigma_phi_deg") * kDeg;
    odo_chi2_ = p.getDouble("icp_odometry_chi2");
    loop_ = p.getBool("loop_closure");
    loop_skip_ = static_cast<int>(p.getInt("loop_skip_recent"));
    loop_radius_ = p.getDouble("loop_radius");
    loop_gate_ = p.getDouble("loop_gate_chi2");
    loop_max_cand_ = static_cast<int>(p.getInt("loop_max_candidates"));
    loop_max_accept_ = static_cast<int>(p.getInt("loop_max_per_keyframe"));
    loop_submap_ = static_cast<int>(p.getInt("loop_submap_half"));
    loop_pert_xy_ = p.getDouble("loop_perturb_xy");
    loop_pert_phi_ = p.getDouble("loop_perturb_phi_deg") * kDeg;
    loop_min_agree_ = static_cast<int>(p.getInt("loop_min_agree"));
    loop_min_goodness_ = p.getDouble("loop_min_goodness");
    loop_min_inliers_ = p.getDouble("loop_min_inlier_ratio");
    loop_max_rmse_ = p.getDouble("loop_max_rmse");
    loop_chi2_ = p.getDouble("loop_chi2");
    if (icp_.smallest_threshold_dist >= icp_.threshold_dist)
      p.fail("icp_smallest_threshold_dist", "must be below icp_threshold_dist");
  }

  bool process(const asf::SensorFrame& f, asf::PoseGraph& g,
               const asf::Marginals& marginals) override {
    switch (kf_.begin(f, g)) {
      case asf::KeyframeTracker::Begin::AddedRoot:
        nodeAdded(g, 0, f);
        return true;
      case asf::KeyframeTracker::Begin::Continued:
        MRPT_LOG_WARN_STREAM("graph not empty on the first frame: continuing from node "
                             << kf_.last());
        return false;
      case asf::KeyframeTracker::Begin::NotFirst: break;
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
    Eigen::Matrix3d cov = acc_cov + odo_floor_;  // additive, frame of `from`
    std::shared_ptr<const Cloud> cur;
    if (f.scan) {
      cur = std::make_shared<const Cloud>(Cloud::fromScan(*f.scan));
      const asf::NodeId span = static_cast<asf::NodeId>(submap_) - 1;
      Cloud ref = submap(g, last, last >= span ? last - span : 0, last);
      // Old keyframes near the predicted pose join the reference: the match then sees the
      // mapped surroundings, not only the last scans. (Uncorrected drift between old and
      // recent scans biases it; revisitEdge() gives the optimizer the direct constraint.)
      if (submap_radius_ > 0)
        addScans(g, last, nearbyKeyframes(g, g.nodes[last].pose + acc, last >= span ? last - span : 0), ref);
      const MatchResult m = asf::icp_graph::match(ref, *cur, acc, icp_, min_points_);
      std::string why;
      if (sequentialGate(m, acc, acc_cov, why)) {
        e.mean = m.pose;
        cov = m.cov + icp_floor_;
        e.kind = asf::EdgeKind::ScanMatch;
        ++n_scan_match_;
      } else {
        ++n_fallback_;
        MRPT_LOG_DEBUG_STREAM("keyframe " << g.size() << ": odometry edge (" << why << ")");
      }
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
  Cloud submap(const asf::PoseGraph& g, asf::NodeId frame, asf::NodeId first,
               asf::NodeId last) {
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
    const CPose2D inv = CPose2D() - g.nodes[k].pose;
    const CPose2D est = inv + xj;
    const MatchResult m = asf::icp_graph::match(ref, *clouds_[j], est, icp_, min_points_);
    if (!m.ran || m.goodness < loop_min_goodness_ || m.inlier_ratio < loop_min_inliers_ ||
        m.rmse > loop_max_rmse_ || !sigmasOk(m.cov))
      return;
    const auto Crel = chainCov(g, k, j);
    if (!Crel) return;
    const Eigen::Vector3d d = poseDiff(m.pose, est);
    const double chi2 = d.dot((*Crel + m.cov + icp_floor_).ldlt().solve(d));
    if (!(chi2 <= loop_chi2_)) return;
    asf::PoseEdge e;
    e.from = k;
    e.to = j;
    e.mean = m.pose;
    e.kind = asf::EdgeKind::ScanMatch;
    e.information = edgeInformation(m.pose, m.cov + icp_floor_, Eigen::Matrix3d::Zero());
    g.addEdge(e);
    ++g.revision;
    ++n_revisits_;
  }

  bool sequentialGate(const MatchResult& m, const CPose2D& acc, const Eigen::Matrix3d& acc_cov,
                      std::string& why) const {
    std::ostringstream os;
    if (!m.ran) why = m.reason;
    else if (static_cast<int>(m.iterations) >= icp_.max_iterations)
      os << "ICP did not converge in " << m.iterations << " iterations";
    else if (m.goodness < min_goodness_)
      os << "goodness " << m.goodness << " < " << min_goodness_;
    else if (!sigmasOk(m.cov))
      os << "ill-conditioned alignment (sigmas " << std::sqrt(m.cov(0, 0)) << ", "
         << std::sqrt(m.cov(1, 1)) << ", " << std::sqrt(m.cov(2, 2)) << ")";
    else {
      const Eigen::Vector3d d = poseDiff(m.pose, acc);
      const Eigen::Matrix3d C = acc_cov + odo_floor_ + m.cov + icp_floor_;
      const double chi2 = d.dot(C.ldlt().solve(d));
      if (!(chi2 <= odo_chi2_)) os << "disagrees with odometry: chi2 " << chi2;
    }
    if (m.ran) why = os.str();
    return why.empty();
  }

  bool sigmasOk(const Eigen::Matrix3d& C) const {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C.topLeftCorner<2, 2>());
    return es.eigenvalues()(1) <= max_sigma_xy_ * max_sigma_xy_ &&
           C(2, 2) <= max_sigma_phi_ * max_sigma_phi_;
  }

  /// Covariance of xi^-1 (+) xj (additive, frame of i) from global marginals Ci, Cj and the
  /// cross-covariance Cij = Cov(xi, xj).
  static Eigen::Matrix3d relativeCov(const CPose2D& xi, const CPose2D& xj,
                                     const Eigen::Matrix3d& Ci, const Eigen::Matrix3d& Cj,
                                     const Eigen::Matrix3d& Cij) {
    const double c = std::cos(xi.phi()), s = std::sin(xi.phi());
    const double dx = xj.x() - xi.x(), dy = xj.y() - xi.y();
    Eigen::Matrix3d Ji = Eigen::Matrix3d::Zero(), Jj = Eigen::Matrix3d::Identity();
    Ji.topLeftCorner<2, 2>() << -c, -s, s, -c;
    Ji(0, 2) = -s * dx + c * dy;
    Ji(1, 2) = -c * dx - s * dy;
    Ji(2, 2) = -1;
    Jj.topLeftCorner<2, 2>() << c, s, -s, c;
    const Eigen::Matrix3d X = Ji * Cij * Jj.transpose();
    return Ji * Ci * Ji.transpose() + Jj * Cj * Jj.transpose() + X + X.transpose();
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
      acc = composeWithCov(acc, C, e.mean, edgeCovInFrom(e), out);
      C = out;
    }
    return C;
  }

  void tryLoopClosure(asf::PoseGraph& g, asf::NodeId j, asf::NodeId prev,
                      const asf::Marginals* marg, const std::optional<Eigen::Matrix3d>& Cj) {
    if (static_cast<long>(j) - loop_skip_ <= 0) return;
    const auto cur = clouds_[j];
    const CPose2D& xj = g.nodes[j].pose;
    struct Cand {
      asf::NodeId id;
      double d2, dist;
    };
    std::vector<Cand> cands;
    for (asf::NodeId i = 0; static_cast<long>(i) < static_cast<long>(j) - loop_skip_; ++i) {
      if (!g.nodes[i].scan) continue;
      const CPose2D rel = CPose2D() - g.nodes[i].pose + xj;
      const double dist = std::hypot(rel.x(), rel.y());
      double d2 = dist <= loop_radius_ ? 0.0 : std::numeric_limits<double>::infinity();
      if (marg && Cj && i < marg->node.size()) {
        // Could the true distance be within the radius? Mahalanobis distance of the part of the
        // relative translation beyond the radius, with the relative covariance.
        auto it = marg->cross.find({i, prev});
        // Cov(xi, xj) ~ Cov(xi, xprev) A^T, A = d xj / d xprev (first order).
        Eigen::Matrix3d Cij = Eigen::Matrix3d::Zero();
        if (it != marg->cross.end()) {
          const CPose2D& xp = g.nodes[prev].pose;
          const CPose2D u = CPose2D() - xp + xj;
          Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
          A(0, 2) = -std::sin(xp.phi()) * u.x() - std::cos(xp.phi()) * u.y();
          A(1, 2) = std::cos(xp.phi()) * u.x() - std::sin(xp.phi()) * u.y();
          Cij = it->second * A.transpose();
        }
        const Eigen::Matrix3d Cr = relativeCov(g.nodes[i].pose, xj, marg->node[i], *Cj, Cij);
        const Eigen::Vector2d t(rel.x(), rel.y());
        const Eigen::Vector2d beyond =
            dist > loop_radius_ ? Eigen::Vector2d(t * (1 - loop_radius_ / dist))
                                : Eigen::Vector2d::Zero();
        const Eigen::Matrix2d S = Cr.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
        d2 = std::min(d2, beyond.dot(S.ldlt().solve(beyond)));
      }
      if (d2 <= loop_gate_) cands.push_back({i, d2, dist});
    }
    std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) {
      return a.dist != b.dist ? a.dist < b.dist : a.id < b.id;
    });
    if (static_cast<int>(cands.size()) > loop_max_cand_) cands.resize(loop_max_cand_);

    int accepted = 0;
    for (const Cand& c : cands) {
      const asf::NodeId i = c.id;
      const asf::NodeId first = i >= static_cast<asf::NodeId>(loop_submap_) ? i - loop_submap_ : 0;
      const asf::NodeId last = std::min<asf::NodeId>(
          i + loop_submap_, static_cast<asf::NodeId>(std::max<long>(0, static_cast<long>(j) - loop_skip_ - 1)));
      const Cloud ref = submap(g, i, first, std::max(last, i));
      const CPose2D est = CPose2D() - g.nodes[i].pose + xj;
      std::vector<CPose2D> guesses{est};
      for (int sgn : {-1, 1}) {
        guesses.push_back(est + CPose2D(sgn * loop_pert_xy_, 0, 0));
        guesses.push_back(est + CPose2D(0, sgn * loop_pert_xy_, 0));
        guesses.push_back(est + CPose2D(0, 0, sgn * loop_pert_phi_));
      }
      std::vector<MatchResult> res;
      for (const auto& q : guesses) res.push_back(asf::icp_graph::match(ref, *cur, q, icp_, min_points_));
      const MatchResult* best = nullptr;
      for (const auto& m : res)
        if (m.ran && (!best || m.inlier_ratio > best->inlier_ratio ||
                      (m.inlier_ratio == best->inlier_ratio && m.rmse < best->rmse)))
          best = &m;
      std::ostringstream why;
      if (!best) why << "no ICP result";
      else {
        int agree = 0;
        for (const auto& m : res) {
          const Eigen::Vector3d d = poseDiff(m.pose, best->pose);
          if (m.ran && std::hypot(d.x(), d.y()) <= 2 * icp_.inlier_dist &&
              std::abs(d.z()) <= 2 * kDeg)
            ++agree;
        }
        if (best->goodness < loop_min_goodness_)
          why << "goodness " << best->goodness;
        else if (best->inlier_ratio < loop_min_inliers_)
          why << "inlier ratio " << best->inlier_ratio;
        else if (best->rmse > loop_max_rmse_)
          why << "rmse " << best->rmse;
        else if (agree < loop_min_agree_)
          why << "only " << agree << " of " << res.size() << " guesses agree";
        else if (!sigmasOk(best->cov))
          why << "ill-conditioned alignment";
        else {
          std::optional<Eigen::Matrix3d> Crel;
          if (marg && Cj && i < marg->node.size()) {
            Crel = relativeCov(g.nodes[i].pose, xj, marg->node[i], *Cj, Eigen::Matrix3d::Zero());
          } else {
            Crel = chainCov(g, i, j);
          }
          if (!Crel) why << "no covariance for the chain " << i << " -> " << j;
          else {
            const Eigen::Vector3d d = poseDiff(best->pose, est);
            const Eigen::Matrix3d C = *Crel + best->cov + icp_floor_;
            const double chi2 = d.dot(C.ldlt().solve(d));
            if (!(chi2 <= loop_chi2_)) why << "chi2 " << chi2 << " > " << loop_chi2_;
            else {
              asf::PoseEdge le;
              le.from = i;
              le.to = j;
              le.mean = best->pose;
              le.kind = asf::EdgeKind::LoopClosure;
              le.information = edgeInformation(best->pose, best->cov + icp_floor_,
                                               Eigen::Matrix3d::Zero());
              g.addEdge(le);
              ++g.revision;
              ++n_loops_;
              MRPT_LOG_INFO_STREAM("loop closure " << i << " -> " << j << ": chi2 " << chi2
                                   << ", inliers " << best->inlier_ratio << ", rmse "
                                   << best->rmse << ", " << agree << "/" << res.size()
                                   << " guesses agree (" << n_loops_ << " accepted, "
                                   << n_loop_rejects_ << " rejected)");
              if (++accepted >= loop_max_accept_) return;
              continue;
            }
          }
        }
      }
      ++n_loop_rejects_;
      MRPT_LOG_DEBUG_STREAM("loop candidate " << i << " -> " << j << " rejected: " << why.str());
    }
  }


  // configuration
  Eigen::Matrix3d odo_floor_ = Eigen::Matrix3d::Identity(), icp_floor_ = Eigen::Matrix3d::Identity();
  asf::icp_graph::IcpOptions icp_;
  int submap_ = 1, submap_nearby_ = 5;
  double submap_radius_ = 0;
  std::size_t normal_k_ = 8;
  double normal_radius_ = 0.3;
  std::size_t min_points_ = 20;
  double min_goodness_ = 0.5, max_sigma_xy_ = 0.1, max_sigma_phi_ = 2 * kDeg, odo_chi2_ = 16;
  bool loop_ = true;
  int loop_skip_ = 20, loop_max_cand_ = 3, loop_max_accept_ = 1, loop_submap_ = 1, loop_min_agree_ = 3;
  double loop_radius_ = 3, loop_gate_ = 9.21, loop_pert_xy_ = 0.3, loop_pert_phi_ = 10 * kDeg;
  double loop_min_goodness_ = 0.6, loop_min_inliers_ = 0.6, loop_max_rmse_ = 0.05, loop_chi2_ = 11.34;
  // state
  asf::KeyframeTracker kf_{"icp_graph front-end"};
  std::vector<std::shared_ptr<const Cloud>> clouds_;  ///< per node, robot frame
  std::vector<long> seq_edge_;  ///< per node: index of the edge from its predecessor, or -1
  long n_scan_match_ = 0, n_fallback_ = 0, n_loops_ = 0, n_loop_rejects_ = 0, n_revisits_ = 0;
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("keyframe_distance", "0.5",
                   "New node when the odometry since the last one exceeds this [m]", 1e-6, 1e6),
    asf::keyDouble("keyframe_angle_deg", "20",
                   "New node when the heading change since the last one exceeds this [deg]",
                   1e-6, 180),
    asf::keyDouble("min_sigma_xy", "1e-3",
                   "Its square is added to the x/y variances of odometry edges [m]", 1e-9, 1e3),
    asf::keyDouble("min_sigma_phi", "1e-4",
                   "Its square is added to the heading variance of odometry edges [rad]", 1e-9,
                   10),
    asf::keyInt("submap_keyframes", "3",
                "ICP reference: the scans of this many last keyframes, placed by the estimate",
                1, 100),
    asf::keyDouble("submap_radius", "0",
                   "Old keyframes within this distance of a new one join its ICP reference, "
                   "and an ICP edge from the nearest one is added when it passes the loop "
                   "gates on one guess (0: off) [m]",
                   0, 1e6),
    asf::keyInt("submap_nearby_keyframes", "5",
                "At most this many of those old keyframes, nearest first", 1, 1000),
    asf::keyInt("icp_max_iterations", "80",
                "CICP maxIterations; an alignment that uses them all is rejected", 1, 10000),
    asf::keyDouble("icp_threshold_dist", "0.75",
                   "CICP thresholdDist: initial correspondence distance [m]", 1e-3, 100),
    asf::keyDouble("icp_threshold_ang_deg", "0.15",
                   "CICP thresholdAng: correspondence distance added per metre of range [deg]",
                   0, 90),
    asf::keyDouble("icp_alfa", "0.5", "CICP ALFA: threshold shrink factor at convergence", 0.01,
                   0.99),
    asf::keyDouble("icp_smallest_threshold_dist", "0.05",
                   "CICP smallestThresholdDist: final correspondence distance [m]", 1e-4, 100),
    asf::keyInt("icp_decimation", "5", "CICP corresponding_points_decimation", 1, 1000),
    asf::keyBool("icp_robust", "false",
                 "Point-to-line refinement with a Cauchy kernel (IRLS, scale from the median "
                 "residual): far or mismatched points weigh less"),
    asf::keyInt("icp_normal_neighbours", "8",
                "Reference normals: PCA of this many nearest points (more for noisier scans)", 3,
                1000),
    asf::keyDouble("icp_normal_radius", "0.3",
                   "Reference normals: only neighbours within this distance [m]", 1e-3, 100),
    asf::keyInt("icp_refine_iterations", "5",
                "Point-to-line Gauss-Newton steps after CICP (0: CICP's point-to-point result)",
                0, 100),
    asf::keyInt("icp_min_points", "20", "Fewer valid points in either scan: no ICP", 3, 1000000),
    asf::keyDouble("icp_min_goodness", "0.6",
                   "Reject an alignment whose CICP goodness (correspondence ratio) is lower",
                   0, 1),
    asf::keyDouble("icp_inlier_dist", "0.1",
                   "A point within this of the reference is an inlier (residual statistics, "
                   "covariance) [m]",
                   1e-4, 10),
    asf::keyDouble("icp_sigma_floor", "0.005",
                   "Lower bound of the point noise std estimated from the residuals [m]", 1e-6,
                   1),
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
    asf::keyInt("loop_skip_recent", "20", "Loop candidates exclude the last this many keyframes",
                1, 1000000),
    asf::keyDouble("loop_radius", "3",
                   "Loop candidates: old keyframes within this distance of the new one [m]", 0,
                   1e6),
    asf::keyDouble("loop_gate_chi2", "9.21",
                   "With valid marginals, also candidates whose distance beyond loop_radius has "
                   "a Mahalanobis distance^2 below this (2 dof; 9.21 = 99%)",
                   0, 1e9),
    asf::keyInt("loop_max_candidates", "3", "Candidates verified per keyframe (nearest first)",
                1, 1000),
    asf::keyInt("loop_max_per_keyframe", "1",
                "Loop edges accepted per keyframe at most (candidates are verified nearest first)",
                1, 1000),
    asf::keyInt("loop_submap_half", "1",
                "Loop reference: the candidate's scan plus this many keyframes each side", 0,
                100),
    asf::keyDouble("loop_perturb_xy", "0.3",
                   "Loop verification: initial guesses shifted by +-this in x and y [m]", 0,
                   100),
    asf::keyDouble("loop_perturb_phi_deg", "10",
                   "Loop verification: initial guesses turned by +-this [deg]", 0, 180),
    asf::keyInt("loop_min_agree", "4",
                "Of the 7 ICP runs (estimate and 6 perturbed guesses), at least this many must "
                "converge to the best one",
                1, 7),
    asf::keyDouble("loop_min_goodness", "0.6", "Loop ICP: minimum CICP goodness", 0, 1),
    asf::keyDouble("loop_min_inlier_ratio", "0.6",
                   "Loop ICP: minimum fraction of points within icp_inlier_dist", 0, 1),
    asf::keyDouble("loop_max_rmse", "0.05", "Loop ICP: maximum RMS residual of the inliers [m]",
                   0, 10),
    asf::keyDouble("loop_chi2", "11.34",
                   "Accept a loop edge only if its chi^2 against the current estimate "
                   "(relative + ICP covariance) is below this (3 dof; 11.34 = 99%)",
                   0, 1e9),
};

}  // namespace

ASF_PLUGIN(IcpGraphFrontend, asf::PluginKind::Frontend, "icp_graph", "1.0.0",
           "Graph-SLAM front-end: keyframes joined by ICP (CICP LM) or odometry edges, ICP-verified "
           "loop closures",
           asf::ThreadSafety::ThreadCompatible, kKeys)
