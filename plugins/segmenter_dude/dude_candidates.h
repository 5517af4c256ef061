#pragma once
// Private to asf_dude: the candidate cuts of the `rooms` decomposition at a pocket minimum
// (dude_candidates.cpp), with what they share with the rounds in dude.cpp: a cut's end, the
// piece being decomposed and the visibility test.
#include <vector>

#include "dude.h"
#include "dude_concavity.h"

namespace asf::dude::detail {

/// Where a cut ends: a vertex of the ring, or a point inside an edge.
struct End {
  int vertex = -1;  ///< ring position, or -1
  int edge = -1;    ///< edge (edge, edge+1) when vertex < 0
  double t = 0;     ///< parameter on the edge
  Vec2 p;
};

struct Candidate {
  int pm = -1;  ///< ring position of the pocket minimum
  End end;
  double length = 0, score = 0;
  int other_pm = -1;  ///< the far end, when it is a minimum this cut also resolves
};

/// A polygon being decomposed: the outer ring (holes already bridged into it, or kept as
/// obstacles to visibility).
struct Work {
  Ring outer;
  std::vector<Ring> holes;  ///< holes kept whole (clockwise)
  int round = 0;
};

/// True when segment pq touches an edge of `ring` anywhere except at p and q themselves
/// (both assumed on the boundary). Edges through p or q are fine when they only meet there.
bool blockedBy(const Ring& ring, Vec2 p, Vec2 q);

/// Appends to `out` the cuts from pocket minimum pm (a position in w.outer) that run inside
/// the polygon and resolve it (both angles they leave there below pi + angle_tolerance): to
/// the nearest reflex vertices, along its two edges continued, and to the nearest boundary
/// points. Score: the concavity resolved (that of a far end deeper than tau too, when the cut
/// resolves it there) over the cut's length.
void addCandidates(const Work& w, const Concavity& c, const std::vector<char>& reflex,
                   const std::vector<int>& reflex_list, int pm, double tau,
                   double angle_tolerance, std::vector<Candidate>& out);

}  // namespace asf::dude::detail
