// asf::mapping::regionsFromLabels and its windowed form: the windowed update must give exactly what
// the whole-image function gives (labels, ids, areas, centroids, outlines, boxes), checked
// against it on random label images with random local changes.
#include <asf/mapping/region_labels.h>
#include <asf/segmentation.h>
#include <gtest/gtest.h>

#include <random>

namespace {

using asf::CellBox;
using asf::LabelImage;
using asf::RegionBoxes;
using asf::RegionId;
using asf::Segmentation;

LabelImage blank(int w, int h) {
  LabelImage L;
  L.width = w;
  L.height = h;
  L.resolution = 0.05;
  L.origin_x = -1.25;
  L.origin_y = 3.5;
  L.labels.assign(static_cast<std::size_t>(w) * h, 0);
  return L;
}

void paint(LabelImage& L, CellBox b, RegionId v) {
  for (int y = std::max(0, b.y); y < std::min(L.height, b.y + b.height); ++y)
    for (int x = std::max(0, b.x); x < std::min(L.width, b.x + b.width); ++x)
      L.labels[static_cast<std::size_t>(y) * L.width + x] = v;
}

void expectSame(const Segmentation& a, const Segmentation& b) {
  ASSERT_EQ(a.labels.labels, b.labels.labels);
  ASSERT_EQ(a.regions.size(), b.regions.size());
  for (std::size_t i = 0; i < a.regions.size(); ++i) {
    const asf::Region &r = a.regions[i], &s = b.regions[i];
    EXPECT_EQ(r.id, s.id);
    EXPECT_EQ(r.area, s.area);
    EXPECT_EQ(r.centroid.x, s.centroid.x);
    EXPECT_EQ(r.centroid.y, s.centroid.y);
    ASSERT_EQ(r.outer.size(), s.outer.size()) << "region " << r.id;
    for (std::size_t k = 0; k < r.outer.size(); ++k) {
      EXPECT_EQ(r.outer[k].x, s.outer[k].x);
      EXPECT_EQ(r.outer[k].y, s.outer[k].y);
    }
    EXPECT_EQ(r.holes.size(), s.holes.size()) << "region " << r.id;
  }
}

void expectSameBoxes(const RegionBoxes& a, const RegionBoxes& b) {
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [id, box] : a) {
    ASSERT_TRUE(b.count(id)) << "region " << id;
    const CellBox& c = b.at(id);
    EXPECT_EQ(box.x, c.x);
    EXPECT_EQ(box.y, c.y);
    EXPECT_EQ(box.width, c.width);
    EXPECT_EQ(box.height, c.height);
  }
}

TEST(RegionsFromLabels, HandCheckedAreasCentroidsBoxesAndIds) {
  LabelImage L = blank(10, 6);
  paint(L, {0, 0, 4, 6}, 7);   // 24 cells
  paint(L, {6, 2, 3, 2}, 99);  // 6 cells
  RegionBoxes boxes;
  RegionId issued = 0;
  const Segmentation s = asf::mapping::regionsFromLabels(L, nullptr, &issued, 1, 0, &boxes);
  ASSERT_EQ(s.regions.size(), 2u);
  EXPECT_EQ(s.regions[0].id, 1);  // fresh ids in order of first appearance
  EXPECT_EQ(s.regions[1].id, 2);
  EXPECT_DOUBLE_EQ(s.regions[0].area, 24 * 0.05 * 0.05);
  EXPECT_DOUBLE_EQ(s.regions[1].centroid.x, -1.25 + 7.5 * 0.05);
  EXPECT_DOUBLE_EQ(s.regions[1].centroid.y, 3.5 + 3.0 * 0.05);
  EXPECT_EQ(boxes.at(2).x, 6);
  EXPECT_EQ(boxes.at(2).width, 3);
  EXPECT_EQ(boxes.at(1).height, 6);
  EXPECT_EQ(issued, 2);
  // Minimum area drops the small region; its id is not issued.
  RegionId issued2 = 0;
  const Segmentation t = asf::mapping::regionsFromLabels(L, nullptr, &issued2, 1, 10 * 0.0025);
  ASSERT_EQ(t.regions.size(), 1u);
  EXPECT_EQ(t.labels.labels[2 * 10 + 7], 0);
}

TEST(RegionsFromLabels, WindowedUpdateEqualsWholeImageOnRandomChanges) {
  std::mt19937 rng(20261125);
  auto uni = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  int windowed_calls = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int W = uni(8, 50), H = uni(8, 40);
    LabelImage L = blank(W, H);
    for (int k = 0; k < uni(1, 12); ++k)
      paint(L, {uni(-3, W - 1), uni(-3, H - 1), uni(1, W), uni(1, H)}, uni(0, 9));
    const double min_area = trial % 3 == 0 ? 4 * 0.0025 : 0.0;
    RegionId issued = 0;
    RegionBoxes boxes;
    Segmentation prev = asf::mapping::regionsFromLabels(L, nullptr, &issued, 1, min_area, &boxes);
    for (int step = 0; step < 8; ++step) {
      // A change confined to a window: existing ids, fresh labels and erased cells.
      const CellBox win{uni(-2, W - 1), uni(-2, H - 1), uni(1, W / 2 + 1), uni(1, H / 2 + 1)};
      LabelImage next = prev.labels;
      RegionId max_id = 0;
      for (const auto& r : prev.regions) max_id = std::max(max_id, r.id);
      for (int k = 0; k < uni(1, 5); ++k) {
        const CellBox b{win.x + uni(0, win.width - 1), win.y + uni(0, win.height - 1),
                        uni(1, win.width), uni(1, win.height)};
        const CellBox inside{std::max(b.x, win.x), std::max(b.y, win.y),
                             std::min(b.x + b.width, win.x + win.width) - std::max(b.x, win.x),
                             std::min(b.y + b.height, win.y + win.height) - std::max(b.y, win.y)};
        const int kind = uni(0, 2);
        const RegionId v = kind == 0 ? 0
                         : kind == 1 && !prev.regions.empty()
                             ? prev.regions[static_cast<std::size_t>(uni(0, static_cast<int>(prev.regions.size()) - 1))].id
                             : max_id + 1000 + uni(0, 3);
        paint(next, inside, v);
      }
      RegionId issued_full = issued, issued_win = issued;
      RegionBoxes boxes_full, boxes_win = boxes;
      const Segmentation full =
          asf::mapping::regionsFromLabels(next, &prev, &issued_full, 2 + step, min_area, &boxes_full);
      const Segmentation win_out = asf::mapping::regionsFromLabelsInWindow(
          next, prev, boxes_win, win, &issued_win, 2 + step, min_area);
      ++windowed_calls;
      SCOPED_TRACE("trial " + std::to_string(trial) + " step " + std::to_string(step));
      expectSame(full, win_out);
      EXPECT_EQ(issued_full, issued_win);
      expectSameBoxes(boxes_full, boxes_win);
      if (::testing::Test::HasFailure()) return;
      prev = win_out;
      boxes = boxes_win;
      issued = issued_win;
    }
  }
  EXPECT_EQ(windowed_calls, 480);
}

TEST(RegionsFromLabels, WindowedFallsBackOnAnotherRasterOrMissingBoxes) {
  LabelImage L = blank(12, 8);
  paint(L, {0, 0, 6, 8}, 1);
  paint(L, {6, 0, 6, 8}, 2);
  RegionId issued = 0;
  RegionBoxes boxes;
  const Segmentation prev = asf::mapping::regionsFromLabels(L, nullptr, &issued, 1, 0, &boxes);
  LabelImage moved = prev.labels;
  moved.origin_x += 0.05;  // another raster: the window says nothing
  RegionBoxes b1 = boxes;
  RegionId i1 = issued, i2 = issued;
  const Segmentation a = asf::mapping::regionsFromLabelsInWindow(moved, prev, b1, {0, 0, 1, 1}, &i1, 2);
  const Segmentation b = asf::mapping::regionsFromLabels(moved, &prev, &i2, 2);
  expectSame(a, b);
  // Boxes that are not the previous segmentation's: whole-image result, boxes rebuilt.
  RegionBoxes wrong;
  LabelImage changed = prev.labels;
  paint(changed, {0, 0, 2, 2}, 0);
  const Segmentation c = asf::mapping::regionsFromLabelsInWindow(changed, prev, wrong, {0, 0, 2, 2}, &i1, 3);
  const Segmentation d = asf::mapping::regionsFromLabels(changed, &prev, &i2, 3);
  expectSame(c, d);
  EXPECT_EQ(wrong.size(), 2u);
}

}  // namespace
