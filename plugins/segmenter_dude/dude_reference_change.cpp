// The author's incremental rule (dude_reference_change.h). As in the author's code, a blob is
// its outer outline with CHAIN_APPROX_SIMPLE (corners only), its size the outline's area, and
// it touches a region when one of its vertices lies within 2 cells (Euclidean, strictly) of a
// vertex of the region's outline. The author's region outlines are DuDe's pieces, whose
// vertices are every boundary cell of the free space (traced with CHAIN_APPROX_NONE) and the
// two ends of each cut; asf's regions are label rasters, so their outlines are traced with
// CHAIN_APPROX_NONE all round, cuts included (a blob meeting a region only along a cut is
// found touching here, where the author's test may miss it).
#include "dude_reference_change.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <map>

namespace asf::dude::incremental {

namespace {

using Contour = std::vector<cv::Point>;

/// One stable region: its outline (frame coordinates) and its bounding box.
struct Outline {
  std::vector<Contour> contours;
  cv::Rect box;
};

std::map<int, Outline> regionOutlines(const cv::Mat& labels) {
  std::map<int, cv::Rect> boxes;
  for (int y = 0; y < labels.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x)
      if (l[x] > 0) {
        cv::Rect& b = boxes[l[x]];
        b = b.area() == 0 ? cv::Rect(x, y, 1, 1) : (b | cv::Rect(x, y, 1, 1));
      }
  }
  std::map<int, Outline> out;
  for (const auto& [id, box] : boxes) {
    const cv::Mat mine = labels(box) == id;
    Outline& o = out[id];
    cv::findContours(mine, o.contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, box.tl());
    o.box = box;
  }
  return out;
}

bool touches(const Contour& a, const cv::Rect& a_box, const Outline& b) {
  const cv::Rect near(a_box.x - 2, a_box.y - 2, a_box.width + 4, a_box.height + 4);
  if ((near & b.box).area() == 0) return false;
  for (const Contour& c : b.contours)
    for (const cv::Point& p : c)
      for (const cv::Point& q : a) {
        const cv::Point d = p - q;
        if (d.x * d.x + d.y * d.y < 4) return true;
      }
  return false;
}

}  // namespace

ReferenceChange referenceChange(const cv::Mat& free, const cv::Mat& labels, int min_side_cells) {
  CV_Assert(free.type() == CV_8U && labels.type() == CV_32S && free.size() == labels.size());
  ReferenceChange r;
  const std::map<int, Outline> regions = regionOutlines(labels);
  // Stable: every region's outline filled; new space is free space outside all of them.
  cv::Mat stable(free.size(), CV_8U, cv::Scalar(0));
  for (const auto& [id, o] : regions) cv::drawContours(stable, o.contours, -1, cv::Scalar(1), cv::FILLED);
  cv::Mat fresh = free.clone();
  fresh.setTo(0, stable);
  std::vector<Contour> blobs;
  cv::findContours(fresh, blobs, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  const double min_area = static_cast<double>(min_side_cells) * min_side_cells;
  cv::Mat expanded(free.size(), CV_8U, cv::Scalar(0));
  std::vector<int> redo_ids;
  for (std::size_t i = 0; i < blobs.size(); ++i) {
    if (cv::contourArea(blobs[i]) <= min_area) {
      ++r.blobs_small;
      continue;
    }
    const cv::Rect box = cv::boundingRect(blobs[i]);
    bool kept = false;
    for (const auto& [id, o] : regions)
      if (touches(blobs[i], box, o)) {
        redo_ids.push_back(id);
        kept = true;
      }
    if (!kept) {
      ++r.blobs_apart;
      continue;
    }
    ++r.blobs_kept;
    cv::drawContours(expanded, blobs, static_cast<int>(i), cv::Scalar(1), cv::FILLED);
  }
  std::sort(redo_ids.begin(), redo_ids.end());
  redo_ids.erase(std::unique(redo_ids.begin(), redo_ids.end()), redo_ids.end());
  for (const int id : redo_ids)
    cv::drawContours(expanded, regions.at(id).contours, -1, cv::Scalar(1), cv::FILLED);
  r.regions = std::move(redo_ids);
  // The union's outer outlines, filled: what the author's code decomposes again.
  std::vector<Contour> outer;
  cv::findContours(expanded, outer, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  r.redo = cv::Mat(free.size(), CV_8U, cv::Scalar(0));
  cv::drawContours(r.redo, outer, -1, cv::Scalar(1), cv::FILLED);
  r.box = cv::boundingRect(r.redo);
  return r;
}

}  // namespace asf::dude::incremental
