#include <asf/errors.h>
#include <asf/pose_covariance.h>
#include <asf/pose_graph.h>
#include <asf/se2_edge.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

namespace asf {

using mrpt::poses::CPose2D;

const char* edgeKindName(EdgeKind k) {
  switch (k) {
    case EdgeKind::Odometry:
      return "odometry";
    case EdgeKind::ScanMatch:
      return "scan-match";
    case EdgeKind::LoopClosure:
      return "loop-closure";
  }
  return "unknown";
}

NodeId PoseGraph::addNode(const mrpt::poses::CPose2D& pose, double timestamp) {
  PoseNode n;
  n.id = static_cast<NodeId>(nodes.size());
  n.pose = pose;
  n.timestamp = timestamp;
  nodes.push_back(n);
  return n.id;
}

void PoseGraph::addEdge(const PoseEdge& e) {
  if (e.from >= nodes.size() || e.to >= nodes.size())
    throw Error("PoseGraph::addEdge: edge " + std::to_string(e.from) + " -> " +
                std::to_string(e.to) + " names a node that does not exist (" +
                std::to_string(nodes.size()) + " nodes)");
  edges.push_back(e);
}

Eigen::Vector3d PoseGraph::edgeError(const PoseEdge& e) const {
  const auto& a = nodes.at(e.from).pose;
  const auto& b = nodes.at(e.to).pose;
  const mrpt::poses::CPose2D rel = b - a;         // a^-1 (+) b
  const mrpt::poses::CPose2D err = rel - e.mean;  // mean^-1 (+) rel
  return {err.x(), err.y(), mrpt::math::wrapToPi(err.phi())};
}

double PoseGraph::chi2() const {
  double s = 0;
  for (const auto& e : edges) {
    const Eigen::Vector3d r = edgeError(e);
    s += r.dot(e.information * r);
  }
  return s;
}

CPose2D composeWithCov(const CPose2D& a, const Eigen::Matrix3d& Ca, const CPose2D& b,
                       const Eigen::Matrix3d& Cb, Eigen::Matrix3d& out) {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  Eigen::Matrix3d Ja = Eigen::Matrix3d::Identity();  // d(a (+) b)/da
  Ja(0, 2) = -s * b.x() - c * b.y();
  Ja(1, 2) = c * b.x() - s * b.y();
  Eigen::Matrix3d Jb = Eigen::Matrix3d::Identity();  // d(a (+) b)/db
  Jb.topLeftCorner<2, 2>() << c, -s, s, c;
  out = Ja * Ca * Ja.transpose() + Jb * Cb * Jb.transpose();
  CPose2D p = a + b;
  p.normalizePhi();
  return p;
}

Eigen::Matrix3d edgeCovarianceInFrom(const PoseEdge& e) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(e.mean.phi()), s = std::sin(e.mean.phi());
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R * e.information.inverse() * R.transpose();
}

CPose2D inverseWithCov(const CPose2D& p, const Eigen::Matrix3d& C, Eigen::Matrix3d& out) {
  const double c = std::cos(p.phi()), s = std::sin(p.phi()), x = p.x(), y = p.y();
  Eigen::Matrix3d J;           // d(-p)/dp, -p = (-(c x + s y), s x - c y, -phi)
  J << -c, -s, s * x - c * y,  //
      s, -c, c * x + s * y,    //
      0, 0, -1;
  out = J * C * J.transpose();
  return CPose2D() - p;
}

Eigen::Matrix3d edgeInformation(const CPose2D& mean, const Eigen::Matrix3d& cov,
                                const Eigen::Matrix3d& floor) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(mean.phi()), s = std::sin(mean.phi());
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  Eigen::Matrix3d ce = R.transpose() * cov * R;
  ce = 0.5 * (ce + ce.transpose()) + floor;
  const Eigen::Matrix3d info = ce.inverse();
  return 0.5 * (info + info.transpose());
}

void requireAnchored(const PoseGraph& g, const std::string& who) {
  const std::size_t n = g.size();
  if (n == 0) return;
  std::vector<std::vector<NodeId>> adj(n);
  for (const auto& e : g.edges) {
    adj[e.from].push_back(e.to);
    adj[e.to].push_back(e.from);
  }
  std::vector<char> seen(n, 0);
  std::vector<NodeId> stack{0};
  seen[0] = 1;
  for (NodeId f : g.fixed)
    if (f < n && !seen[f]) {
      seen[f] = 1;
      stack.push_back(f);
    }
  while (!stack.empty()) {
    const NodeId v = stack.back();
    stack.pop_back();
    for (NodeId w : adj[v])
      if (!seen[w]) {
        seen[w] = 1;
        stack.push_back(w);
      }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!seen[i])
      throw Error(who + ": node " + std::to_string(i) +
                  " is not connected to node 0 (nor to a fixed node): its covariance is "
                  "undefined");
}

Eigen::MatrixXd denseInformation(const PoseGraph& g, std::vector<int>& index) {
  index.assign(g.size(), -1);
  std::vector<char> held(g.size(), 0);
  if (!g.empty()) held[0] = 1;
  for (NodeId f : g.fixed)
    if (f < g.size()) held[f] = 1;
  int dim = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (!held[i]) {
      index[i] = dim;
      dim += 3;
    }
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  for (const PoseEdge& e : g.edges) {
    const auto& a = g.nodes[e.from].pose;
    const auto& b = g.nodes[e.to].pose;
    const auto L = se2::linearizeEdge({a.x(), a.y(), a.phi()}, {b.x(), b.y(), b.phi()},
                                      {e.mean.x(), e.mean.y(), e.mean.phi()});
    const int i = index[e.from], j = index[e.to];
    const Eigen::Matrix3d& W = e.information;
    if (i >= 0) H.block<3, 3>(i, i) += L.Ji.transpose() * W * L.Ji;
    if (j >= 0) H.block<3, 3>(j, j) += L.Jj.transpose() * W * L.Jj;
    if (i >= 0 && j >= 0) {
      H.block<3, 3>(i, j) += L.Ji.transpose() * W * L.Jj;
      H.block<3, 3>(j, i) += L.Jj.transpose() * W * L.Ji;
    }
  }
  return H;
}

}  // namespace asf
