// asf::evaluation::RasterDiskReveal (the thesis' incremental protocol) with centres, disks and
// publications worked out by hand, and `asf segment-eval --exploration raster_disks`.
#include <asf/errors.h>
#include <asf/evaluation/segmentation_eval.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using asf::io::GrayImage;
using asf_test::has;
using asf_test::runHost;

asf::io::GrayImage filled(int w, int h, std::uint8_t v) {
  return asf::io::GrayImage{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, v)};
}

/// Pixels (image orientation) the published map knows, with their state (1 free, 0 wall).
std::map<std::pair<int, int>, int> knownPixels(const asf::GridMap& m, int W, int H) {
  std::map<std::pair<int, int>, int> out;
  for (int row = 0; row < H; ++row)
    for (int col = 0; col < W; ++col) {
      const float p = m.grid->getCell(col, H - 1 - row);
      if (p > 0.9f) out[{col, row}] = 1;
      else if (p < 0.1f) out[{col, row}] = 0;
    }
  return out;
}

// 120 x 60 px, step 50: centres (0,0), (50,0), (100,0), (30,50), (80,50), then (10,100),
// below the image: the last disk. Radius 0 reveals only the centre.
TEST(RasterDiskReveal, CentresStepAlongRowsAndTheLastIsBelowTheImage) {
  const asf::io::GrayImage g = filled(120, 60, 255);
  asf::evaluation::RasterDiskOptions o;
  o.radius_px = 0;
  o.min_free_px = 0;
  asf::evaluation::RasterDiskReveal reveal(g, 0.1, o);
  const std::vector<std::pair<int, int>> centres{{0, 0}, {50, 0}, {100, 0}, {30, 50}, {80, 50}};
  std::size_t published = 0;
  while (reveal.step()) {
    ++published;
    const asf::GridMap& m = reveal.map();
    EXPECT_EQ(m.version, published);
    EXPECT_FALSE(m.rebuilt);
    const auto known = knownPixels(m, g.width, g.height);
    ASSERT_EQ(known.size(), std::min<std::size_t>(published, centres.size()));
    for (std::size_t k = 0; k < known.size(); ++k) EXPECT_EQ(known.count(centres[k]), 1u) << k;
    if (published <= centres.size()) {
      // `changed` is the one pixel's cell: column c, grid row H-1-r.
      const auto [c, r] = centres[published - 1];
      EXPECT_DOUBLE_EQ(m.changed.min_x, c * 0.1);
      EXPECT_DOUBLE_EQ(m.changed.max_x, (c + 1) * 0.1);
      EXPECT_NEAR(m.changed.min_y, (59 - r) * 0.1, 1e-12);
      EXPECT_NEAR(m.changed.max_y, (60 - r) * 0.1, 1e-12);
    } else {
      EXPECT_TRUE(m.changed.empty());  // the disk below the image revealed nothing
    }
  }
  EXPECT_EQ(published, 6u);  // the sixth (below the image) is still published, as the author's
  EXPECT_EQ(reveal.disks(), 6u);
  EXPECT_DOUBLE_EQ(reveal.coverage(), 5.0 / (120 * 60));
  EXPECT_FALSE(reveal.step());  // and it stays over
}

// A disk of radius 2 at the corner (0,0): the pixels with dx^2 + dy^2 <= 4 inside the image,
// (0,0) (1,0) (2,0) (0,1) (1,1) (0,2); walls are revealed as walls.
TEST(RasterDiskReveal, ADiskIsThePixelsWithinTheRadiusWallsIncluded) {
  asf::io::GrayImage g = filled(10, 10, 255);
  g.pixels[1 * 10 + 1] = 0;  // (1,1) is a wall
  asf::evaluation::RasterDiskOptions o;
  o.radius_px = 2;
  o.step_px = 100;  // one disk on the image, the next below it
  o.min_free_px = 0;
  asf::evaluation::RasterDiskReveal reveal(g, 0.05, o);
  ASSERT_TRUE(reveal.step());
  const auto known = knownPixels(reveal.map(), 10, 10);
  const std::map<std::pair<int, int>, int> expected{{{0, 0}, 1}, {{1, 0}, 1}, {{2, 0}, 1},
                                                    {{0, 1}, 1}, {{1, 1}, 0}, {{0, 2}, 1}};
  EXPECT_EQ(known, expected);
  EXPECT_DOUBLE_EQ(reveal.coverage(), 5.0 / 99);
}

// No map is published while at most min_free_px free pixels are known; the first one then
// carries every pixel revealed so far, and its `changed` box covers them all.
TEST(RasterDiskReveal, NothingIsPublishedUntilEnoughFreePixelsAreKnown) {
  asf::io::GrayImage g = filled(120, 60, 0);
  g.pixels[50 * 120 + 80] = 255;  // the fifth centre is the one free pixel
  asf::evaluation::RasterDiskOptions o;
  o.radius_px = 0;
  o.min_free_px = 0;
  asf::evaluation::RasterDiskReveal reveal(g, 0.1, o);
  ASSERT_TRUE(reveal.step());
  EXPECT_EQ(reveal.disks(), 5u);
  const asf::GridMap& m = reveal.map();
  EXPECT_EQ(m.version, 1u);
  const auto known = knownPixels(m, 120, 60);
  EXPECT_EQ(known.size(), 5u);
  EXPECT_EQ(known.at({80, 50}), 1);
  EXPECT_EQ(known.at({30, 50}), 0);
  EXPECT_DOUBLE_EQ(m.changed.min_x, 0.0);  // from (0,0) ...
  EXPECT_DOUBLE_EQ(m.changed.max_x, 10.1);  // ... to (100,0), column 100 included
  EXPECT_NEAR(m.changed.min_y, 0.9, 1e-12);  // row 50 is grid row 9
  EXPECT_NEAR(m.changed.max_y, 6.0, 1e-12);  // row 0 is grid row 59
  EXPECT_DOUBLE_EQ(reveal.coverage(), 1.0);
  ASSERT_TRUE(reveal.step());  // the disk below the image
  EXPECT_FALSE(reveal.step());
  // With min_free_px = 1 the one free pixel is not enough: nothing is ever published.
  o.min_free_px = 1;
  asf::evaluation::RasterDiskReveal never(g, 0.1, o);
  EXPECT_FALSE(never.step());
  EXPECT_EQ(never.disks(), 6u);
}

TEST(RasterDiskReveal, BadOptionsAreErrors) {
  const asf::io::GrayImage g = filled(10, 10, 255);
  asf::evaluation::RasterDiskOptions o;
  o.step_px = 0;
  EXPECT_THROW(asf::evaluation::RasterDiskReveal(g, 0.05, o), asf::Error);
  o.step_px = 5;
  o.radius_px = -1;
  EXPECT_THROW(asf::evaluation::RasterDiskReveal(g, 0.05, o), asf::Error);
  EXPECT_THROW(asf::evaluation::RasterDiskReveal(g, 0.0), asf::Error);
}

fs::path writeDataset() {
  const fs::path d = fs::temp_directory_path() / "asf_test_raster_disk_reveal";
  fs::remove_all(d);
  for (const char* sub : {"plain", "gt", "furnished"}) fs::create_directories(d / sub);
  asf::io::GrayImage room = filled(240, 160, 0);
  for (int r = 10; r < 150; ++r)
    for (int c = 10; c < 230; ++c) room.pixels[static_cast<std::size_t>(r) * 240 + c] = 255;
  asf::io::writeGrayImage((d / "plain/a.png").string(), room);
  asf::io::writeGrayImage((d / "gt/a_gt_segmentation.png").string(), room);
  asf::io::writeGrayImage((d / "furnished/a_furnitures.png").string(), room);
  return d;
}

TEST(RasterDiskReveal, SegmentEvalRunsTheThesisProtocolOnPlainAndFurnishedMaps) {
  const fs::path d = writeDataset();
  const std::string args = "segment-eval --plain " + (d / "plain").string() + " --gt " +
                           (d / "gt").string() + " --resolution 0.05 --segmenter free_components";
  const std::string furnished = " --furnished " + (d / "furnished").string();
  const auto r = runHost(args + furnished + " --incremental --exploration raster_disks " +
                         "--incremental-on both --json " + (d / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream f(d / "out.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_EQ(j["exploration"], "raster_disks");
  ASSERT_EQ(j["maps"].size(), 2u);
  for (const auto& m : j["maps"]) {
    ASSERT_TRUE(m.contains("incremental")) << m["variant"];
    // 240 px wide, step 50: rows at y = 0, 50, 100, 150 take 5 centres each (x = 0..200,
    // 10..210, 20..220, 30..230), then (40, 200), below the image, ends it: 21 disks, all
    // published (the first one already reveals thousands of free pixels).
    EXPECT_EQ(m["incremental"]["updates"], 21);
    EXPECT_DOUBLE_EQ(m["incremental"]["coverage"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(m["incremental"]["path_length_m"].get<double>(), 0.0);
  }
  EXPECT_TRUE(j["summary"]["furnished"].contains("incremental"));
  EXPECT_TRUE(j["summary"]["plain"]["incremental"].contains("map_mean_ms_mean"));
  // Bad combinations name the option.
  const auto no_furnished = runHost(args + " --incremental --incremental-on both");
  EXPECT_EQ(no_furnished.code, 1);
  EXPECT_TRUE(has(no_furnished.out, "--incremental-on both needs --furnished")) << no_furnished.out;
  const auto no_incremental = runHost(args + " --exploration raster_disks");
  EXPECT_EQ(no_incremental.code, 1);
  EXPECT_TRUE(has(no_incremental.out, "--exploration needs --incremental")) << no_incremental.out;
  const auto unknown = runHost(args + " --incremental --exploration spiral");
  EXPECT_NE(unknown.code, 0);
  EXPECT_TRUE(has(unknown.out, "spiral")) << unknown.out;
}

}  // namespace
