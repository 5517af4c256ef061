// Tests of the free_components segmenter on hand-made occupancy grids.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/segmenter.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace {

using Grid = mrpt::maps::COccupancyGridMap2D;
// MRPT cell values are p(free): 1 = certainly empty, 0 = certainly occupied.
constexpr float kFree = 0.95f, kWall = 0.05f;

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/segmenter_free_components.so");
  return i;
}

asf::framework::PluginHandle<asf::Segmenter> make(
    const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Segmenter>(info());
  h->configure(asf::Params::fromSpecs("free_components", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

/// 4 m x 2 m at 0.1 m (40 x 20 cells), all unknown.
std::shared_ptr<Grid> unknownGrid() {
  auto g = std::make_shared<Grid>(0.f, 4.f, 0.f, 2.f, 0.1f);
  g->fill(0.5f);
  return g;
}

void setBox(Grid& g, int cx0, int cy0, int cx1, int cy1, float p) {
  for (int cy = cy0; cy <= cy1; ++cy)
    for (int cx = cx0; cx <= cx1; ++cx) g.setCell(cx, cy, p);
}

/// Two 16 x 16-cell rooms (cells 2..17 and 22..37 in x, 2..17 in y), walls around them.
std::shared_ptr<Grid> twoRooms(bool corridor) {
  auto g = unknownGrid();
  setBox(*g, 1, 1, 38, 18, kWall);  // walls
  setBox(*g, 2, 2, 17, 17, kFree);
  setBox(*g, 22, 2, 37, 17, kFree);
  if (corridor) setBox(*g, 18, 10, 21, 10, kFree);  // one free cell wide
  return g;
}

asf::GridMap mapOf(std::shared_ptr<Grid> g, std::uint64_t version = 1) {
  asf::GridMap m;
  m.grid = std::move(g);
  m.version = version;
  return m;
}

/// The contract: labels aligned with the grid, on free cells only, labels <-> regions,
/// areas = labelled cells x cell area.
void checkConsistency(const asf::Segmentation& s, const Grid& g, double free_threshold = 0.4) {
  ASSERT_EQ(s.labels.width, static_cast<int>(g.getSizeX()));
  ASSERT_EQ(s.labels.height, static_cast<int>(g.getSizeY()));
  EXPECT_DOUBLE_EQ(s.labels.resolution, g.getResolution());
  EXPECT_DOUBLE_EQ(s.labels.origin_x, g.getXMin());
  EXPECT_DOUBLE_EQ(s.labels.origin_y, g.getYMin());
  ASSERT_EQ(s.labels.labels.size(), std::size_t(s.labels.width) * s.labels.height);
  std::map<asf::RegionId, int> count;
  for (int cy = 0; cy < s.labels.height; ++cy)
    for (int cx = 0; cx < s.labels.width; ++cx) {
      const asf::RegionId id = s.labels.at(cx, cy);
      EXPECT_GE(id, 0);
      if (id > 0) {
        ++count[id];
        EXPECT_LT(1.0 - g.getCell(cx, cy), free_threshold) << cx << "," << cy;
      }
    }
  std::set<asf::RegionId> ids;
  const double res = g.getResolution();
  const double cell = res * res;
  for (const auto& r : s.regions) {
    EXPECT_GT(r.id, 0);
    EXPECT_TRUE(ids.insert(r.id).second) << "duplicate id " << r.id;
    ASSERT_TRUE(count.count(r.id)) << "region " << r.id << " has no cells";
    EXPECT_NEAR(r.area, count[r.id] * cell, 1e-9);
    EXPECT_EQ(s.find(r.id), &r);
  }
  EXPECT_EQ(ids.size(), count.size());
}

double signedArea(const asf::Polygon& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    a += u.x * v.y - v.x * u.y;
  }
  return a / 2;
}

TEST(FreeComponents, RoomsJoinedByAOneCellCorridorAreOneRegion) {
  auto seg = make();
  auto g = twoRooms(true);
  const auto s = seg->segment(mapOf(g, 5), nullptr);
  EXPECT_EQ(s.map_version, 5u);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_NEAR(s.regions[0].area, (2 * 256 + 4) * 0.01, 1e-6);
  checkConsistency(s, *g);
}

TEST(FreeComponents, SeparatedRoomsAreTwoRegionsWithExactAreasAndCentroids) {
  auto seg = make();
  auto g = twoRooms(false);
  const auto s = seg->segment(mapOf(g), nullptr);
  ASSERT_EQ(s.regions.size(), 2u);
  checkConsistency(s, *g);
  std::vector<asf::Region> r = s.regions;
  std::sort(r.begin(), r.end(), [](auto& a, auto& b) { return a.centroid.x < b.centroid.x; });
  EXPECT_NEAR(r[0].area, 2.56, 1e-6);
  EXPECT_NEAR(r[1].area, 2.56, 1e-6);
  // Cells 2..17 have centres 0.25 .. 1.75 m: centroid 1.0; the right room's is 3.0.
  EXPECT_NEAR(r[0].centroid.x, 1.0, 1e-6);
  EXPECT_NEAR(r[0].centroid.y, 1.0, 1e-6);
  EXPECT_NEAR(r[1].centroid.x, 3.0, 1e-6);
  // Outer boundary through the border cells' centres, counter-clockwise, no holes.
  EXPECT_GT(signedArea(r[0].outer), 0);
  EXPECT_NEAR(signedArea(r[0].outer), 1.5 * 1.5, 1e-6);
  double minx = 1e9, maxx = -1e9;
  for (const auto& p : r[0].outer) {
    minx = std::min(minx, p.x);
    maxx = std::max(maxx, p.x);
  }
  EXPECT_NEAR(minx, 0.25, 1e-6);
  EXPECT_NEAR(maxx, 1.75, 1e-6);
  EXPECT_TRUE(r[0].holes.empty());
  EXPECT_NE(r[0].id, r[1].id);
}

TEST(FreeComponents, AllUnknownOrNoGridGivesNoRegions) {
  auto seg = make();
  auto g = unknownGrid();
  const auto s = seg->segment(mapOf(g), nullptr);
  EXPECT_TRUE(s.regions.empty());
  checkConsistency(s, *g);
  for (auto l : s.labels.labels) EXPECT_EQ(l, 0);
  const auto none = seg->segment(asf::GridMap{}, nullptr);
  EXPECT_TRUE(none.regions.empty());
}

TEST(FreeComponents, DiagonalTouchDependsOnConnectivity) {
  auto g = unknownGrid();
  setBox(*g, 2, 2, 11, 11, kFree);    // 10 x 10 cells
  setBox(*g, 12, 12, 21, 19, kFree);  // touches the first only at a corner
  const auto s8 = make({{"connectivity", "8"}})->segment(mapOf(g), nullptr);
  const auto s4 = make({{"connectivity", "4"}})->segment(mapOf(g), nullptr);
  EXPECT_EQ(s8.regions.size(), 1u);
  EXPECT_EQ(s4.regions.size(), 2u);
  checkConsistency(s8, *g);
  checkConsistency(s4, *g);
  EXPECT_THROW(make({{"connectivity", "6"}}), asf::ConfigError);
}

TEST(FreeComponents, SmallComponentsAreDroppedAndThresholdIsRespected) {
  auto g = twoRooms(false);
  setBox(*g, 19, 5, 20, 6, kFree);   // 2 x 2 cells = 0.04 m^2 inside the wall
  setBox(*g, 2, 2, 17, 17, 0.55f);   // left room only "fairly" free: p(occ) 0.45
  auto seg = make({{"min_area", "0.25"}});
  const auto s = seg->segment(mapOf(g), nullptr);
  ASSERT_EQ(s.regions.size(), 1u);  // left room above free_threshold 0.4, blob too small
  EXPECT_NEAR(s.regions[0].centroid.x, 3.0, 1e-6);
  EXPECT_EQ(s.labels.at(19, 5), 0);
  checkConsistency(s, *g);
  const auto s2 = make({{"free_threshold", "0.5"}, {"min_area", "0.01"}})->segment(mapOf(g),
                                                                                    nullptr);
  EXPECT_EQ(s2.regions.size(), 3u);
  checkConsistency(s2, *g, 0.5);
}

TEST(FreeComponents, HolesAreReportedClockwise) {
  auto g = twoRooms(false);
  setBox(*g, 8, 8, 11, 11, kWall);  // a pillar in the left room
  const auto s = make()->segment(mapOf(g), nullptr);
  ASSERT_EQ(s.regions.size(), 2u);
  const asf::Region& left = s.regions[0].centroid.x < 2 ? s.regions[0] : s.regions[1];
  ASSERT_EQ(left.holes.size(), 1u);
  EXPECT_LT(signedArea(left.holes[0]), 0);
  for (const auto& p : left.holes[0]) {  // around the pillar: centres of cells 7..12
    EXPECT_GE(p.x, 0.75 - 1e-6);
    EXPECT_LE(p.x, 1.25 + 1e-6);
  }
  EXPECT_NEAR(left.area, 2.56 - 0.16, 1e-6);
  checkConsistency(s, *g);
}

TEST(FreeComponents, IdsPersistAcrossUpdates) {
  auto seg = make();
  auto g1 = twoRooms(false);
  const auto s1 = seg->segment(mapOf(g1, 1), nullptr);
  ASSERT_EQ(s1.regions.size(), 2u);
  const asf::RegionId left = s1.labels.atPoint(1, 1), right = s1.labels.atPoint(3, 1);
  ASSERT_GT(left, 0);
  ASSERT_GT(right, 0);

  // A bigger map (new origin and size): the right room grows, a third room appears.
  auto g2 = std::make_shared<Grid>(-1.f, 6.f, 0.f, 2.f, 0.1f);
  g2->fill(0.5f);
  const int off = 10;  // x = 0 is cell 10 now
  setBox(*g2, off + 2, 2, off + 17, 17, kFree);
  setBox(*g2, off + 22, 2, off + 39, 17, kFree);
  setBox(*g2, off + 45, 2, off + 55, 17, kFree);
  const auto s2 = seg->segment(mapOf(g2, 2), &s1);
  ASSERT_EQ(s2.regions.size(), 3u);
  checkConsistency(s2, *g2);
  EXPECT_EQ(s2.labels.atPoint(1, 1), left);
  EXPECT_EQ(s2.labels.atPoint(3, 1), right);
  const asf::RegionId fresh = s2.labels.atPoint(5, 1);
  EXPECT_GT(fresh, std::max(left, right));

  // The rooms merge: the merged region keeps one previous id, never both; the third keeps its.
  setBox(*g2, off + 18, 10, off + 21, 10, kFree);
  const auto s3 = seg->segment(mapOf(g2, 3), &s2);
  ASSERT_EQ(s3.regions.size(), 2u);
  const asf::RegionId merged = s3.labels.atPoint(1, 1);
  EXPECT_EQ(s3.labels.atPoint(3, 1), merged);
  EXPECT_TRUE(merged == right) << "largest overlap is the grown right room";
  EXPECT_EQ(s3.labels.atPoint(5, 1), fresh);

  // They split again: the left room gets an id never issued before.
  setBox(*g2, off + 18, 10, off + 21, 10, kWall);
  const auto s4 = seg->segment(mapOf(g2, 4), &s3);
  ASSERT_EQ(s4.regions.size(), 3u);
  EXPECT_EQ(s4.labels.atPoint(3, 1), right);
  EXPECT_GT(s4.labels.atPoint(1, 1), fresh);
  checkConsistency(s4, *g2);
}

}  // namespace
