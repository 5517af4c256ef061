#pragma once
/// \file drawing.h
/// Drawings of edge weights on a graph (thesis figs. 5.11-5.13: the optimal weights of one
/// graph under E, A and D, edge thickness proportional to the weight).
#include <asf/graph/multigraph.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace asf::graph {

/// Node positions for a graph without geometry: stress majorization (Gansner, Koren and North,
/// "Graph drawing by stress majorization", 2004) of the hop distances, weights d^-2, started
/// from classical MDS and run `iterations` times. Disconnected pairs get the largest finite
/// distance plus one. Deterministic (no random start).
std::vector<Eigen::Vector2d> stressLayout(const Multigraph& g, int iterations = 300);

struct WeightPanel {
  std::string title;
  Eigen::VectorXd weights;  ///< one per edge, >= 0
};

/// One SVG with one panel per weight vector, side by side: each edge a straight line whose
/// width is proportional to its weight (the panel's largest weight drawn 8 px wide, zero
/// weights as a thin dotted line), nodes as small dots. Throws InputError when the sizes do
/// not match the graph, Error when the file cannot be written.
void writeWeightsSvg(const Multigraph& g, const std::vector<Eigen::Vector2d>& positions,
                     const std::vector<WeightPanel>& panels, const std::string& title,
                     const std::string& path);

}  // namespace asf::graph
