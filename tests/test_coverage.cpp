// Coverage bookkeeping: MapAreaTracker keeps the free area and the coverage of a growing map
// from the change box of each version; after every step of a run it must equal the full
// recount (freeArea, CoverageMeter::coverage), through grid growth, rebuilds and skipped
// versions.
#include <asf/mapping/coverage.h>
#include <asf/mapping/map_builder.h>
#include <asf/mapping/segment_world.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

/// A 360-ray scan from `pose` (world frame), exact ranges up to `range`; farther: no echo.
std::shared_ptr<mrpt::obs::CObservation2DRangeScan> scanAt(const asf::mapping::SegmentWorld& w,
                                                           const mrpt::poses::CPose2D& pose,
                                                           double range) {
  const double kRange = range;
  auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
  const int n = 360;
  s->aperture = static_cast<float>(2 * M_PI * (n - 1) / n);
  s->rightToLeft = true;
  s->maxRange = static_cast<float>(kRange);
  s->resizeScan(n);
  for (int i = 0; i < n; ++i) {
    const double a = -0.5 * s->aperture + i * s->aperture / (n - 1);
    const double r = w.castRay(pose.x(), pose.y(), pose.phi() + a, kRange);
    s->setScanRange(i, static_cast<float>(r));
    s->setScanRangeValidity(i, r < kRange);
  }
  return s;
}

/// The world as a grid: free inside [0, 12] x [0, 4] away from the walls, occupied elsewhere.
asf::WorldTruth worldTruth(const asf::mapping::SegmentWorld& w, const mrpt::poses::CPose2D& start) {
  auto g = std::make_shared<mrpt::maps::COccupancyGridMap2D>(-0.5f, 12.5f, -0.5f, 4.5f, 0.05f);
  for (unsigned y = 0; y < g->getSizeY(); ++y)
    for (unsigned x = 0; x < g->getSizeX(); ++x) {
      const asf::Point2 p{g->idx2x(x), g->idx2y(y)};
      const bool inside = p.x > 0 && p.x < 12 && p.y > 0 && p.y < 4;
      g->setCell(x, y, inside && !w.collides(p, p, 0.05) ? 1.0f : 0.0f);
    }
  asf::WorldTruth t;
  t.grid = g;
  t.map_origin = start;
  return t;
}

struct MappingRun {
  asf::mapping::SegmentWorld world = asf::mapping::SegmentWorld::twoRooms(6, 4, 1);
  mrpt::poses::CPose2D start{11, 2, 0.3};
  asf::WorldTruth truth = worldTruth(world, start);
  asf::mapping::CoverageMeter meter{truth};
  asf::PoseGraph graph;
  asf::mapping::MapBuilder builder;

  double range = 6;  ///< of the scans

  explicit MappingRun(const char* max_insertion_range = "5") {
    std::size_t n;
    const asf::KeySpec* k = asf::mapping::MapBuilder::keys(n);
    // A small first grid so that the run grows it several times; change boxes (5.1 m
    // around the sensor) smaller than the world.
    builder.configure(asf::Params::fromSpecs("map", k, n,
                                             {{"resolution", "0.05"},
                                              {"initial_half_size", "1.5"},
                                              {"max_insertion_range", max_insertion_range}}));
  }
  /// Adds a keyframe at world pose `p`; true if the map changed.
  bool step(const mrpt::poses::CPose2D& p) {
    graph.addNode(p - start);
    graph.nodes.back().scan = scanAt(world, p, range);
    return builder.update(graph);
  }
};

void expectSameAsRecount(const asf::mapping::MapAreaTracker& t, const asf::GridMap& map,
                         const asf::mapping::CoverageMeter& meter, const std::string& when) {
  EXPECT_DOUBLE_EQ(t.freeArea(), asf::mapping::freeArea(map)) << when;
  EXPECT_DOUBLE_EQ(t.coverage(), meter.coverage(map)) << when;
  EXPECT_EQ(t.informationBits(), asf::mapping::mapInformationBits(map))
      << when << ": the running total is exact";
}

}  // namespace

// The contract the tracker (and the incremental segmenter) rely on: GridMap::changed covers
// every cell whose value changed, no-echo rays included (MRPT clears free space along them
// beyond the scan's maxRange).
TEST(MapBuilder, ChangeBoxCoversEveryChangedCell) {
  MappingRun run("15");  // farther than the scans' maxRange
  run.range = 2.5;       // many no-echo rays side by side
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> before;
  std::size_t changed_cells = 0;
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(run.step({11 - 0.8 * i, 1 + 0.15 * i, 0.5 * i}));
    const asf::GridMap& m = run.builder.map();
    if (before) {
      const auto& g = *m.grid;
      for (unsigned y = 0; y < g.getSizeY(); ++y)
        for (unsigned x = 0; x < g.getSizeX(); ++x) {
          const float xm = g.idx2x(x), ym = g.idx2y(y);
          if (g.getCell(x, y) == before->getPos(xm, ym)) continue;  // 0.5 outside `before`
          ++changed_cells;
          const double h = g.getResolution() / 2;  // the cell overlaps the box
          ASSERT_TRUE(xm + h >= m.changed.min_x && xm - h <= m.changed.max_x &&
                      ym + h >= m.changed.min_y && ym - h <= m.changed.max_y)
              << "keyframe " << i << ": cell (" << xm << ", " << ym << ") changed outside the box ["
              << m.changed.min_x << ", " << m.changed.max_x << "] x [" << m.changed.min_y << ", "
              << m.changed.max_y << "]";
        }
    }
    before = m.grid;
  }
  EXPECT_GT(changed_cells, 1000u);
}

// GridMap's contract: a version a consumer keeps is never modified; a version no one keeps
// is changed in place for the next (no copy of the whole grid per keyframe). Both through
// incremental insertions and a rebuild, each result equal to a builder whose versions were
// all kept (every version a copy).
TEST(MapBuilder, KeptVersionsStayUnchangedAndUnkeptOnesAreReused) {
  MappingRun reused, kept;
  std::vector<std::shared_ptr<const mrpt::maps::COccupancyGridMap2D>> held;
  std::vector<std::vector<mrpt::maps::COccupancyGridMap2D::cellType>> held_cells;
  std::size_t in_place = 0;
  for (int i = 0; i < 14; ++i) {
    const mrpt::poses::CPose2D p(11 - 0.7 * i, 2 + 0.2 * std::sin(i), 0.3 * i);
    const void* before = reused.builder.map().grid.get();
    ASSERT_TRUE(reused.step(p));
    ASSERT_TRUE(kept.step(p));
    if (i == 9) {  // the back-end moves a keyframe: both rebuild
      for (MappingRun* r : {&reused, &kept}) {
        r->graph.nodes[1].pose = r->graph.nodes[1].pose + mrpt::poses::CPose2D(0.2, 0, 0.05);
        ASSERT_TRUE(r->builder.update(r->graph));
        ASSERT_TRUE(r->builder.map().rebuilt);
      }
    }
    const auto& a = *reused.builder.map().grid;
    const auto& b = *kept.builder.map().grid;
    if (reused.builder.map().grid.get() == before) ++in_place;
    ASSERT_EQ(a.getSizeX(), b.getSizeX());
    ASSERT_EQ(a.getSizeY(), b.getSizeY());
    ASSERT_EQ(a.getXMin(), b.getXMin());
    ASSERT_TRUE(a.getRawMap() == b.getRawMap()) << "keyframe " << i;
    held.push_back(kept.builder.map().grid);
    held_cells.push_back(held.back()->getRawMap());
    for (std::size_t k = 0; k < held.size(); ++k)
      ASSERT_TRUE(held[k]->getRawMap() == held_cells[k])
          << "version " << k + 1 << " changed after keyframe " << i;
  }
  EXPECT_GT(in_place, 10u) << "unkept versions are changed in place";
  for (std::size_t k = 1; k < held.size(); ++k)
    EXPECT_NE(held[k].get(), held[k - 1].get()) << "a kept version is never reused";
}

// A rebuild keeps the grid's extent instead of growing again from the initial size: the
// cells are those of a builder given the moved graph from scratch (outside its extent:
// unknown).
TEST(MapBuilder, ARebuildHoldsWhatAFreshBuilderWould) {
  MappingRun run;
  for (int i = 0; i < 12; ++i) ASSERT_TRUE(run.step({11 - 0.8 * i, 1.5 + 0.1 * i, 0.4 * i}));
  run.graph.nodes[2].pose = run.graph.nodes[2].pose + mrpt::poses::CPose2D(0.15, -0.1, 0.03);
  ASSERT_TRUE(run.builder.update(run.graph));
  ASSERT_TRUE(run.builder.map().rebuilt);
  MappingRun fresh;
  ASSERT_TRUE(fresh.builder.update(run.graph));
  const auto& a = *run.builder.map().grid;
  const auto& b = *fresh.builder.map().grid;
  EXPECT_LE(a.getXMin(), b.getXMin());
  EXPECT_GE(a.getXMax(), b.getXMax());
  std::size_t differ = 0, known = 0;
  for (unsigned y = 0; y < a.getSizeY(); ++y)
    for (unsigned x = 0; x < a.getSizeX(); ++x) {
      const float xm = a.idx2x(x), ym = a.idx2y(y);
      if (a.getCell(x, y) != b.getPos(xm, ym)) ++differ;  // 0.5 outside `b`
      if (a.getCell(x, y) != 0.5f) ++known;
    }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(known, 5000u);
}

TEST(MapAreaTracker, EqualsTheFullRecountAfterEveryStepOfARun) {
  MappingRun run;
  asf::mapping::MapAreaTracker tracker(&run.meter);
  std::size_t updates = 0;
  // From the second room through the door (x = 6, y in [1.5, 2.5]) into the first, and
  // back: the grid grows towards -x (its origin moves) and +-y.
  std::vector<mrpt::poses::CPose2D> path;
  for (int i = 0; i <= 40; ++i)
    path.emplace_back(11 - 0.25 * i, 2 + 0.3 * std::sin(0.4 * i), 0.1 * i);
  for (int i = 0; i <= 10; ++i) path.emplace_back(1 + 0.5 * i, 1.2, 0);
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::string when = "after keyframe " + std::to_string(i);
    if (!run.step(path[i])) continue;
    tracker.update(run.builder.map());
    ++updates;
    expectSameAsRecount(tracker, run.builder.map(), run.meter, when);
    if (i == 30) {  // the back-end moves the first keyframe: the map is rebuilt
      run.graph.nodes[0].pose = mrpt::poses::CPose2D(0.2, 0.1, 0.05);
      ASSERT_TRUE(run.builder.update(run.graph));
      ASSERT_TRUE(run.builder.map().rebuilt);
      tracker.update(run.builder.map());
      expectSameAsRecount(tracker, run.builder.map(), run.meter, when + " and a rebuild");
    }
    if (i == 40) {  // two versions, the tracker sees only the second: it must recount
      ASSERT_TRUE(run.step(path[i] + mrpt::poses::CPose2D(0.1, 0, 0)));
      ASSERT_TRUE(run.step(path[i] + mrpt::poses::CPose2D(0.2, 0, 0)));
      tracker.update(run.builder.map());
      expectSameAsRecount(tracker, run.builder.map(), run.meter, when + " and a skipped version");
    }
  }
  EXPECT_GT(tracker.coverage(), 0.9) << "the run saw both rooms";
  // Recounts: the first map, the rebuild, the skipped version; every other update counted
  // the change box only.
  EXPECT_EQ(tracker.recounts(), 3u);
  EXPECT_GT(updates, 40u);
}

TEST(MapEntropy, BitsByHand) {
  // 20 x 10 unknown cells: one bit each. Then one cell nearly certain (its stored value's
  // probability p: -p log2 p - (1-p) log2 (1-p)).
  using Grid = mrpt::maps::COccupancyGridMap2D;
  auto g = std::make_shared<Grid>(0.f, 2.f, 0.f, 1.f, 0.1f);
  ASSERT_EQ(g->getSizeX() * g->getSizeY(), 200u);
  asf::GridMap m;
  m.grid = g;
  m.version = 1;
  EXPECT_EQ(asf::mapping::mapEntropyBits(m), 200.0);
  g->setCell(3, 4, 0.95f);
  const double p = g->getCell(3, 4);
  const double h = -(p * std::log2(p) + (1 - p) * std::log2(1 - p));
  EXPECT_NEAR(asf::mapping::mapEntropyBits(m), 199.0 + h, 1e-9);
  EXPECT_NEAR(asf::mapping::mapInformationBits(m), 1.0 - h, 1e-9) << "unknown cells say nothing";
  EXPECT_LT(h, 0.35) << "a nearly certain cell: far below 1 bit";
  EXPECT_EQ(asf::mapping::mapEntropyBits(asf::GridMap{}), 0.0) << "no map";
  EXPECT_EQ(asf::mapping::mapInformationBits(asf::GridMap{}), 0.0);
}

TEST(MapAreaTracker, UntrustedBoxesAreRecounted) {
  MappingRun run;
  asf::mapping::MapAreaTracker tracker(&run.meter);
  ASSERT_TRUE(run.step({11, 2, 0}));
  tracker.update(run.builder.map());
  ASSERT_TRUE(run.step({10, 2, 0}));
  asf::GridMap said_nothing = run.builder.map();
  said_nothing.changed = asf::Box2{};  // an empty box says nothing: no incremental update
  tracker.update(said_nothing);
  expectSameAsRecount(tracker, said_nothing, run.meter, "empty box");
  EXPECT_EQ(tracker.recounts(), 2u);
  tracker.update(said_nothing);
  EXPECT_EQ(tracker.recounts(), 2u) << "the same version again: nothing to do";

  // A box that lies (misses the changed cells) would give a wrong count; a correct one does
  // not: the tracker reads the grid only inside it.
  ASSERT_TRUE(run.step({8, 2.5, 0}));
  asf::GridMap lying = run.builder.map();
  lying.changed = asf::Box2{};
  lying.changed.extend(-5, -5);
  lying.changed.extend(-4.9, -4.9);
  tracker.update(lying);
  EXPECT_NE(tracker.freeArea(), asf::mapping::freeArea(lying));

  asf::mapping::MapAreaTracker no_meter;
  no_meter.update(run.builder.map());
  EXPECT_EQ(no_meter.coverage(), 0.0);
  EXPECT_DOUBLE_EQ(no_meter.freeArea(), asf::mapping::freeArea(run.builder.map()));
  no_meter.update(asf::GridMap{});
  EXPECT_EQ(no_meter.freeArea(), 0.0);
}

// The counts through a GridIndex (cell positions computed once per grid geometry, cells read
// from the raw buffer) are the direct ones: the same cells, the same threshold. The free-cell
// count is checked against getCell() cell by cell.
TEST(CoverageMeter, GridIndexCountsEqualTheDirectOnes) {
  MappingRun run;
  ASSERT_TRUE(run.step({11, 2, 0}));
  ASSERT_TRUE(run.step({8, 2.2, 0.4}));
  const auto& g = *run.builder.map().grid;
  const asf::mapping::CoverageMeter::GridIndex index = run.meter.indexFor(g);
  ASSERT_TRUE(index.fits(g));
  ASSERT_EQ(index.cell.size(), run.meter.reachableCells());
  const std::size_t seen = run.meter.observedCount(g);
  EXPECT_GT(seen, 100u);
  EXPECT_EQ(run.meter.observedCount(g, index), seen);
  for (const asf::Box2& box : {asf::Box2{0, 0, 5, 4}, asf::Box2{6.5, 1, 12, 3.5},
                               asf::Box2{-3, -3, 30, 30}, asf::Box2{7.1, 2.1, 7.3, 2.2}}) {
    std::size_t v1 = 0, v2 = 0;
    EXPECT_EQ(run.meter.observedIn(g, box, index, v1), run.meter.observedIn(g, box, v2));
    EXPECT_EQ(v1, v2);
  }
  std::size_t free_cells = 0;
  for (unsigned y = 0; y < g.getSizeY(); ++y)
    for (unsigned x = 0; x < g.getSizeX(); ++x)
      if (g.getCell(x, y) >= 0.5f + 0.02f) ++free_cells;
  EXPECT_GT(free_cells, 100u);
  const double r = g.getResolution();
  EXPECT_DOUBLE_EQ(asf::mapping::freeArea(run.builder.map()), static_cast<double>(free_cells) * r * r);

  // A grid that covers part of the world, its cells set at random: the cells off it count as
  // unobserved both ways.
  mrpt::maps::COccupancyGridMap2D small(1.0f, 5.0f, 0.5f, 3.0f, 0.05f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> p(0.f, 1.f);
  for (unsigned y = 0; y < small.getSizeY(); ++y)
    for (unsigned x = 0; x < small.getSizeX(); ++x)
      small.setCell(x, y, p(rng) < 0.3 ? 0.5f : p(rng));
  const asf::mapping::CoverageMeter::GridIndex part = run.meter.indexFor(small);
  const std::size_t off =
      static_cast<std::size_t>(std::count(part.cell.begin(), part.cell.end(), std::int32_t{-1}));
  EXPECT_GT(off, run.meter.reachableCells() / 2) << "most of the world is off this grid";
  EXPECT_GT(run.meter.observedCount(small), 100u);
  EXPECT_EQ(run.meter.observedCount(small, part), run.meter.observedCount(small));
  std::size_t v1 = 0, v2 = 0;
  const asf::Box2 box{0, 0, 4, 4};
  EXPECT_EQ(run.meter.observedIn(small, box, part, v1), run.meter.observedIn(small, box, v2));
  EXPECT_FALSE(part.fits(g));
}
