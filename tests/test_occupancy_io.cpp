// The occupancy grid as map_server PNG + YAML (occupancy_io.h): a round trip keeps every
// cell and the frame; the YAML reader names the file and line of what it rejects.
#include <asf/errors.h>
#include <asf/occupancy_io.h>
#include <asf/segmentation_eval.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_occupancy_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// 7 x 5 cells at 0.1 m, lower-left corner at (-3.2, 1.5): free except an occupied column
/// (cx = 2) and an unknown cell (4, 3).
asf::GridMap smallMap() {
  auto g = std::make_shared<mrpt::maps::COccupancyGridMap2D>(-3.2f, -2.5f, 1.5f, 2.0f, 0.1f);
  for (unsigned cy = 0; cy < g->getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g->getSizeX(); ++cx) g->setCell(cx, cy, cx == 2 ? 0.0f : 1.0f);
  g->setCell(4, 3, 0.5f);
  asf::GridMap m;
  m.grid = g;
  m.version = 1;
  return m;
}

TEST(OccupancyIo, RoundTripKeepsTheCellsAndTheFrame) {
  const fs::path d = tempDir("roundtrip");
  const asf::GridMap m = smallMap();
  ASSERT_EQ(m.grid->getSizeX(), 7u);
  ASSERT_EQ(m.grid->getSizeY(), 5u);
  asf::writeOccupancyMap(m, (d / "occ").string());
  const asf::OccupancyMapInfo info = asf::readOccupancyYaml((d / "occ.yaml").string());
  EXPECT_EQ(info.image, "occ.png");
  EXPECT_NEAR(info.resolution, 0.1, 1e-7);
  EXPECT_NEAR(info.origin_x, -3.2, 1e-6);
  EXPECT_NEAR(info.origin_y, 1.5, 1e-6);
  // The image: row 0 is the top; free 255, occupied 0, unknown 128.
  const asf::GrayImage img = asf::readGrayImage((d / "occ.png").string());
  ASSERT_EQ(img.width, 7);
  ASSERT_EQ(img.height, 5);
  EXPECT_EQ(img.at(2, 0), 0);
  EXPECT_EQ(img.at(0, 4), 255);
  EXPECT_NEAR(img.at(4, 5 - 1 - 3), 128, 2);
  // Read back: same size and frame; free where it was free, unknown is not free.
  const asf::GridMap back = asf::readOccupancyMap((d / "occ.yaml").string());
  ASSERT_TRUE(back.grid);
  ASSERT_EQ(back.grid->getSizeX(), 7u);
  ASSERT_EQ(back.grid->getSizeY(), 5u);
  EXPECT_NEAR(back.grid->getXMin(), -3.2, 1e-6);
  EXPECT_NEAR(back.grid->getYMin(), 1.5, 1e-6);
  for (unsigned cy = 0; cy < 5; ++cy)
    for (unsigned cx = 0; cx < 7; ++cx) {
      const bool free = cx != 2 && !(cx == 4 && cy == 3);
      EXPECT_EQ(back.grid->getCell(cx, cy) > 0.5f, free) << cx << ", " << cy;
    }
  // A point in the map frame lands on the same cell: (-3.2 + 0.25, 1.5 + 0.35) is (2, 3).
  EXPECT_LT(back.grid->getPos(-2.95, 1.85), 0.5);
  EXPECT_GT(back.grid->getPos(-3.15, 1.85), 0.5);
}

std::string errorOf(const fs::path& d, const std::string& yaml) {
  const fs::path f = d / "bad.yaml";
  std::ofstream(f) << yaml;
  try {
    asf::readOccupancyYaml(f.string());
  } catch (const asf::InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(OccupancyIo, YamlErrorsNameTheFileAndLine) {
  const fs::path d = tempDir("errors");
  const std::string ok = "image: m.png\nresolution: 0.05\norigin: [1, 2, 0]\n";
  const std::string f = (d / "bad.yaml").string();
  EXPECT_EQ(errorOf(d, ok), "accepted");
  auto expect = [&](const std::string& yaml, const std::string& where, const std::string& what) {
    const std::string e = errorOf(d, yaml);
    EXPECT_NE(e.find(where), std::string::npos) << yaml << " -> " << e;
    EXPECT_NE(e.find(what), std::string::npos) << yaml << " -> " << e;
  };
  expect(ok + "colour: red\n", f + ":4", "unknown key 'colour'");
  expect(ok + "resolution: 0.1\n", f + ":4", "given twice");
  expect("image: m.png\nresolution: 0.05\n", f, "no 'origin'");
  expect("image: m.png\nresolution: five\norigin: [1, 2, 0]\n", f + ":2", "not a finite number");
  expect("image: m.png\nresolution: -1\norigin: [1, 2, 0]\n", f + ":2", "must be > 0");
  expect("image: m.png\nresolution: 0.05\norigin: [1, 2]\n", f + ":3", "three numbers");
  expect("image: m.png\nresolution: 0.05\norigin: [1, 2, 0.5]\n", f + ":3", "rotated map");
  expect(ok + "free_thresh: 1.5\n", f + ":4", "[0, 1]");
  expect(ok + "negate: 2\n", f + ":4", "negate");
  expect("image m.png\n", f + ":1", "key: value");
  // Fuzzing: an origin float cannot place cells at (MRPT asserted, uncaught).
  expect("image: m.png\nresolution: 0.05\norigin: [5777777777077777, -0.5, 0]\n", f + ":3",
         "more than 100 km from 0");
  EXPECT_THROW(asf::readOccupancyMap((d / "missing.yaml").string()), asf::InputError);
  // The image the YAML names must exist: the error names it.
  std::ofstream(d / "noimg.yaml") << ok;
  try {
    asf::readOccupancyMap((d / "noimg.yaml").string());
    FAIL() << "a missing image was accepted";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m.png"), std::string::npos) << e.what();
  }
}

TEST(OccupancyIo, OnlyKnownImageFormatsAreDecoded) {
  // OpenCV hands a file to any decoder that claims it; GDCM (DICOM) asserted, aborting the
  // process, on one starting "P\n" (fuzzing). asf decodes PNG, PNM, BMP, JPEG, TIFF only.
  const fs::path d = tempDir("formats");
  std::ofstream(d / "m.yaml") << "image: m.png\nresolution: 0.05\norigin: [1, 2, 0]\n";
  std::ofstream(d / "m.png", std::ios::binary) << "P\n" << std::string(64, '\xff');
  try {
    asf::readOccupancyMap((d / "m.yaml").string());
    FAIL() << "an unknown format was decoded";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "m.png: cannot be read as an image (not PNG, PGM/PPM/PBM, BMP, JPEG or TIFF)"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(d / "m.png", std::ios::binary) << "P2\n3 2\n255\n0 255 128\n255 254 0\n";
  EXPECT_EQ(asf::readOccupancyMap((d / "m.yaml").string()).grid->getSizeX(), 3u)
      << "a PGM under any name is read";
}

}  // namespace
