#pragma once
// Private to the graph library: the checks and walk helpers the route files (graph_routes.cpp,
// graph_explorers.cpp, graph_tsp.cpp) share.
#include <asf/graph/routes.h>

#include <limits>
#include <string>
#include <vector>

namespace asf::graph::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Node v as users number them (from 1).
std::string node1(int v);
/// "edge 3 (1-2)" for messages.
std::string edgeName(const Multigraph& g, int e);
/// Endpoints in range and lengths usable as costs; every public entry point calls it.
void checkGraph(const Multigraph& g);
/// InputError naming `what` unless v is a node of g.
void checkNode(const Multigraph& g, int v, const char* what);
/// The end of e that is not v.
int otherEnd(const Edge& e, int v);
/// Appends one step to a walk.
void step(const Multigraph& g, Walk& w, int e);
/// Nodes of odd degree, in increasing order.
std::vector<int> oddVertices(const Multigraph& g);

/// Bookkeeping of a walk as it is taken (the explorers', and every route's coverage): the
/// walk, coverage and the step counts (graph_explorers.cpp).
struct Tracker {
  const Multigraph& g;
  Walk w;
  std::vector<int> count;
  std::vector<char> seen;
  int uncovered, unseen;
  ExploreResult r;

  Tracker(const Multigraph& graph, int start);
  int at() const { return w.nodes.back(); }
  /// One step along edge e; bounded: a walk longer than twice the edges is a logic error.
  void go(int e, bool bounded = true);
  ExploreResult finish();
};

}  // namespace asf::graph::detail
