#include <asf/topo_graph.h>

namespace asf {

const TopoNode* TopoGraph::node(RegionId r) const {
  for (const auto& n : nodes)
    if (n.region == r) return &n;
  return nullptr;
}

TopoNode* TopoGraph::node(RegionId r) {
  for (auto& n : nodes)
    if (n.region == r) return &n;
  return nullptr;
}

std::vector<int> TopoGraph::incident(RegionId r) const {
  std::vector<int> v;
  for (std::size_t i = 0; i < edges.size(); ++i)
    if (edges[i].a == r || edges[i].b == r) v.push_back(static_cast<int>(i));
  return v;
}

int TopoGraph::outwardTraversals(int e, RegionId r) const {
  const TopoEdge& ed = edges.at(static_cast<std::size_t>(e));
  int n = 0;
  for (const auto& t : ed.traversals)
    if ((t.forward && ed.a == r) || (!t.forward && ed.b == r)) ++n;
  return n;
}

}  // namespace asf
