// Two segmentations compared region by region (evaluation::compareSegmentations): hand-computed
// cases, the adjusted Rand index against plain pair counting, the reference DuDe's colour
// images read as regions, and `asf segment-eval --reference` end to end.
#include <asf/errors.h>
#include <asf/evaluation/segmentation_eval.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <vector>

#include "test_util.h"

using asf::io::LabelRaster;
using asf_test::has;
using asf_test::runHost;
namespace fs = std::filesystem;
using asf::evaluation::compareSegmentations;

namespace {

LabelRaster filled(int w, int h, std::int32_t v = 0) {
  return LabelRaster{w, h, std::vector<std::int32_t>(static_cast<std::size_t>(w) * h, v)};
}

/// Sets [c0, c1] x [r0, r1] (inclusive) to v.
void box(LabelRaster& L, int c0, int r0, int c1, int r1, std::int32_t v) {
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) L.labels[static_cast<std::size_t>(r) * L.width + c] = v;
}

/// The adjusted Rand index by enumerating every pair of pixels labelled (> 0) on both sides.
double ariByPairs(const LabelRaster& a, const LabelRaster& b) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < a.labels.size(); ++i)
    if (a.labels[i] > 0 && b.labels[i] > 0) idx.push_back(i);
  double same_a = 0, same_b = 0, same_both = 0, all = 0;
  for (std::size_t x = 0; x < idx.size(); ++x)
    for (std::size_t y = x + 1; y < idx.size(); ++y) {
      const bool sa = a.labels[idx[x]] == a.labels[idx[y]], sb = b.labels[idx[x]] == b.labels[idx[y]];
      same_a += sa;
      same_b += sb;
      same_both += sa && sb;
      all += 1;
    }
  const double expected = same_a * same_b / all;
  return (same_both - expected) / (0.5 * (same_a + same_b) - expected);
}

}  // namespace

TEST(SegmentationAgreement, TheSamePartitionUnderOtherLabelsAgreesFully) {
  LabelRaster ref = filled(40, 20), seg = filled(40, 20);
  box(ref, 0, 0, 19, 19, 1);
  box(ref, 20, 0, 39, 19, 2);
  box(seg, 0, 0, 19, 19, 7);
  box(seg, 20, 0, 39, 19, 3);
  const auto a = compareSegmentations(seg, ref);
  EXPECT_DOUBLE_EQ(a.iou_reference, 1.0);
  EXPECT_DOUBLE_EQ(a.iou_segmentation, 1.0);
  EXPECT_DOUBLE_EQ(a.ari, 1.0);
  EXPECT_EQ(a.segments, 2);
  EXPECT_EQ(a.reference_regions, 2);
  EXPECT_EQ(a.pixels_compared, 800u);
}

TEST(SegmentationAgreement, MergedAndSplitRegionsByHand) {
  // Two 200 px reference rooms merged into one 400 px segment: each room's best IoU is
  // 200 / 400, the segment's too; one side a single cluster: ARI 0.
  LabelRaster ref = filled(40, 10), merged = filled(40, 10, 1);
  box(ref, 0, 0, 19, 9, 1);
  box(ref, 20, 0, 39, 9, 2);
  auto a = compareSegmentations(merged, ref);
  EXPECT_DOUBLE_EQ(a.iou_reference, 0.5);
  EXPECT_DOUBLE_EQ(a.iou_segmentation, 0.5);
  EXPECT_NEAR(a.ari, 0.0, 1e-12);
  // One 400 px reference room cut 250 + 150: the room's best IoU 250 / 400; from the
  // segments' side (250 * 250 / 400 + 150 * 150 / 400) / 400.
  LabelRaster room = filled(40, 10, 5), split = filled(40, 10, 1);
  box(split, 25, 0, 39, 9, 2);
  a = compareSegmentations(split, room);
  EXPECT_DOUBLE_EQ(a.iou_reference, 250.0 / 400.0);
  EXPECT_DOUBLE_EQ(a.iou_segmentation, (250.0 * 250 / 400 + 150.0 * 150 / 400) / 400);
  // A region of at most 100 px counts on neither side (the benchmark's rule): a 10 x 10
  // piece cut off the room changes nothing but the pixels compared.
  LabelRaster nibbled = filled(40, 10, 1);
  box(nibbled, 30, 0, 39, 9, 9);
  a = compareSegmentations(nibbled, room);
  EXPECT_EQ(a.segments, 1);
  EXPECT_DOUBLE_EQ(a.iou_reference, 300.0 / 400.0);
  EXPECT_DOUBLE_EQ(a.iou_segmentation, 300.0 / 400.0);
  EXPECT_EQ(a.pixels_compared, 300u);
  EXPECT_THROW(compareSegmentations(filled(3, 3), filled(3, 4)), asf::Error);
}

TEST(SegmentationAgreement, AdjustedRandIndexMatchesPairCounting) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    LabelRaster a = filled(12, 9), b = filled(12, 9);
    std::uniform_int_distribution<int> la(0, 3), lb(0, 4);
    for (auto& v : a.labels) v = la(rng);
    for (auto& v : b.labels) v = lb(rng);
    box(a, 0, 0, 5, 8, 1);  // structure shared by both, so the index is not only noise
    box(b, 0, 0, 5, 8, 2);
    const auto got = compareSegmentations(a, b, 0);  // every region counts
    EXPECT_NEAR(got.ari, ariByPairs(a, b), 1e-12) << "trial " << trial;
  }
}

TEST(SegmentationAgreement, ColourRegionsAreRead8ConnectedPerColour) {
  const fs::path d = asf_test::freshTempDir("asf_test_segmentation_agreement_colour");
  const int w = 12, h = 6;
  std::vector<std::uint8_t> bgr(static_cast<std::size_t>(w) * h * 3, 0);
  const auto paint = [&](int c0, int c1, int r0, int r1, std::uint8_t b, std::uint8_t g, std::uint8_t r) {
    for (int y = r0; y <= r1; ++y)
      for (int x = c0; x <= c1; ++x) {
        std::uint8_t* p = &bgr[(static_cast<std::size_t>(y) * w + x) * 3];
        p[0] = b, p[1] = g, p[2] = r;
      }
  };
  paint(0, 3, 0, 5, 0, 0, 255);    // red, left
  paint(5, 7, 0, 5, 0, 255, 0);    // green, middle (column 4 black: a drawn wall)
  paint(9, 11, 0, 2, 0, 0, 255);   // red again, apart from the first: its own region
  paint(9, 11, 4, 5, 255, 0, 0);   // blue
  asf::io::writeBgrImage((d / "ref.png").string(), w, h, bgr.data());
  const LabelRaster L = asf::io::readColourRegions((d / "ref.png").string());
  ASSERT_EQ(L.width, w);
  ASSERT_EQ(L.height, h);
  EXPECT_EQ(L.at(0, 0), 1);
  EXPECT_EQ(L.at(3, 5), 1);
  EXPECT_EQ(L.at(4, 2), 0);
  EXPECT_EQ(L.at(5, 0), 2);
  EXPECT_EQ(L.at(9, 0), 3);
  EXPECT_EQ(L.at(8, 3), 0);
  EXPECT_EQ(L.at(11, 5), 4);
  EXPECT_THROW(asf::io::readColourRegions((d / "missing.png").string()), asf::InputError);
}

// segment-eval --reference: a 20 x 20 px room segmented whole by free_components, against a
// reference that has it whole (full agreement) or cut in two colours (IoU 1/2), and the
// reference scored against the ground truth as the segmenter is.
TEST(SegmentationAgreement, SegmentEvalComparesWithTheReferenceOutputs) {
  const fs::path d = asf_test::freshTempDir("asf_test_segmentation_agreement_eval");
  for (const char* sub : {"plain", "gt", "ref_whole", "ref_cut"}) fs::create_directories(d / sub);
  asf::io::GrayImage map{30, 30, std::vector<std::uint8_t>(900, 0)};
  for (int r = 5; r < 25; ++r)
    for (int c = 5; c < 25; ++c) map.pixels[static_cast<std::size_t>(r) * 30 + c] = 255;
  asf::io::writeGrayImage((d / "plain/a.png").string(), map);
  asf::io::writeGrayImage((d / "gt/a_gt_segmentation.png").string(), map);
  std::vector<std::uint8_t> whole(900 * 3, 0), cut(900 * 3, 0);
  for (int r = 5; r < 25; ++r)
    for (int c = 5; c < 25; ++c) {
      const std::size_t i = (static_cast<std::size_t>(r) * 30 + c) * 3;
      whole[i + 1] = 200;
      cut[i + (c < 15 ? 0 : 2)] = 200;
    }
  asf::io::writeBgrImage((d / "ref_whole/a_DuDe.png").string(), 30, 30, whole.data());
  asf::io::writeBgrImage((d / "ref_cut/a_DuDe.png").string(), 30, 30, cut.data());
  const std::string base = "segment-eval --plain " + (d / "plain").string() + " --gt " +
                           (d / "gt").string() + " --segmenter free_components --json ";
  auto r = runHost(base + (d / "whole.json").string() + " --reference " + (d / "ref_whole").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "against the reference: IoU 1.000")) << r.out;
  EXPECT_TRUE(has(r.out, "summary plain against the reference (1 maps)")) << r.out;
  nlohmann::json j = nlohmann::json::parse(std::ifstream(d / "whole.json"));
  const auto& ref = j["maps"][0]["reference"];
  EXPECT_DOUBLE_EQ(ref["iou"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ref["ari"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ref["score"]["precision"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(ref["score"]["recall"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["summary"]["plain"]["reference_iou_min"].get<double>(), 1.0);

  r = runHost(base + (d / "cut.json").string() + " --reference " + (d / "ref_cut").string());
  ASSERT_EQ(r.code, 0) << r.out;
  j = nlohmann::json::parse(std::ifstream(d / "cut.json"));
  const auto& cut_ref = j["maps"][0]["reference"];
  EXPECT_DOUBLE_EQ(cut_ref["iou"].get<double>(), 0.5);  // each 200 px half against the 400 px room
  EXPECT_DOUBLE_EQ(cut_ref["iou_segments"].get<double>(), 0.5);
  EXPECT_EQ(cut_ref["reference_regions"], 2);
  EXPECT_DOUBLE_EQ(cut_ref["score"]["precision"].get<double>(), 1.0);  // halves of one room
  EXPECT_DOUBLE_EQ(cut_ref["score"]["recall"].get<double>(), 0.5);

  // A map without its reference output: an error naming the file, exit 1.
  fs::remove(d / "ref_cut/a_DuDe.png");
  r = runHost(base + (d / "none.json").string() + " --reference " + (d / "ref_cut").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, (d / "ref_cut/a_DuDe.png").string() + ": no such file (--reference")) << r.out;
  r = runHost(base + (d / "none.json").string() + " --reference " + (d / "nowhere").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "nowhere: no such folder (--reference)")) << r.out;
}
