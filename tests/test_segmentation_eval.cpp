// Room segmentation scoring (asf/evaluation/segmentation_eval.h): hand-computed precision, recall,
// pooled values and MCC; the benchmark's reading rules (thresholds, 8-connectivity, > 100 px);
// image orientation round trips; the simulated exploration; asf segment and asf segment-eval end to
// end on synthetic maps (and on ../shared's benchmark when present).
//
// The synthetic PNGs are written with asf::io::writeGrayImage (OpenCV inside the framework): this
// target does not link OpenCV itself.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/segmenter.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "test_util.h"

using asf::io::GrayImage;
using asf::io::LabelRaster;
using asf_test::has;
using asf_test::runHost;
namespace fs = std::filesystem;

namespace {

asf::io::LabelRaster raster(int w, int h, std::vector<std::int32_t> labels) {
  return asf::io::LabelRaster{w, h, std::move(labels)};
}

asf::io::LabelRaster filled(int w, int h, std::int32_t v = 0) {
  return raster(w, h, std::vector<std::int32_t>(static_cast<std::size_t>(w) * h, v));
}

/// Sets [c0, c1] x [r0, r1] (inclusive, image coordinates) to v.
void box(asf::io::LabelRaster& L, int c0, int r0, int c1, int r1, std::int32_t v) {
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) L.labels[static_cast<std::size_t>(r) * L.width + c] = v;
}
void box(asf::io::GrayImage& g, int c0, int r0, int c1, int r1, std::uint8_t v) {
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) g.pixels[static_cast<std::size_t>(r) * g.width + c] = v;
}

asf::io::GrayImage blank(int w, int h, std::uint8_t v = 0) {
  return asf::io::GrayImage{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h, v)};
}

fs::path tempDir(const std::string& test) {
  const fs::path d = fs::temp_directory_path() / "asf_test_segmentation_eval" / test;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// 50 x 30 px: room A (cols 2..21, rows 2..21) and room B (cols 24..43, rows 2..21), 400 px
/// each, joined by a 2 x 2 px door (cols 22..23, rows 10..11); 804 free pixels.
asf::io::GrayImage twoRoomsMap() {
  asf::io::GrayImage g = blank(50, 30, 0);
  box(g, 2, 2, 21, 21, 255);
  box(g, 24, 2, 43, 21, 255);
  box(g, 22, 10, 23, 11, 254);  // >= 250 counts as free
  return g;
}

/// Its ground truth: the door closed by a separator line.
asf::io::GrayImage twoRoomsGt() {
  asf::io::GrayImage g = twoRoomsMap();
  box(g, 22, 10, 23, 11, 0);
  return g;
}

std::shared_ptr<const asf::framework::PluginInfo> freeComponents() {
  static auto i =
      asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/segmenter_free_components.so");
  return i;
}

asf::framework::PluginHandle<asf::Segmenter> makeFreeComponents(
    const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Segmenter>(freeComponents());
  h->configure(asf::Params::fromSpecs("free_components", freeComponents()->descriptor->keys,
                                      freeComponents()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json readJson(const fs::path& p) {
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

}  // namespace

// The thesis' scoring on a 13 x 7 map, worked by hand: a wall at column 6 splits two rooms.
// Eroded once (the image border counts as wall) and dilated back, the rooms are columns
// 0-5 and 7-12 (42 px each); column 6 belongs to none. Segments: 1 = columns 0-3, 2 = 4-9,
// 3 = 10-12. Per room (thesis "precision"): left 28/42 = 66.7 -> 66 %, right 21/42 = 50 %.
// Per segment (thesis "recall"), on pixels that are in a room: 28/28, 21/35 (column 6 does not
// count), 21/21 -> 100, 60, 100 %.
TEST(SegmentationEvalThesis, ScoresAsTheAuthorsCodeDoes) {
  asf::io::GrayImage gt;
  gt.width = 13;
  gt.height = 7;
  gt.pixels.assign(13 * 7, 255);
  for (int r = 0; r < 7; ++r) gt.pixels[r * 13 + 6] = 0;
  asf::io::LabelRaster seg;
  seg.width = 13;
  seg.height = 7;
  seg.labels.resize(13 * 7);
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 13; ++c) seg.labels[r * 13 + c] = c <= 3 ? 1 : (c <= 9 ? 2 : 3);
  const asf::evaluation::ThesisProtocolScore s = asf::evaluation::scoreThesisProtocol(seg, gt);
  EXPECT_EQ(s.rooms, 2);
  EXPECT_EQ(s.segments, 3);
  EXPECT_NEAR(s.precision, (0.66 + 0.50) / 2, 1e-12);
  EXPECT_NEAR(s.recall, (1.0 + 0.60 + 1.0) / 3, 1e-12);
  asf::io::LabelRaster small = seg;
  small.width = 12;
  EXPECT_THROW(asf::evaluation::scoreThesisProtocol(small, gt), asf::Error);
}

TEST(SegmentationEvalScore, HandComputedExample) {
  // GT rooms (3 x 2 image):   segmentation:
  //   A A A                     1 1 2
  //   B B B                     2 2 0
  // |A| = |B| = 3, |s1| = 2, |s2| = 3; O[s1] = {A: 2, B: 0}, O[s2] = {A: 1, B: 2}.
  // precision: s1 = 2/2 = 1, s2 = 2/3 -> mean 5/6; pooled (2 + 2) / (2 + 3) = 4/5.
  // recall: A = max(2, 1)/3 = 2/3, B = 2/3 -> mean 2/3; pooled (2 + 2) / 6 = 2/3.
  // MCC over the C(6, 2) = 15 pixel pairs (all 6 pixels are in a room; the unlabelled one is a
  // segment of its own): same segment C(2,2) + C(3,2) = 4, same room 3 + 3 = 6,
  // TP = C(2,2) [s1 n A] + C(1,2) [s2 n A] + C(2,2) [s2 n B] = 2, FP = 4 - 2 = 2,
  // FN = 6 - 2 = 4, TN = 15 - 4 - 6 + 2 = 7:
  // MCC = (2*7 - 2*4) / sqrt((2+2)(2+4)(7+2)(7+4)) = 6 / sqrt(2376).
  const auto rooms = raster(3, 2, {1, 1, 1, 2, 2, 2});
  const auto seg = raster(3, 2, {1, 1, 2, 2, 2, 0});
  const auto s = asf::evaluation::scoreSegmentation(seg, rooms, 0);
  EXPECT_EQ(s.segments, 2);
  EXPECT_EQ(s.rooms, 2);
  EXPECT_DOUBLE_EQ(s.precision, 5.0 / 6.0);
  EXPECT_DOUBLE_EQ(s.precision_pooled, 4.0 / 5.0);
  EXPECT_DOUBLE_EQ(s.recall, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall_pooled, 2.0 / 3.0);
  EXPECT_NEAR(s.mcc, 6.0 / std::sqrt(2376.0), 1e-12);
  ASSERT_EQ(s.segment_precision.size(), 2u);
  EXPECT_DOUBLE_EQ(s.segment_precision[0], 1.0);
  EXPECT_DOUBLE_EQ(s.segment_precision[1], 2.0 / 3.0);
  // A perfect segmentation (other label values) scores 1 everywhere.
  const auto perfect =
      asf::evaluation::scoreSegmentation(raster(3, 2, {7, 7, 7, 9, 9, 9}), rooms, 0);
  EXPECT_DOUBLE_EQ(perfect.precision, 1);
  EXPECT_DOUBLE_EQ(perfect.recall, 1);
  EXPECT_DOUBLE_EQ(perfect.mcc, 1);
}

TEST(SegmentationEvalScore, UnlabelledFreePixelsLowerRecallOnly) {
  auto rooms = filled(30, 30);
  box(rooms, 0, 0, 19, 19, 1);  // 400 px
  auto seg = filled(30, 30);
  box(seg, 0, 0, 19, 14, 5);  // 300 px of it, the rest unlabelled
  const auto s = asf::evaluation::scoreSegmentation(seg, rooms);
  EXPECT_DOUBLE_EQ(s.precision, 1);
  EXPECT_DOUBLE_EQ(s.recall, 0.75);
  EXPECT_DOUBLE_EQ(s.recall_pooled, 0.75);
  // Pairs: U = 400 px; same room C(400,2) = 79800, same segment = TP = C(300,2) = 44850,
  // FP = 0, FN = 34950, TN = 0 -> a zero factor: MCC 0 (not 1: FN > 0).
  EXPECT_DOUBLE_EQ(s.mcc, 0);
}

TEST(SegmentationEvalScore, RegionsOfAtMost100PixelsAreIgnored) {
  auto rooms = filled(40, 40);
  box(rooms, 0, 0, 19, 19, 1);    // 400 px
  box(rooms, 0, 30, 9, 39, 2);    // 100 px: not a room
  box(rooms, 30, 0, 39, 9, 3);    // 100 px
  box(rooms, 30, 10, 30, 10, 3);  // + 1 = 101 px: a room
  auto seg = filled(40, 40);
  box(seg, 0, 0, 19, 19, 1);
  box(seg, 0, 30, 9, 39, 2);    // 100 px, perfect on the ignored room: ignored
  box(seg, 21, 21, 30, 30, 4);  // 100 px straddling nothing: ignored (would have precision 0)
  const auto s = asf::evaluation::scoreSegmentation(seg, rooms);
  EXPECT_EQ(s.segments, 1);
  EXPECT_EQ(s.rooms, 2);
  EXPECT_DOUBLE_EQ(s.precision, 1);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);  // room 3 has no segment
  // 101 px counts.
  box(seg, 31, 21, 31, 21, 4);  // segment 4 grows to 101 px
  const auto s2 = asf::evaluation::scoreSegmentation(seg, rooms);
  EXPECT_EQ(s2.segments, 2);
  EXPECT_DOUBLE_EQ(s2.precision, 0.5);  // (1 + 0) / 2
}

TEST(SegmentationEvalScore, OverAndUnderSegmentation) {
  auto rooms = filled(40, 20);
  box(rooms, 0, 0, 19, 19, 1);
  box(rooms, 20, 0, 39, 19, 2);
  // Over-segmentation: every room split in two halves -> precision 1, recall 1/2.
  auto over = filled(40, 20);
  box(over, 0, 0, 9, 19, 1);
  box(over, 10, 0, 19, 19, 2);
  box(over, 20, 0, 29, 19, 3);
  box(over, 30, 0, 39, 19, 4);
  const auto o = asf::evaluation::scoreSegmentation(over, rooms);
  EXPECT_EQ(o.segments, 4);
  EXPECT_DOUBLE_EQ(o.precision, 1);
  EXPECT_DOUBLE_EQ(o.recall, 0.5);
  EXPECT_DOUBLE_EQ(o.recall_pooled, 0.5);
  // Under-segmentation: one segment over both rooms -> precision 1/2, recall 1.
  const auto u = asf::evaluation::scoreSegmentation(filled(40, 20, 8), rooms);
  EXPECT_EQ(u.segments, 1);
  EXPECT_DOUBLE_EQ(u.precision, 0.5);
  EXPECT_DOUBLE_EQ(u.recall, 1);
  // Either mistake costs MCC; a half-way split is better than merging everything.
  EXPECT_GT(o.mcc, 0);
  EXPECT_LT(o.mcc, 1);
  EXPECT_DOUBLE_EQ(u.mcc, 0);
  // Sizes must match.
  EXPECT_TRUE(has(asf_test::errorOf<asf::Error>(
                      [&] { asf::evaluation::scoreSegmentation(filled(10, 10), rooms); }),
                  "10 x 10"));
}

TEST(SegmentationEval, GroundTruthRoomsAre8ConnectedAndLargerThan100Pixels) {
  asf::io::GrayImage gt = blank(40, 40, 0);
  box(gt, 0, 0, 9, 9, 251);      // 100 px ...
  box(gt, 10, 10, 19, 19, 255);  // ... touching this 100 px block at a corner: one room of 200
  box(gt, 30, 30, 39, 39, 255);  // 100 px alone: dropped
  box(gt, 25, 0, 39, 9, 250);    // 250 is not > 250: not a room
  const asf::io::LabelRaster rooms = asf::evaluation::groundTruthRooms(gt);
  std::set<std::int32_t> ids(rooms.labels.begin(), rooms.labels.end());
  EXPECT_EQ(ids, (std::set<std::int32_t>{0, 1}));
  EXPECT_EQ(rooms.at(0, 0), 1);
  EXPECT_EQ(rooms.at(19, 19), 1);
  EXPECT_EQ(rooms.at(35, 35), 0);
  EXPECT_EQ(rooms.at(30, 5), 0);
}

TEST(SegmentationEval, MeanStdAndPercentile) {
  const auto m = asf::meanStd({1, 2, 3, 4});
  EXPECT_DOUBLE_EQ(m.mean, 2.5);
  EXPECT_DOUBLE_EQ(m.std, std::sqrt(1.25));  // population std
  EXPECT_DOUBLE_EQ(asf::percentile({5, 1, 4, 2, 3}, 50), 3);
  EXPECT_DOUBLE_EQ(asf::percentile({5, 1, 4, 2, 3}, 95), 5);
  EXPECT_DOUBLE_EQ(asf::percentile({5, 1, 4, 2, 3}, 0), 1);
  EXPECT_DOUBLE_EQ(asf::percentile({}, 50), 0);
}

TEST(SegmentationEval, ImageRowZeroIsTheTopOfTheGrid) {
  // Free pixel at the top-left corner only.
  asf::io::GrayImage img = blank(4, 3, 0);
  img.pixels[0] = 255;
  const asf::GridMap map = asf::io::gridFromImage(img, 0.5);
  ASSERT_TRUE(map.grid);
  EXPECT_EQ(map.version, 1u);
  // The grid's cell (0, 2) (top row, y up) is the free one: the image comes back unchanged.
  const asf::io::GrayImage back = asf::io::imageFromGrid(map);
  ASSERT_EQ(back.width, 4);
  ASSERT_EQ(back.height, 3);
  EXPECT_GE(back.at(0, 0), 250);
  for (std::size_t i = 1; i < back.pixels.size(); ++i) EXPECT_LE(back.pixels[i], 5) << i;
  // Labels of the free_components segmenter on it: cell (0, 2) is labelled.
  auto seg = makeFreeComponents({{"min_area", "0"}});
  const asf::Segmentation s = seg->segment(map, nullptr);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_GT(s.labels.at(0, 2), 0);
  EXPECT_EQ(asf::evaluation::toRaster(s.labels).labels[0], s.labels.at(0, 2));
  // Raster <-> grid labels round trip, with the flip.
  const auto r = raster(4, 3, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
  const asf::LabelImage L = asf::evaluation::fromRaster(r, 0.5, 1.0, 2.0);
  EXPECT_EQ(L.at(0, 2), 1);
  EXPECT_EQ(L.at(3, 0), 12);
  EXPECT_EQ(L.atPoint(1.1, 2.1), 9);  // bottom-left cell
  EXPECT_EQ(asf::evaluation::toRaster(L).labels, r.labels);
}

TEST(SegmentationEval, LabelAndGrayPngRoundTripAndErrors) {
  const fs::path d = tempDir("png");
  auto r = filled(5, 4);
  r.labels[1] = 1;
  r.labels[7] = 300;  // needs 16 bits
  r.labels[19] = 65535;
  asf::io::writeLabelImage((d / "l.png").string(), r);
  const auto back = asf::io::readLabelImage((d / "l.png").string());
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 4);
  EXPECT_EQ(back.labels, r.labels);
  r.labels[0] = 65536;
  EXPECT_TRUE(has(
      asf_test::errorOf<asf::Error>([&] { asf::io::writeLabelImage((d / "big.png").string(), r); }),
      "65536"));
  const asf::io::GrayImage g = twoRoomsMap();
  asf::io::writeGrayImage((d / "g.png").string(), g);
  EXPECT_EQ(asf::io::readGrayImage((d / "g.png").string()).pixels, g.pixels);
  EXPECT_TRUE(has(asf_test::errorOf<asf::InputError>(
                      [&] { asf::io::readGrayImage((d / "missing.png").string()); }),
                  "missing.png: no such file"));
  std::ofstream(d / "bad.png") << "not a png";
  EXPECT_TRUE(has(
      asf_test::errorOf<asf::InputError>([&] { asf::io::readGrayImage((d / "bad.png").string()); }),
      "bad.png: cannot be read"));
}

TEST(SegmentationEvalSegmentCommand, EndToEndOnASyntheticMap) {
  const fs::path d = tempDir("segment");
  asf::io::GrayImage g = twoRoomsMap();
  box(g, 2, 25, 13, 27, 255);  // a 36 px strip near the bottom-left: a third component
  asf::io::writeGrayImage((d / "map.png").string(), g);
  const auto r = runHost("segment " + (d / "map.png").string() +
                         " --resolution 0.05 --segmenter free_components --set min_area=0 -o " +
                         (d / "labels.png").string() + " --graph " + (d / "graph.json").string() +
                         " --overlay " + (d / "overlay.png").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "2 regions")) << r.out;
  const asf::io::LabelRaster labels = asf::io::readLabelImage((d / "labels.png").string());
  ASSERT_EQ(labels.width, g.width);
  ASSERT_EQ(labels.height, g.height);
  // Same orientation as the input: labelled exactly where the input is free.
  for (int row = 0; row < g.height; ++row)
    for (int col = 0; col < g.width; ++col)
      ASSERT_EQ(labels.at(col, row) > 0, g.at(col, row) >= 250) << col << "," << row;
  EXPECT_EQ(labels.at(3, 3), labels.at(30, 3));  // the rooms joined by the door
  EXPECT_NE(labels.at(3, 26), labels.at(3, 3));  // the strip at the bottom
  EXPECT_GT(labels.at(3, 26), 0);
  const auto j = readJson(d / "graph.json");
  ASSERT_EQ(j["nodes"].size(), 3u);  // 2 regions + unexplored
  // Node centroids are in map coordinates, y up: the strip (rows 25..27 of 30) is low.
  for (const auto& n : j["nodes"])
    if (n["region"] == labels.at(3, 26)) {
      // MRPT keeps the resolution as a float: metres carry ~1e-8 of rounding.
      EXPECT_NEAR(n["centroid"][1].get<double>(), (30 - 26 - 0.5) * 0.05, 1e-6);
      EXPECT_NEAR(n["area_m2"].get<double>(), 36 * 0.0025, 1e-6);
    }
  EXPECT_TRUE(j["edges"].is_array());
  EXPECT_TRUE(fs::file_size(d / "overlay.png") > 0);
  // The same overlay as SVG: the raster regions embedded, one vector node per region.
  const auto rs =
      runHost("segment " + (d / "map.png").string() +
              " --resolution 0.05 --segmenter free_components --set min_area=0 -o " +
              (d / "labels2.png").string() + " --overlay " + (d / "overlay.svg").string());
  ASSERT_EQ(rs.code, 0) << rs.out;
  std::ifstream svg_in(d / "overlay.svg");
  const std::string svg((std::istreambuf_iterator<char>(svg_in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_TRUE(has(svg, "data:image/png;base64,"));
  std::size_t circles = 0;
  for (std::size_t at = svg.find("<circle"); at != std::string::npos;
       at = svg.find("<circle", at + 1))
    ++circles;
  EXPECT_EQ(circles, 2u) << "one node per region, none current";
  EXPECT_TRUE(has(svg, "</svg>"));
  // Errors name the file / plugin.
  const auto missing = runHost("segment " + (d / "nope.png").string() +
                               " --segmenter free_components -o " + (d / "x.png").string());
  EXPECT_EQ(missing.code, 1);
  EXPECT_TRUE(has(missing.out, "nope.png: no such file")) << missing.out;
  const auto unknown = runHost("segment " + (d / "map.png").string() +
                               " --segmenter no_such_segmenter -o " + (d / "x.png").string());
  EXPECT_EQ(unknown.code, 1);
  EXPECT_TRUE(has(unknown.out, "no_such_segmenter")) << unknown.out;
}

TEST(SegmentationEvalSegmentCommand, FrontierEdgesAndTopologyKeys) {
  // Room A reaches the image's left edge over rows 2..21 (beyond the grid = unexplored):
  // one frontier edge 20 px = 1 m wide, through the centres of column 0.
  const fs::path d = tempDir("segment_topology");
  asf::io::GrayImage g = twoRoomsGt();  // door closed: two components, no shared border
  box(g, 0, 2, 1, 21, 255);
  asf::io::writeGrayImage((d / "map.png").string(), g);
  const std::string base = "segment " + (d / "map.png").string() +
                           " --segmenter free_components -o " + (d / "l.png").string() +
                           " --graph " + (d / "g.json").string();
  const auto r = runHost(base);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto labels = asf::io::readLabelImage((d / "l.png").string());
  auto j = readJson(d / "g.json");
  EXPECT_EQ(j["nodes"].size(), 3u);
  ASSERT_EQ(j["edges"].size(), 1u) << j.dump();
  const auto& e = j["edges"][0];
  EXPECT_TRUE(e["frontier"].get<bool>());
  EXPECT_EQ(e["a"], labels.at(0, 2));
  EXPECT_EQ(e["b"], -1);
  EXPECT_NEAR(e["width_m"].get<double>(), 1.0, 1e-6);  // float resolution in MRPT
  EXPECT_NEAR(e["midpoint"][0].get<double>(), 0.025, 1e-6);
  EXPECT_NEAR(e["midpoint"][1].get<double>(), 0.9, 1e-6);  // cy 8..27, y up
  // The threshold is a topology key.
  ASSERT_EQ(runHost(base + " --set topology.min_frontier_width=1.5").code, 0);
  EXPECT_EQ(readJson(d / "g.json")["edges"].size(), 0u);
  const auto bad = runHost(base + " --set topology.no_such_key=1");
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "no_such_key")) << bad.out;
}

TEST(SegmentationEval, TopologyJsonShape) {
  asf::TopoGraph t;
  asf::TopoNode n1, n2, u;
  n1.region = 1, n1.centroid = {1, 2}, n1.area = 3;
  n2.region = 2;
  u.region = asf::kUnexplored;
  t.nodes = {n1, n2, u};
  asf::TopoEdge e;
  e.a = 1, e.b = 2, e.midpoint = {1.5, 2.5}, e.width = 0.9;
  e.traversals.push_back({true, 4.0});
  t.edges = {e};
  const auto j = nlohmann::json::parse(asf::graph::topologyJson(t));
  ASSERT_EQ(j["nodes"].size(), 3u);
  EXPECT_EQ(j["nodes"][0]["region"], 1);
  EXPECT_EQ(j["nodes"][0]["centroid"], nlohmann::json({1.0, 2.0}));
  EXPECT_EQ(j["nodes"][0]["area_m2"], 3.0);
  EXPECT_EQ(j["nodes"][2]["region"], -1);
  ASSERT_EQ(j["edges"].size(), 1u);
  EXPECT_EQ(j["edges"][0]["a"], 1);
  EXPECT_EQ(j["edges"][0]["b"], 2);
  EXPECT_FALSE(j["edges"][0]["frontier"].get<bool>());
  EXPECT_EQ(j["edges"][0]["width_m"], 0.9);
  EXPECT_EQ(j["edges"][0]["traversals"][0]["time_s"], 4.0);
}

namespace {

/// plain/{a,b}.png, gt/{a,b}_gt_segmentation.png, furnished/{a,b}_furnitures.png:
/// a = twoRoomsMap (one free component over two GT rooms), b = one room alone; a's furnished
/// version has a 5 x 5 px table in room A.
fs::path writeDataset(const std::string& test) {
  const fs::path d = tempDir(test);
  for (const char* sub : {"plain", "gt", "furnished"}) fs::create_directories(d / sub);
  asf::io::writeGrayImage((d / "plain/a.png").string(), twoRoomsMap());
  asf::io::writeGrayImage((d / "gt/a_gt_segmentation.png").string(), twoRoomsGt());
  asf::io::GrayImage furnished = twoRoomsMap();
  box(furnished, 5, 5, 9, 9, 120);
  asf::io::writeGrayImage((d / "furnished/a_furnitures.png").string(), furnished);
  asf::io::GrayImage b = blank(30, 30, 0);
  box(b, 5, 5, 24, 24, 255);
  asf::io::writeGrayImage((d / "plain/b.png").string(), b);
  asf::io::writeGrayImage((d / "gt/b_gt_segmentation.png").string(), b);
  asf::io::writeGrayImage((d / "furnished/b_furnitures.png").string(), b);
  return d;
}

std::string evalArgs(const fs::path& d, bool furnished = true) {
  return "segment-eval --plain " + (d / "plain").string() + " --gt " + (d / "gt").string() +
         (furnished ? " --furnished " + (d / "furnished").string() : std::string()) +
         " --resolution 0.05 --segmenter free_components";
}

}  // namespace

TEST(SegmentationEvalCommand, ScoresEveryMapAsTheProtocolSays) {
  const fs::path d = writeDataset("eval");
  const auto r = runHost(evalArgs(d) + " --json " + (d / "out.json").string() + " --images " +
                         (d / "img").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "[1/2] a plain")) << r.out;  // progress
  EXPECT_TRUE(has(r.out, "summary plain (2 maps)")) << r.out;
  const auto j = readJson(d / "out.json");
  EXPECT_TRUE(j["complete"].get<bool>());
  ASSERT_EQ(j["maps"].size(), 4u);
  // a, plain: one 804 px segment (rooms of 400 px and the 4 px door) over two 400 px rooms.
  const auto& ap = j["maps"][0];
  EXPECT_EQ(ap["name"], "a");
  EXPECT_EQ(ap["variant"], "plain");
  EXPECT_EQ(ap["segments"], 1);
  EXPECT_DOUBLE_EQ(ap["precision"].get<double>(), 400.0 / 804.0);
  EXPECT_DOUBLE_EQ(ap["recall"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ap["recall_pooled"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ap["mcc"].get<double>(), 0.0);  // every pair "same": TN = FN = 0
  EXPECT_GE(ap["time_ms"].get<double>(), 0.0);
  // a, furnished: the 25 px table leaves 779 px; room A keeps 375 of its 400 px.
  const auto& af = j["maps"][1];
  EXPECT_EQ(af["variant"], "furnished");
  EXPECT_DOUBLE_EQ(af["precision"].get<double>(), 400.0 / 779.0);
  EXPECT_DOUBLE_EQ(af["recall"].get<double>(), (375.0 / 400.0 + 1.0) / 2);
  EXPECT_DOUBLE_EQ(af["recall_pooled"].get<double>(), 775.0 / 800.0);
  // b is segmented perfectly.
  const auto& bp = j["maps"][2];
  EXPECT_EQ(bp["name"], "b");
  EXPECT_DOUBLE_EQ(bp["precision"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(bp["mcc"].get<double>(), 1.0);
  // Summary: mean and population std over the maps of a variant.
  const auto& sp = j["summary"]["plain"];
  EXPECT_EQ(sp["maps"], 2);
  EXPECT_DOUBLE_EQ(sp["precision_mean"].get<double>(), (400.0 / 804.0 + 1) / 2);
  EXPECT_NEAR(sp["precision_std"].get<double>(), (1 - 400.0 / 804.0) / 2, 1e-12);
  EXPECT_DOUBLE_EQ(sp["recall_std"].get<double>(), 0.0);
  EXPECT_TRUE(j["summary"].contains("furnished"));
  for (const char* f : {"a_plain.png", "a_furnished.png", "b_plain_labels.png"})
    EXPECT_TRUE(fs::exists(d / "img" / f)) << f;
  // The label images are in the input's orientation and score the same.
  const auto labels = asf::io::readLabelImage((d / "img/a_plain_labels.png").string());
  const auto rooms = asf::evaluation::groundTruthRooms(
      asf::io::readGrayImage((d / "gt/a_gt_segmentation.png").string()));
  EXPECT_DOUBLE_EQ(asf::evaluation::scoreSegmentation(labels, rooms).precision, 400.0 / 804.0);
  // --set reaches the segmenter: min_area above every component leaves no segment.
  const auto none =
      runHost(evalArgs(d, false) + " --set min_area=100 --json " + (d / "none.json").string());
  ASSERT_EQ(none.code, 0) << none.out;
  EXPECT_EQ(readJson(d / "none.json")["maps"][0]["segments"], 0);
  EXPECT_DOUBLE_EQ(readJson(d / "none.json")["maps"][0]["recall"].get<double>(), 0.0);
  const auto topo = runHost(evalArgs(d, false) + " --set topology.min_border_width=1");
  EXPECT_EQ(topo.code, 1);
  EXPECT_TRUE(has(topo.out, "no topological graph here")) << topo.out;
}

// A benchmark map given as a ROS map_server map (plain/a.yaml naming its image, with its own
// resolution and origin) scores as the same pixels given as a PNG.
TEST(SegmentationEvalCommand, AMapServerMapScoresAsItsImage) {
  const fs::path d = writeDataset("eval_yaml");
  const auto png = runHost(evalArgs(d, false) + " --json " + (d / "png.json").string());
  ASSERT_EQ(png.code, 0) << png.out;
  fs::rename(d / "plain/a.png", d / "plain/a_image.png");
  std::ofstream(d / "plain/a.yaml") << "image: a_image.png\nresolution: 0.1\n"
                                    << "origin: [2.0, -3.0, 0.0]\nnegate: 0\n"
                                    << "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  const auto yaml = runHost(evalArgs(d, false) + " --json " + (d / "yaml.json").string());
  ASSERT_EQ(yaml.code, 0) << yaml.out;
  const auto a = readJson(d / "png.json")["maps"], b = readJson(d / "yaml.json")["maps"];
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (const char* k : {"name", "segments", "precision", "recall", "mcc"})
    for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(a[i][k], b[i][k]) << k << " " << i;
  // Only the map's frame came from the YAML: "a" alone with --map finds it by its stem.
  const auto one = runHost(evalArgs(d, false) + " --map a");
  EXPECT_EQ(one.code, 0) << one.out;
}

// segment-report: the thesis' Table 4.1 beside every report, both protocols, and the figures.
TEST(SegmentReportCommand, TableAndFiguresFromTwoReports) {
  const fs::path d = writeDataset("report41");
  const auto r = runHost(evalArgs(d) + " --incremental --json " + (d / "a.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "summary plain thesis protocol")) << r.out;
  const auto ev = readJson(d / "a.json");
  // b is segmented perfectly under the thesis' protocol too.
  EXPECT_DOUBLE_EQ(ev["maps"][2]["thesis_protocol"]["precision"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ev["maps"][2]["thesis_protocol"]["recall"].get<double>(), 1.0);
  EXPECT_FALSE(ev["maps"][0]["incremental"]["update_ms"].empty());
  const auto rep = runHost("segment-report " + (d / "a.json").string() + " " +
                           (d / "a.json").string() + " -l one -l two -o " + (d / "rep").string());
  ASSERT_EQ(rep.code, 0) << rep.out;
  const auto t = readJson(d / "rep/table_4_1.json");
  ASSERT_EQ(t["rows"].size(), 4u);
  for (const auto& row : t["rows"]) {
    EXPECT_EQ(row["thesis"]["dude_batch"].size(), 2u);  // mean, std
    ASSERT_EQ(row["asf"].size(), 2u);
    EXPECT_EQ(row["asf"][1]["label"], "two");
    for (const char* k : {"thesis_protocol", "roomseg"})
      EXPECT_EQ(row["asf"][0][k].size(), 2u) << k;
    // Incremental runs exist for the plain maps only.
    EXPECT_EQ(row["asf"][0]["thesis_protocol_incremental"].is_null(),
              row["scenario"] == "furnished");
  }
  // The plain recall row of the thesis is 86.3 +- 9.7 (Table 4.1).
  EXPECT_DOUBLE_EQ(t["rows"][0]["thesis"]["dude_batch"][0].get<double>(), 86.3);
  const std::string md = readText(d / "rep/table_4_1.md");
  EXPECT_TRUE(
      has(md, "| no furniture | recall (per segment) | 95.0 ± 2.3 | 86.3 ± 9.7 | 87.5 ± 10.7 |"))
      << md;
  for (const char* f : {"fig4_1_precision.svg", "fig4_1_recall.svg", "fig4_2_batch_time.svg",
                        "fig4_2_incremental_time.svg"})
    EXPECT_TRUE(has(readText(d / "rep" / f), "<svg")) << f;
  // Bad input: named, non-zero exit.
  std::ofstream(d / "bad.json") << "{not json";
  const auto bad =
      runHost("segment-report " + (d / "bad.json").string() + " -o " + (d / "x").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(has(bad.out, "bad.json")) << bad.out;
  const auto labels =
      runHost("segment-report " + (d / "a.json").string() + " -l a -l b -o " + (d / "x").string());
  EXPECT_EQ(labels.code, 1);
  EXPECT_TRUE(has(labels.out, "--label")) << labels.out;
}

TEST(SegmentationEvalCommand, AMissingFileIsNamedAndEarlierMapsAreKept) {
  const fs::path d = writeDataset("eval_missing");
  fs::remove(d / "gt/b_gt_segmentation.png");
  const auto r = runHost(evalArgs(d) + " --json " + (d / "out.json").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "b_gt_segmentation.png: no such file")) << r.out;
  EXPECT_TRUE(has(r.out, "summary plain (1 maps)")) << r.out;
  const auto j = readJson(d / "out.json");
  EXPECT_FALSE(j["complete"].get<bool>());
  EXPECT_TRUE(has(j["error"].get<std::string>(), "b_gt_segmentation.png"));
  ASSERT_EQ(j["maps"].size(), 2u);  // a plain and a furnished
  EXPECT_EQ(j["maps"][0]["name"], "a");
  // A malformed furnished map is named too.
  std::ofstream(d / "furnished/a_furnitures.png", std::ios::trunc) << "garbage";
  const auto m = runHost(evalArgs(d));
  EXPECT_EQ(m.code, 1);
  EXPECT_TRUE(has(m.out, "a_furnitures.png: cannot be read as an image")) << m.out;
  // Unknown segmenter: the registry's message lists what exists.
  const auto u = runHost("segment-eval --plain " + (d / "plain").string() + " --gt " +
                         (d / "gt").string() + " --segmenter no_such_one");
  EXPECT_EQ(u.code, 1);
  EXPECT_TRUE(has(u.out, "no_such_one")) << u.out;
}

// ---------------------------------------------------------------- exploration -------------

namespace {

/// 120 x 60 px at 0.1 m (12 m x 6 m): three rooms along a corridor, so a 5 m laser cannot see
/// everything from the start.
asf::io::GrayImage officeMap() {
  asf::io::GrayImage g = blank(120, 60, 0);
  box(g, 2, 25, 117, 34, 255);  // corridor
  for (int k = 0; k < 3; ++k) {
    box(g, 2 + 40 * k, 2, 36 + 40 * k, 22, 255);    // rooms above
    box(g, 15 + 40 * k, 23, 20 + 40 * k, 24, 255);  // their doors
  }
  box(g, 100, 45, 110, 50, 255);  // unreachable closet: never explored
  return g;
}

}  // namespace

TEST(SegmentationEvalExploration, RevealsTheReachableMapStepByStep) {
  const asf::io::GrayImage g = officeMap();
  asf::evaluation::ExplorationSimulator sim(g, 0.1);
  std::uint64_t version = 0;
  std::vector<std::pair<double, double>> robots;
  bool first = true;
  while (sim.step()) {
    const asf::GridMap& m = sim.map();
    ASSERT_EQ(m.version, version + 1);
    version = m.version;
    EXPECT_FALSE(m.rebuilt);
    EXPECT_FALSE(m.changed.empty());
    robots.push_back({sim.robot().x, sim.robot().y});
    if (first) {
      // The first scan stays within the 5 m range: the far end of the corridor is unknown.
      EXPECT_LT(sim.coverage(), 1.0);
      const double r = sim.robot().x;
      const int far_col = r < 6 ? 117 : 2;
      EXPECT_EQ(asf::io::imageFromGrid(m).at(far_col, 30), 128);
      first = false;
    }
    ASSERT_LT(robots.size(), 5000u);
  }
  EXPECT_GT(version, 3u);
  EXPECT_DOUBLE_EQ(sim.coverage(), 1.0);
  EXPECT_GT(sim.pathLength(), 5.0);
  // Every free pixel of the reachable space is known free, the closet still unknown.
  const asf::io::GrayImage explored = asf::io::imageFromGrid(sim.map());
  for (int row = 0; row < g.height; ++row)
    for (int col = 0; col < g.width; ++col) {
      const int p = explored.at(col, row);
      const bool closet = col >= 100 && col <= 110 && row >= 45 && row <= 50;
      if (closet) {
        ASSERT_EQ(p, 128) << col << "," << row;
      } else if (g.at(col, row) >= 250) {
        ASSERT_GE(p, 250) << col << "," << row;
      } else if (p != 128) {
        ASSERT_LE(p, 5) << col << "," << row;  // known: a wall
      }
    }
  // Deterministic: a second run takes the same path.
  asf::evaluation::ExplorationSimulator again(g, 0.1);
  std::size_t i = 0;
  while (again.step()) {
    ASSERT_LT(i, robots.size());
    EXPECT_EQ(again.robot().x, robots[i].first);
    EXPECT_EQ(again.robot().y, robots[i].second);
    ++i;
  }
  EXPECT_EQ(i, robots.size());
}

TEST(SegmentationEvalExploration, IncrementalEvaluationPassesThePreviousSegmentation) {
  const asf::io::GrayImage g = officeMap();
  auto rooms =
      asf::evaluation::groundTruthRooms(g);  // one component: corridor + rooms (closet too)
  auto seg = makeFreeComponents();
  std::size_t calls = 0;
  const auto r = asf::evaluation::evaluateIncremental(*seg, g, rooms, 0.1, {},
                                                      [&](std::size_t n, double) { calls = n; });
  EXPECT_GT(r.update_ms.size(), 3u);
  EXPECT_EQ(calls, r.update_ms.size());
  EXPECT_DOUBLE_EQ(r.coverage, 1.0);
  // free_components reuses the id of the growing component: still region 1 at the end.
  ASSERT_EQ(r.final_segmentation.regions.size(), 1u);
  EXPECT_EQ(r.final_segmentation.regions[0].id, 1);
  EXPECT_EQ(r.final_segmentation.map_version, r.final_map.version);
  EXPECT_DOUBLE_EQ(r.final_score.precision, 1.0);
  // The closet (66 px) is no GT room; the one room (corridor and rooms) is found whole.
  EXPECT_EQ(r.final_score.rooms, 1);
  EXPECT_DOUBLE_EQ(r.final_score.recall, 1.0);
}

TEST(SegmentationEvalCommand, IncrementalReportsUpdateTimes) {
  const fs::path d = writeDataset("eval_incremental");
  const auto r = runHost(evalArgs(d, false) + " --incremental --json " + (d / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = readJson(d / "out.json");
  for (const auto& m : j["maps"]) {
    ASSERT_TRUE(m.contains("incremental")) << m.dump();
    const auto& i = m["incremental"];
    EXPECT_GE(i["updates"].get<int>(), 1);
    EXPECT_LE(i["median_ms"].get<double>(), i["p95_ms"].get<double>());
    EXPECT_LE(i["p95_ms"].get<double>(), i["max_ms"].get<double>());
    EXPECT_DOUBLE_EQ(i["coverage"].get<double>(), 1.0);
  }
  // Fully explored, the final maps score as in batch.
  EXPECT_DOUBLE_EQ(j["maps"][0]["incremental"]["precision"].get<double>(),
                   j["maps"][0]["precision"].get<double>());
  EXPECT_DOUBLE_EQ(j["maps"][1]["incremental"]["recall"].get<double>(), 1.0);
  ASSERT_TRUE(j["summary"]["plain"].contains("incremental"));
  EXPECT_GE(j["summary"]["plain"]["incremental"]["updates"].get<int>(), 2);
}

// ---------------------------------------------------------------- the benchmark -----------

TEST(SegmentationEvalBenchmark, LabIpaHasTenGroundTruthRooms) {
  const fs::path gt =
      fs::path(ASF_TEST_SHARED_DIR) / "datasets/roomseg/gt/lab_ipa_gt_segmentation.png";
  if (!fs::exists(gt)) GTEST_SKIP() << gt << " is absent (the shared benchmark data)";
  const auto rooms = asf::evaluation::groundTruthRooms(asf::io::readGrayImage(gt.string()));
  const std::set<std::int32_t> ids(rooms.labels.begin(), rooms.labels.end());
  EXPECT_EQ(ids.size(), 11u);  // 10 rooms + 0 (the protocol's note: 4-connectivity gives 11)
}

TEST(SegmentationEvalBenchmark, FreeComponentsOnOneBenchmarkMap) {
  const fs::path root = fs::path(ASF_TEST_SHARED_DIR) / "datasets/roomseg";
  if (!fs::exists(root / "plain/lab_ipa.png")) GTEST_SKIP() << root << " is absent";
  const fs::path d = tempDir("benchmark");
  const auto r =
      runHost("segment-eval --plain " + (root / "plain").string() + " --gt " +
              (root / "gt").string() + " --furnished " + (root / "furnished").string() +
              " --map lab_ipa --segmenter free_components --json " + (d / "out.json").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = readJson(d / "out.json");
  ASSERT_EQ(j["maps"].size(), 2u);
  // One component over everything: every room found whole (recall ~1), precision low.
  EXPECT_GT(j["maps"][0]["recall"].get<double>(), 0.99);
  EXPECT_LT(j["maps"][0]["precision"].get<double>(), 0.5);
  EXPECT_EQ(j["maps"][0]["rooms"], 10);
}
