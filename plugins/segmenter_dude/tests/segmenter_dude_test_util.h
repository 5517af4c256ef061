#pragma once
// Helpers of the dude segmenter's plugin tests: the plugin loaded and configured, grids built
// box by box, and the contract's checks on a result.
#include <asf/framework/registry.h>
#include <asf/segmenter.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <string>

namespace dude_test {

using Grid = mrpt::maps::COccupancyGridMap2D;
// MRPT cell values are p(free): 1 = certainly empty, 0 = certainly occupied.
constexpr float kFree = 0.95f, kWall = 0.05f;
constexpr float kRes = 0.05f;

inline std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/segmenter_dude.so");
  return i;
}

inline asf::framework::PluginHandle<asf::Segmenter> make(
    const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Segmenter>(info());
  h->configure(asf::Params::fromSpecs("dude", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

/// w x h metres at 5 cm, all unknown.
inline std::shared_ptr<Grid> unknownGrid(float w, float h) {
  auto g = std::make_shared<Grid>(0.f, w, 0.f, h, kRes);
  g->fill(0.5f);
  return g;
}

/// Sets the cells of the box [x0,x1) x [y0,y1) (metres).
inline void setBox(Grid& g, double x0, double y0, double x1, double y1, float p) {
  const int cx0 = g.x2idx(x0 + 1e-6), cy0 = g.y2idx(y0 + 1e-6);
  const int cx1 = g.x2idx(x1 - 1e-6), cy1 = g.y2idx(y1 - 1e-6);
  for (int cy = std::max(cy0, 0); cy <= cy1 && cy < static_cast<int>(g.getSizeY()); ++cy)
    for (int cx = std::max(cx0, 0); cx <= cx1 && cx < static_cast<int>(g.getSizeX()); ++cx)
      g.setCell(cx, cy, p);
}

inline asf::GridMap mapOf(std::shared_ptr<const Grid> g, std::uint64_t version = 1, bool rebuilt = false) {
  asf::GridMap m;
  m.grid = std::move(g);
  m.version = version;
  m.rebuilt = rebuilt;
  return m;
}

inline bool isFree(const Grid& g, int cx, int cy) { return 1.0 - g.getCell(cx, cy) < 0.4; }

/// The contract, plus: every free cell of a component larger than min_component_area has a
/// label (the plugin promises it).
inline void checkConsistency(const asf::Segmentation& s, const Grid& g) {
  ASSERT_EQ(s.labels.width, static_cast<int>(g.getSizeX()));
  ASSERT_EQ(s.labels.height, static_cast<int>(g.getSizeY()));
  EXPECT_DOUBLE_EQ(s.labels.resolution, g.getResolution());
  EXPECT_DOUBLE_EQ(s.labels.origin_x, g.getXMin());
  EXPECT_DOUBLE_EQ(s.labels.origin_y, g.getYMin());
  std::map<asf::RegionId, int> count;
  for (int cy = 0; cy < s.labels.height; ++cy)
    for (int cx = 0; cx < s.labels.width; ++cx) {
      const asf::RegionId id = s.labels.at(cx, cy);
      EXPECT_GE(id, 0);
      if (id > 0) {
        ++count[id];
        EXPECT_TRUE(isFree(g, cx, cy)) << cx << "," << cy;
      }
    }
  std::set<asf::RegionId> ids;
  const double cell = g.getResolution() * g.getResolution();
  for (const auto& r : s.regions) {
    EXPECT_GT(r.id, 0);
    EXPECT_TRUE(ids.insert(r.id).second) << "duplicate id " << r.id;
    ASSERT_TRUE(count.count(r.id)) << "region " << r.id << " has no cells";
    EXPECT_NEAR(r.area, count[r.id] * cell, 1e-6 * r.area);  // float resolution
    EXPECT_GE(r.outer.size(), 3u);
  }
  EXPECT_EQ(ids.size(), count.size());
}

inline int unlabelledFreeCells(const asf::Segmentation& s, const Grid& g) {
  int n = 0;
  for (int cy = 0; cy < s.labels.height; ++cy)
    for (int cx = 0; cx < s.labels.width; ++cx)
      if (isFree(g, cx, cy) && s.labels.at(cx, cy) == 0) ++n;
  return n;
}

/// A walled room [x0,x1) x [y0,y1) (free inside, 0.1 m walls outside it).
inline void room(Grid& g, double x0, double y0, double x1, double y1) {
  setBox(g, x0 - 0.1, y0 - 0.1, x1 + 0.1, y1 + 0.1, kWall);
  setBox(g, x0, y0, x1, y1, kFree);
}

}  // namespace dude_test
