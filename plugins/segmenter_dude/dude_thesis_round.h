#pragma once
// Internal to the `thesis` variant: one round of DuDe 2D on one piece (the reference's
// c_dude::build) and the cut sets it builds, shared by the round (dude_thesis_round.cpp), the
// cut sets (dude_thesis_cutsets.cpp) and the selection (dude_thesis.cpp).
#include "dude_thesis_geometry.h"

#include <utility>
#include <vector>

namespace asf::dude::thesis::detail {

/// Per-vertex state of one round.
struct VertexInfo {
  double concavity = 0;
  int bpc = -1;   ///< bridge-pocket whose pocket minimum this is (set on candidates too)
  int hole = -1;  ///< hole ring whose feature this is
  bool feature = false;
  int pre_feature = -1, next_feature = -1;  ///< neighbours in the simplified polygon
  bool isPM() const { return (bpc >= 0 || hole >= 0) && concavity > 0; }
};

/// A cut set of one pocket minimum: one or two diagonals that resolve it (reference
/// c_cutset), with the number of pocket minima it resolves and its weight.
struct CutSet {
  enum Type { SinglePM, SingleTip, DoublePMPM, DoublePMTip, DoubleTipTip };
  int v = -1;
  std::vector<std::pair<int, int>> diagonals;  ///< (v, other) each
  Type type = SingleTip;
  int resolves = 1;
  double weight = 0;
};

struct RoundState {
  const Poly* P = nullptr;
  double tau = 0;
  std::vector<VertexInfo> info;
  std::vector<int> pms;  ///< every pocket minimum (outer and holes), ascending ids
  std::vector<std::vector<int>> diagonals;  ///< per vertex: other ends
  std::vector<std::vector<CutSet>> cutsets;  ///< per vertex
  std::vector<CutSet> all_cutsets;
  std::vector<int> ignored_holes;  ///< heads of holes narrower than tau (dropped, as the reference)
};

/// Runs one round: fills `st` and returns the selected cuts (vertex id pairs of P).
/// `clip` (the reference's isInitPolygon): cuts crossing the boundary are shortened.
/// `depth` bounds the recursion into pockets. `chains`: the reference's chain approximation
/// (else Douglas-Peucker) for the feature points.
std::vector<std::pair<int, int>> roundCuts(const Poly& P, double tau, bool chains, bool clip,
                                           int depth, RoundState* st);

/// Reference selection (c_knapsack::build + getOptimalCuts) over st.all_cutsets.
std::vector<std::pair<int, int>> selectCuts(RoundState& st);

/// Does diagonal (v, o) resolve v (residual concavity below tau on both sides)?
bool resolves(const RoundState& st, int v, int o);

/// Reference isHoleDiagonalValid: from a hole feature, not to a vertex of the same hole between
/// it and its neighbouring features.
bool holeDiagonalValid(const RoundState& st, int u, int v);

/// Fills st.cutsets[v] (and appends to st.all_cutsets) with the cut sets of pocket minimum v
/// from its diagonals st.diagonals[v] (reference build_cutsets, residual-concavity version).
void buildCutsets(RoundState& st, int v);

}  // namespace asf::dude::thesis::detail
