// The on-line explorers of a graph (Tarry, Tremaux, depth-first): the walks of an agent that
// sees only the edges at its node, the baselines of the exploration chapter's routes.
#include <asf/errors.h>
#include <asf/graph/routes.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "route_helpers.h"

namespace asf::graph {

using namespace detail;

int tarryChoose(const std::vector<TarryCandidate>& candidates, const TarryOptions& options,
                std::mt19937& rng) {
  std::vector<const TarryCandidate*> allowed;
  for (const auto& c : candidates)
    if (!c.traversed_outward && !c.entrance) allowed.push_back(&c);
  if (allowed.empty()) {
    for (const auto& c : candidates)
      if (c.entrance && !c.traversed_outward) return c.edge;  // the last resort
    return -1;
  }
  if (options.loop_closing_first &&
      std::any_of(allowed.begin(), allowed.end(), [](auto* c) { return c->leads_to_visited; }))
    allowed.erase(std::remove_if(allowed.begin(), allowed.end(),
                                 [](auto* c) { return !c->leads_to_visited; }),
                  allowed.end());
  if (options.nearest_first) {
    double best = kInf;
    for (auto* c : allowed) best = std::min(best, c->cost);
    const double tol = 1e-12 * std::max(1.0, std::abs(best));
    allowed.erase(std::remove_if(allowed.begin(), allowed.end(),
                                 [&](auto* c) { return c->cost > best + tol; }),
                  allowed.end());
  }
  if (allowed.size() == 1) return allowed.front()->edge;
  return allowed[rng() % allowed.size()]->edge;
}

Tracker::Tracker(const Multigraph& graph, int start)
    : g(graph), count(graph.m(), 0), seen(graph.n, 0), uncovered(graph.m()), unseen(graph.n - 1) {
  w.nodes.push_back(start);
  seen[start] = 1;
  if (uncovered == 0) r.steps_to_cover_edges = 0;
  if (unseen == 0) r.steps_to_visit_nodes = 0;
}

void Tracker::go(int e, bool bounded) {
  if (bounded && w.steps() > 2 * g.m() + 2)  // the explorers walk each edge at most twice
    throw std::logic_error("explorer: walk longer than twice the edges");
  step(g, w, e);
  if (count[e]++ == 0 && --uncovered == 0) r.steps_to_cover_edges = w.steps();
  if (!seen[at()]) {
    seen[at()] = 1;
    if (--unseen == 0) r.steps_to_visit_nodes = w.steps();
  }
}

ExploreResult Tracker::finish() {
  r.covered_all_edges = uncovered == 0;
  r.visited_all_nodes = unseen == 0;
  r.walk = std::move(w);
  return r;
}

ExploreResult tarry(const Multigraph& g, int start, const TarryOptions& options,
                    std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  // Darts: 2e leaves edges[e].u, 2e+1 leaves edges[e].v (both leave the node of a self-loop).
  std::vector<char> dart_used(2 * g.m(), 0);
  std::vector<int> entrance(g.n, -1);
  // What the explorer knows: edges at visited nodes; never-traversed ones among them.
  std::vector<char> known(g.m(), 0);
  int known_untraversed = 0;
  Tracker tr(g, start);
  auto arrive = [&](int v) {
    for (int e : inc[v])
      if (!known[e]) known[e] = 1, ++known_untraversed;
  };
  arrive(start);
  std::vector<TarryCandidate> cands;
  for (;;) {
    if (options.stop_when_covered && known_untraversed == 0) break;
    const int cur = tr.at();
    cands.clear();
    for (int e : inc[cur]) {
      const Edge& ed = g.edges[e];
      TarryCandidate c;
      c.edge = e;
      c.traversed_outward = ed.u == ed.v ? (dart_used[2 * e] && dart_used[2 * e + 1])
                                         : dart_used[ed.u == cur ? 2 * e : 2 * e + 1];
      c.entrance = e == entrance[cur];
      c.leads_to_visited = tr.seen[otherEnd(ed, cur)] != 0;
      c.cost = ed.length;
      cands.push_back(c);
    }
    const int e = tarryChoose(cands, options, rng);
    if (e < 0) break;
    const Edge& ed = g.edges[e];
    const int d =
        ed.u == ed.v ? (dart_used[2 * e] ? 2 * e + 1 : 2 * e) : (ed.u == cur ? 2 * e : 2 * e + 1);
    dart_used[d] = 1;
    if (tr.count[e] == 0) --known_untraversed;
    const int next = otherEnd(ed, cur);
    const bool first_visit = !tr.seen[next];
    tr.go(e);
    if (first_visit) {
      entrance[next] = e;
      arrive(next);
    }
  }
  return tr.finish();
}

ExploreResult tremaux(const Multigraph& g, int start, std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  std::vector<int> entrance(g.n, -1);
  Tracker tr(g, start);
  int turn_back = -1;  // edge to walk back at once (arrived at an old node by a new edge)
  std::vector<int> fresh;
  for (;;) {
    const int cur = tr.at();
    int e = turn_back;
    if (e < 0) {
      fresh.clear();
      for (int f : inc[cur])
        if (tr.count[f] == 0) fresh.push_back(f);
      if (!fresh.empty())
        e = fresh.size() == 1 ? fresh[0] : fresh[rng() % fresh.size()];
      else if (entrance[cur] >= 0 && tr.count[entrance[cur]] < 2)
        e = entrance[cur];
      else
        break;
    }
    const int next = otherEnd(g.edges[e], cur);
    const bool old = tr.seen[next] != 0;
    tr.go(e);
    turn_back = -1;
    if (!old)
      entrance[next] = e;
    else if (tr.count[e] == 1)
      turn_back = e;
  }
  return tr.finish();
}

ExploreResult dfsExplore(const Multigraph& g, int start, std::uint32_t seed) {
  checkGraph(g);
  checkNode(g, start, "start");
  std::mt19937 rng(seed);
  const auto inc = g.incidence();
  std::vector<int> parent(g.n, -1);
  Tracker tr(g, start);
  std::vector<int> forward;
  for (;;) {
    const int cur = tr.at();
    forward.clear();
    for (int e : inc[cur])
      if (!tr.seen[otherEnd(g.edges[e], cur)]) forward.push_back(e);
    if (!forward.empty()) {
      const int e = forward.size() == 1 ? forward[0] : forward[rng() % forward.size()];
      parent[otherEnd(g.edges[e], cur)] = e;
      tr.go(e);
    } else if (cur != start) {
      tr.go(parent[cur]);
    } else {
      break;
    }
  }
  return tr.finish();
}

}  // namespace asf::graph
