// planner_shortest: Dijkstra on the pose graph; an edge is as long as the Euclidean distance
// between its nodes' current estimates. The "distance" baseline for uncertainty-aware planners.
#include <asf/planner.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

namespace {

class ShortestPlanner final : public asf::Planner {
 public:
  void configure(const asf::Params&, const asf::PluginContext&) override {}

  asf::PlanResult plan(const asf::PlanRequest& req) override {
    asf::PlanResult r;
    r.criterion = "distance";
    if (!req.graph) {
      r.reason = "no pose graph given";
      return r;
    }
    const asf::PoseGraph& g = *req.graph;
    const std::size_t n = g.size();
    if (req.start >= n || req.goal >= n) {
      r.reason = "node " + std::to_string(req.start >= n ? req.start : req.goal) +
                 " does not exist (the graph has " + std::to_string(n) + " nodes)";
      return r;
    }
    // Adjacency (both directions); edges naming missing nodes are ignored.
    std::vector<std::vector<std::pair<asf::NodeId, double>>> adj(n);
    for (const auto& e : g.edges) {
      if (e.from >= n || e.to >= n) continue;
      const double len = std::hypot(g.nodes[e.to].pose.x() - g.nodes[e.from].pose.x(),
                                    g.nodes[e.to].pose.y() - g.nodes[e.from].pose.y());
      adj[e.from].emplace_back(e.to, len);
      adj[e.to].emplace_back(e.from, len);
    }
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<double> dist(n, kInf);
    std::vector<asf::NodeId> prev(n, 0);
    using Item = std::pair<double, asf::NodeId>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    dist[req.start] = 0;
    open.emplace(0.0, req.start);
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist[v]) continue;
      if (v == req.goal) break;
      for (const auto& [w, len] : adj[v])
        if (d + len < dist[w]) {
          dist[w] = d + len;
          prev[w] = v;
          open.emplace(dist[w], w);
        }
    }
    if (dist[req.goal] == kInf) {
      r.reason = "node " + std::to_string(req.goal) + " is not connected to node " +
                 std::to_string(req.start);
      return r;
    }
    for (asf::NodeId v = req.goal;; v = prev[v]) {
      r.nodes.push_back(v);
      if (v == req.start) break;
    }
    std::reverse(r.nodes.begin(), r.nodes.end());
    r.found = true;
    r.cost = dist[req.goal];
    return r;
  }
};

}  // namespace

ASF_PLUGIN_NO_KEYS(ShortestPlanner, asf::PluginKind::Planner, "shortest", "1.0.0",
                   "Shortest path in the pose graph by Euclidean edge length (Dijkstra)",
                   asf::ThreadSafety::ThreadCompatible)
