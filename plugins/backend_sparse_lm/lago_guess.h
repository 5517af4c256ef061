#pragma once
// Private to backend_sparse_lm: the LAGO-style initial guess (lago_guess.cpp).
#include "sparse_problem.h"

namespace asf::sparse_lm::detail {

/// A LAGO-style initial guess (orientations as in Carlone et al., "A fast and accurate
/// approximation for planar pose graph optimization", IJRR 2014): orientations by linear
/// least squares on the relative rotations, each unwrapped against a spanning tree (which
/// fixes the 2 pi winding of every cycle); positions composed down the same tree with those
/// orientations (the first Gauss-Newton step then solves them: with the orientations right
/// the problem is nearly linear in positions). It lets the iteration start in the basin of
/// the best minimum on all the shared benchmarks (README.md). Nodes not linked to node 0 or a
/// fixed node keep their pose. Returns false if the orientation system could not be solved.
bool lagoGuess(const Problem& P, const Structure& S, Poses& x);

}  // namespace asf::sparse_lm::detail
