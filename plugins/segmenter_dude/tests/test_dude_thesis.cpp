// Tests of the `thesis` variant of DuDe (dude_thesis.h) on hand-made polygons (metres), with
// answers worked out by hand and a brute-force oracle for the candidate diagonals.
#include <dude.h>
#include <dude_thesis.h>
#include <dude_thesis_geometry.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace {

using asf::dude::Cut;
using asf::dude::Ring;
using asf::dude::Shape;
using asf::dude::Vec2;
namespace th = asf::dude::thesis;

th::Options tau(double t) {
  th::Options o;
  o.max_concavity = t;
  return o;
}

double area(const Shape& s) {
  double a = asf::dude::signedArea(s.outer);
  for (const Ring& h : s.holes) a -= std::abs(asf::dude::signedArea(h));
  return a;
}

double totalArea(const asf::dude::Result& r) {
  double a = 0;
  for (const Shape& s : r.pieces) a += area(s);
  return a;
}

bool same(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y) < 1e-9; }
bool sameCut(const Cut& c, Vec2 a, Vec2 b) {
  return (same(c.a, a) && same(c.b, b)) || (same(c.a, b) && same(c.b, a));
}

/// Convex (no reflex vertex) counter-clockwise ring?
bool convex(const Ring& r) {
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Vec2 a = r[(i + r.size() - 1) % r.size()], b = r[i], c = r[(i + 1) % r.size()];
    if ((b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x) < -1e-9) return false;
  }
  return true;
}

TEST(DudeThesis, ConvexPolygonIsOnePiece) {
  Shape s;
  for (int k = 0; k < 12; ++k) s.outer.push_back({5 * std::cos(k * M_PI / 6), 5 * std::sin(k * M_PI / 6)});
  const auto r = th::decompose(s, tau(2.5));
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_TRUE(r.cuts.empty());
  EXPECT_NEAR(totalArea(r), asf::dude::signedArea(s.outer), 1e-9);
}

// L-shaped room, arms 4 m wide and 10 m long. The only pocket minimum is the reflex corner
// (4,4), 4.24 m below the hull bridge (10,4)-(4,10). Its Delaunay diagonals go to (0,0),
// (10,0) and (0,10); only (0,0) leaves both angles at the corner below 180 degrees (135 + 135);
// the others leave a residual concavity of 3.1 m > tau. So: one cut, (4,4)-(0,0).
TEST(DudeThesis, LShapedRoomIsCutOnceAtItsReflexCorner) {
  Shape L;
  L.outer = {{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}};
  const auto rep = th::analyzeRound(L, 2.5);
  ASSERT_EQ(rep.pocket_minima.size(), 1u);
  EXPECT_TRUE(same(rep.pocket_minima[0], {4, 4}));
  EXPECT_NEAR(rep.concavities[0], 6 / std::sqrt(2.0), 1e-9);
  ASSERT_EQ(rep.cuts.size(), 1u);
  EXPECT_TRUE(sameCut(rep.cuts[0], {4, 4}, {0, 0}));
  const auto r = th::decompose(L, tau(2.5));
  ASSERT_EQ(r.pieces.size(), 2u);
  for (const Shape& p : r.pieces) {
    EXPECT_TRUE(convex(p.outer));
    EXPECT_NEAR(area(p), 32, 1e-9);
  }
}

// U: 12 x 10 with a 4 x 6 notch from the top. The notch's own decomposition gives the
// sub-bridge (4,10)-(8,4), whose end (8,4) can no longer be a minimum: (4,4) alone (6 m below
// the hull bridge) is cut first, to (0,0); the remaining L is cut at (8,4) in the next round.
// Three convex pieces of 32 m^2.
TEST(DudeThesis, UIsThreeConvexPieces) {
  Shape U;
  U.outer = {{0, 0}, {12, 0}, {12, 10}, {8, 10}, {8, 4}, {4, 4}, {4, 10}, {0, 10}};
  const auto rep = th::analyzeRound(U, 2.5);
  ASSERT_EQ(rep.pocket_minima.size(), 1u);
  EXPECT_TRUE(same(rep.pocket_minima[0], {4, 4}));
  EXPECT_NEAR(rep.concavities[0], 6, 1e-9);
  const auto r = th::decompose(U, tau(2.5));
  ASSERT_EQ(r.pieces.size(), 3u);
  for (const Shape& p : r.pieces) {
    EXPECT_TRUE(convex(p.outer));
    EXPECT_NEAR(area(p), 32, 1e-9);
  }
}

// Room with a pillar. A 2 x 2 pillar (diameter 2.83 m > tau) has its diameter pair, the
// corners (4,4) and (6,6), as minima; each is cut to the nearest room corner: two pieces, no
// hole left. A 1 x 1 pillar (diameter 1.41 m < tau) is ignored, as the reference ignores it:
// one piece, and the pillar is no longer part of the geometry.
TEST(DudeThesis, RoomWithAPillar) {
  Shape room;
  room.outer = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  room.holes = {{{4, 4}, {4, 6}, {6, 6}, {6, 4}}};
  const auto rep = th::analyzeRound(room, 2.5);
  ASSERT_EQ(rep.pocket_minima.size(), 2u);
  for (double c : rep.concavities) EXPECT_NEAR(c, std::sqrt(8.0), 1e-9);
  const auto r = th::decompose(room, tau(2.5));
  ASSERT_EQ(r.pieces.size(), 2u);
  for (const Shape& p : r.pieces) {
    EXPECT_TRUE(p.holes.empty());
    EXPECT_NEAR(area(p), 48, 1e-9);
  }
  ASSERT_EQ(r.cuts.size(), 2u);
  EXPECT_TRUE(sameCut(r.cuts[0], {4, 4}, {0, 0}) || sameCut(r.cuts[1], {4, 4}, {0, 0}));
  EXPECT_TRUE(sameCut(r.cuts[0], {6, 6}, {10, 10}) || sameCut(r.cuts[1], {6, 6}, {10, 10}));

  room.holes = {{{4.5, 4.5}, {4.5, 5.5}, {5.5, 5.5}, {5.5, 4.5}}};
  const auto small = th::decompose(room, tau(2.5));
  ASSERT_EQ(small.pieces.size(), 1u);
  EXPECT_TRUE(small.pieces[0].holes.empty());
  EXPECT_NEAR(area(small.pieces[0]), 100, 1e-9);
}

// A 20 x 2 m corridor with two 9 x 5.8 m rooms above it, each through a 1 m door in a 0.2 m
// wall. The door jambs are the minima; each door is closed by a jamb-to-jamb cut (1 m).
TEST(DudeThesis, CorridorWithDoorsIsCutAtTheDoors) {
  Shape s;
  s.outer = {{0, 0},     {20, 0},    {20, 2},  {14.5, 2}, {14.5, 2.2}, {19, 2.2}, {19, 8},
             {10, 8},    {10, 2.2},  {13.5, 2.2}, {13.5, 2}, {5.5, 2},  {5.5, 2.2}, {9, 2.2},
             {9, 8},     {0, 8},     {0, 2.2}, {4.5, 2.2}, {4.5, 2},  {0, 2}};
  const auto r = th::decompose(s, tau(2.5));
  ASSERT_EQ(r.pieces.size(), 3u);
  std::vector<double> areas;
  for (const Shape& p : r.pieces) areas.push_back(area(p));
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], 40, 1e-9);    // the corridor
  EXPECT_NEAR(areas[1], 52.4, 1e-9);  // a room and its doorway
  EXPECT_NEAR(areas[2], 52.4, 1e-9);
  ASSERT_EQ(r.cuts.size(), 2u);
  for (const Cut& c : r.cuts) EXPECT_NEAR(std::hypot(c.a.x - c.b.x, c.a.y - c.b.y), 1.0, 1e-9);
}

// --- Brute-force oracle for the candidate diagonals -----------------------------------

double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

/// Proper crossing (interiors intersect in one point, no shared end).
bool properCross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (same(a, c) || same(a, d) || same(b, c) || same(b, d)) return false;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

bool insideRing(Vec2 p, const Ring& r) {
  bool in = false;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
    if ((r[i].y > p.y) != (r[j].y > p.y) &&
        p.x < (r[j].x - r[i].x) * (p.y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
      in = !in;
  return in;
}

using Edge = std::pair<std::pair<double, double>, std::pair<double, double>>;
Edge key(Vec2 a, Vec2 b) {
  auto p = std::make_pair(a.x, a.y), q = std::make_pair(b.x, b.y);
  return p < q ? Edge{p, q} : Edge{q, p};
}

/// Edges of the constrained Delaunay triangulation of `ring`'s points (over their convex
/// hull), by definition: a triangle belongs when none of its edges crosses a constraint and
/// no point visible from its centroid lies inside its circumcircle.
std::set<Edge> bruteCdtEdges(const Ring& ring) {
  std::vector<std::pair<Vec2, Vec2>> cons;
  for (std::size_t i = 0; i < ring.size(); ++i) cons.push_back({ring[i], ring[(i + 1) % ring.size()]});
  auto blocked = [&](Vec2 a, Vec2 b) {
    for (const auto& [c, d] : cons)
      if (properCross(a, b, c, d)) return true;
    return false;
  };
  std::set<Edge> out;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        Vec2 a = ring[i], b = ring[j], c = ring[k];
        const double o = orient(a, b, c);
        if (std::abs(o) < 1e-12) continue;
        if (o < 0) std::swap(b, c);
        if (blocked(a, b) || blocked(b, c) || blocked(c, a)) continue;
        const Vec2 g{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
        bool empty = true;
        for (const Vec2& x : ring) {
          if (same(x, a) || same(x, b) || same(x, c)) continue;
          // In-circle determinant (counter-clockwise a, b, c): > 0 strictly inside.
          const double ax = a.x - x.x, ay = a.y - x.y, bx = b.x - x.x, by = b.y - x.y, cx = c.x - x.x, cy = c.y - x.y;
          const double det = (ax * ax + ay * ay) * (bx * cy - by * cx) - (bx * bx + by * by) * (ax * cy - ay * cx) +
                             (cx * cx + cy * cy) * (ax * by - ay * bx);
          if (det > 1e-12 && !blocked(g, x)) empty = false;
        }
        if (!empty) continue;
        for (auto [p, q] : {std::pair<Vec2, Vec2>{a, b}, {b, c}, {c, a}}) out.insert(key(p, q));
      }
  for (const auto& [c, d] : cons) out.erase(key(c, d));
  return out;
}

// Two generic notches (no four points on a circle). The oracle: every unconstrained edge of
// the brute-force CDT of the simplified polygon (the round's feature points) and of the full
// polygon, with a pocket minimum at one end, its midpoint inside the polygon, and the other
// end outside that minimum's pocket. It must equal the round's candidate set exactly.
TEST(DudeThesis, CandidateDiagonalsEqualABruteForceEnumeration) {
  Shape s;
  s.outer = {{0, 0},     {4, 0.2},   {4.3, 3.1}, {5.6, 3.0}, {6, 0.1},   {12, 0},
             {12.2, 7},  {7.1, 7.3}, {6.7, 3.9}, {5.3, 4.2}, {4.8, 7.2}, {0.1, 7}};
  const auto rep = th::analyzeRound(s, 2.5);
  ASSERT_GE(rep.pocket_minima.size(), 2u);
  // Pockets: chains between consecutive hull vertices (the hull, by brute force).
  const Ring& R = s.outer;
  const std::size_t n = R.size();
  std::vector<std::size_t> hull;
  for (std::size_t i = 0; i < n; ++i) {
    bool extreme = false;
    for (std::size_t j = 0; j < n && !extreme; ++j) {
      if (j == i) continue;
      bool all_left = true;  // every point on the left of (or on) line i->j: i-j is a hull edge
      for (std::size_t k = 0; k < n; ++k)
        if (orient(R[i], R[j], R[k]) < -1e-12) all_left = false;
      extreme = all_left;
    }
    if (extreme) hull.push_back(i);
  }
  auto pocketOf = [&](std::size_t v) {  // (s, e) positions with v strictly between
    for (std::size_t h = 0; h < hull.size(); ++h) {
      const std::size_t a = hull[h], b = hull[(h + 1) % hull.size()];
      const std::size_t len = (b + n - a) % n, d = (v + n - a) % n;
      if (d > 0 && d < len) return std::make_pair(a, b);
    }
    return std::make_pair(v, v);
  };
  auto indexOf = [&](Vec2 p) {
    for (std::size_t i = 0; i < n; ++i)
      if (same(R[i], p)) return i;
    return n;
  };
  std::set<std::size_t> pms;
  for (const Vec2& p : rep.pocket_minima) pms.insert(indexOf(p));
  Ring simplified;
  for (const Vec2& p : R)
    if (std::any_of(rep.features.begin(), rep.features.end(), [&](Vec2 f) { return same(f, p); }))
      simplified.push_back(p);
  std::set<Edge> expected;
  for (const Ring* ring : std::vector<const Ring*>{&simplified, &R})
    for (const Edge& e : bruteCdtEdges(*ring)) {
      const Vec2 a{e.first.first, e.first.second}, b{e.second.first, e.second.second};
      if (!insideRing({(a.x + b.x) / 2, (a.y + b.y) / 2}, *ring)) continue;
      const std::size_t ia = indexOf(a), ib = indexOf(b);
      bool ok = false;
      for (auto [u, v] : {std::make_pair(ia, ib), std::make_pair(ib, ia)}) {
        if (!pms.count(u)) continue;
        if (pms.count(v) && pocketOf(u) != pocketOf(v)) ok = true;  // two bridges broken
        const auto [ps, pe] = pocketOf(u);
        const std::size_t len = (pe + n - ps) % n, d = (v + n - ps) % n;
        if (!pms.count(v) && !(d > 0 && d <= len)) ok = true;  // leaves u's pocket
      }
      if (ok) expected.insert(e);
    }
  std::set<Edge> got;
  for (const auto& d : rep.diagonals) got.insert(key(d.a, d.b));
  EXPECT_FALSE(expected.empty());
  EXPECT_EQ(got, expected);
}

// --- The reference's two approximations ---------------------------------------------------

// Both keep the ends, return sorted positions, keep nothing else on a straight line and keep
// a vertex of a hill higher than the tolerance.
TEST(DudeThesisApproximation, PropertiesOfBothMethods) {
  namespace d = asf::dude::thesis::detail;
  const std::vector<Vec2> line{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}};
  const std::vector<Vec2> hill{{0, 0}, {1, 0.1}, {2, 3}, {3, 3.1}, {4, 3}, {5, 0.1}, {6, 0}};
  for (auto fn : {&d::approximate, &d::approximateChains}) {
    EXPECT_EQ(fn(line, 0.5), (std::vector<int>{0, 4}));
    const std::vector<int> h = fn(hill, 1.0);
    EXPECT_TRUE(std::is_sorted(h.begin(), h.end()));
    EXPECT_EQ(h.front(), 0);
    EXPECT_EQ(h.back(), 6);
    EXPECT_TRUE(std::any_of(h.begin(), h.end(), [&](int i) { return hill[i].y >= 3; }));
    EXPECT_EQ(fn({{0, 0}, {1, 1}}, 1.0), (std::vector<int>{0, 1}));
  }
  // Chains, traced by hand: the summit 3 joins [0, 6]; the chains of (0,3) and (3,6) are
  // seeded at 1 and 4 (first of two equally far vertices, 0.649 m), grow nearest first and
  // meet at 3; the first then takes 4 from the second (0.139 m from its line, a better fit)
  // and the second ends at 6 (0.649 m). Ends: 0, 4, 6; largest distance 0.649 < 1.
  EXPECT_EQ(d::approximateChains(hill, 1.0), (std::vector<int>{0, 4, 6}));
  // Douglas-Peucker keeps the summit and nothing else.
  EXPECT_EQ(d::approximate(hill, 1.0), (std::vector<int>{0, 3, 6}));
}

// The hand-worked shapes give the same cuts with either approximation.
TEST(DudeThesisApproximation, HandWorkedShapesAgree) {
  Shape L;
  L.outer = {{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}};
  for (auto a : {th::Approximation::Chains, th::Approximation::DouglasPeucker}) {
    const auto rep = th::analyzeRound(L, 2.5, a);
    ASSERT_EQ(rep.cuts.size(), 1u);
    EXPECT_TRUE(sameCut(rep.cuts[0], {4, 4}, {0, 0}));
  }
}

// --- Bad geometry -----------------------------------------------------------------------

TEST(DudeThesis, DegenerateInputGivesNoPieceAndNeverThrows) {
  Shape empty;
  EXPECT_TRUE(th::decompose(empty, tau(2.5)).pieces.empty());
  Shape line;
  line.outer = {{0, 0}, {1, 1}, {2, 2}};
  EXPECT_TRUE(th::decompose(line, tau(2.5)).pieces.empty());
  Shape nan;
  nan.outer = {{0, 0}, {NAN, 1}, {2, 0}, {2, 2}};
  EXPECT_NO_THROW(th::decompose(nan, tau(2.5)));
}

// A self-touching contour (two 6 x 6 rooms meeting at one corner, traced as one ring) and a
// zero-width spike: no crash, and the pieces keep the area.
TEST(DudeThesis, SelfTouchingAndSpikyContoursKeepTheirArea) {
  Shape eight;
  eight.outer = {{0, 0}, {6, 0}, {6, 6}, {12, 6}, {12, 12}, {6, 12}, {6, 6}, {0, 6}};
  const auto r = th::decompose(eight, tau(2.5));
  EXPECT_NEAR(totalArea(r), 72, 1e-6);
  Shape spike;
  spike.outer = {{0, 0}, {10, 0}, {10, 4}, {5, 4}, {5, 9}, {5, 4}, {0, 4}};
  const auto rs = th::decompose(spike, tau(2.5));
  EXPECT_NEAR(totalArea(rs), 40, 1e-6);
}

// The two variants differ by design: on the L, asf's `rooms` core cuts along a wall's
// extension (rectangles), the published DuDe along the Delaunay diagonal (trapezoids).
TEST(DudeThesis, DiffersFromTheRoomsVariantOnAnL) {
  Shape L;
  L.outer = {{0, 0}, {10, 0}, {10, 4}, {4, 4}, {4, 10}, {0, 10}};
  const auto thesis = th::decompose(L, tau(2.5));
  const auto rooms = asf::dude::decompose(L, {});
  ASSERT_EQ(thesis.cuts.size(), 1u);
  ASSERT_EQ(rooms.cuts.size(), 1u);
  EXPECT_TRUE(sameCut(thesis.cuts[0], {4, 4}, {0, 0}));
  EXPECT_FALSE(sameCut(rooms.cuts[0], {4, 4}, {0, 0}));
}

}  // namespace
