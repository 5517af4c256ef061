#pragma once
// Private to asf_dude: the concavity of a ring's vertices through the hierarchy of bridges
// (DuDe's concavity measure; dude_concavity.cpp), used by the `rooms` decomposition.
#include <vector>

#include "dude.h"

namespace asf::dude::detail {

struct Concavity {
  std::vector<double> value;  ///< per ring vertex
  std::vector<int> pocket;    ///< innermost pocket of the vertex, -1 on the hull
  int pockets = 0;
};

/// Concavity of every vertex of `r` (counter-clockwise): 0 on the convex hull; inside a pocket
/// its distance to the pocket's bridge plus the bridge's own concavity where it projects.
Concavity analyse(const Ring& r);

/// Strict convex hull (Andrew's monotone chain): positions into `pts`, ascending.
std::vector<int> hullPositions(const std::vector<Vec2>& pts);

}  // namespace asf::dude::detail
