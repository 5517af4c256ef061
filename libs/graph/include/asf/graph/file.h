#pragma once
/// \file file.h
/// A graph read from whatever file names it: a g2o pose graph (or a run folder, for its
/// graph.g2o), a topology.json, or one line of a graph list. `asf optimal` and `asf route`
/// read their graphs so.
#include <asf/graph/multigraph.h>
#include <asf/pose_graph.h>
#include <asf/graph/pose_graph_information.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace asf::graph {

struct GraphFile {
  Multigraph g;
  std::vector<Eigen::Vector2d> positions;  ///< node positions; empty: to be laid out
  int line = 0;                            ///< graph lists: the line read
  std::optional<PoseGraph> pose_graph;     ///< g2o files
  std::optional<BoundedNoise> noise;       ///< g2o files: the bounded-noise model
};

/// Reads `path`: a folder (its graph.g2o), a .g2o file (one node per pose, one edge per
/// measurement, edge information alpha_j from the bounded-noise model under `reference`, or
/// 1 when `unit`), a .json topology (region centroids as positions) or a graph list (the graph
/// on `line`, the first when none). Throws InputError naming the file (and line): a folder
/// without graph.g2o, a pose graph without edges, `line` given for a g2o or JSON file, no
/// graph on that line.
GraphFile readGraphFile(const std::string& path, std::optional<int> line, bool unit,
                        NoiseReference reference);

/// The graph of `list` on `line` (the first when none); InputError naming path:line when
/// there is none.
const ListedGraph& graphOnLine(const std::vector<ListedGraph>& list, const std::string& path,
                               std::optional<int> line);

}  // namespace asf::graph
