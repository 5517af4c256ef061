#include "loop_search.h"

#include <asf/pose_graph.h>

#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <vector>

namespace asf::icp_graph {

namespace {

struct Kept {
  std::vector<float> x, y;
  Points2 points() const { return {x, y}; }
};

/// The points of `c` within `range` of (cx, cy).
Kept within(const Cloud& c, double cx, double cy, double range) {
  Kept k;
  const double r2 = range * range;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double dx = c.xs()[i] - cx, dy = c.ys()[i] - cy;
    if (dx * dx + dy * dy > r2) continue;
    k.x.push_back(c.xs()[i]);
    k.y.push_back(c.ys()[i]);
  }
  return k;
}

/// Branch-and-bound levels: the coarsest block about a quarter of the window.
int levelsFor(double window, double resolution) {
  int levels = 1;
  while (levels < 8 && (1 << levels) * resolution <= window / 2) ++levels;
  return levels;
}

}  // namespace

CorrelativeLoopResult correlativeLoopSearch(const Cloud& ref, const Cloud& cur,
                                            const mrpt::poses::CPose2D& est,
                                            const CorrelativeLoopOptions& o) {
  CorrelativeLoopResult r;
  const Kept scan = within(cur, 0, 0, o.max_range);
  const Kept near = within(ref, est.x(), est.y(), o.max_range + o.window_xy);
  if (scan.x.size() < 10 || near.x.size() < 10) {
    r.why = "too few points for the correlative search";
    return r;
  }
  const LikelihoodGrid grid(near.points(), o.resolution, o.sigma,
                            levelsFor(o.window_xy, o.resolution), 0.0);
  CorrelativeOptions co;
  co.window_xy = o.window_xy;
  co.window_phi = o.window_phi;
  co.min_score = o.min_score;
  const Eigen::Vector3d guess(est.x(), est.y(), est.phi());
  const CorrelativeResult best = correlativeMatch(grid, scan.points(), guess, co);
  std::ostringstream why;
  if (!best.found) {
    why << "correlative score below " << o.min_score;
    r.why = why.str();
    return r;
  }
  r.score = best.score;
  r.pose = mrpt::poses::CPose2D(best.pose.x(), best.pose.y(), best.pose.z());
  // The best pose outside the peak: only poses scoring above what would make it ambiguous
  // need be found, so the search is bounded by that.
  co.min_score = o.max_ambiguity * best.score;
  const CorrelativeResult second =
      correlativeMatch(grid, scan.points(), guess, co, best.pose.head<2>(), o.peak_radius);
  r.second = second.found ? second.score : 0.0;
  if (second.found) {
    why << "ambiguous: a pose " << (second.pose.head<2>() - best.pose.head<2>()).norm()
        << " m away scores " << second.score << " against " << best.score;
    r.why = why.str();
    return r;
  }
  r.ok = true;
  return r;
}

std::optional<MatchResult> loopAlignment(const Cloud& ref, const Cloud& cur,
                                         const mrpt::poses::CPose2D& est,
                                         const LoopSearchOptions& o, std::string& why,
                                         std::string& how) {
  using mrpt::poses::CPose2D;
  constexpr double kTwoDeg = 2 * M_PI / 180;
  std::ostringstream said;
  if (o.correlative) {
    const auto s = correlativeLoopSearch(ref, cur, est, o.csm);
    if (!s.ok) {
      why = s.why;
      return std::nullopt;
    }
    const MatchResult m = match(ref, cur, s.pose, o.icp, o.min_points);
    if (!m.ran) {
      why = m.reason;
      return std::nullopt;
    }
    const Eigen::Vector3d d = poseDiff(m.pose, s.pose);
    if (std::hypot(d.x(), d.y()) > 2 * o.csm.resolution || std::abs(d.z()) > kTwoDeg) {
      said << "ICP left the correlative peak (" << std::hypot(d.x(), d.y()) << " m, "
           << std::abs(d.z()) * 180 / M_PI << " deg)";
      why = said.str();
      return std::nullopt;
    }
    said << "correlative score " << s.score << " (" << s.second << " off the peak)";
    how = said.str();
    return m;
  }
  std::vector<CPose2D> guesses{est};
  for (int sgn : {-1, 1}) {
    guesses.push_back(est + CPose2D(sgn * o.perturb_xy, 0, 0));
    guesses.push_back(est + CPose2D(0, sgn * o.perturb_xy, 0));
    guesses.push_back(est + CPose2D(0, 0, sgn * o.perturb_phi));
  }
  std::vector<MatchResult> res;
  for (const auto& q : guesses) res.push_back(match(ref, cur, q, o.icp, o.min_points));
  const MatchResult* best = nullptr;
  for (const auto& m : res)
    if (m.ran && (!best || m.inlier_ratio > best->inlier_ratio ||
                  (m.inlier_ratio == best->inlier_ratio && m.rmse < best->rmse)))
      best = &m;
  if (!best) {
    why = "no ICP result";
    return std::nullopt;
  }
  int agree = 0;
  for (const auto& m : res) {
    const Eigen::Vector3d d = poseDiff(m.pose, best->pose);
    if (m.ran && std::hypot(d.x(), d.y()) <= 2 * o.icp.inlier_dist && std::abs(d.z()) <= kTwoDeg)
      ++agree;
  }
  if (agree < o.min_agree) {
    said << "only " << agree << " of " << res.size() << " guesses agree";
    why = said.str();
    return std::nullopt;
  }
  said << agree << "/" << res.size() << " guesses agree";
  how = said.str();
  return *best;
}

mrpt::poses::CPose2D inverseWithCov(const mrpt::poses::CPose2D& p, const Eigen::Matrix3d& C,
                                    Eigen::Matrix3d& out) {
  const double c = std::cos(p.phi()), s = std::sin(p.phi()), x = p.x(), y = p.y();
  Eigen::Matrix3d J;           // d(-p)/dp, -p = (-(c x + s y), s x - c y, -phi)
  J << -c, -s, s * x - c * y,  //
      s, -c, c * x + s * y,    //
      0, 0, -1;
  out = J * C * J.transpose();
  return mrpt::poses::CPose2D() - p;
}

double loopPairChi2(const LoopHypothesis& a, const LoopHypothesis& b,
                    const mrpt::poses::CPose2D& ia_to_ib, const Eigen::Matrix3d& C_i,
                    const mrpt::poses::CPose2D& ja_to_jb, const Eigen::Matrix3d& C_j) {
  // jb in ia's frame, through a and the new trajectory, and through the old one and b.
  Eigen::Matrix3d C1, C2;
  const mrpt::poses::CPose2D via_a = asf::composeWithCov(a.mean, a.cov, ja_to_jb, C_j, C1);
  const mrpt::poses::CPose2D via_b = asf::composeWithCov(ia_to_ib, C_i, b.mean, b.cov, C2);
  const Eigen::Vector3d d = poseDiff(via_a, via_b);
  return d.dot((C1 + C2).ldlt().solve(d));
}

Eigen::Matrix3d relativeCov(const mrpt::poses::CPose2D& xi, const mrpt::poses::CPose2D& xj,
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

Eigen::Matrix3d edgeCovInFrom(const asf::PoseEdge& e) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(e.mean.phi()), s = std::sin(e.mean.phi());
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R * e.information.inverse() * R.transpose();
}

}  // namespace asf::icp_graph
