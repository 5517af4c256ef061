// Tests of the voronoi segmenter: hand-made floor plans and one benchmark map.
#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <asf/segmenter.h>
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

namespace {

using Grid = mrpt::maps::COccupancyGridMap2D;
// MRPT cell values are p(free): 1 = certainly empty, 0 = certainly occupied.
constexpr float kFree = 0.95f, kWall = 0.05f;
constexpr double kRes = 0.05;

std::shared_ptr<const asf::framework::PluginInfo> info() {
  static auto i = asf::framework::Registry::loadFile(ASF_TEST_PLUGIN_DIR "/segmenter_voronoi.so");
  return i;
}

asf::framework::PluginHandle<asf::Segmenter> make(
    const std::map<std::string, std::string>& kv = {}) {
  auto h = asf::framework::Registry::create<asf::Segmenter>(info());
  h->configure(asf::Params::fromSpecs("voronoi", info()->descriptor->keys,
                                      info()->descriptor->num_keys, kv),
               asf::PluginContext{});
  return h;
}

/// w x h metres at 5 cm, all unknown.
std::shared_ptr<Grid> unknownGrid(double w, double h) {
  auto g = std::make_shared<Grid>(0.f, float(w), 0.f, float(h), float(kRes));
  g->fill(0.5f);
  return g;
}

/// Sets the cells whose centres lie in [x0, x1] x [y0, y1] (metres).
void setBox(Grid& g, double x0, double y0, double x1, double y1, float p) {
  for (int cy = g.y2idx(y0 + 1e-9); cy <= g.y2idx(y1 - 1e-9); ++cy)
    for (int cx = g.x2idx(x0 + 1e-9); cx <= g.x2idx(x1 - 1e-9); ++cx)
      if (cx >= 0 && cy >= 0 && cx < int(g.getSizeX()) && cy < int(g.getSizeY()))
        g.setCell(cx, cy, p);
}

asf::GridMap mapOf(std::shared_ptr<Grid> g, std::uint64_t version = 1) {
  asf::GridMap m;
  m.grid = std::move(g);
  m.version = version;
  return m;
}

/// The contract: labels aligned with the grid, on free cells only, labels <-> regions.
void checkConsistency(const asf::Segmentation& s, const Grid& g) {
  ASSERT_EQ(s.labels.width, static_cast<int>(g.getSizeX()));
  ASSERT_EQ(s.labels.height, static_cast<int>(g.getSizeY()));
  EXPECT_DOUBLE_EQ(s.labels.resolution, g.getResolution());
  std::set<asf::RegionId> in_image, in_list;
  for (int cy = 0; cy < s.labels.height; ++cy)
    for (int cx = 0; cx < s.labels.width; ++cx) {
      const asf::RegionId id = s.labels.at(cx, cy);
      if (id == 0) continue;
      in_image.insert(id);
      ASSERT_GT(g.getCell(cx, cy), 0.6f) << "label on a non-free cell " << cx << "," << cy;
    }
  for (const auto& r : s.regions) in_list.insert(r.id);
  EXPECT_EQ(in_image, in_list);
}

/// Every free cell carries a label (the wavefront fill reaches all of them).
int unlabelledFreeCells(const asf::Segmentation& s, const Grid& g) {
  int n = 0;
  for (int cy = 0; cy < s.labels.height; ++cy)
    for (int cx = 0; cx < s.labels.width; ++cx)
      if (g.getCell(cx, cy) > 0.6f && s.labels.at(cx, cy) == 0) ++n;
  return n;
}

double freeArea(const Grid& g) {
  int n = 0;
  for (unsigned cy = 0; cy < g.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < g.getSizeX(); ++cx) n += g.getCell(cx, cy) > 0.6f;
  return n * kRes * kRes;
}

/// Two 4 x 4 m rooms side by side, a 0.1 m wall between them with a 0.9 m door.
std::shared_ptr<Grid> twoRoomsWithDoor() {
  auto g = unknownGrid(9.0, 5.0);
  setBox(*g, 0.2, 0.2, 8.5, 4.5, kWall);
  setBox(*g, 0.3, 0.3, 4.3, 4.3, kFree);
  setBox(*g, 4.4, 0.3, 8.4, 4.3, kFree);
  setBox(*g, 4.3, 1.5, 4.4, 2.4, kFree);  // the door through the wall
  return g;
}

TEST(Voronoi, TwoRoomsJoinedByADoorAreSplitAtTheDoor) {
  auto g = twoRoomsWithDoor();
  const auto s = make()->segment(mapOf(g, 7), nullptr);
  EXPECT_EQ(s.map_version, 7u);
  checkConsistency(s, *g);
  ASSERT_EQ(s.regions.size(), 2u);
  const asf::RegionId left = s.labels.atPoint(2.0, 2.0), right = s.labels.atPoint(6.5, 2.0);
  EXPECT_GT(left, 0);
  EXPECT_GT(right, 0);
  EXPECT_NE(left, right);
  // The split is at the door: each room's cells carry one label, away from the door.
  for (double y = 0.4; y < 4.25; y += 0.25) {
    EXPECT_EQ(s.labels.atPoint(0.4, y), left) << y;
    EXPECT_EQ(s.labels.atPoint(4.0, y), left) << y;
    EXPECT_EQ(s.labels.atPoint(4.8, y), right) << y;
    EXPECT_EQ(s.labels.atPoint(8.3, y), right) << y;
  }
  for (const auto& r : s.regions) EXPECT_NEAR(r.area, 16.0, 0.5);
  EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
}

TEST(Voronoi, ClosedDoorGivesTwoRegionsAndOpenWallGivesOne) {
  auto g = twoRoomsWithDoor();
  setBox(*g, 4.3, 1.5, 4.4, 2.4, kWall);
  EXPECT_EQ(make()->segment(mapOf(g), nullptr).regions.size(), 2u);
  setBox(*g, 4.3, 0.3, 4.4, 4.3, kFree);  // no wall at all: one 8 x 4 m hall
  const auto s = make()->segment(mapOf(g), nullptr);
  EXPECT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
}

TEST(Voronoi, SingleRectangularRoomStaysOne) {
  auto g = unknownGrid(7.0, 4.0);
  setBox(*g, 0.2, 0.2, 6.6, 3.6, kWall);
  setBox(*g, 0.3, 0.3, 6.5, 3.5, kFree);
  const auto s = make()->segment(mapOf(g), nullptr);
  checkConsistency(s, *g);
  ASSERT_EQ(s.regions.size(), 1u);
  EXPECT_NEAR(s.regions[0].area, freeArea(*g), 1e-6);
  EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
}

TEST(Voronoi, FurnitureNearAWallDoesNotSplitARoom) {
  // 6 x 4 m room; four 0.2 x 0.2 m table legs 0.8 m from the south wall: the gaps between legs
  // and wall are clearance minima, but cut lines ending on furniture are not drawn.
  auto g = unknownGrid(7.0, 5.0);
  setBox(*g, 0.2, 0.2, 6.6, 4.6, kWall);
  setBox(*g, 0.3, 0.3, 6.5, 4.5, kFree);
  for (double x : {2.0, 3.5})
    for (double y : {1.1, 2.3}) setBox(*g, x, y, x + 0.2, y + 0.2, kWall);
  const auto s = make()->segment(mapOf(g), nullptr);
  checkConsistency(s, *g);
  EXPECT_EQ(s.regions.size(), 1u);
  EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
  // As published (every minimum cut), the legs split the room.
  const auto published = make({{"max_furniture_area", "0"}})->segment(mapOf(g), nullptr);
  EXPECT_GT(published.regions.size(), 1u);
}

TEST(Voronoi, CorridorWithRoomsOffItGivesOneRegionPerRoom) {
  // A 1.6 m wide, 12 m long corridor; three 3.5 x 3 m rooms above it with 0.9 m doors and a
  // 4 x 3 m room below its east end.
  auto g = unknownGrid(13.0, 9.0);
  setBox(*g, 0.2, 0.2, 12.6, 8.4, kWall);
  setBox(*g, 0.3, 3.3, 12.5, 4.9, kFree);  // corridor
  const double room_x[3] = {0.3, 4.4, 8.5};
  for (double x : room_x) {
    setBox(*g, x, 5.0, x + 3.5, 8.3, kFree);
    setBox(*g, x + 1.3, 4.9, x + 2.2, 5.0, kFree);  // door
  }
  setBox(*g, 8.5, 0.3, 12.5, 3.2, kFree);
  setBox(*g, 9.0, 3.2, 9.9, 3.3, kFree);  // door of the room below
  const auto s = make()->segment(mapOf(g), nullptr);
  checkConsistency(s, *g);
  EXPECT_EQ(unlabelledFreeCells(s, *g), 0);
  ASSERT_EQ(s.regions.size(), 5u);
  std::set<asf::RegionId> ids;
  const asf::RegionId corridor = s.labels.atPoint(6.0, 4.1);
  for (double x = 0.5; x < 12.4; x += 0.5) EXPECT_EQ(s.labels.atPoint(x, 4.1), corridor) << x;
  ids.insert(corridor);
  for (double x : room_x) ids.insert(s.labels.atPoint(x + 1.75, 6.8));
  ids.insert(s.labels.atPoint(10.5, 1.5));
  EXPECT_EQ(ids.size(), 5u);
  EXPECT_EQ(ids.count(0), 0u);
}

TEST(Voronoi, EmptyOrUnknownMapGivesNoRegions) {
  auto seg = make();
  EXPECT_TRUE(seg->segment(asf::GridMap{}, nullptr).regions.empty());
  auto g = unknownGrid(4.0, 3.0);
  const auto s = seg->segment(mapOf(g), nullptr);
  EXPECT_TRUE(s.regions.empty());
  checkConsistency(s, *g);
  setBox(*g, 0, 0, 4.0, 3.0, kWall);
  EXPECT_TRUE(seg->segment(mapOf(g), nullptr).regions.empty());
}

TEST(Voronoi, IdsPersistBetweenCallsWithPrevious) {
  auto seg = make();
  auto g = twoRoomsWithDoor();
  const auto s1 = seg->segment(mapOf(g, 1), nullptr);
  const auto s2 = seg->segment(mapOf(g, 2), &s1);
  ASSERT_EQ(s1.regions.size(), 2u);
  ASSERT_EQ(s2.regions.size(), 2u);
  EXPECT_EQ(s1.labels.labels, s2.labels.labels);
  for (std::size_t i = 0; i < s1.regions.size(); ++i) EXPECT_EQ(s1.regions[i].id, s2.regions[i].id);
  // Without `previous` the same instance issues fresh ids.
  const auto s3 = seg->segment(mapOf(g, 3), nullptr);
  ASSERT_EQ(s3.regions.size(), 2u);
  EXPECT_GT(s3.regions[0].id, s1.regions[1].id);
}

TEST(Voronoi, BadValuesAreRejected) {
  EXPECT_THROW(make({{"min_room_area", "20"}, {"max_merge_area", "10"}}), asf::ConfigError);
  EXPECT_THROW(make({{"robot_radius", "-1"}}), asf::ConfigError);
  EXPECT_THROW(make({{"merge_border_ratio", "1.5"}}), asf::ConfigError);
  EXPECT_NO_THROW(make({{"robot_radius", "0"}}));
}

// ---- Benchmark maps (../shared/datasets/roomseg, protocol of ../shared/docs/roomseg-eval.md)

const std::filesystem::path kRoomseg = ASF_TEST_SHARED_DIR "/datasets/roomseg";

/// Map image (row 0 at the top) -> grid (cy 0 at the bottom); pixel >= 250 is free.
std::shared_ptr<Grid> gridFromImage(const cv::Mat& img) {
  auto g = std::make_shared<Grid>(0.f, float(img.cols * kRes), 0.f, float(img.rows * kRes),
                                  float(kRes));
  if (int(g->getSizeX()) != img.cols || int(g->getSizeY()) != img.rows) return nullptr;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      g->setCell(c, img.rows - 1 - r, img.at<uchar>(r, c) >= 250 ? 1.0f : 0.0f);
  return g;
}

struct Score {
  double recall = 0, precision = 0;
  int rooms = 0, segments = 0;
};

/// Per-map means: precision over segments (> 100 px), recall over GT rooms (8-connected
/// components of GT pixels > 250 with > 100 px).
Score score(const asf::Segmentation& s, const cv::Mat& gt_img) {
  cv::Mat gt_comp;
  cv::connectedComponents(gt_img > 250, gt_comp, 8, CV_32S);
  std::map<int, int> room_size, seg_size;
  std::map<std::pair<int, int>, int> overlap;  // (segment, room)
  const int rows = gt_img.rows;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < gt_img.cols; ++c) {
      const int room = gt_comp.at<int>(r, c), seg = s.labels.at(c, rows - 1 - r);
      if (room > 0) ++room_size[room];
      if (seg > 0) ++seg_size[seg];
      if (room > 0 && seg > 0) ++overlap[{seg, room}];
    }
  std::map<int, int> best_seg, best_room;
  for (const auto& [k, n] : overlap) {
    best_seg[k.first] = std::max(best_seg[k.first], n);
    best_room[k.second] = std::max(best_room[k.second], n);
  }
  Score out;
  for (const auto& [room, n] : room_size)
    if (n > 100) {
      out.recall += double(best_room[room]) / n;
      ++out.rooms;
    }
  for (const auto& [seg, n] : seg_size)
    if (n > 100) {
      out.precision += double(best_seg[seg]) / n;
      ++out.segments;
    }
  if (out.rooms) out.recall /= out.rooms;
  if (out.segments) out.precision /= out.segments;
  return out;
}

Score runMap(const std::string& map_file, const std::string& gt_file, asf::Segmenter& seg,
             double* seconds = nullptr) {
  const cv::Mat img = cv::imread(map_file, cv::IMREAD_GRAYSCALE);
  const cv::Mat gt = cv::imread(gt_file, cv::IMREAD_GRAYSCALE);
  if (img.empty() || gt.empty() || img.size() != gt.size()) {
    ADD_FAILURE() << "cannot read " << map_file << " / " << gt_file;
    return {};
  }
  auto g = gridFromImage(img);
  if (!g) {
    ADD_FAILURE() << "grid size mismatch for " << map_file;
    return {};
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto s = seg.segment(mapOf(g), nullptr);
  if (seconds)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (const char* dir = std::getenv("ASF_VORONOI_DUMP")) {  // a picture for tuning
    cv::Mat pic(img.rows, img.cols, CV_8UC3);
    for (int r = 0; r < img.rows; ++r)
      for (int c = 0; c < img.cols; ++c) {
        const int l = s.labels.at(c, img.rows - 1 - r);
        const uchar v = img.at<uchar>(r, c) >= 250 ? 255 : 0;
        pic.at<cv::Vec3b>(r, c) =
            l ? cv::Vec3b(50 + l * 73 % 200, 50 + l * 151 % 200, 50 + l * 37 % 200)
              : cv::Vec3b(v, v, v);
        if (gt.at<uchar>(r, c) <= 250 && v) pic.at<cv::Vec3b>(r, c) = cv::Vec3b(0, 0, 255);
      }
    cv::imwrite(std::string(dir) + "/" + std::filesystem::path(map_file).stem().string() + ".png",
                pic);
  }
  return score(s, gt);
}

TEST(VoronoiDataset, OfficeAPlainAndFurnishedScoreWithinMeasuredBounds) {
  if (!std::filesystem::exists(kRoomseg / "gt"))
    GTEST_SKIP() << "benchmark maps not found at " << kRoomseg << " (../shared is absent)";
  auto seg = make();
  const Score plain = runMap(kRoomseg / "plain/office_a.png",
                             kRoomseg / "gt/office_a_gt_segmentation.png", *seg);
  const Score furnished = runMap(kRoomseg / "furnished/office_a_furnitures.png",
                                 kRoomseg / "gt/office_a_gt_segmentation.png", *seg);
  // Measured with the defaults: plain recall 0.999, precision 0.996; furnished recall 0.943,
  // precision 0.987 (furnished recall is 0.629 without the furniture rule).
  EXPECT_GE(plain.recall, 0.97);
  EXPECT_GE(plain.precision, 0.97);
  EXPECT_GE(furnished.recall, 0.90);
  EXPECT_GE(furnished.precision, 0.95);
  EXPECT_NEAR(plain.segments, plain.rooms, 2);
  std::cout << "office_a plain: recall " << plain.recall << " precision " << plain.precision
            << " (" << plain.segments << " segments, " << plain.rooms << " rooms)\n"
            << "office_a furnished: recall " << furnished.recall << " precision "
            << furnished.precision << " (" << furnished.segments << " segments)\n";
}

/// Scores all maps; for tuning. Runs only with ASF_VORONOI_REPORT=1; ASF_VORONOI_SET holds
/// key=value overrides separated by ';'.
TEST(VoronoiDataset, AllMapsReport) {
  if (!std::getenv("ASF_VORONOI_REPORT")) GTEST_SKIP() << "set ASF_VORONOI_REPORT=1 to run";
  if (!std::filesystem::exists(kRoomseg / "gt"))
    GTEST_SKIP() << "benchmark maps not found at " << kRoomseg;
  std::map<std::string, std::string> kv;
  if (const char* set = std::getenv("ASF_VORONOI_SET")) {
    std::stringstream ss(set);
    std::string item;
    while (std::getline(ss, item, ';'))
      if (auto eq = item.find('='); eq != std::string::npos)
        kv[item.substr(0, eq)] = item.substr(eq + 1);
  }
  auto seg = make(kv);
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(kRoomseg / "plain"))
    names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  for (const char* kind : {"plain", "furnished"}) {
    double sr = 0, sp = 0, st = 0;
    for (const auto& n : names) {
      const std::string file = std::string(kind) == "plain"
                                   ? (kRoomseg / "plain" / (n + ".png")).string()
                                   : (kRoomseg / "furnished" / (n + "_furnitures.png")).string();
      double t = 0;
      const Score s = runMap(file, kRoomseg / "gt" / (n + "_gt_segmentation.png"), *seg, &t);
      std::printf("%-9s %-16s recall %.3f precision %.3f segments %3d rooms %3d  %.3f s\n", kind,
                  n.c_str(), s.recall, s.precision, s.segments, s.rooms, t);
      sr += s.recall;
      sp += s.precision;
      st += t;
    }
    std::printf("%-9s MEAN recall %.3f precision %.3f  %.3f s/map\n", kind, sr / names.size(),
                sp / names.size(), st / names.size());
  }
}

}  // namespace
