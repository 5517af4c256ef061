// The author's incremental rule (change_rule = reference, dude_reference_change.h): the rule
// on hand-made rasters, then the plugin on grids, each case against asf's own rule.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "dude_reference_change.h"
#include "segmenter_dude_test_util.h"

namespace {

using namespace dude_test;
using asf::dude::incremental::referenceChange;

// One region: the 20 x 20 cells at (10, 10); free: it plus a square blob of `side` cells
// against its right side, rows 15..15+side-1.
struct RegionAndBlob {
  cv::Mat free = cv::Mat::zeros(60, 60, CV_8U);
  cv::Mat labels = cv::Mat::zeros(60, 60, CV_32S);
  explicit RegionAndBlob(int side, int gap = 0) {
    labels(cv::Rect(10, 10, 20, 20)).setTo(7);
    free(cv::Rect(10, 10, 20, 20)).setTo(1);
    free(cv::Rect(30 + gap, 15, side, side)).setTo(1);
  }
};

TEST(DudeReferenceChange, ABlobIsKeptOnlyWhenItsOutlineEnclosesMoreThanTheSquare) {
  // An 11-cell square's outline (through the cell centres) encloses 10 x 10 = 100: not more
  // than the 10-cell square, dropped; a 12-cell one encloses 121: kept.
  const RegionAndBlob small(11), big(12);
  const auto a = referenceChange(small.free, small.labels, 10);
  EXPECT_EQ(a.blobs_small, 1);
  EXPECT_EQ(a.blobs_kept, 0);
  EXPECT_TRUE(a.regions.empty());
  EXPECT_EQ(a.box.area(), 0);
  const auto b = referenceChange(big.free, big.labels, 10);
  EXPECT_EQ(b.blobs_small, 0);
  EXPECT_EQ(b.blobs_kept, 1);
  EXPECT_EQ(b.regions, std::vector<int>{7});
  // Decomposed again: the region and the blob, nothing else.
  EXPECT_EQ(cv::countNonZero(b.redo), 20 * 20 + 12 * 12);
  EXPECT_EQ(b.box, cv::Rect(10, 10, 32, 20));
}

TEST(DudeReferenceChange, ABlobTouchesARegionWhenVerticesAreUnderTwoCellsApart) {
  // One empty column between them: the blob's corners are 2 cells from the region's boundary
  // (not under 2): apart, dropped. Side by side: touching.
  const RegionAndBlob apart(15, 1), touching(15, 0);
  const auto a = referenceChange(apart.free, apart.labels, 10);
  EXPECT_EQ(a.blobs_apart, 1);
  EXPECT_EQ(a.box.area(), 0);
  const auto t = referenceChange(touching.free, touching.labels, 10);
  EXPECT_EQ(t.blobs_kept, 1);
  // A region cell that is no longer free is still the region's: no new space, no change.
  RegionAndBlob pillar(0);
  pillar.free(cv::Rect(18, 18, 4, 4)).setTo(0);
  const auto p = referenceChange(pillar.free, pillar.labels, 10);
  EXPECT_EQ(p.blobs_kept + p.blobs_small + p.blobs_apart, 0);
  EXPECT_EQ(p.box.area(), 0);
}

std::map<std::string, std::string> rule(const char* r) { return {{"change_rule", r}}; }

TEST(DudeReferenceChange, SmallNewSpaceChangesNothingWhereAsfsRuleRedecomposes) {
  auto g = unknownGrid(12, 8);
  room(*g, 1, 1, 7, 7);
  auto g2 = std::make_shared<Grid>(*g);
  setBox(*g2, 7, 3, 7.3, 3.3, kFree);  // a 0.3 m notch in the east wall
  for (const char* r : {"reference", "asf"}) {
    auto seg = make(rule(r));
    const auto s1 = seg->segment(mapOf(g, 1), nullptr);
    const auto s2 = seg->segment(mapOf(g2, 2), &s1);
    checkConsistency(s2, *g2);
    EXPECT_EQ(s2.mode, asf::Segmentation::Mode::Incremental);
    if (std::string(r) == "reference") {
      EXPECT_EQ(s2.labels.labels, s1.labels.labels) << r;
      EXPECT_EQ(s2.labels.atPoint(7.15, 3.15), 0) << r;
    } else {
      EXPECT_GT(s2.labels.atPoint(7.15, 3.15), 0) << r;
    }
  }
}

TEST(DudeReferenceChange, NewSpaceIsTakenWithTheRegionItTouchesAndNotBefore) {
  auto seg = make(rule("reference"));
  auto g = unknownGrid(30, 10);
  room(*g, 1, 1, 7, 7);    // A
  room(*g, 12, 1, 18, 7);  // B
  const auto s1 = seg->segment(mapOf(g, 1), nullptr);
  const asf::RegionId a = s1.labels.atPoint(4, 4), b = s1.labels.atPoint(15, 4);
  ASSERT_GT(a, 0);
  ASSERT_GT(b, 0);
  // Room C appears touching no region: dropped, B's and A's cells as they were.
  auto g2 = std::make_shared<Grid>(*g);
  room(*g2, 25, 1, 29, 8);
  const auto s2 = seg->segment(mapOf(g2, 2), &s1);
  checkConsistency(s2, *g2);
  EXPECT_EQ(s2.labels.labels, s1.labels.labels);
  // A corridor joins B to C: both are one blob touching B, decomposed with B; A untouched.
  auto g3 = std::make_shared<Grid>(*g2);
  setBox(*g3, 18, 3, 18.1, 5, kFree);
  setBox(*g3, 18.1, 2.9, 25, 5.1, kWall);
  setBox(*g3, 18.1, 3, 25, 5, kFree);
  setBox(*g3, 24.9, 3, 25, 5, kFree);
  const auto s3 = seg->segment(mapOf(g3, 3), &s2);
  checkConsistency(s3, *g3);
  EXPECT_GT(s3.labels.atPoint(21, 4), 0);
  EXPECT_GT(s3.labels.atPoint(27, 4), 0);
  EXPECT_EQ(s3.labels.atPoint(15, 4), b);  // largest overlap keeps the id
  EXPECT_EQ(s3.labels.atPoint(4, 4), a);
  const asf::Region* ra1 = s1.find(a);
  const asf::Region* ra3 = s3.find(a);
  ASSERT_TRUE(ra1 && ra3);
  EXPECT_DOUBLE_EQ(ra1->area, ra3->area);
}

TEST(DudeReferenceChange, ARegionKeepsItsOutlineWhileCellsInsideComeAndGo) {
  auto seg = make(rule("reference"));
  auto g = unknownGrid(10, 8);
  room(*g, 1, 1, 7, 7);
  const auto s1 = seg->segment(mapOf(g, 1), nullptr);
  const asf::RegionId a = s1.labels.atPoint(4, 4);
  // A pillar seen inside: its cells lose their label (free cells only), nothing else changes.
  auto g2 = std::make_shared<Grid>(*g);
  setBox(*g2, 3.8, 3.8, 4.2, 4.2, kWall);
  const auto s2 = seg->segment(mapOf(g2, 2), &s1);
  checkConsistency(s2, *g2);
  EXPECT_EQ(s2.labels.atPoint(4, 4), 0);
  EXPECT_EQ(s2.labels.atPoint(2, 2), a);
  EXPECT_EQ(s2.regions.size(), s1.regions.size());
  // Gone again: inside the region's outline, so not new space: the first labels come back.
  const auto s3 = seg->segment(mapOf(g, 3), &s2);
  checkConsistency(s3, *g);
  EXPECT_EQ(s3.labels.labels, s1.labels.labels);
}

}  // namespace
