#include <asf/segmentation.h>
#include <asf/topo_graph.h>

#include <cmath>

namespace asf {

RegionId LabelImage::atPoint(double x, double y) const {
  if (resolution <= 0) return 0;
  const int cx = static_cast<int>(std::floor((x - origin_x) / resolution));
  const int cy = static_cast<int>(std::floor((y - origin_y) / resolution));
  if (cx < 0 || cy < 0 || cx >= width || cy >= height) return 0;
  return at(cx, cy);
}

const Region* Segmentation::find(RegionId id) const {
  for (const auto& r : regions)
    if (r.id == id) return &r;
  return nullptr;
}

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
