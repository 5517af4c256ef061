// The occupancy grid as map_server PNG + YAML (occupancy_io.h): a round trip keeps every
// cell and the frame; the YAML reader names the file and line of what it rejects.
#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/evaluation/segmentation_eval.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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
  asf::io::writeOccupancyMap(m, (d / "occ").string());
  const asf::io::OccupancyMapInfo info = asf::io::readOccupancyYaml((d / "occ.yaml").string());
  EXPECT_EQ(info.image, "occ.pgm");
  EXPECT_EQ(info.mode, asf::io::MapMode::Trinary);
  EXPECT_NEAR(info.resolution, 0.1, 1e-7);
  EXPECT_NEAR(info.origin_x, -3.2, 1e-6);
  EXPECT_NEAR(info.origin_y, 1.5, 1e-6);
  // The image (binary PGM, read by OpenCV): row 0 is the top; free 255, occupied 0, unknown 128.
  const asf::io::GrayImage img = asf::io::readGrayImage((d / "occ.pgm").string());
  ASSERT_EQ(img.width, 7);
  ASSERT_EQ(img.height, 5);
  EXPECT_EQ(img.at(2, 0), 0);
  EXPECT_EQ(img.at(0, 4), 255);
  EXPECT_NEAR(img.at(4, 5 - 1 - 3), 128, 2);
  // Read back: same size and frame; free where it was free, unknown is not free.
  const asf::GridMap back = asf::io::readOccupancyMap((d / "occ.yaml").string());
  ASSERT_TRUE(back.grid);
  ASSERT_EQ(back.grid->getSizeX(), 7u);
  ASSERT_EQ(back.grid->getSizeY(), 5u);
  EXPECT_NEAR(back.grid->getXMin(), -3.2, 1e-6);
  EXPECT_NEAR(back.grid->getYMin(), 1.5, 1e-6);
  for (unsigned cy = 0; cy < 5; ++cy)
    for (unsigned cx = 0; cx < 7; ++cx) {
      // free 1, occupied 0, unknown 0.5: neither (asf's consumers: free above 0.65)
      const float want = cx == 2 ? 0.0f : cx == 4 && cy == 3 ? 0.5f : 1.0f;
      EXPECT_NEAR(back.grid->getCell(cx, cy), want, 0.01) << cx << ", " << cy;
    }
  // A point in the map frame lands on the same cell: (-3.2 + 0.25, 1.5 + 0.35) is (2, 3).
  EXPECT_LT(back.grid->getPos(-2.95, 1.85), 0.5);
  EXPECT_GT(back.grid->getPos(-3.15, 1.85), 0.5);
}

std::string errorOf(const fs::path& d, const std::string& yaml) {
  const fs::path f = d / "bad.yaml";
  std::ofstream(f) << yaml;
  try {
    asf::io::readOccupancyYaml(f.string());
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
  expect(ok + "mode: fancy\n", f + ":4", "trinary, scale or raw");
  expect("image m.png\n", f + ":1", "key: value");
  // Fuzzing: an origin float cannot place cells at (MRPT asserted, uncaught).
  expect("image: m.png\nresolution: 0.05\norigin: [5777777777077777, -0.5, 0]\n", f + ":3",
         "more than 100 km from 0");
  EXPECT_THROW(asf::io::readOccupancyMap((d / "missing.yaml").string()), asf::InputError);
  // The image the YAML names must exist: the error names it.
  std::ofstream(d / "noimg.yaml") << ok;
  try {
    asf::io::readOccupancyMap((d / "noimg.yaml").string());
    FAIL() << "a missing image was accepted";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("m.png"), std::string::npos) << e.what();
  }
}

/// A 6 x 1 binary PGM written here (not by asf) with the gray levels 0, 50, 100, 205, 254, 255.
void writeGrayRow(const fs::path& f) {
  std::ofstream(f, std::ios::binary) << "P5\n6 1\n255\n"
                                     << std::string("\x00\x32\x64\xcd\xfe\xff", 6);
}

std::vector<float> cellsOf(const fs::path& d, const std::string& extra) {
  writeGrayRow(d / "row.pgm");
  std::ofstream(d / "row.yaml") << "image: row.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n"
                                << "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
                                << extra;
  const asf::GridMap m = asf::io::readOccupancyMap((d / "row.yaml").string());
  std::vector<float> v;
  for (unsigned cx = 0; cx < m.grid->getSizeX(); ++cx) v.push_back(m.grid->getCell(cx, 0));
  return v;
}

TEST(OccupancyIo, ModesClassifyPixelsAsMapServerDoes) {
  // occ = (255 - p) / 255 for 0, 50, 100, 205, 254, 255: 1, 0.804, 0.608, 0.196, 0.004, 0.
  const fs::path d = tempDir("modes");
  auto expect = [](const std::vector<float>& got, const std::vector<float>& want,
                   const char* mode) {
    ASSERT_EQ(got.size(), want.size()) << mode;
    for (std::size_t i = 0; i < want.size(); ++i)
      EXPECT_NEAR(got[i], want[i], 0.01) << mode << " pixel " << i;
  };
  // trinary: occupied above 0.65, free below 0.196, else unknown (0.196 itself is unknown).
  expect(cellsOf(d, ""), {0, 0, 0.5, 0.5, 1, 1}, "trinary");
  expect(cellsOf(d, "mode: trinary\n"), {0, 0, 0.5, 0.5, 1, 1}, "trinary");
  // scale: between the thresholds, occupancy (occ - 0.196) / (0.65 - 0.196), rounded to %:
  // 100 -> 0.608 -> 91 %; 205 -> 0.196 -> 0 % (p(free) 1 - occ).
  expect(cellsOf(d, "mode: scale\n"), {0, 0, 0.09f, 1, 1, 1}, "scale");
  // raw: the pixel is the occupancy in percent; above 100 unknown.
  expect(cellsOf(d, "mode: raw\n"), {1, 0.5f, 0, 0.5, 0.5, 0.5}, "raw");
  // negate: occ = p / 255: 0 free, 50 (0.196) unknown, 100 (0.39) unknown, 205+ occupied.
  expect(cellsOf(d, "negate: 1\n"), {1, 0.5, 0.5, 0, 0, 0}, "negate");
  // The class rule beside the percent rule.
  asf::io::OccupancyMapInfo info;
  EXPECT_EQ(asf::io::mapServerClass(info, 205), asf::io::MapCell::Unknown);
  EXPECT_EQ(asf::io::mapServerClass(info, 254), asf::io::MapCell::Free);
  EXPECT_EQ(asf::io::mapServerClass(info, 0), asf::io::MapCell::Occupied);
  info.mode = asf::io::MapMode::Raw;
  EXPECT_EQ(asf::io::mapServerClass(info, 100), asf::io::MapCell::Occupied);
  EXPECT_EQ(asf::io::mapServerClass(info, 10), asf::io::MapCell::Free);
  EXPECT_EQ(asf::io::mapServerClass(info, 101), asf::io::MapCell::Unknown);
  EXPECT_TRUE(asf::io::isOccupancyYaml("a/b.yaml"));
  EXPECT_TRUE(asf::io::isOccupancyYaml("b.yml"));
  EXPECT_FALSE(asf::io::isOccupancyYaml("b.yaml.png"));
}

TEST(OccupancyIo, OnlyKnownImageFormatsAreDecoded) {
  // OpenCV hands a file to any decoder that claims it; GDCM (DICOM) asserted, aborting the
  // process, on one starting "P\n" (fuzzing). asf decodes PNG, PNM, BMP, JPEG, TIFF only.
  const fs::path d = tempDir("formats");
  std::ofstream(d / "m.yaml") << "image: m.png\nresolution: 0.05\norigin: [1, 2, 0]\n";
  std::ofstream(d / "m.png", std::ios::binary) << "P\n" << std::string(64, '\xff');
  try {
    asf::io::readOccupancyMap((d / "m.yaml").string());
    FAIL() << "an unknown format was decoded";
  } catch (const asf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "m.png: cannot be read as an image (not PNG, PGM/PPM/PBM, BMP, JPEG or TIFF)"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(d / "m.png", std::ios::binary) << "P2\n3 2\n255\n0 255 128\n255 254 0\n";
  EXPECT_EQ(asf::io::readOccupancyMap((d / "m.yaml").string()).grid->getSizeX(), 3u)
      << "a PGM under any name is read";
}

}  // namespace
