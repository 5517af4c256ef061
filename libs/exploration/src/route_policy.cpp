#include <asf/errors.h>
#include <asf/exploration/route_policy.h>

#include <cmath>
#include <map>
#include <sstream>

namespace asf::exploration {

namespace {
double dist(const Point2& a, const Point2& b) { return std::hypot(a.x - b.x, a.y - b.y); }
}  // namespace

void RoutePolicy::configure(const Params& params, const PluginContext& ctx) {
  tolerance_ = params.getDouble("goal_tolerance");
  seed_ = static_cast<std::uint32_t>(ctx.seed);
  planned_ = false;
  plan_ = {};
  next_ = 0;
  skipped_ = 0;
}

RoutePolicy::Plan RoutePolicy::plan(const TopoGraph& topo, RegionId start, Route route,
                                    double tolerance, std::uint32_t seed) {
  Plan p;
  // Regions reachable from the start over region edges (tiny pockets with no wide enough
  // border form other components; they cannot be part of a walk).
  std::map<RegionId, std::vector<int>> adj;
  for (std::size_t i = 0; i < topo.edges.size(); ++i) {
    const TopoEdge& e = topo.edges[i];
    if (e.frontier() || e.a == e.b) continue;
    adj[e.a].push_back(static_cast<int>(i));
    adj[e.b].push_back(static_cast<int>(i));
  }
  std::map<RegionId, int> index;
  std::vector<RegionId> stack{start};
  index[start] = 0;
  p.regions.push_back(start);
  while (!stack.empty()) {
    const RegionId r = stack.back();
    stack.pop_back();
    for (int ei : adj[r]) {
      const TopoEdge& e = topo.edges[ei];
      const RegionId o = e.a == r ? e.b : e.a;
      if (index.count(o)) continue;
      index[o] = static_cast<int>(p.regions.size());
      p.regions.push_back(o);
      stack.push_back(o);
    }
  }
  graph::Multigraph g;
  g.n = static_cast<int>(p.regions.size());
  std::vector<int> topo_edge;  // multigraph edge -> topo edge
  for (std::size_t i = 0; i < topo.edges.size(); ++i) {
    const TopoEdge& e = topo.edges[i];
    if (e.frontier() || e.a == e.b || !index.count(e.a) || !index.count(e.b)) continue;
    const TopoNode* a = topo.node(e.a);
    const TopoNode* b = topo.node(e.b);
    const double len = dist(a->centroid, e.midpoint) + dist(e.midpoint, b->centroid);
    g.edges.push_back({index[e.a], index[e.b], len});
    topo_edge.push_back(static_cast<int>(i));
  }
  p.edges = g.m();
  for (const auto& e : g.edges) p.edges_length += e.length;
  if (g.edges.empty()) {
    p.walk.nodes = {0};
    return p;
  }
  if (route == Route::ChinesePostman) {
    p.walk = graph::chinesePostman(g, 0).walk;
  } else {
    graph::TspOptions o;
    o.seed = seed;
    p.walk = graph::travelingSalesman(g, 0, o).walk;
  }
  for (std::size_t i = 0; i < p.walk.edges.size(); ++i) {
    const TopoEdge& e = topo.edges[topo_edge[p.walk.edges[i]]];
    const RegionId to = p.regions[p.walk.nodes[i + 1]];
    p.goals.push_back({e.midpoint.x, e.midpoint.y, tolerance});
    std::ostringstream a, b;
    a << "step " << i + 1 << "/" << p.walk.edges.size() << ": border " << p.regions[p.walk.nodes[i]]
      << "-" << to;
    p.labels.push_back(a.str());
    const TopoNode* n = topo.node(to);
    p.goals.push_back({n->centroid.x, n->centroid.y, tolerance});
    b << "step " << i + 1 << "/" << p.walk.edges.size() << ": centre of region " << to;
    p.labels.push_back(b.str());
  }
  return p;
}

Decision RoutePolicy::decide(const ExplorationState& s) {
  const char* name = route_ == Route::ChinesePostman ? "Chinese postman" : "TSP";
  if (!s.world_topo)
    return Decision::done(std::string("the ") + name +
                          " baseline needs the true world (a simulator source) and a "
                          "segmenter; this pipeline has none");
  if (!planned_) {
    RegionId start = s.world_topo->current;
    if (start <= 0 || !s.world_topo->node(start)) {
      // The start is on no region cell: take the region whose centroid is nearest.
      double best = 1e300;
      for (const auto& n : s.world_topo->nodes)
        if (n.region != kUnexplored &&
            dist(n.centroid, {s.robot.x(), s.robot.y()}) < best) {
          best = dist(n.centroid, {s.robot.x(), s.robot.y()});
          start = n.region;
        }
    }
    if (start <= 0) return Decision::done("the true world has no regions");
    plan_ = plan(*s.world_topo, start, route_, tolerance_, seed_);
    planned_ = true;
    std::ostringstream os;
    os << name << " walk over the true world's graph: " << plan_.walk.edges.size()
       << " steps, " << plan_.walk.length << " m (" << plan_.regions.size() << " regions, "
       << plan_.edges << " edges of total length " << plan_.edges_length << " m)";
    MRPT_LOG_INFO(os.str());
  } else if (next_ > 0 && (s.last_status == NavStatus::Unreachable ||
                           s.last_status == NavStatus::Blocked)) {
    ++skipped_;
    MRPT_LOG_WARN_STREAM("skipped " << plan_.labels[next_ - 1] << ": "
                                    << navStatusName(s.last_status));
  } else if (next_ > 0 && s.last_status != NavStatus::Reached) {
    --next_;  // no outcome yet: the same goal again
  }
  if (next_ >= plan_.goals.size()) {
    std::ostringstream os;
    os << name << " walk done: " << plan_.walk.edges.size() << " steps, " << plan_.walk.length
       << " m planned over " << plan_.edges << " edges of total length " << plan_.edges_length
       << " m, " << skipped_ << " goals skipped";
    return Decision::done(os.str());
  }
  const std::size_t i = next_++;
  return Decision::goTo(plan_.goals[i], plan_.labels[i]);
}

}  // namespace asf::exploration
