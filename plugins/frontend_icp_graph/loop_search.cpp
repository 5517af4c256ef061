#include "loop_search.h"

#include <asf/pose_graph.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
  // The grid covers every place a scan point can be moved to (the window, the scan's reach
  // and a coarsest block beyond): reads without bounds tests, same values.
  double reach2 = 0;
  for (std::size_t i = 0; i < scan.x.size(); ++i)
    reach2 = std::max(reach2, double(scan.x[i]) * scan.x[i] + double(scan.y[i]) * scan.y[i]);
  const int levels = levelsFor(o.window_xy, o.resolution);
  const double span = o.window_xy + std::sqrt(reach2) + ((1 << (levels - 1)) + 2) * o.resolution;
  const std::array<double, 4> cover{est.x() - span, est.y() - span, est.x() + span, est.y() + span};
  const LikelihoodGrid grid(near.points(), o.resolution, o.sigma, levels, 0.0, &cover);
  CorrelativeOptions co;
  co.window_xy = o.window_xy;
  co.window_phi = o.window_phi;
  const Eigen::Vector3d guess(est.x(), est.y(), est.phi());
  const CorrelativeSearch search(grid, scan.points(), guess, co);
  const CorrelativeResult best = search.run(o.min_score);
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
  const CorrelativeResult second =
      search.run(o.max_ambiguity * best.score, best.pose.head<2>(), o.peak_radius);
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
                                         std::string& how, const LoopGate& gate) {
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
  const MatchResult first = match(ref, cur, est, o.icp, o.min_points);
  if (!first.ran) {
    why = first.reason;
    return std::nullopt;
  }
  if (gate) {
    const std::string failed = gate(first);
    if (!failed.empty()) {
      why = "from the estimate: " + failed;
      return std::nullopt;
    }
  }
  std::vector<CPose2D> perturbed;
  for (int sgn : {-1, 1}) {
    perturbed.push_back(est + CPose2D(sgn * o.perturb_xy, 0, 0));
    perturbed.push_back(est + CPose2D(0, sgn * o.perturb_xy, 0));
    perturbed.push_back(est + CPose2D(0, 0, sgn * o.perturb_phi));
  }
  const int runs = 1 + static_cast<int>(perturbed.size());
  // The perturbed runs only test the basin: the result is the run from the estimate.
  int agree = 1, tried = 1;
  for (const CPose2D& q : perturbed) {
    if (agree >= o.min_agree || agree + (runs - tried) < o.min_agree) break;
    const MatchResult m = match(ref, cur, q, o.icp, o.min_points);
    ++tried;
    const Eigen::Vector3d d = poseDiff(m.pose, first.pose);
    if (m.ran && std::hypot(d.x(), d.y()) <= 2 * o.icp.inlier_dist && std::abs(d.z()) <= kTwoDeg)
      ++agree;
  }
  if (agree < o.min_agree) {
    said << "only " << agree << " of " << tried << " guesses agree (" << o.min_agree << " needed)";
    why = said.str();
    return std::nullopt;
  }
  said << agree << "/" << tried << " guesses agree";
  how = said.str();
  return first;
}

bool mayConfirm(const LoopHypothesis& held, const LoopHypothesis& h, std::size_t span) {
  if (held.to == h.to || held.from == h.from) return false;  // one scan twice is no second cue
  const std::size_t apart = held.from > h.from ? held.from - h.from : h.from - held.from;
  return span == 0 || apart <= span;
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

std::vector<char> linkedNear(const asf::PoseGraph& g, asf::NodeId start,
                             const mrpt::poses::CPose2D& centre, double radius,
                             asf::NodeId exclude) {
  const std::size_t n = g.size();
  std::vector<char> inside(n, 0), linked(n, 0);
  for (asf::NodeId k = 0; k < n; ++k)
    inside[k] = k != exclude && std::hypot(g.nodes[k].pose.x() - centre.x(),
                                           g.nodes[k].pose.y() - centre.y()) <= radius;
  if (start >= n || !inside[start]) return linked;
  std::vector<std::vector<asf::NodeId>> adjacent(n);
  for (const asf::PoseEdge& e : g.edges)
    if (e.from < n && e.to < n && inside[e.from] && inside[e.to]) {
      adjacent[e.from].push_back(e.to);
      adjacent[e.to].push_back(e.from);
    }
  std::vector<asf::NodeId> todo{start};
  linked[start] = 1;
  while (!todo.empty()) {
    const asf::NodeId k = todo.back();
    todo.pop_back();
    for (const asf::NodeId m : adjacent[k])
      if (!linked[m]) linked[m] = 1, todo.push_back(m);
  }
  return linked;
}

std::vector<asf::NodeId> loopCandidates(const asf::PoseGraph& g, asf::NodeId j, asf::NodeId prev,
                                        const asf::Marginals* marg,
                                        const std::optional<Eigen::Matrix3d>& Cj,
                                        const CandidateGate& o) {
  using mrpt::poses::CPose2D;
  struct Cand {
    asf::NodeId id;
    double dist;
  };
  std::vector<Cand> cands;
  const CPose2D& xj = g.nodes[j].pose;
  const std::vector<char> linked =
      o.skip_linked ? linkedNear(g, prev, xj, o.radius, j) : std::vector<char>();
  for (asf::NodeId i = 0; static_cast<long>(i) < static_cast<long>(j) - o.skip_recent; ++i) {
    if (!g.nodes[i].scan || (!linked.empty() && linked[i])) continue;
    const CPose2D rel = CPose2D() - g.nodes[i].pose + xj;
    const double dist = std::hypot(rel.x(), rel.y());
    double d2 = dist <= o.radius ? 0.0 : std::numeric_limits<double>::infinity();
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
          dist > o.radius ? Eigen::Vector2d(t * (1 - o.radius / dist)) : Eigen::Vector2d::Zero();
      const Eigen::Matrix2d S = Cr.topLeftCorner<2, 2>() + 1e-9 * Eigen::Matrix2d::Identity();
      d2 = std::min(d2, beyond.dot(S.ldlt().solve(beyond)));
    }
    if (d2 <= o.gate_chi2) cands.push_back({i, dist});
  }
  std::sort(cands.begin(), cands.end(), [](const Cand& a, const Cand& b) {
    return a.dist != b.dist ? a.dist < b.dist : a.id < b.id;
  });
  std::vector<asf::NodeId> ids;
  for (const Cand& c : cands) {
    if (static_cast<int>(ids.size()) >= o.max_candidates) break;
    const bool close = std::any_of(ids.begin(), ids.end(), [&](asf::NodeId k) {
      return std::abs(static_cast<long>(k) - static_cast<long>(c.id)) < o.min_gap;
    });
    if (!close) ids.push_back(c.id);
  }
  return ids;
}

}  // namespace asf::icp_graph
