// Expected-uncertainty planning (thesis chapter 3): the reduced graph and the path search
// (candidate paths scored by a criterion).
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/params.h>
#include <asf/planning/place_recognition.h>
#include <asf/io/image_io.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <set>
#include <sstream>
#include <unordered_map>

#include "path_index.h"

namespace asf::planning {

using Mat3 = Eigen::Matrix3d;
using mrpt::poses::CPose2D;
using namespace detail;

// ---------------------------------------------------------------------------------------

namespace {

/// Neighbour sets without self-loops and without repeats (parallel edges merged).
std::vector<std::vector<NodeId>> simpleAdjacency(const PoseGraph& g) {
  std::vector<std::set<NodeId>> s(g.size());
  for (const auto& e : g.edges) {
    if (e.from == e.to || e.from >= g.size() || e.to >= g.size()) continue;
    s[e.from].insert(e.to);
    s[e.to].insert(e.from);
  }
  std::vector<std::vector<NodeId>> adj(g.size());
  for (std::size_t v = 0; v < g.size(); ++v) adj[v].assign(s[v].begin(), s[v].end());
  return adj;
}

ReducedGraph reduce(const std::vector<std::vector<NodeId>>& adj, NodeId start, NodeId goal,
                    bool collapse) {
  ReducedGraph r;
  const std::size_t n = adj.size();
  std::vector<char> kept(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    kept[v] = !collapse || adj[v].size() != 2 || v == start || v == goal;
  for (std::size_t v = 0; v < n; ++v)
    if (kept[v]) r.kept.push_back(static_cast<NodeId>(v));
  for (NodeId a : r.kept)
    for (NodeId first : adj[a]) {
      ReducedGraph::Edge e{a, 0, {}};
      NodeId prev = a, cur = first;
      while (!kept[cur]) {
        e.interior.push_back(cur);
        const NodeId next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        prev = cur;
        cur = next;
      }
      e.b = cur;
      // Each chain is met from both ends: keep it once; a chain back to a is never simple.
      if (e.b == a) continue;
      if (a > e.b) continue;
      r.edges.push_back(std::move(e));
    }
  return r;
}

}  // namespace

ReducedGraph reduceGraph(const PoseGraph& g, NodeId start, NodeId goal) {
  return reduce(simpleAdjacency(g), start, goal, true);
}

const char* searchMethodName(SearchMethod m) {
  switch (m) {
    case SearchMethod::Auto:
      return "auto";
    case SearchMethod::All:
      return "all";
    case SearchMethod::Yen:
      return "yen";
  }
  return "?";
}

namespace {

double planarDistance(const PoseGraph& g, NodeId a, NodeId b) {
  return std::hypot(g.nodes[a].pose.x() - g.nodes[b].pose.x(),
                    g.nodes[a].pose.y() - g.nodes[b].pose.y());
}

/// A loop closure for the alias merge: so marked, or joining nodes that are not consecutive
/// in the trajectory (readG2o marks them so; hand-built graphs may not).
bool isLoopClosure(const PoseEdge& e) {
  const NodeId gap = e.from > e.to ? e.from - e.to : e.to - e.from;
  return e.kind == EdgeKind::LoopClosure || gap > 1;
}

void checkNodes(const PoseGraph& g, NodeId start, NodeId goal) {
  const std::size_t n = g.size();
  if (start >= n || goal >= n)
    throw Error("node " + std::to_string(start >= n ? start : goal) +
                " does not exist (the graph has " + std::to_string(n) + " nodes)");
}

/// Dijkstra over the pose graph (edge length: distance between the estimates) from `start`
/// to `goal`, moving from v to w only when allowed(v, w). Empty when goal is unreachable.
/// Ties resolve by node id, so the result is deterministic.
template <class Allowed>
std::vector<NodeId> dijkstraNodes(const PoseGraph& g, const std::vector<std::vector<NodeId>>& adj,
                                  NodeId start, NodeId goal, const Allowed& allowed) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t n = g.size();
  std::vector<double> dist(n, kInf);
  std::vector<NodeId> prev(n, 0);
  using Item = std::pair<double, NodeId>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[start] = 0;
  open.emplace(0.0, start);
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > dist[v]) continue;
    if (v == goal) break;
    for (NodeId w : adj[v]) {
      if (!allowed(v, w)) continue;
      const double nd = d + planarDistance(g, v, w);
      if (nd < dist[w]) {
        dist[w] = nd;
        prev[w] = v;
        open.emplace(nd, w);
      }
    }
  }
  std::vector<NodeId> path;
  if (dist[goal] == kInf) return path;
  for (NodeId v = goal;; v = prev[v]) {
    path.push_back(v);
    if (v == start) break;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace

namespace {

/// Clusters of nodes aliased by short loop closures, with explicit member lists: label[v] is
/// v's cluster, relabelled on merges (smaller into larger), so a lookup is O(1) and all merges
/// O(n log n).
struct AliasClusters {
  std::vector<NodeId> label;
  std::vector<std::vector<NodeId>> mem;
};

/// Merges the ends of loop closures no longer than merge_radius, shortest first, while every
/// pair of the two clusters' members stays within merge_radius and start and goal stay apart.
/// Edges at index >= first_virtual are virtual: never loop closures.
AliasClusters aliasClusters(const PoseGraph& g, NodeId start, NodeId goal, double merge_radius,
                            std::size_t first_virtual) {
  const std::size_t n = g.size();
  AliasClusters clusters;
  std::vector<NodeId>& label = clusters.label;
  std::vector<std::vector<NodeId>>& mem = clusters.mem;
  label.resize(n);
  mem.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    label[v] = static_cast<NodeId>(v);
    mem[v] = {static_cast<NodeId>(v)};
  }
  if (merge_radius > 0) {
    std::vector<std::pair<double, std::size_t>> closures;
    for (std::size_t i = 0; i < g.edges.size(); ++i) {
      const PoseEdge& e = g.edges[i];
      if (i >= first_virtual || e.from == e.to || e.from >= n || e.to >= n || !isLoopClosure(e))
        continue;
      const double d = planarDistance(g, e.from, e.to);
      if (d <= merge_radius) closures.emplace_back(d, i);
    }
    std::sort(closures.begin(), closures.end());
    for (const auto& [d, i] : closures) {
      NodeId ca = label[g.edges[i].from], cb = label[g.edges[i].to];
      if (ca == cb) continue;
      const NodeId cs = label[start], cg = label[goal];
      if ((ca == cs && cb == cg) || (ca == cg && cb == cs)) continue;
      bool close = true;
      for (NodeId a : mem[ca]) {
        for (NodeId b : mem[cb])
          if (planarDistance(g, a, b) > merge_radius) {
            close = false;
            break;
          }
        if (!close) break;
      }
      if (!close) continue;
      if (mem[ca].size() < mem[cb].size()) std::swap(ca, cb);
      for (NodeId v : mem[cb]) label[v] = ca;
      mem[ca].insert(mem[ca].end(), mem[cb].begin(), mem[cb].end());
      mem[cb].clear();
    }
  }
  return clusters;
}

/// buildSearchGraph; edges at index >= first_virtual are virtual: never loop closures.
SearchGraph buildSearchGraphImpl(const PoseGraph& g, NodeId start, NodeId goal, double merge_radius,
                                 bool collapse, std::size_t first_virtual) {
  checkNodes(g, start, goal);
  const std::size_t n = g.size();
  const auto [label, mem] = aliasClusters(g, start, goal, merge_radius, first_virtual);
  // Vertices numbered in the order of their smallest node.
  SearchGraph sg;
  sg.vertex_of.assign(n, 0);
  std::vector<NodeId> vertex_of_label(n, std::numeric_limits<NodeId>::max());
  for (std::size_t v = 0; v < n; ++v) {
    NodeId& id = vertex_of_label[label[v]];
    if (id == std::numeric_limits<NodeId>::max()) {
      id = static_cast<NodeId>(sg.members.size());
      sg.members.push_back(mem[label[v]]);
      std::sort(sg.members.back().begin(), sg.members.back().end());
    }
    sg.vertex_of[v] = id;
  }
  for (const auto& m : sg.members) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (NodeId v : m) c += Eigen::Vector2d(g.nodes[v].pose.x(), g.nodes[v].pose.y());
    sg.centre.push_back(c / static_cast<double>(m.size()));
    if (m.size() > 1) ++sg.merged_vertices;
  }
  sg.start = sg.vertex_of[start];
  sg.goal = sg.vertex_of[goal];
  std::vector<std::set<NodeId>> s(sg.members.size());
  for (const auto& e : g.edges) {
    if (e.from >= n || e.to >= n) continue;
    const NodeId a = sg.vertex_of[e.from], b = sg.vertex_of[e.to];
    if (a == b) continue;
    s[a].insert(b);
    s[b].insert(a);
  }
  std::vector<std::vector<NodeId>> adj(s.size());
  for (std::size_t v = 0; v < s.size(); ++v) adj[v].assign(s[v].begin(), s[v].end());
  sg.reduced = reduce(adj, sg.start, sg.goal, collapse);
  for (const auto& e : sg.reduced.edges) {
    double len = 0;
    NodeId prev = e.a;
    for (NodeId v : e.interior) {
      len += (sg.centre[v] - sg.centre[prev]).norm();
      prev = v;
    }
    sg.length.push_back(len + (sg.centre[e.b] - sg.centre[prev]).norm());
  }
  return sg;
}

}  // namespace

SearchGraph buildSearchGraph(const PoseGraph& g, NodeId start, NodeId goal, double merge_radius,
                             bool collapse) {
  return buildSearchGraphImpl(g, start, goal, merge_radius, collapse,
                              std::numeric_limits<std::size_t>::max());
}

std::vector<NodeId> routeVertices(const SearchGraph& sg,
                                  const std::vector<std::pair<std::size_t, bool>>& edges) {
  std::vector<NodeId> seq{sg.start};
  for (const auto& [i, fwd] : edges) {
    const auto& e = sg.reduced.edges.at(i);
    if (seq.back() != (fwd ? e.a : e.b))
      throw Error("routeVertices: reduced edge " + std::to_string(i) +
                  " does not continue the route");
    if (fwd)
      seq.insert(seq.end(), e.interior.begin(), e.interior.end());
    else
      seq.insert(seq.end(), e.interior.rbegin(), e.interior.rend());
    seq.push_back(fwd ? e.b : e.a);
  }
  return seq;
}

std::vector<NodeId> expandRoute(const PoseGraph& g, const SearchGraph& sg,
                                const std::vector<NodeId>& vertices, NodeId start, NodeId goal) {
  checkNodes(g, start, goal);
  if (sg.vertex_of.size() != g.size())
    throw Error("expandRoute: the search graph belongs to another pose graph");
  if (vertices.empty() || vertices.front() != sg.vertex_of[start] ||
      vertices.back() != sg.vertex_of[goal])
    throw Error("expandRoute: the route does not run from the start's to the goal's vertex");
  std::vector<int> pos(sg.members.size(), -1);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (vertices[i] >= sg.members.size() || pos[vertices[i]] >= 0)
      throw Error("expandRoute: vertex " + std::to_string(vertices[i]) +
                  " is missing or repeated in the route");
    pos[vertices[i]] = static_cast<int>(i);
  }
  const auto adj = simpleAdjacency(g);
  const auto path = dijkstraNodes(g, adj, start, goal, [&](NodeId v, NodeId w) {
    const int pw = pos[sg.vertex_of[w]], pv = pos[sg.vertex_of[v]];
    return pw >= 0 && (pw == pv || pw == pv + 1);
  });
  if (path.empty())
    throw Error(
        "expandRoute: the route is not realizable in the pose graph (consecutive "
        "vertices not adjacent)");
  return path;
}

std::vector<NodeId> shortestPath(const PoseGraph& g, NodeId start, NodeId goal) {
  checkNodes(g, start, goal);
  return dijkstraNodes(g, simpleAdjacency(g), start, goal, [](NodeId, NodeId) { return true; });
}

namespace {

/// `g` plus the virtual edges as pose-graph edges (mean: the relative pose of the estimates;
/// information from the a -> b covariance), appended after g's own edges.
PoseGraph withVirtualEdges(const PoseGraph& g, const std::vector<VirtualEdge>& v) {
  PoseGraph a = g;
  for (const auto& e : v) {
    if (e.a >= g.size() || e.b >= g.size() || e.a == e.b)
      throw Error("virtual edge " + std::to_string(e.a) + " - " + std::to_string(e.b) +
                  ": not two distinct nodes of the graph");
    PoseEdge pe;
    pe.from = e.a;
    pe.to = e.b;
    pe.mean = g.nodes[e.b].pose - g.nodes[e.a].pose;
    pe.mean.normalizePhi();
    pe.information = edgeInformation(pe.mean, e.covariance_ab, Mat3::Identity() * 1e-12);
    pe.kind = EdgeKind::Odometry;
    a.edges.push_back(pe);
  }
  return a;
}

PathSearchResult searchPathsImpl(const PoseGraph& g, NodeId start, NodeId goal,
                                 const PathSearchOptions& o, std::size_t first_virtual);

}  // namespace

PathSearchResult searchPaths(const PoseGraph& g, NodeId start, NodeId goal,
                             const PathSearchOptions& o,
                             const std::vector<VirtualEdge>* virtual_edges) {
  if (!virtual_edges || virtual_edges->empty())
    return searchPathsImpl(g, start, goal, o, std::numeric_limits<std::size_t>::max());
  checkNodes(g, start, goal);
  return searchPathsImpl(withVirtualEdges(g, *virtual_edges), start, goal, o, g.edges.size());
}

namespace {

using Route = std::vector<std::pair<std::size_t, bool>>;  // reduced edges taken, forward?

/// Depth-first enumeration of the simple routes. search = auto gives up (for Yen's) once it
/// has more than max_paths routes or has spent 64 x max_paths expansions: a loopy graph can
/// hide few routes in a huge search tree (out.fell_back, and no routes).
std::vector<Route> enumerateRoutes(const SearchGraph& sg, const PathSearchOptions& o,
                                   PathSearchResult& out) {
  const std::size_t nv = sg.members.size();
  std::vector<Route> routes;
  const bool automatic = o.method == SearchMethod::Auto;
  const std::size_t max_expansions = automatic ? std::max<std::size_t>(64 * o.max_paths, 4096) : 0;
  std::vector<std::vector<std::pair<std::size_t, bool>>> inc(nv);
  for (std::size_t i = 0; i < sg.reduced.edges.size(); ++i) {
    inc[sg.reduced.edges[i].a].emplace_back(i, true);
    inc[sg.reduced.edges[i].b].emplace_back(i, false);
  }
  std::vector<char> on_path(nv, 0);
  Route stack;
  bool stop = false;
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t expansions = 0;
  std::function<void(NodeId)> dfs = [&](NodeId v) {
    if (stop) return;
    ++expansions;
    if (o.max_seconds > 0 && (expansions & 4095) == 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
            o.max_seconds) {
      out.timed_out = true;
      stop = true;
      return;
    }
    if (automatic && expansions > max_expansions) {
      out.fell_back = true;
      stop = true;
      return;
    }
    if (v == sg.goal) {
      if (routes.size() >= o.max_paths) {
        if (automatic)
          out.fell_back = true;
        else
          out.capped = true;
        stop = true;
        return;
      }
      routes.push_back(stack);
      return;
    }
    on_path[v] = 1;
    for (const auto& [i, fwd] : inc[v]) {
      const NodeId w = fwd ? sg.reduced.edges[i].b : sg.reduced.edges[i].a;
      if (on_path[w]) continue;
      stack.emplace_back(i, fwd);
      dfs(w);
      stack.pop_back();
      if (stop) break;
    }
    on_path[v] = 0;
  };
  dfs(sg.start);
  if (automatic && out.timed_out) out.fell_back = true;
  if (out.timed_out && !automatic) out.capped = true;
  if (out.fell_back) {
    routes.clear();
    out.timed_out = false;
  }
  return routes;
}

/// Yen's k shortest simple routes, plus the penalty method's diverse ones.
std::vector<Route> yenRoutes(const SearchGraph& sg, const PathSearchOptions& o,
                             PathSearchResult& out) {
  const std::size_t nv = sg.members.size();
  std::vector<WeightedEdge> we;
  for (std::size_t i = 0; i < sg.reduced.edges.size(); ++i)
    we.push_back({sg.reduced.edges[i].a, sg.reduced.edges[i].b, sg.length[i]});
  auto edge_paths = kShortestSimplePaths(nv, we, sg.start, sg.goal, o.k_paths);
  if (o.diverse_paths > 0) {
    std::set<std::vector<std::size_t>> have(edge_paths.begin(), edge_paths.end());
    for (auto& p : diversePaths(nv, we, sg.start, sg.goal, o.diverse_paths, o.diverse_penalty))
      if (have.insert(p).second) {
        edge_paths.push_back(std::move(p));
        ++out.diverse_added;
      }
  }
  std::vector<Route> routes;
  for (const auto& p : edge_paths) {
    Route r;
    NodeId at = sg.start;
    for (std::size_t i : p) {
      const bool fwd = sg.reduced.edges[i].a == at;
      r.emplace_back(i, fwd);
      at = fwd ? sg.reduced.edges[i].b : sg.reduced.edges[i].a;
    }
    routes.push_back(std::move(r));
  }
  return routes;
}

PathSearchResult searchPathsImpl(const PoseGraph& g, NodeId start, NodeId goal,
                                 const PathSearchOptions& o, std::size_t first_virtual) {
  checkNodes(g, start, goal);
  PathSearchResult out;
  out.method = o.method == SearchMethod::Yen ? SearchMethod::Yen : SearchMethod::All;
  if (start == goal) {
    out.paths.push_back({start});
    return out;
  }
  const SearchGraph sg =
      buildSearchGraphImpl(g, start, goal, o.merge_radius, o.reduce, first_virtual);
  out.reduced_nodes = sg.reduced.kept.size();
  out.reduced_edges = sg.reduced.edges.size();
  out.merged_vertices = sg.merged_vertices;
  std::vector<Route> routes;
  if (o.method != SearchMethod::Yen) routes = enumerateRoutes(sg, o, out);
  if (o.method == SearchMethod::Yen || out.fell_back) {
    out.method = SearchMethod::Yen;
    std::vector<Route> yen = yenRoutes(sg, o, out);
    routes.insert(routes.end(), std::make_move_iterator(yen.begin()),
                  std::make_move_iterator(yen.end()));
  }
  std::set<std::vector<NodeId>> seen;
  for (const auto& r : routes) {
    auto p = expandRoute(g, sg, routeVertices(sg, r), start, goal);
    if (seen.insert(p).second) out.paths.push_back(std::move(p));
  }
  if (o.add_shortest) {
    auto p = shortestPath(g, start, goal);
    if (!p.empty() && seen.insert(p).second) {
      out.paths.push_back(std::move(p));
      out.added_shortest = true;
    }
  }
  return out;
}

}  // namespace

PathSearchResult allSimplePaths(const PoseGraph& g, NodeId start, NodeId goal,
                                const PathSearchOptions& o) {
  PathSearchOptions a = o;
  a.method = SearchMethod::All;
  a.add_shortest = false;
  return searchPaths(g, start, goal, a);
}

}  // namespace asf::planning
