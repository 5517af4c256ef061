#pragma once
/// \file dude_thesis.h
/// Dual-Space Decomposition as the thesis ran it (`[dude] variant = thesis`): the cut
/// generation and selection of DuDe 2D (Liu, Xi, Lien, CVPR 2014), the implementation the
/// thesis used (bundled in lfermin77/Incremental_DuDe_ROS). Written here from reading that
/// code, none of it copied. Per piece and round:
///   convex hull -> bridges and pockets; each pocket decomposed recursively, its cuts become
///   the pocket's sub-bridges -> pocket minima (PMs): salient vertices of the convex hull of
///   each pocket deeper than tau -> hole PMs (diameter pair of each hole wider than tau) ->
///   feature points -> constrained Delaunay triangulations (CGAL) of the simplified polygon
///   (feature points only) and of the full polygon -> diagonals at the PMs that break a bridge
///   -> cut sets of one or two diagonals per PM (residual concavity) -> knapsack selection ->
///   cuts clipped to the polygon -> split -> next round, until a round finds no cut.
/// Every difference from the reference is listed in the plugin README.
/// Pure geometry (no MRPT, no OpenCV); CGAL only inside the .cpp.
#include "dude.h"

#include <vector>

namespace asf::dude::thesis {

/// How boundary chains are simplified into feature points (both are the reference's; it uses
/// Chains unless told otherwise).
enum class Approximation {
  Chains,         ///< its default `approximate`: chains grown around the farthest vertices
  DouglasPeucker  ///< its `dp_approximate`
};

struct Options {
  /// tau: the maximum concavity a piece may keep [same unit as the input].
  double max_concavity = 2.5;
  Approximation approximation = Approximation::Chains;
  /// Safety limits: a shape that reaches them is returned in its current pieces with a warning.
  int max_rounds = 200;
  int max_pieces = 20000;
};

/// Decomposes `shape` (outer ring + holes, any orientation; repeated consecutive points are
/// dropped) until no piece has a cut left. Degenerate input gives no piece. Deterministic;
/// never throws on bad geometry (a piece that cannot be cut is kept whole with a warning).
Result decompose(const Shape& shape, const Options& options);

/// One diagonal candidate of the first round, for tests: end points as positions.
struct Diagonal {
  Vec2 a, b;
};

/// What one round of the reference computes on `shape` (exposed for tests): its pocket
/// minima, every diagonal at a pocket minimum from the two triangulations, and the cuts it
/// selects (before they are applied).
struct RoundReport {
  std::vector<Vec2> pocket_minima;
  std::vector<double> concavities;  ///< of each pocket minimum
  std::vector<Vec2> features;       ///< vertices of the simplified polygon
  std::vector<Diagonal> diagonals;  ///< candidate cuts (both triangulations, deduplicated)
  std::vector<Cut> cuts;            ///< selected
};
RoundReport analyzeRound(const Shape& shape, double max_concavity,
                         Approximation approximation = Approximation::Chains);

}  // namespace asf::dude::thesis
