#include <asf/errors.h>
#include <asf/graph/routes.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>

#include "route_helpers.h"

namespace asf::graph {

namespace detail {

std::string node1(int v) { return std::to_string(v + 1); }

std::string edgeName(const Multigraph& g, int e) {
  return "edge " + std::to_string(e + 1) + " (" + node1(g.edges[e].u) + "-" + node1(g.edges[e].v) +
         ")";
}

/// Endpoints in range and lengths usable as costs; every public entry point calls it.
void checkGraph(const Multigraph& g) {
  if (g.n < 0) throw InputError("graph: negative node count");
  for (int e = 0; e < g.m(); ++e) {
    const Edge& ed = g.edges[e];
    if (ed.u < 0 || ed.u >= g.n || ed.v < 0 || ed.v >= g.n)
      throw InputError("graph: edge " + std::to_string(e + 1) + " names a node outside 1.." +
                       std::to_string(g.n));
    if (!std::isfinite(ed.length) || ed.length < 0)
      throw InputError("graph: " + edgeName(g, e) + " has length " + std::to_string(ed.length) +
                       " (must be finite and >= 0)");
  }
}

void checkNode(const Multigraph& g, int v, const char* what) {
  if (v < 0 || v >= g.n)
    throw InputError(std::string(what) + " node " + std::to_string(v + 1) + " is outside 1.." +
                     std::to_string(g.n));
}

int otherEnd(const Edge& e, int v) { return e.u == v ? e.v : e.u; }

/// Appends one step to a walk.
void step(const Multigraph& g, Walk& w, int e) {
  const int from = w.nodes.back();
  w.nodes.push_back(otherEnd(g.edges[e], from));
  w.edges.push_back(e);
  w.length += g.edges[e].length;
}

/// Hierholzer on the multiset of edges `copies` (original edge indices, repeated for
/// duplicated edges), from `start`. Returns an empty optional-like walk (nodes empty) when
/// some copy is not reachable from start; parity is the caller's business.
Walk hierholzer(const Multigraph& g, const std::vector<int>& copies, int start) {
  std::vector<std::vector<int>> adj(g.n);
  for (int c = 0; c < static_cast<int>(copies.size()); ++c) {
    const Edge& e = g.edges[copies[c]];
    adj[e.u].push_back(c);
    if (e.v != e.u) adj[e.v].push_back(c);
  }
  std::vector<char> used(copies.size(), 0);
  std::vector<std::size_t> ptr(g.n, 0);
  std::vector<std::pair<int, int>> stack{{start, -1}};  // node, copy used to arrive there
  std::vector<std::pair<int, int>> out;
  out.reserve(copies.size() + 1);
  while (!stack.empty()) {
    const int v = stack.back().first;
    std::size_t& p = ptr[v];
    while (p < adj[v].size() && used[adj[v][p]]) ++p;
    if (p == adj[v].size()) {
      out.push_back(stack.back());
      stack.pop_back();
    } else {
      const int c = adj[v][p];
      used[c] = 1;
      stack.push_back({otherEnd(g.edges[copies[c]], v), c});
    }
  }
  Walk w;
  if (out.size() != copies.size() + 1) return w;
  std::reverse(out.begin(), out.end());
  w.nodes.push_back(start);
  for (std::size_t i = 1; i < out.size(); ++i) step(g, w, copies[out[i].second]);
  return w;
}

std::string firstUnreached(const Multigraph& g, const std::vector<int>& copies, int start) {
  // Reachability from start, to name an edge the walk could not reach.
  const auto inc = g.incidence();
  std::vector<char> seen(g.n, 0);
  std::vector<int> st{start};
  seen[start] = 1;
  while (!st.empty()) {
    const int a = st.back();
    st.pop_back();
    for (int e : inc[a]) {
      const int b = otherEnd(g.edges[e], a);
      if (!seen[b]) seen[b] = 1, st.push_back(b);
    }
  }
  for (int e : copies)
    if (!seen[g.edges[e].u]) return edgeName(g, e);
  return "an edge";
}

std::vector<int> oddVertices(const Multigraph& g) {
  std::vector<int> odd;
  const auto deg = g.degrees();
  for (int v = 0; v < g.n; ++v)
    if (deg[v] % 2) odd.push_back(v);
  return odd;
}

std::string nodeList(const std::vector<int>& vs) {
  std::string s;
  for (std::size_t i = 0; i < vs.size() && i < 12; ++i) s += (i ? ", " : "") + node1(vs[i]);
  if (vs.size() > 12) s += ", ...";
  return s;
}

std::vector<int> allEdges(const Multigraph& g) {
  std::vector<int> c(g.m());
  std::iota(c.begin(), c.end(), 0);
  return c;
}

}  // namespace detail

using namespace detail;

// ----------------------------------------------------------------------------------------------
// Walk

std::vector<int> Walk::traversals(int m) const {
  std::vector<int> x(m, 0);
  for (int e : edges)
    if (e >= 0 && e < m) ++x[e];
  return x;
}

std::vector<double> Walk::weights(int m) const {
  const auto x = traversals(m);
  return std::vector<double>(x.begin(), x.end());
}

std::string walkError(const Multigraph& g, const Walk& w) {
  if (w.nodes.empty()) return "walk has no node";
  if (w.nodes.size() != w.edges.size() + 1)
    return "walk has " + std::to_string(w.nodes.size()) + " nodes for " +
           std::to_string(w.edges.size()) + " edges";
  for (int v : w.nodes)
    if (v < 0 || v >= g.n)
      return "walk names node " + std::to_string(v) + " (0-based) outside the graph";
  double len = 0;
  for (std::size_t i = 0; i < w.edges.size(); ++i) {
    const int e = w.edges[i];
    if (e < 0 || e >= g.m())
      return "step " + std::to_string(i) + " names edge " + std::to_string(e) +
             " outside the graph";
    const Edge& ed = g.edges[e];
    const int a = w.nodes[i], b = w.nodes[i + 1];
    if (!((ed.u == a && ed.v == b) || (ed.u == b && ed.v == a)))
      return "step " + std::to_string(i) + ": " + edgeName(g, e) + " does not join " + node1(a) +
             " and " + node1(b);
    len += ed.length;
  }
  if (std::abs(len - w.length) > 1e-9 * std::max(1.0, std::abs(len)))
    return "walk length " + std::to_string(w.length) + " but its edges sum to " +
           std::to_string(len);
  return "";
}

bool coversAllEdges(const Multigraph& g, const Walk& w) {
  const auto x = w.traversals(g.m());
  return std::all_of(x.begin(), x.end(), [](int c) { return c > 0; });
}

bool visitsAllNodes(const Multigraph& g, const Walk& w) {
  std::vector<char> seen(g.n, 0);
  for (int v : w.nodes)
    if (v >= 0 && v < g.n) seen[v] = 1;
  return std::all_of(seen.begin(), seen.end(), [](char c) { return c != 0; });
}

// ----------------------------------------------------------------------------------------------
// Euler

bool hasEulerCircuit(const Multigraph& g) {
  checkGraph(g);
  if (!oddVertices(g).empty()) return false;
  if (g.m() == 0) return true;
  return !hierholzer(g, allEdges(g), g.edges[0].u).nodes.empty();
}

Walk eulerCircuit(const Multigraph& g, int start) {
  checkGraph(g);
  checkNode(g, start, "start");
  const auto odd = oddVertices(g);
  if (!odd.empty())
    throw Error("no Euler circuit: " + std::to_string(odd.size()) + " nodes of odd degree (" +
                nodeList(odd) + ")");
  const auto all = allEdges(g);
  Walk w = hierholzer(g, all, start);
  if (w.nodes.empty())
    throw Error("no Euler circuit from node " + node1(start) + ": " +
                firstUnreached(g, all, start) + " is not reachable from it");
  return w;
}

Walk eulerTrail(const Multigraph& g, int start) {
  checkGraph(g);
  const auto odd = oddVertices(g);
  if (odd.size() > 2)
    throw Error("no Euler trail: " + std::to_string(odd.size()) + " nodes of odd degree (" +
                nodeList(odd) + "), at most 2 allowed");
  if (start < 0) {
    // The lower odd node, else the first node with an edge (node 0 for an edgeless graph).
    start = 0;
    if (!odd.empty()) {
      start = odd.front();
    } else {
      const auto deg = g.degrees();
      for (int v = g.n - 1; v >= 0; --v)
        if (deg[v] > 0) start = v;
    }
  }
  checkNode(g, start, "start");
  if (odd.size() == 2 && start != odd[0] && start != odd[1])
    throw Error("no Euler trail from node " + node1(start) +
                ": a trail must start at an odd node (" + nodeList(odd) + ")");
  const auto all = allEdges(g);
  Walk w = hierholzer(g, all, start);
  if (w.nodes.empty())
    throw Error("no Euler trail from node " + node1(start) + ": " + firstUnreached(g, all, start) +
                " is not reachable from it");
  return w;
}

// ----------------------------------------------------------------------------------------------
// Shortest paths

Walk ShortestPaths::walkTo(const Multigraph& g, int target) const {
  if (target < 0 || target >= static_cast<int>(dist.size()) || !std::isfinite(dist[target]))
    throw Error("no path from node " + node1(source) + " to node " + node1(target));
  std::vector<int> rev;
  for (int v = target; v != source;) {
    const int e = pred_edge[v];
    rev.push_back(e);
    v = otherEnd(g.edges[e], v);
  }
  Walk w;
  w.nodes.push_back(source);
  for (auto it = rev.rbegin(); it != rev.rend(); ++it) step(g, w, *it);
  return w;
}

ShortestPaths dijkstra(const Multigraph& g, int source) {
  checkGraph(g);
  checkNode(g, source, "source");
  const auto inc = g.incidence();
  ShortestPaths sp;
  sp.source = source;
  sp.dist.assign(g.n, kInf);
  sp.pred_edge.assign(g.n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> pq;
  sp.dist[source] = 0;
  pq.push({0, source});
  while (!pq.empty()) {
    const auto [d, a] = pq.top();
    pq.pop();
    if (d > sp.dist[a]) continue;
    for (int e : inc[a]) {
      const int b = otherEnd(g.edges[e], a);
      const double nd = d + g.edges[e].length;
      if (nd < sp.dist[b]) {
        sp.dist[b] = nd;
        sp.pred_edge[b] = e;
        pq.push({nd, b});
      }
    }
  }
  return sp;
}

// ----------------------------------------------------------------------------------------------
// Chinese postman

PostmanResult chinesePostman(const Multigraph& g, int start, int end, MatchingMethod method) {
  checkGraph(g);
  checkNode(g, start, "start");
  if (end >= 0) checkNode(g, end, "end");
  if (end < 0) end = start;
  PostmanResult r;
  r.duplicates.assign(g.m(), 0);
  for (const Edge& e : g.edges) r.edges_length += e.length;

  // Vertices whose parity is wrong for a closed (or start -> end) walk.
  std::vector<char> odd(g.n, 0);
  for (int v : oddVertices(g)) odd[v] = 1;
  if (end != start) odd[start] ^= 1, odd[end] ^= 1;
  for (int v = 0; v < g.n; ++v)
    if (odd[v]) r.odd_vertices.push_back(v);

  const ShortestPaths from_start = dijkstra(g, start);
  for (int e = 0; e < g.m(); ++e)
    if (!std::isfinite(from_start.dist[g.edges[e].u]))
      throw Error("no postman walk from node " + node1(start) + ": " + edgeName(g, e) +
                  " is not reachable from it");
  if (!std::isfinite(from_start.dist[end]))
    throw Error("no postman walk: node " + node1(end) + " is not reachable from node " +
                node1(start));

  const int k = static_cast<int>(r.odd_vertices.size());
  std::vector<ShortestPaths> sp;
  sp.reserve(k);
  for (int v : r.odd_vertices) sp.push_back(dijkstra(g, v));
  std::vector<std::vector<double>> cost(k, std::vector<double>(k, 0));
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) cost[i][j] = sp[i].dist[r.odd_vertices[j]];
  // Dijkstra from i and from j may differ in the last bits; the matching wants symmetry.
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) cost[i][j] = cost[j][i] = std::min(cost[i][j], cost[j][i]);
  const auto mate = minWeightPerfectMatching(cost, method);

  std::vector<int> copies = allEdges(g);
  for (int i = 0; i < k; ++i) {
    if (mate[i] < i) continue;
    const Walk p = sp[i].walkTo(g, r.odd_vertices[mate[i]]);
    for (int e : p.edges) {
      ++r.duplicates[e];
      copies.push_back(e);
    }
  }
  r.walk = hierholzer(g, copies, start);
  if (r.walk.nodes.empty() || r.walk.nodes.back() != end)
    throw std::logic_error("chinesePostman: augmented graph not Eulerian");
  r.added_length = r.walk.length - r.edges_length;
  return r;
}

// ----------------------------------------------------------------------------------------------
// Dispatch

namespace {
const std::pair<RouteAlgorithm, const char*> kAlgorithmNames[] = {
    {RouteAlgorithm::Euler, "euler"},
    {RouteAlgorithm::ChinesePostman, "cpp"},
    {RouteAlgorithm::Tsp, "tsp"},
    {RouteAlgorithm::Tarry, "tarry"},
    {RouteAlgorithm::TarryModified, "tarry_modified"},
    {RouteAlgorithm::Tremaux, "tremaux"},
    {RouteAlgorithm::Dfs, "dfs"},
};
}  // namespace

RouteAlgorithm parseRouteAlgorithm(const std::string& name) {
  std::string all;
  for (const auto& [a, s] : kAlgorithmNames) {
    if (name == s) return a;
    all += (all.empty() ? "" : ", ") + std::string(s);
  }
  throw InputError("unknown route algorithm '" + name + "' (one of " + all + ")");
}

std::string routeAlgorithmName(RouteAlgorithm a) {
  for (const auto& [b, s] : kAlgorithmNames)
    if (a == b) return s;
  return "?";
}

RouteResult computeRoute(const Multigraph& g, RouteAlgorithm algorithm, int start,
                         std::uint32_t seed, int end) {
  RouteResult r;
  r.algorithm = algorithm;
  if (end >= 0 && algorithm != RouteAlgorithm::Euler && algorithm != RouteAlgorithm::ChinesePostman)
    throw InputError("an end node applies to euler and cpp only");
  auto fromExplore = [&](ExploreResult x) { r.walk = std::move(x.walk); };
  switch (algorithm) {
    case RouteAlgorithm::Euler:
      if (end < 0) {
        r.walk = eulerCircuit(g, start);
      } else {
        r.walk = eulerTrail(g, start);
        if (r.walk.nodes.back() != end)
          throw Error("no Euler trail from node " + node1(start) + " to node " + node1(end) +
                      " (it would end at node " + node1(r.walk.nodes.back()) + ")");
      }
      r.exact = true;
      r.lower_bound = r.walk.length;
      break;
    case RouteAlgorithm::ChinesePostman:
      r.walk = chinesePostman(g, start, end).walk;
      r.exact = true;
      r.lower_bound = r.walk.length;
      break;
    case RouteAlgorithm::Tsp: {
      TspResult t = travelingSalesman(g, start);
      r.walk = std::move(t.walk);
      r.exact = t.exact;
      r.lower_bound = t.lower_bound;
      break;
    }
    case RouteAlgorithm::Tarry:
      fromExplore(tarry(g, start, TarryOptions{}, seed));
      break;
    case RouteAlgorithm::TarryModified:
      fromExplore(tarry(g, start, TarryOptions::modified(), seed));
      break;
    case RouteAlgorithm::Tremaux:
      fromExplore(tremaux(g, start, seed));
      break;
    case RouteAlgorithm::Dfs:
      fromExplore(dfsExplore(g, start, seed));
      break;
  }
  // Coverage along the walk, the same way for every algorithm.
  Tracker tr(g, r.walk.nodes.front());
  for (int e : r.walk.edges) tr.go(e, /*bounded=*/false);
  const ExploreResult x = tr.finish();
  r.covered_all_edges = x.covered_all_edges;
  r.visited_all_nodes = x.visited_all_nodes;
  r.steps_to_cover_edges = x.steps_to_cover_edges;
  r.steps_to_visit_nodes = x.steps_to_visit_nodes;
  return r;
}

}  // namespace asf::graph
