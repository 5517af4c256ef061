#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <mrpt/math/wrap2pi.h>

namespace asf {

const char* edgeKindName(EdgeKind k) {
  switch (k) {
    case EdgeKind::Odometry: return "odometry";
    case EdgeKind::ScanMatch: return "scan-match";
    case EdgeKind::LoopClosure: return "loop-closure";
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
  const mrpt::poses::CPose2D rel = b - a;          // a^-1 (+) b
  const mrpt::poses::CPose2D err = rel - e.mean;   // mean^-1 (+) rel
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

}  // namespace asf
