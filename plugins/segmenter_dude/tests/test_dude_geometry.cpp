// Tests of the DuDe geometry core on hand-made polygons (metres).
#include <dude.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

using asf::dude::Ring;
using asf::dude::Shape;
using asf::dude::Vec2;

Ring rect(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

double totalArea(const asf::dude::Result& r) {
  double a = 0;
  for (const Shape& s : r.pieces) {
    a += asf::dude::signedArea(s.outer);
    for (const Ring& h : s.holes) a -= std::abs(asf::dude::signedArea(h));
  }
  return a;
}

double maxConcavity(const Ring& ccw) {
  const auto c = asf::dude::concavities(ccw);
  return c.empty() ? 0 : *std::max_element(c.begin(), c.end());
}

bool strictlyInside(Vec2 p, const Ring& r) {
  bool in = false;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
    if ((r[i].y > p.y) != (r[j].y > p.y) &&
        p.x < (r[j].x - r[i].x) * (p.y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
      in = !in;
  }
  return in;
}

/// L-shaped corridor, 2 m wide, arms 10 m long.
Ring lCorridor() { return {{0, 0}, {10, 0}, {10, 2}, {2, 2}, {2, 10}, {0, 10}}; }

TEST(DudeGeometry, ConcavityOfAnLIsTheDepthOfItsInnerCorner) {
  const auto c = asf::dude::concavities(lCorridor());
  ASSERT_EQ(c.size(), 6u);
  // Hull bridge from (10,2) to (2,10); the inner corner (2,2) is 8/sqrt(2) from it.
  EXPECT_NEAR(c[3], 8 / std::sqrt(2.0), 1e-9);
  for (int i : {0, 1, 2, 4, 5}) EXPECT_NEAR(c[i], 0, 1e-9) << i;
}

TEST(DudeGeometry, ConvexPolygonStaysOneRegion) {
  Shape s;
  for (int k = 0; k < 12; ++k)
    s.outer.push_back({5 * std::cos(k * M_PI / 6), 5 * std::sin(k * M_PI / 6)});
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_TRUE(r.cuts.empty());
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_NEAR(totalArea(r), std::abs(asf::dude::signedArea(s.outer)), 1e-9);
}

TEST(DudeGeometry, ClockwiseInputIsAccepted) {
  Shape s;
  s.outer = rect(0, 0, 6, 3);
  std::reverse(s.outer.begin(), s.outer.end());
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_GT(asf::dude::signedArea(r.pieces[0].outer), 0);
}

TEST(DudeGeometry, LShapedCorridorGivesTwoConvexPieces) {
  Shape s;
  s.outer = lCorridor();
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 2u);
  ASSERT_EQ(r.cuts.size(), 1u);
  EXPECT_NEAR(totalArea(r), 36, 1e-9);
  // The cut leaves the inner corner straight across the corridor (2 m).
  const auto& c = r.cuts[0];
  EXPECT_NEAR(std::hypot(c.a.x - c.b.x, c.a.y - c.b.y), 2, 1e-9);
  for (const Shape& p : r.pieces) EXPECT_LT(maxConcavity(p.outer), 1e-9);
}

TEST(DudeGeometry, ShallowNotchBelowMaxConcavityIsNotCut) {
  Shape s;  // 10 x 6 room with a 1 m deep notch: concavity 1 < 2.5
  s.outer = {{0, 0}, {10, 0}, {10, 6}, {6, 6}, {5, 5}, {4, 6}, {0, 6}};
  const auto r = asf::dude::decompose(s, {});
  EXPECT_EQ(r.pieces.size(), 1u);
  asf::dude::Options tight;
  tight.max_concavity = 0.5;
  EXPECT_EQ(asf::dude::decompose(s, tight).pieces.size(), 2u);
}

TEST(DudeGeometry, TwoRoomsJoinedByADoorAreCutAtTheDoor) {
  // Rooms [0,5]x[0,5] and [5.1,10.1]x[0,5], wall x in [5,5.1] with a door y in [1,2]:
  // the wall above the door is 3 m deep (> tau), the stub below it 1 m.
  Shape s;
  s.outer = {{0, 0},   {5, 0},   {5, 1},     {5.1, 1},   {5.1, 0}, {10.1, 0},
             {10.1, 5}, {5.1, 5}, {5.1, 2}, {5, 2},   {5, 5},   {0, 5}};
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 2u) << r.cuts.size() << " cuts";
  for (const auto& c : r.cuts) {
    EXPECT_GE(std::min(c.a.x, c.b.x), 5 - 1e-9);
    EXPECT_LE(std::max(c.a.x, c.b.x), 5.1 + 1e-9);
  }
  EXPECT_NEAR(totalArea(r), 50.1, 1e-9);
}

TEST(DudeGeometry, PolygonWithAHoleIsDecomposedWithoutCuttingThroughTheHole) {
  Shape s;
  s.outer = rect(0, 0, 20, 20);
  const Ring hole = rect(6, 6, 14, 14);
  s.holes.push_back(hole);
  const auto r = asf::dude::decompose(s, {});
  ASSERT_GE(r.pieces.size(), 2u);
  EXPECT_NEAR(totalArea(r), 400 - 64, 1e-6);
  for (const Shape& p : r.pieces) EXPECT_TRUE(p.holes.empty());
  // No cut passes through the hole's interior.
  ASSERT_FALSE(r.cuts.empty());
  for (const auto& c : r.cuts)
    for (int k = 1; k < 100; ++k) {
      const double t = k / 100.0;
      const Vec2 p{c.a.x + t * (c.b.x - c.a.x), c.a.y + t * (c.b.y - c.a.y)};
      EXPECT_FALSE(strictlyInside(p, rect(6.001, 6.001, 13.999, 13.999)))
          << "cut (" << c.a.x << "," << c.a.y << ")-(" << c.b.x << "," << c.b.y << ")";
    }
  // No piece contains part of the hole: every piece's centroid-ish point is outside it.
  for (const Shape& p : r.pieces)
    for (const Vec2& v : p.outer) EXPECT_FALSE(strictlyInside(v, rect(6.001, 6.001, 13.999, 13.999)));
}

TEST(DudeGeometry, SmallHoleStaysInsideOnePiece) {
  Shape s;
  s.outer = rect(0, 0, 8, 6);
  s.holes.push_back(rect(3.5, 2.5, 4.5, 3.5));  // a 1 m pillar: narrower than tau
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  ASSERT_EQ(r.pieces[0].holes.size(), 1u);
  EXPECT_LT(asf::dude::signedArea(r.pieces[0].holes[0]), 0);  // clockwise
  EXPECT_NEAR(totalArea(r), 47, 1e-9);
}

TEST(DudeGeometry, DeterministicAndIndependentOfTheStartVertex) {
  Shape a, b;
  a.outer = {{0, 0}, {12, 0}, {12, 3}, {3, 3}, {3, 12}, {12, 12}, {12, 15}, {0, 15}};
  b.outer = a.outer;
  std::rotate(b.outer.begin(), b.outer.begin() + 3, b.outer.end());
  const auto ra1 = asf::dude::decompose(a, {}), ra2 = asf::dude::decompose(a, {});
  const auto rb = asf::dude::decompose(b, {});
  ASSERT_EQ(ra1.pieces.size(), ra2.pieces.size());
  for (std::size_t i = 0; i < ra1.pieces.size(); ++i) {
    ASSERT_EQ(ra1.pieces[i].outer.size(), ra2.pieces[i].outer.size());
    for (std::size_t k = 0; k < ra1.pieces[i].outer.size(); ++k) {
      EXPECT_EQ(ra1.pieces[i].outer[k].x, ra2.pieces[i].outer[k].x);
      EXPECT_EQ(ra1.pieces[i].outer[k].y, ra2.pieces[i].outer[k].y);
    }
  }
  EXPECT_EQ(ra1.pieces.size(), rb.pieces.size());
  EXPECT_EQ(ra1.pieces.size(), 3u);  // a C: two arms and the back
}

// ---- degenerate input ----------------------------------------------------------------

TEST(DudeGeometry, EmptyAndTinyInputGiveNoPiece) {
  EXPECT_TRUE(asf::dude::decompose(Shape{}, {}).pieces.empty());
  Shape two;
  two.outer = {{0, 0}, {1, 1}};
  EXPECT_TRUE(asf::dude::decompose(two, {}).pieces.empty());
  Shape same;
  same.outer = {{1, 1}, {1, 1}, {1, 1}, {1, 1}};
  EXPECT_TRUE(asf::dude::decompose(same, {}).pieces.empty());
  Shape nan;
  nan.outer = {{0, 0}, {NAN, 1}, {1, 1}};
  EXPECT_TRUE(asf::dude::decompose(nan, {}).pieces.empty());
}

TEST(DudeGeometry, CollinearPointsGiveNoPiece) {
  Shape s;
  s.outer = {{0, 0}, {1, 0}, {2, 0}, {5, 0}, {3, 0}};
  EXPECT_TRUE(asf::dude::decompose(s, {}).pieces.empty());
}

TEST(DudeGeometry, CollinearVerticesOnEdgesAreHarmless) {
  Shape s;
  s.outer = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2}, {0, 2}, {0, 1}};
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.pieces[0].outer.size(), 4u);
}

TEST(DudeGeometry, ZeroWidthSpikesAreRemoved) {
  Shape s;  // square with a spike going 6 m out and straight back
  s.outer = {{0, 0}, {4, 0}, {4, 2}, {10, 2}, {4, 2}, {4, 4}, {0, 4}};
  const auto r = asf::dude::decompose(s, {});
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_NEAR(totalArea(r), 16, 1e-9);
  Shape inward;  // and one going 3 m into the square
  inward.outer = {{0, 0}, {4, 0}, {4, 2}, {1, 2}, {4, 2}, {4, 4}, {0, 4}};
  EXPECT_NEAR(totalArea(asf::dude::decompose(inward, {})), 16, 1e-9);
}

TEST(DudeGeometry, OnePixelCorridorBetweenRoomsDoesNotBreakTheDecomposition) {
  // Two 4 x 8 rooms joined by a 0.05 m wide, 3 m long corridor.
  Shape s;
  s.outer = {{0, 0},    {4, 0},   {4, 2},   {7, 2}, {7, 0},
             {11, 0},   {11, 8},  {7, 8},   {7, 2.05}, {4, 2.05},
             {4, 8},    {0, 8}};
  const auto r = asf::dude::decompose(s, {});
  EXPECT_GE(r.pieces.size(), 2u);
  EXPECT_NEAR(totalArea(r), 64 + 0.15, 1e-9);
  for (const Shape& p : r.pieces) EXPECT_LT(maxConcavity(p.outer), 2.5 + 1e-9);
}

TEST(DudeGeometry, SelfTouchingContourDoesNotCrashOrLoop) {
  // Two squares touching at one vertex, traced as one ring (figure of eight).
  Shape s;
  s.outer = {{0, 0}, {4, 0}, {4, 4}, {8, 4}, {8, 8}, {4, 8}, {4, 4}, {0, 4}};
  const auto r = asf::dude::decompose(s, {});
  EXPECT_LE(r.pieces.size(), 4u);
  EXPECT_NEAR(totalArea(r), 32, 1e-9);
  // A ring that crosses itself (bow tie): anything but a crash or a hang.
  Shape bow;
  bow.outer = {{0, 0}, {10, 10}, {10, 0}, {0, 10}};
  const auto rb = asf::dude::decompose(bow, {});
  EXPECT_LE(rb.pieces.size(), 4u);
  // A hole touching the outer boundary.
  Shape touch;
  touch.outer = rect(0, 0, 10, 10);
  touch.holes.push_back({{0, 3}, {6, 3}, {6, 7}, {0, 7}});
  const auto rt = asf::dude::decompose(touch, {});
  EXPECT_GE(rt.pieces.size(), 1u);
}

TEST(DudeGeometry, ManyRoomsAlongACorridorTerminate) {
  // A comb: 20 rooms of 4 x 4 above a 2 m corridor, 1 m doors, 0.1 m walls.
  Shape s;
  s.outer.push_back({0, 0});
  s.outer.push_back({20 * 4.1, 0});
  s.outer.push_back({20 * 4.1, 2});
  for (int k = 19; k >= 0; --k) {
    const double x0 = k * 4.1 + 0.1, x1 = x0 + 4;
    s.outer.push_back({x1 - 1.5, 2});
    s.outer.push_back({x1 - 1.5, 2.1});
    s.outer.push_back({x1, 2.1});
    s.outer.push_back({x1, 6.1});
    s.outer.push_back({x0, 6.1});
    s.outer.push_back({x0, 2.1});
    s.outer.push_back({x1 - 2.5, 2.1});
    s.outer.push_back({x1 - 2.5, 2});
  }
  s.outer.push_back({0, 2});
  const auto r = asf::dude::decompose(s, {});
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_GE(r.pieces.size(), 21u);
  EXPECT_NEAR(totalArea(r), std::abs(asf::dude::signedArea(s.outer)), 1e-6);
}

}  // namespace
