// Framework services: the map builder (scans at keyframe poses -> occupancy grid) and the
// topological graph builder (label image -> regions graph with traversal history).
#include <asf/mapping/map_builder.h>
#include <asf/mapping/segment_world.h>
#include <asf/mapping/topo_builder.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

namespace {

/// A 360-ray scan from `pose` in a world, exact ranges.
std::shared_ptr<mrpt::obs::CObservation2DRangeScan> scanAt(const asf::mapping::SegmentWorld& w,
                                                           const mrpt::poses::CPose2D& pose) {
  auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  const int n = 360;
  s->aperture = static_cast<float>(2 * M_PI * (n - 1) / n);
  s->rightToLeft = true;
  s->maxRange = 10;
  s->resizeScan(n);
  for (int i = 0; i < n; ++i) {
    const double a = -0.5 * s->aperture + i * s->aperture / (n - 1);
    const double r = w.castRay(pose.x(), pose.y(), pose.phi() + a, 10);
    s->setScanRange(i, static_cast<float>(r));
    s->setScanRangeValidity(i, r < 10);
  }
  return s;
}

}  // namespace

TEST(MapBuilder, WallsOccupiedInteriorFreeOutsideUnknown) {
  const auto world = asf::mapping::SegmentWorld::rectangle(-2, -1.5, 3, 2.5);
  asf::PoseGraph g;
  g.addNode({0, 0, 0});
  g.nodes[0].scan = scanAt(world, g.nodes[0].pose);
  const asf::KeySpec* k;
  std::size_t n;
  k = asf::mapping::MapBuilder::keys(n);
  asf::mapping::MapBuilder mb;
  mb.configure(asf::Params::fromSpecs("map", k, n, {{"resolution", "0.05"}}));
  ASSERT_TRUE(mb.update(g));
  EXPECT_FALSE(mb.update(g)) << "nothing new: no new version";
  const auto& grid = *mb.map().grid;
  EXPECT_EQ(mb.map().version, 1u);
  // MRPT's convention: a cell holds the probability of being FREE.
  EXPECT_GT(grid.getPos(1.0, 1.0), 0.6) << "inside the room: free";
  EXPECT_GT(grid.getPos(-1.0, -1.0), 0.6);
  auto minAround = [&](double x, double y) {
    float m = 1;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) m = std::min(m, grid.getPos(x + dx * 0.05, y + dy * 0.05));
    return m;
  };
  EXPECT_LT(minAround(3.0, 0.0), 0.4) << "on the wall x = 3: occupied";
  EXPECT_LT(minAround(0.0, 2.5), 0.4) << "on the wall y = 2.5: occupied";
  EXPECT_GT(minAround(2.5, 0.0), 0.55) << "0.5 m before the wall: free";
  EXPECT_NEAR(grid.getPos(5.0, 0.0), 0.5, 1e-3) << "behind the wall: unknown";
}

TEST(MapBuilder, RebuildsWhenKeyframesMove) {
  const auto world = asf::mapping::SegmentWorld::rectangle(-2, -2, 2, 2);
  asf::PoseGraph g;
  g.addNode({0, 0, 0});
  g.nodes[0].scan = scanAt(world, g.nodes[0].pose);
  std::size_t n;
  const asf::KeySpec* k = asf::mapping::MapBuilder::keys(n);
  asf::mapping::MapBuilder mb;
  mb.configure(asf::Params::fromSpecs("map", k, n));
  ASSERT_TRUE(mb.update(g));
  EXPECT_FALSE(mb.map().rebuilt);
  g.addNode({0.5, 0, 0});
  g.nodes[1].scan = scanAt(world, g.nodes[1].pose);
  ASSERT_TRUE(mb.update(g));
  EXPECT_FALSE(mb.map().rebuilt) << "a new keyframe is inserted incrementally";
  EXPECT_EQ(mb.rebuilds(), 0u);
  // The back-end moves node 0 by 0.3 m: the map must be rebuilt with the scan moved.
  g.nodes[0].pose = mrpt::poses::CPose2D(0.3, 0, 0);
  ASSERT_TRUE(mb.update(g));
  EXPECT_TRUE(mb.map().rebuilt);
  EXPECT_EQ(mb.map().version, 3u);
  EXPECT_EQ(mb.rebuilds(), 1u);
  EXPECT_FALSE(mb.update(g)) << "nothing moved since";
  mb.configure(asf::Params::fromSpecs("map", k, n));
  EXPECT_EQ(mb.rebuilds(), 0u) << "configure starts a new map";
}

TEST(TopoBuilder, RegionsBordersFrontiersAndTraversals) {
  // 12 x 6 cells at 0.1 m, walls on rows 0 and 5 and column 0; free cells x = 1..9:
  // region 1 (x < 5) and region 2 (x >= 5) share a 4-cell border; columns 10-11 are
  // unknown, so region 2 borders unexplored space over 4 cells.
  asf::Segmentation seg;
  auto& L = seg.labels;
  L.width = 12, L.height = 6, L.resolution = 0.1;
  L.labels.assign(72, 0);
  auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(0.0f, 1.2f, 0.0f, 0.6f, 0.1f);
  ASSERT_EQ(grid->getSizeX(), 12u);
  ASSERT_EQ(grid->getSizeY(), 6u);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 12; ++x) {
      const bool wall = y == 0 || y == 5 || x == 0;
      const bool free = !wall && x <= 9;
      grid->setCell(x, y, wall ? 0.9f : free ? 0.1f : 0.5f);
      if (free) L.labels[y * 12 + x] = x < 5 ? 1 : 2;
    }
  asf::Region r1, r2;
  r1.id = 1, r1.centroid = {0.3, 0.3}, r1.area = 0.16;
  r2.id = 2, r2.centroid = {0.75, 0.3}, r2.area = 0.2;
  seg.regions = {r1, r2};
  asf::GridMap map;
  map.grid = grid;
  map.version = 1;

  std::size_t n;
  const asf::KeySpec* k = asf::mapping::TopoBuilder::keys(n);
  asf::mapping::TopoBuilder tb;
  tb.configure(asf::Params::fromSpecs(
      "topology", k, n, {{"min_border_width", "0.3"}, {"min_frontier_width", "0.3"}}));
  tb.update(seg, map);
  const auto& t = tb.graph();
  ASSERT_EQ(t.nodes.size(), 3u);  // two regions + unexplored
  ASSERT_EQ(t.edges.size(), 2u);
  const asf::TopoEdge& e12 = t.edges[0].frontier() ? t.edges[1] : t.edges[0];
  const asf::TopoEdge& ef = t.edges[0].frontier() ? t.edges[0] : t.edges[1];
  EXPECT_EQ(e12.a, 1);
  EXPECT_EQ(e12.b, 2);
  EXPECT_NEAR(e12.width, 0.4, 1e-9);
  EXPECT_NEAR(e12.midpoint.x, 0.5, 1e-9);
  EXPECT_NEAR(e12.midpoint.y, 0.3, 1e-9);
  EXPECT_EQ(ef.a, 2);
  EXPECT_NEAR(ef.width, 0.4, 1e-9);
  EXPECT_NEAR(ef.midpoint.x, 0.95, 1e-9);
  EXPECT_NEAR(ef.midpoint.y, 0.3, 1e-9);

  tb.observeRobot(0.2, 0.25, 1.0);
  EXPECT_EQ(tb.graph().current, 1);
  EXPECT_TRUE(tb.graph().node(1)->visited);
  EXPECT_EQ(tb.graph().node(1)->entrance_edge, -1) << "start region has no entrance";
  tb.observeRobot(0.7, 0.25, 2.0);
  tb.observeRobot(0.3, 0.25, 3.0);
  const auto& t2 = tb.graph();
  const int ie = t2.edges[0].frontier() ? 1 : 0;
  ASSERT_EQ(t2.edges[ie].traversals.size(), 2u);
  EXPECT_TRUE(t2.edges[ie].traversals[0].forward);
  EXPECT_FALSE(t2.edges[ie].traversals[1].forward);
  EXPECT_EQ(t2.outwardTraversals(ie, 1), 1);
  EXPECT_EQ(t2.outwardTraversals(ie, 2), 1);
  EXPECT_EQ(t2.node(2)->entrance_edge, ie);
  // History survives a new segmentation with the same regions.
  tb.update(seg, map);
  const int je = tb.graph().edges[0].frontier() ? 1 : 0;
  EXPECT_EQ(tb.graph().edges[je].traversals.size(), 2u);
  EXPECT_TRUE(tb.graph().node(2)->visited);
  EXPECT_EQ(tb.graph().node(2)->entrance_edge, je);
  // The border cells of each edge lie on its first region's side.
  for (const auto& b : tb.graph().edges[je].border) EXPECT_LT(b.x, 0.5);
  EXPECT_EQ(tb.graph().edges[je].border.size(), 4u);

  // A re-segmentation renames the regions (7 and 9, say after a loop closure): with the pose
  // graph as history the traversals are those of the robot's path, not lost with the ids.
  asf::Segmentation renamed = seg;
  for (auto& l : renamed.labels.labels) l = l == 1 ? 7 : l == 2 ? 9 : 0;
  renamed.regions[0].id = 7;
  renamed.regions[1].id = 9;
  asf::PoseGraph history;
  history.addNode(mrpt::poses::CPose2D(0.2, 0.25, 0), 10.0);  // in 7
  history.addNode(mrpt::poses::CPose2D(0.8, 0.25, 0), 11.0);  // into 9
  history.addNode(mrpt::poses::CPose2D(0.3, 0.35, 0), 12.0);  // back into 7
  history.addNode(mrpt::poses::CPose2D(0.85, 0.3, 0), 13.0);  // into 9 again
  tb.update(renamed, map, &history);
  const auto& t3 = tb.graph();
  const int ke = t3.edges[0].frontier() ? 1 : 0;
  ASSERT_EQ(t3.edges[ke].a, 7);
  // Then the robot's last observed position (0.3, 0.25), in 7: a fourth crossing.
  ASSERT_EQ(t3.edges[ke].traversals.size(), 4u);
  EXPECT_TRUE(t3.edges[ke].traversals[0].forward);
  EXPECT_FALSE(t3.edges[ke].traversals[1].forward);
  EXPECT_TRUE(t3.edges[ke].traversals[2].forward);
  EXPECT_FALSE(t3.edges[ke].traversals[3].forward);
  EXPECT_EQ(t3.outwardTraversals(ke, 7), 2);
  EXPECT_EQ(t3.outwardTraversals(ke, 9), 2);
  EXPECT_TRUE(t3.node(7)->visited);
  EXPECT_TRUE(t3.node(9)->visited);
  EXPECT_EQ(t3.node(7)->entrance_edge, -1) << "the start region has no entrance";
  EXPECT_EQ(t3.node(9)->entrance_edge, ke);
  EXPECT_EQ(t3.current, 7);
}

TEST(TopoBuilder, FrontierEdgesNeedAStretchOfAdjacentCells) {
  // One region, 11 x 6 free cells inside walls; column 11 is wall except the rows listed as
  // unknown. Three unknown cells far apart (0.3 m in total, but 0.1 m each) are no frontier;
  // three adjacent ones (a 0.3 m stretch) are.
  auto frontierEdges = [](std::vector<int> unknown_rows) {
    asf::Segmentation seg;
    auto& L = seg.labels;
    L.width = 12, L.height = 8, L.resolution = 0.1;
    L.labels.assign(96, 0);
    auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(0.0f, 1.2f, 0.0f, 0.8f, 0.1f);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 12; ++x) {
        const bool wall = y == 0 || y == 7 || x == 0 || x == 11;
        const bool unknown =
            x == 11 && std::find(unknown_rows.begin(), unknown_rows.end(), y) != unknown_rows.end();
        grid->setCell(x, y, unknown ? 0.5f : wall ? 0.0f : 1.0f);
        if (!wall) L.labels[y * 12 + x] = 1;
      }
    asf::Region r;
    r.id = 1, r.centroid = {0.6, 0.4}, r.area = 0.6;
    seg.regions = {r};
    asf::GridMap map;
    map.grid = grid;
    map.version = 1;
    std::size_t n;
    const asf::KeySpec* k = asf::mapping::TopoBuilder::keys(n);
    asf::mapping::TopoBuilder tb;
    tb.configure(asf::Params::fromSpecs("topology", k, n, {{"min_frontier_width", "0.3"}}));
    tb.update(seg, map);
    return tb.graph().edges;
  };
  EXPECT_TRUE(frontierEdges({1, 3, 5}).empty());
  const auto edges = frontierEdges({2, 3, 4});
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_TRUE(edges[0].frontier());
  EXPECT_NEAR(edges[0].width, 0.3, 1e-9);
  EXPECT_NEAR(edges[0].midpoint.y, 0.35, 1e-6);  // the middle of rows 2..4
  EXPECT_EQ(edges[0].border.size(), 3u);
  // A stretch plus a stray cell: only the stretch's cells are kept.
  const auto mixed = frontierEdges({1, 2, 3, 6});
  ASSERT_EQ(mixed.size(), 1u);
  EXPECT_EQ(mixed[0].border.size(), 3u);
}

// The builder keeps its borders in stripes of rows between updates and recomputes only the
// stripes whose labels or grid lookups changed: after every update of a random sequence
// (labels repainted in a patch, grid cells turned unknown or known, the same grid object
// again) its graph must equal that of a builder that sees only the current input.
TEST(TopoBuilder, StripeCacheGivesWhatAFreshBuilderGives) {
  constexpr int W = 37, H = 70;  // several stripes; width not a multiple of anything
  std::mt19937 rng(7);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  asf::Segmentation seg;
  auto& L = seg.labels;
  L.width = W, L.height = H, L.resolution = 0.1, L.origin_x = -1.0, L.origin_y = 0.5;
  L.labels.assign(W * H, 0);
  auto grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(-1.0f, 2.7f, 0.5f, 7.5f, 0.1f);
  ASSERT_EQ(grid->getSizeX(), static_cast<unsigned>(W));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) grid->setCell(x, y, 1.0f);
  // Paints the rectangle with a label (0: unlabelled) and, for the grid, a cell value.
  auto paint = [&](int x0, int y0, int w, int h, int label, float p) {
    for (int y = y0; y < std::min(y0 + h, H); ++y)
      for (int x = x0; x < std::min(x0 + w, W); ++x) {
        if (label >= 0) L.labels[y * W + x] = label;
        if (p >= 0) grid->setCell(x, y, p);
      }
  };
  for (int y = 0; y < H; y += 10)  // rooms with unlabelled walls between them
    for (int x = 0; x < W; x += 9) paint(x + 1, y + 1, 8, 9, 1 + (x / 9) + 5 * (y / 10), -1);
  std::size_t n;
  const asf::KeySpec* k = asf::mapping::TopoBuilder::keys(n);
  const auto params = asf::Params::fromSpecs(
      "topology", k, n, {{"min_border_width", "0.2"}, {"min_frontier_width", "0.2"}});
  asf::mapping::TopoBuilder incremental;
  incremental.configure(params);
  asf::GridMap map;
  for (int step = 0; step < 60; ++step) {
    const int kind = pick(0, 3);
    if (kind == 0 || kind == 3)  // a patch relabelled or cleared
      paint(pick(0, W - 1), pick(0, H - 1), pick(1, 8), pick(1, 8), std::max(0, pick(-10, 40)), -1);
    if (kind == 1 || kind == 3) {  // a patch of the grid unknown, free or occupied
      grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(*grid);
      const float values[3] = {0.5f, 1.0f, 0.0f};
      paint(pick(0, W - 1), pick(0, H - 1), pick(1, 6), pick(1, 6), -1, values[pick(0, 2)]);
    }
    // kind 2: nothing changes (the same grid object, the same labels)
    seg.regions.clear();
    std::set<int> ids(L.labels.begin(), L.labels.end());
    for (int id : ids)
      if (id > 0) seg.regions.push_back(asf::Region{id, {}, {}, 1.0, {0, 0}});
    map.grid = grid;
    ++map.version;
    incremental.update(seg, map);
    asf::mapping::TopoBuilder fresh;
    fresh.configure(params);
    fresh.update(seg, map);
    const auto& a = incremental.graph().edges;
    const auto& b = fresh.graph().edges;
    ASSERT_EQ(a.size(), b.size()) << "step " << step;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].a, b[i].a) << "step " << step;
      EXPECT_EQ(a[i].b, b[i].b) << "step " << step;
      EXPECT_EQ(a[i].width, b[i].width) << "step " << step;
      EXPECT_EQ(a[i].midpoint.x, b[i].midpoint.x) << "step " << step;
      EXPECT_EQ(a[i].midpoint.y, b[i].midpoint.y) << "step " << step;
      ASSERT_EQ(a[i].border.size(), b[i].border.size()) << "step " << step;
      for (std::size_t j = 0; j < a[i].border.size(); ++j)
        EXPECT_TRUE(a[i].border[j].x == b[i].border[j].x && a[i].border[j].y == b[i].border[j].y);
    }
    if (step == 30) {  // a copy carries the cache and goes on alone
      asf::mapping::TopoBuilder copy = incremental;
      incremental = copy;
    }
  }
}

TEST(Geometry, PolygonAreaAndCentroid) {
  const asf::Polygon sq{{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(asf::polygonArea(sq), 2.0);
  EXPECT_DOUBLE_EQ(asf::polygonCentroid(sq).x, 1.0);
  EXPECT_DOUBLE_EQ(asf::polygonCentroid(sq).y, 0.5);
  const asf::Polygon cw{{0, 0}, {0, 1}, {2, 1}, {2, 0}};
  EXPECT_DOUBLE_EQ(asf::polygonArea(cw), -2.0);
}
