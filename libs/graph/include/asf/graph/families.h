#pragma once
/// \file families.h
/// Seeded generators of test graph families for the optimal-exploration analysis (grids,
/// trees, small worlds, rooms along corridors), and the graph-list writer.
#include <asf/graph/multigraph.h>

#include <cstdint>
#include <string>
#include <vector>

namespace asf::graph {

/// rows x cols 4-connected grid (rows, cols >= 1).
Multigraph gridGraph(int rows, int cols);
/// Simple connected graph with n nodes and m >= n-1 edges (m <= n(n-1)/2): node i > 0 joins
/// a uniformly drawn earlier node, then distinct random pairs are added.
Multigraph randomConnectedGraph(int n, int m, std::uint32_t seed);
/// Uniformly random labelled tree on n >= 1 nodes (random Pruefer sequence).
Multigraph randomTree(int n, std::uint64_t seed);
/// Watts-Strogatz small world: a ring where each node joins its k/2 nearest on each side
/// (k even, 2 <= k < n), each edge rewired with probability beta (no self-loops, no
/// duplicates); redrawn until connected.
Multigraph smallWorld(int n, int k, double beta, std::uint64_t seed);
/// An indoor-like topological graph: a corridor of `corridor` segments (a chain, closed into a
/// loop with probability loop_prob), each corridor node with 0..max_rooms rooms attached
/// (leaves), and a door between rooms attached to the same or neighbouring corridor nodes
/// with probability door_prob (the cycles of real buildings).
Multigraph roomsAndCorridor(int corridor, int max_rooms, double door_prob, double loop_prob,
                            std::uint64_t seed);

/// Families by name for `asf graph-gen`: "grid", "tree", "smallworld", "rooms", "mixed"
/// (cycling through the four). `count` graphs with at most `max_nodes` nodes (>= 4) and at
/// least 4, each drawn from its own seed (seed + index): the list does not depend on count.
std::vector<Multigraph> generateFamily(const std::string& family, int count, int max_nodes,
                                       std::uint64_t seed);

/// Writes graphs in the graph-list format of readGraphList (1-based `n m u-v ...`), with a
/// leading '#' comment line. Throws Error if the file cannot be written.
void writeGraphList(const std::string& path, const std::vector<Multigraph>& graphs,
                    const std::string& comment = "");

}  // namespace asf::graph
