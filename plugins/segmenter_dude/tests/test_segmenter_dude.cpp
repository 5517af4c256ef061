// Tests of the dude segmenter plugin on occupancy grids (MRPT) and, when ../shared is there,
// on one map of the room segmentation benchmark.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/segmenter.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "segmenter_dude_test_util.h"

namespace {

using namespace dude_test;

TEST(SegmenterDude, BadConfigurationNamesTheKey) {
  try {
    make({{"free_threshold", "0.7"}, {"occupied_threshold", "0.5"}});
    FAIL() << "expected a ConfigError";
  } catch (const asf::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("occupied_threshold"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make({{"max_concavity", "0"}}), asf::ConfigError);
}

TEST(SegmenterDude, EmptyMapGivesNoRegions) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    EXPECT_TRUE(seg->segment(asf::GridMap{}, nullptr).regions.empty());
    auto g = unknownGrid(4, 3);
    const auto s = seg->segment(mapOf(g), nullptr);
    EXPECT_TRUE(s.regions.empty());
    checkConsistency(s, *g);
    auto walls = unknownGrid(4, 3);
    walls->fill(kWall);
    EXPECT_TRUE(seg->segment(mapOf(walls, 2), nullptr).regions.empty());
  }
}

// A map above max_cells is an input error naming its size, thrown before anything is
// allocated (a 20000 x 20000 px map would need about 5 GB of working images).
TEST(SegmenterDude, AMapAboveMaxCellsIsAnInputErrorNamingItsSize) {
  for (const char* variant : {"rooms", "thesis"}) {
    auto seg = make({{"variant", variant}, {"max_cells", "1000"}});
    auto g = unknownGrid(2, 2);  // 40 x 40 cells
    room(*g, 0.5, 0.5, 1.5, 1.5);
    try {
      seg->segment(mapOf(g), nullptr);
      FAIL() << "expected an InputError";
    } catch (const asf::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("40 x 40"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("max_cells"), std::string::npos) << e.what();
    }
    EXPECT_EQ(make({{"variant", variant}})->segment(mapOf(g), nullptr).regions.size(), 1u);
  }
}

TEST(SegmenterDude, ConvexRoomIsOneRegion) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = unknownGrid(8, 6);
    room(*g, 1, 1, 7, 5);
    const auto s = seg->segment(mapOf(g, 3), nullptr);
    EXPECT_EQ(s.map_version, 3u);
    ASSERT_EQ(s.regions.size(), 1u);
    EXPECT_NEAR(s.regions[0].area, 24, 1e-6);
    EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
    checkConsistency(s, *g);
  }
}

TEST(SegmenterDude, LShapedCorridorGivesTwoRegions) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = unknownGrid(12, 12);
    g->fill(kWall);
    setBox(*g, 1, 1, 11, 3, kFree);   // horizontal arm, 2 m wide
    setBox(*g, 1, 1, 3, 11, kFree);   // vertical arm
    const auto s = seg->segment(mapOf(g), nullptr);
    ASSERT_EQ(s.regions.size(), 2u);
    EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
    checkConsistency(s, *g);
    // The far ends of both arms are in different regions.
    EXPECT_NE(s.labels.atPoint(10.5, 2), s.labels.atPoint(2, 10.5));
  }
}

TEST(SegmenterDude, RoomWithALargeObstacleIsSplitAroundIt) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = unknownGrid(22, 22);
    room(*g, 1, 1, 21, 21);
    setBox(*g, 7, 7, 15, 15, kWall);  // an 8 m block in the middle: a hole wider than tau
    const auto s = seg->segment(mapOf(g), nullptr);
    EXPECT_GE(s.regions.size(), 2u);
    EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
    checkConsistency(s, *g);
    for (const auto& r : s.regions)  // no region reaches into the block
      EXPECT_FALSE(r.centroid.x > 7.5 && r.centroid.x < 14.5 && r.centroid.y > 7.5 &&
                   r.centroid.y < 14.5);
  }
}

TEST(SegmenterDude, SmallPillarDoesNotSplitARoom) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = unknownGrid(10, 8);
    room(*g, 1, 1, 9, 7);
    setBox(*g, 4.5, 3.5, 5.5, 4.5, kWall);
    const auto s = seg->segment(mapOf(g), nullptr);
    ASSERT_EQ(s.regions.size(), 1u);
    EXPECT_FALSE(s.regions[0].holes.empty());
    checkConsistency(s, *g);
  }
}

/// Two 5 x 5 rooms side by side, 0.1 m wall between them with a 1 m door 1 m from a
/// corner (the wall beside the door is 3 m deep: more than max_concavity).
std::shared_ptr<Grid> twoRoomsWithDoor() {
  auto g = unknownGrid(13, 8);
  room(*g, 1, 1, 6, 6);
  room(*g, 6.1, 1, 11.1, 6);
  setBox(*g, 6, 2, 6.1, 3, kFree);  // the door
  return g;
}

TEST(SegmenterDude, RoomsJoinedByADoorAreTwoRegions) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = twoRoomsWithDoor();
    const auto s = seg->segment(mapOf(g), nullptr);
    ASSERT_EQ(s.regions.size(), 2u);
    EXPECT_NE(s.labels.atPoint(3, 3), s.labels.atPoint(9, 3));
    for (const auto& r : s.regions) EXPECT_NEAR(r.area, 25, 0.3);
    EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
    checkConsistency(s, *g);
  }
}

TEST(SegmenterDude, OnePixelCorridorsAndSpecksAreLabelled) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}, {"gap_closing", "0"}});
    auto g = unknownGrid(14, 12);
    room(*g, 1, 1, 5, 10);
    room(*g, 9, 1, 13, 10);
    setBox(*g, 5, 3, 9, 3.05, kFree);  // one cell wide, 4 m long
    setBox(*g, 2, 2, 2.05, 2.05, kWall);  // a one-cell speck in a room
    const auto s = seg->segment(mapOf(g), nullptr);
    EXPECT_GE(s.regions.size(), 2u);
    EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
    checkConsistency(s, *g);
    // Diagonal one-cell chain (8-connected only).
    auto d = unknownGrid(6, 6);
    for (int k = 0; k < 60; ++k) d->setCell(20 + k % 40, 20 + k % 40, kFree);
    const auto sd = seg->segment(mapOf(d, 2), nullptr);
    checkConsistency(sd, *d);
  }
}

/// A floor plan drawn as an image (255 free, 0 wall): three rooms off a corridor, one with
/// a pillar.
asf::io::GrayImage floorPlan() {
  asf::io::GrayImage img;
  img.width = 240;
  img.height = 160;
  img.pixels.assign(static_cast<std::size_t>(img.width) * img.height, 0);
  auto fill = [&](int c0, int r0, int c1, int r1, std::uint8_t v) {
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) img.pixels[static_cast<std::size_t>(r) * img.width + c] = v;
  };
  fill(4, 4, 236, 36, 255);     // corridor
  fill(4, 44, 76, 156, 255);    // room 1
  fill(84, 44, 156, 156, 255);  // room 2
  fill(164, 44, 236, 156, 255); // room 3
  fill(110, 90, 126, 106, 0);   // pillar in room 2
  for (int c : {30, 110, 190}) fill(c, 36, c + 18, 44, 255);  // doors
  return img;
}

// The update reads only the map's `changed` box when the map is the next version. Fed the
// same exploration with and without that box (then every cell is read again), the results
// must be the same at every step: nothing outside the box may be stale.
TEST(SegmenterDude, ChangedBoxUpdateEqualsWholeMapUpdateThroughAnExploration) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto boxed = make({{"variant", variant}});
    auto whole = make({{"variant", variant}});
    asf::evaluation::ExplorationOptions opt;
    opt.sensor_range = 3.0;
    asf::evaluation::ExplorationSimulator sim(floorPlan(), 0.05, opt);
    asf::Segmentation a, b;
    int steps = 0, incremental = 0;
    while (sim.step()) {
      asf::GridMap m = sim.map();
      ASSERT_FALSE(m.changed.empty());
      asf::GridMap m_whole = m;
      m_whole.changed = asf::Box2{};
      a = boxed->segment(m, steps ? &a : nullptr);
      b = whole->segment(m_whole, steps ? &b : nullptr);
      ++steps;
      incremental += a.mode == asf::Segmentation::Mode::Incremental;
      ASSERT_EQ(a.labels.labels, b.labels.labels) << "step " << steps;
      ASSERT_EQ(a.regions.size(), b.regions.size()) << "step " << steps;
      for (std::size_t k = 0; k < a.regions.size(); ++k)
        ASSERT_EQ(a.regions[k].id, b.regions[k].id);
      EXPECT_EQ(a.changed_cells, b.changed_cells) << "step " << steps;
    }
    EXPECT_GT(steps, 20);
    EXPECT_EQ(incremental, steps - 1);
    EXPECT_GE(a.regions.size(), 4u);
  }
}

TEST(SegmenterDude, IncrementalOnAFixedMapEqualsBatch) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto batch = make({{"variant", variant}, {"incremental", "false"}});
    auto inc = make({{"variant", variant}, {"incremental", "true"}});
    auto g = twoRoomsWithDoor();
    setBox(*g, 2, 2, 3, 3, kWall);
    const auto b = batch->segment(mapOf(g, 1), nullptr);
    const auto i1 = inc->segment(mapOf(g, 1), nullptr);
    const auto i2 = inc->segment(mapOf(g, 2), &i1);
    const auto i3 = inc->segment(mapOf(g, 3), &i2);
    EXPECT_EQ(b.labels.labels, i1.labels.labels);
    EXPECT_EQ(b.labels.labels, i2.labels.labels);
    EXPECT_EQ(b.labels.labels, i3.labels.labels);
    ASSERT_EQ(b.regions.size(), i3.regions.size());
    for (std::size_t k = 0; k < b.regions.size(); ++k) EXPECT_EQ(b.regions[k].id, i3.regions[k].id);
  }
}

/// True when a and b group the cells the same way (ids aside).
bool samePartition(const asf::LabelImage& a, const asf::LabelImage& b) {
  if (a.labels.size() != b.labels.size()) return false;
  std::map<asf::RegionId, asf::RegionId> ab, ba;
  for (std::size_t i = 0; i < a.labels.size(); ++i) {
    const asf::RegionId x = a.labels[i], y = b.labels[i];
    if ((x > 0) != (y > 0)) return false;
    if (x <= 0) continue;
    if (ab.emplace(x, y).first->second != y) return false;
    if (ba.emplace(y, x).first->second != x) return false;
  }
  return true;
}

// An obstacle that appears in unknown space changes no free cell, but it can close a gap
// (gap_closing) and so change the free space DuDe decomposes: the update must see it. A
// room and a closet (2 m deep: too shallow to be cut off) joined by a 0.2 m gap in their
// 0.3 m thick shared wall; the cells beside the gap are unknown (a 0.4 m gap between
// obstacles: it stays open, one region), then become wall (gap_closing = 0.3 m closes the
// 0.2 m gap: the closet is a component of its own). The incremental
// result must group the cells as a batch segmentation of the new map does.
TEST(SegmenterDude, AnObstacleInUnknownSpaceThatClosesAGapIsSeen) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto g = unknownGrid(10, 6);
    setBox(*g, 0.4, 0.4, 9.6, 5.6, kWall);
    setBox(*g, 0.5, 2.8, 9.5, 5.5, kFree);   // room
    setBox(*g, 4.0, 0.5, 5.5, 2.5, kFree);   // closet
    setBox(*g, 4.6, 2.5, 4.8, 2.8, kFree);   // the gap
    setBox(*g, 4.8, 2.5, 5.0, 2.8, 0.5f);    // unknown beside it: the gap stays open
    auto g2 = std::make_shared<Grid>(*g);
    setBox(*g2, 4.8, 2.5, 5.0, 2.8, kWall);  // seen: the gap closes
    auto inc = make({{"variant", variant}, {"gap_closing", "0.3"}});
    auto batch = make({{"variant", variant}, {"gap_closing", "0.3"}, {"incremental", "false"}});
    const auto s1 = inc->segment(mapOf(g, 1), nullptr);
    asf::GridMap m2 = mapOf(g2, 2);
    m2.changed.extend(4.8, 2.5);
    m2.changed.extend(5.0, 2.8);
    const auto s2 = inc->segment(m2, &s1);
    const auto b2 = batch->segment(mapOf(g2, 1), nullptr);
    const auto b1 = batch->segment(mapOf(g, 1), nullptr);
    ASSERT_FALSE(samePartition(b1.labels, b2.labels))
        << "the case must change the batch result: " << b1.regions.size() << " / "
        << b2.regions.size();
    EXPECT_EQ(s2.mode, asf::Segmentation::Mode::Incremental);
    EXPECT_EQ(s2.changed_cells, 0);  // no free cell changed
    EXPECT_TRUE(samePartition(s2.labels, b2.labels));
    checkConsistency(s2, *g2);
  }
}

TEST(SegmenterDude, RegionIdsPersistAcrossUnrelatedUpdates) {
  auto seg = make();
  auto g = unknownGrid(30, 10);
  room(*g, 1, 1, 7, 7);    // room A, far from where the map grows
  room(*g, 12, 1, 18, 7);  // room B
  const auto s1 = seg->segment(mapOf(g, 1), nullptr);
  ASSERT_EQ(s1.regions.size(), 2u);
  const asf::RegionId a = s1.labels.atPoint(4, 4), b = s1.labels.atPoint(15, 4);
  ASSERT_GT(a, 0);
  ASSERT_GT(b, 0);

  // Exploration continues east of B: a corridor from B and a separate new room C.
  auto g2 = std::make_shared<Grid>(*g);
  setBox(*g2, 18, 3, 18.1, 5, kFree);  // open B's east wall
  setBox(*g2, 18.1, 2.9, 24, 5.1, kWall);
  setBox(*g2, 18.1, 3, 24, 5, kFree);  // corridor
  room(*g2, 25, 1, 29, 8);             // C: touches no region
  asf::GridMap m2 = mapOf(g2, 2);
  m2.changed.extend(18, 1);
  m2.changed.extend(29, 8);
  const auto s2 = seg->segment(m2, &s1);
  checkConsistency(s2, *g2);
  EXPECT_EQ(unlabelledFreeCells(s2, *g2), 0);
  EXPECT_EQ(s2.labels.atPoint(4, 4), a);
  const asf::Region* ra1 = s1.find(a);
  const asf::Region* ra2 = s2.find(a);
  ASSERT_TRUE(ra1 && ra2);
  EXPECT_DOUBLE_EQ(ra1->area, ra2->area);
  EXPECT_DOUBLE_EQ(ra1->centroid.x, ra2->centroid.x);
  // B was touched: still there (largest overlap keeps its id), and C is a new region.
  EXPECT_EQ(s2.labels.atPoint(15, 4), b);
  const asf::RegionId c = s2.labels.atPoint(27, 4);
  EXPECT_GT(c, 0);
  EXPECT_NE(c, a);
  EXPECT_NE(c, b);

  // A loop closure (rebuilt) that changed no cell stays incremental: same labels, same ids.
  const auto s3 = seg->segment(mapOf(g2, 3, /*rebuilt=*/true), &s2);
  EXPECT_EQ(s3.labels.labels, s2.labels.labels);
  EXPECT_EQ(s3.labels.atPoint(4, 4), a);
  EXPECT_EQ(s1.mode, asf::Segmentation::Mode::Full);
  EXPECT_EQ(s1.changed_cells, static_cast<std::int64_t>(g->getSizeX() * g->getSizeY()));
  EXPECT_EQ(s2.mode, asf::Segmentation::Mode::Incremental);
  EXPECT_GT(s2.changed_cells, 0);
  EXPECT_EQ(s3.mode, asf::Segmentation::Mode::Incremental);
  EXPECT_EQ(s3.changed_cells, 0);
}

// A loop closure that moves keyframes by a few centimetres changes a few cells: the update
// stays incremental and the regions far from the change keep their cells and ids; a rebuilt
// map that changed most cells, or rebuild_full_fraction = 0, is segmented in full.
TEST(SegmenterDude, LoopClosureWithALocalChangeStaysIncremental) {
  for (const char* variant : {"rooms", "thesis"}) {
    SCOPED_TRACE(variant);
    auto seg = make({{"variant", variant}});
    auto g = unknownGrid(30, 10);
    room(*g, 1, 1, 7, 7);    // A
    room(*g, 12, 1, 18, 7);  // B
    const auto s1 = seg->segment(mapOf(g, 1), nullptr);
    const asf::RegionId a = s1.labels.atPoint(4, 4);
    // B's east wall moves one cell (5 cm) east: a column of new free cells, the wall shifted.
    auto g2 = std::make_shared<Grid>(*g);
    setBox(*g2, 18, 1, 18.05, 7, kFree);
    setBox(*g2, 18.05, 0.9, 18.15, 7.1, kWall);
    int changed = 0;
    for (unsigned cy = 0; cy < g->getSizeY(); ++cy)
      for (unsigned cx = 0; cx < g->getSizeX(); ++cx)
        changed += isFree(*g, cx, cy) != isFree(*g2, cx, cy);
    ASSERT_GT(changed, 0);
    const auto s2 = seg->segment(mapOf(g2, 2, /*rebuilt=*/true), &s1);
    checkConsistency(s2, *g2);
    EXPECT_EQ(s2.mode, asf::Segmentation::Mode::Incremental);
    EXPECT_EQ(s2.changed_cells, changed);
    EXPECT_EQ(s2.labels.atPoint(4, 4), a);
    const asf::Region *ra1 = s1.find(a), *ra2 = s2.find(a);
    ASSERT_TRUE(ra1 && ra2);
    EXPECT_DOUBLE_EQ(ra1->area, ra2->area);
    for (unsigned cy = 0; cy < g->getSizeY(); ++cy)  // A's cells are exactly A's cells
      for (unsigned cx = 0; cx < g->getSizeX(); ++cx)
        EXPECT_EQ(s1.labels.at(cx, cy) == a, s2.labels.at(cx, cy) == a);

    auto full = make({{"variant", variant}, {"rebuild_full_fraction", "0"}});
    const auto f1 = full->segment(mapOf(g, 1), nullptr);
    EXPECT_EQ(full->segment(mapOf(g2, 2, true), &f1).mode, asf::Segmentation::Mode::Full);
    auto g3 = unknownGrid(30, 10);  // a different building: most cells changed
    room(*g3, 2, 2, 28, 9);
    EXPECT_EQ(seg->segment(mapOf(g3, 3, true), &s2).mode, asf::Segmentation::Mode::Full);
  }
}

TEST(SegmenterDude, IncrementalFollowsAGrowingGrid) {
  auto seg = make();
  auto g = std::make_shared<Grid>(0.f, 10.f, 0.f, 8.f, kRes);
  g->fill(0.5f);
  room(*g, 1, 1, 6, 6);
  const auto s1 = seg->segment(mapOf(g, 1), nullptr);
  ASSERT_EQ(s1.regions.size(), 1u);
  auto g2 = std::make_shared<Grid>(*g);
  g2->resizeGrid(-5.f, 20.f, 0.f, 8.f, 0.5f, false);
  room(*g2, 12, 1, 18, 6);
  const auto s2 = seg->segment(mapOf(g2, 2), &s1);
  checkConsistency(s2, *g2);
  EXPECT_EQ(s2.regions.size(), 2u);
  EXPECT_EQ(s2.labels.atPoint(3, 3), s1.labels.atPoint(3, 3));
}

// ---- the benchmark (skipped without ../shared) ------------------------------------------

TEST(SegmenterDude, OfficeMapOfTheBenchmarkIsSegmentedIntoRooms) {
  const std::string dir = ASF_TEST_SHARED_DIR "/datasets/roomseg";
  if (!std::filesystem::exists(dir + "/plain/office_a.png"))
    GTEST_SKIP() << "benchmark maps not found in " << dir << " (../shared absent)";
  const cv::Mat img = cv::imread(dir + "/plain/office_a.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat gt = cv::imread(dir + "/gt/office_a_gt_segmentation.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty());
  ASSERT_EQ(img.size(), gt.size());
  auto g = std::make_shared<Grid>(0.f, img.cols * 0.05f, 0.f, img.rows * 0.05f, 0.05f);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) g->setCell(c, r, img.at<uchar>(r, c) >= 250 ? 1.f : 0.f);
  auto seg = make({{"incremental", "false"}});
  const auto s = seg->segment(mapOf(g), nullptr);
  checkConsistency(s, *g);
  // Scoring as in roomseg-eval.md: GT rooms = 8-connected components of GT > 250.
  cv::Mat rooms;
  const int n_rooms = cv::connectedComponents(gt > 250, rooms, 8, CV_32S);
  std::map<int, int> room_size, seg_size;
  std::map<std::pair<int, int>, int> overlap;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const int gr = rooms.at<int>(r, c), sl = s.labels.at(c, r);
      if (gr > 0) ++room_size[gr];
      if (sl > 0) ++seg_size[sl];
      if (gr > 0 && sl > 0) ++overlap[{sl, gr}];
    }
  std::map<int, int> best_s, best_r;
  for (const auto& [k, n] : overlap) {
    best_s[k.first] = std::max(best_s[k.first], n);
    best_r[k.second] = std::max(best_r[k.second], n);
  }
  double prec = 0, rec = 0;
  int ns = 0, nr = 0;
  for (const auto& [l, n] : seg_size)
    if (n > 100) prec += static_cast<double>(best_s[l]) / n, ++ns;
  for (const auto& [l, n] : room_size)
    if (n > 100) rec += static_cast<double>(best_r[l]) / n, ++nr;
  ASSERT_GT(ns, 0);
  ASSERT_GT(nr, 0);
  prec /= ns;
  rec /= nr;
  RecordProperty("precision", std::to_string(prec));
  RecordProperty("recall", std::to_string(rec));
  EXPECT_GT(n_rooms, 10);
  // Loose bounds: this guards against a broken pipeline, the benchmark measures quality.
  EXPECT_GT(prec, 0.85);
  EXPECT_GT(rec, 0.7);
}

}  // namespace
