#pragma once
// The thesis author's incremental rule (lfermin77/Incremental_DuDe_ROS, its incremental
// decomposer), as asf's segmenter_dude applies it with `change_rule = reference`: the regions
// of the last decomposition are stable and keep their outline; only free space outside them is
// new; a blob of new space is dropped while its outline encloses no more than a square of
// `min_side` (the author's safety distance) or while it touches no stable region; the stable
// regions a kept blob touches are decomposed again together with it.
#include <opencv2/core.hpp>

#include <vector>

namespace asf::dude::incremental {

struct ReferenceChange {
  cv::Mat redo;              ///< CV_8U 0/1, the frame's size: the cells decomposed again
  cv::Rect box;              ///< bounding box of `redo`; empty: nothing changes
  std::vector<int> regions;  ///< the stable regions decomposed again, ascending
  int blobs_kept = 0;
  int blobs_small = 0;  ///< dropped: no larger than the square of min_side
  int blobs_apart = 0;  ///< dropped: touching no stable region
};

/// `free`: CV_8U 0/1, the pre-processed free space now; `labels`: CV_32S, the last
/// decomposition's regions (> 0) in the same frame. `min_side_cells`: the square's side in
/// cells, rounded down as the author's code does.
ReferenceChange referenceChange(const cv::Mat& free, const cv::Mat& labels, int min_side_cells);

}  // namespace asf::dude::incremental
