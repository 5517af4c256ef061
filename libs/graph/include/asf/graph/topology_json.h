#pragma once
/// \file topology_json.h
/// The topological graph as JSON, as `asf run` writes topology.json (readTopologyJson in
/// multigraph.h reads it back as a region graph).
#include <asf/topo_graph.h>

#include <string>

namespace asf::graph {

/// The topological graph as JSON text (the shape of `asf run`'s topology.json): current,
/// nodes [{region, centroid [x, y], area_m2, visited, entrance_edge}], edges [{a, b, frontier,
/// midpoint [x, y], width_m, traversals [{forward, time_s}]}]; b = -1 is the unexplored node.
std::string topologyJson(const TopoGraph& topo);

}  // namespace asf::graph
