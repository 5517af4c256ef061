#pragma once
/// \file multigraph.h
/// Undirected weighted multigraph: the common input of the graph analysis (information of
/// walks, optimal edge weights) and of the route algorithms (Euler, Chinese postman, TSP,
/// Tarry). Parallel edges and self-loops are allowed; nodes are 0-based here (files are
/// 1-based, see readGraphList).
#include <string>
#include <utility>
#include <vector>

namespace asf::graph {

struct Edge {
  int u = 0, v = 0;
  double length = 1;  ///< traversal cost (metres, or 1 for unweighted graphs)
  /// Information one traversal adds, relative to a common Sigma^-1: the alpha_j of the
  /// thesis' bounded-noise model (eq. 5.53), so that L_w = sum_j alpha_j E_j. 1 for graphs
  /// whose edges all carry the same information (Corollary 5.2.2). Must be > 0 and finite.
  double information = 1;
};

struct Multigraph {
  int n = 0;
  std::vector<Edge> edges;

  int m() const { return static_cast<int>(edges.size()); }
  /// Every node reachable from node 0 (a graph without nodes is not connected).
  bool connected() const;
  /// Degree of each node (a self-loop counts twice).
  std::vector<int> degrees() const;
  /// Edge indices incident to each node (a self-loop listed once).
  std::vector<std::vector<int>> incidence() const;
};

/// One graph of a graph-list file, with its 1-based line number.
struct ListedGraph {
  int line = 0;
  Multigraph graph;
};

/// Reads a graph-list file: one graph per line, `n m u1-v1 u2-v2 ...` with 1-based node ids
/// (unit lengths). Blank lines and lines starting with '#' are skipped. Throws InputError naming
/// file:line for a malformed line (bad count, id out of range, m not matching the edge list).
std::vector<ListedGraph> readGraphList(const std::string& path);
/// Parses one graph-list line; `where` prefixes error messages (e.g. "file.txt:3").
Multigraph parseGraphLine(const std::string& line, const std::string& where);

/// The region graph of a topology.json (written by `asf run` and `asf segment --graph`): one
/// node per region (ids > 0), one unit edge per region border; frontier edges and the
/// unexplored node (region <= 0) are left out.
struct RegionGraph {
  Multigraph graph;
  std::vector<long> regions;  ///< region id of each node
  /// Centroid (x, y) of each node; empty when some node has none.
  std::vector<std::pair<double, double>> centroids;
};
/// Throws InputError naming the file: not JSON, no "nodes"/"edges", a field missing or of
/// another type, an edge naming a region that is not a node.
RegionGraph readTopologyJson(const std::string& path);
/// The same from text; `name` is the file named in errors.
RegionGraph parseTopologyJson(const std::string& text, const std::string& name);

}  // namespace asf::graph
