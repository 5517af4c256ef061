#pragma once
// Private to the planning library: edges of a pose graph and virtual (Voronoi) edges by node
// pair, and the path model built through them; shared by expected_uncertainty.cpp and
// path_search.cpp.
#include <asf/planning/expected_uncertainty.h>

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace asf::planning::detail {

/// Edges by unordered node pair, built once per graph.
struct EdgeIndex {
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_pair;
  static std::uint64_t key(NodeId a, NodeId b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
  }
  explicit EdgeIndex(const PoseGraph& g) {
    for (std::size_t i = 0; i < g.edges.size(); ++i)
      by_pair[key(g.edges[i].from, g.edges[i].to)].push_back(i);
  }
  const std::vector<std::size_t>* find(NodeId a, NodeId b) const {
    auto it = by_pair.find(key(a, b));
    return it == by_pair.end() ? nullptr : &it->second;
  }
};

/// Virtual edges by unordered node pair.
struct VirtualIndex {
  std::unordered_map<std::uint64_t, const VirtualEdge*> by_pair;
  explicit VirtualIndex(const std::vector<VirtualEdge>* v) {
    if (v)
      for (const auto& e : *v) by_pair.emplace(EdgeIndex::key(e.a, e.b), &e);
  }
  const VirtualEdge* find(NodeId a, NodeId b) const {
    auto it = by_pair.find(EdgeIndex::key(a, b));
    return it == by_pair.end() ? nullptr : it->second;
  }
};

/// The PathModel of `path` (consecutive nodes joined by graph edges, parallel ones fused, or
/// by virtual edges from `virt`); Error when two consecutive nodes share neither.
PathModel makePathModel(const PoseGraph& g, const EdgeIndex& index, const Marginals* m,
                        const std::vector<NodeId>& path, const VirtualIndex* virt = nullptr);

}  // namespace asf::planning::detail
