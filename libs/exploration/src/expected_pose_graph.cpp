// The pose graph expected after driving a path, weighted by the D-criterion of each edge's
// information, and its D-optimality (expected_pose_graph.h).
#include <asf/errors.h>
#include <asf/exploration/expected_pose_graph.h>
#include <asf/graph/information.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace asf::exploration {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

}  // namespace

double edgeDOptimality(const Eigen::Matrix3d& information) {
  const Eigen::Vector3d ev =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(information, Eigen::EigenvaluesOnly)
          .eigenvalues();
  if (!(ev.minCoeff() > 0)) return 0;
  return std::exp(ev.array().log().mean());
}

ExpectedPoseGraph::ExpectedPoseGraph(const PoseGraph& g, const ExpectedGraphOptions& options)
    : options_(options) {
  if (g.empty()) throw InputError("ExpectedPoseGraph: the pose graph has no node");
  base_.n = static_cast<int>(g.size());
  positions_.reserve(g.size());
  for (const PoseNode& n : g.nodes) positions_.push_back({n.pose.x(), n.pose.y()});
  std::vector<double> odometry, loops;
  for (const PoseEdge& e : g.edges) {
    const double w = edgeDOptimality(e.information);
    if (!(w > 0) || e.from == e.to) continue;  // carries nothing the Laplacian can hold
    base_.edges.push_back({static_cast<int>(e.from), static_cast<int>(e.to), 1, w});
    if (e.kind == EdgeKind::LoopClosure)
      loops.push_back(w);
    else if (e.to == e.from + 1 || e.from == e.to + 1)
      odometry.push_back(w);
  }
  if (base_.edges.empty()) throw InputError("ExpectedPoseGraph: no edge with information");
  if (odometry.empty())  // no consecutive nodes joined: every edge is a sample
    for (const graph::Edge& e : base_.edges) odometry.push_back(e.information);
  odometry_weight_ = median(odometry);
  loop_weight_ = loops.empty() ? odometry_weight_ : median(loops);
  for (int i = 0; i < base_.n; ++i) cells_[cellKey(positions_[i])].push_back(i);
}

std::int64_t ExpectedPoseGraph::cellKey(const Point2& p, int dx, int dy) const {
  const auto cx = static_cast<std::int64_t>(std::floor(p.x / options_.loop_radius)) + dx;
  const auto cy = static_cast<std::int64_t>(std::floor(p.y / options_.loop_radius)) + dy;
  return (cx << 32) ^ (cy & 0xffffffff);
}

int ExpectedPoseGraph::nearestOldNode(const Point2& p, int max_id) const {
  int best = -1;
  double best_d2 = options_.loop_radius * options_.loop_radius;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const auto it = cells_.find(cellKey(p, dx, dy));
      if (it == cells_.end()) continue;
      for (const int i : it->second) {
        if (i > max_id) continue;
        const double d2 = (positions_[i].x - p.x) * (positions_[i].x - p.x) +
                          (positions_[i].y - p.y) * (positions_[i].y - p.y);
        if (d2 < best_d2 || (d2 == best_d2 && best >= 0 && i < best)) best_d2 = d2, best = i;
      }
    }
  return best;
}

Expectation ExpectedPoseGraph::afterPath(const std::vector<Point2>& path,
                                         const AreaFn& area) const {
  // Arc lengths where new nodes go: every node_spacing, and the path's end.
  std::vector<Point2> added;
  double arc = 0, next = options_.node_spacing;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Point2 &a = path[i - 1], &b = path[i];
    const double step = std::hypot(b.x - a.x, b.y - a.y);
    while (step > 0 && next <= arc + step) {
      const double t = (next - arc) / step;
      added.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
      next += options_.node_spacing;
    }
    arc += step;
  }
  const double last_at = next - options_.node_spacing;  // arc of the last node placed
  if (path.size() > 1 && arc - last_at > 1e-9) added.push_back(path.back());

  graph::Multigraph g = base_;
  Expectation out;
  int previous = base_.n - 1;
  for (const Point2& p : added) {
    const int id = g.n++;
    const AreaShares a = area ? area(p) : AreaShares{};
    g.edges.push_back({previous, id, 1, odometry_weight_ * (1 + a.unknown)});
    const int old = nearestOldNode(p, id - options_.loop_skip_recent - 1);
    // The authors' loop: only with structure to match, weighed by its age and that structure.
    const double loop = area ? loop_weight_ * 1.5 * (id - old) / g.n * a.occupied : loop_weight_;
    if (old >= 0 && (!area || a.occupied > 0.03) && loop > 0) {
      g.edges.push_back({old, id, 1, loop});
      ++out.loops;
    }
    previous = id;
  }
  out.nodes = static_cast<int>(added.size());
  out.d_optimality = graph::dOptimalitySparse(g, Eigen::VectorXd::Ones(g.m()));
  return out;
}

double ExpectedPoseGraph::present() const {
  return graph::dOptimalitySparse(base_, Eigen::VectorXd::Ones(base_.m()));
}

}  // namespace asf::exploration
