#pragma once
// Internal to the `thesis` variant (dude_thesis*.cpp): the polygon with holes as linked rings
// (a cut is applied by splicing two vertices, as the reference does), and the CGAL-backed
// predicates. Not installed; no CGAL types in here.
#include "dude.h"

#include <memory>
#include <utility>
#include <vector>

namespace asf::dude::thesis::detail {

/// Rings as doubly linked vertex lists. A cut (a, b) splices the two vertices: on one ring it
/// splits it in two, across two rings (outer and hole, two holes) it merges them.
struct Poly {
  std::vector<Vec2> p;
  std::vector<int> nx, pv;
  std::vector<int> heads;  ///< one vertex per ring; heads[0] is the outer ring (counter-clockwise)

  int add(Vec2 q) {
    p.push_back(q);
    nx.push_back(-1);
    pv.push_back(-1);
    return static_cast<int>(p.size()) - 1;
  }
  /// Appends a closed ring; returns its head.
  int addRing(const Ring& r);
  /// Ring members from `head` in order.
  std::vector<int> ring(int head) const;
};

/// Ring vertices -> positions.
Ring positions(const Poly& P, const std::vector<int>& ids);

double dist2Seg(Vec2 s, Vec2 t, Vec2 q);
double signedAreaIds(const Poly& P, const std::vector<int>& ids);

/// Inner angle at b from ray b->a to ray b->c, in [0, 2 pi): a left turn a-b-c gives < pi.
double angleAt(Vec2 a, Vec2 b, Vec2 c);

/// Convex hull (CGAL) of pts: positions into pts, in ascending order.
std::vector<int> hullPositions(const std::vector<Vec2>& pts);

/// Douglas-Peucker on an open polyline: kept positions (first and last always), ascending.
std::vector<int> approximate(const std::vector<Vec2>& pts, double tolerance);

/// The reference's default approximation of an open polyline (DuDe 2D's `approximate`): the
/// vertex farthest from its current segment is added, then every segment gets a "chain"
/// seeded at its farthest vertex and parallel to it; the chains grow over the neighbouring
/// vertices, nearest first, until they meet (a shared vertex goes to the chain it fits
/// better), and the approximation is the chains' ends. Repeats until the largest chain
/// distance is below `tolerance`. Kept positions, ascending (first and last always).
std::vector<int> approximateChains(const std::vector<Vec2>& pts, double tolerance);

/// Unconstrained edges of the constrained Delaunay triangulation (CGAL) of the rings, as
/// pairs of the ids given in `rings` (edges at constructed intersection points are dropped).
std::vector<std::pair<int, int>> cdtFreeEdges(const Poly& P, const std::vector<std::vector<int>>& rings);

/// q strictly inside the polygon made of rings[0] (outer) minus the others (holes) (CGAL).
bool insidePolygon(const Poly& P, const std::vector<std::vector<int>>& rings, Vec2 q);

/// The same test for many points against one polygon: the rings are converted once.
class InsideTest {
 public:
  InsideTest(const Poly& P, const std::vector<std::vector<int>>& rings);
  ~InsideTest();
  bool operator()(Vec2 q) const;

 private:
  struct Rings;
  std::unique_ptr<Rings> rings_;
};

/// Proper or touching intersection of segments ab and cd; *at receives the point.
bool segmentsIntersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d, Vec2* at);

}  // namespace asf::dude::thesis::detail
