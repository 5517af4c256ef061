// Two segmentations compared region by region (segmentation_eval.h, compareSegmentations):
// how closely asf's decomposition reproduces the reference implementation's own outputs.
#include <asf/errors.h>
#include <asf/evaluation/segmentation_eval.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

namespace asf::evaluation {

namespace {

using Label = std::int32_t;

std::map<Label, std::size_t> sizes(const io::LabelRaster& r) {
  std::map<Label, std::size_t> n;
  for (Label l : r.labels)
    if (l > 0) ++n[l];
  return n;
}

/// Labels with more than `min_pixels` pixels.
std::map<Label, std::size_t> counted(const std::map<Label, std::size_t>& all, int min_pixels) {
  std::map<Label, std::size_t> out;
  for (const auto& [l, n] : all)
    if (n > static_cast<std::size_t>(std::max(0, min_pixels))) out.emplace(l, n);
  return out;
}

double pairs(double n) { return 0.5 * n * (n - 1); }

/// Area-weighted mean over `from`'s regions of each one's best IoU with a region of `to`.
double bestMatchIou(const std::map<Label, std::size_t>& from, const std::map<Label, std::size_t>& to,
                    const std::map<std::pair<Label, Label>, std::size_t>& overlap, bool from_is_first) {
  double weighted = 0, total = 0;
  std::map<Label, double> best;
  for (const auto& [key, both] : overlap) {
    const Label f = from_is_first ? key.first : key.second, t = from_is_first ? key.second : key.first;
    const auto fi = from.find(f), ti = to.find(t);
    if (fi == from.end() || ti == to.end()) continue;
    const double iou = static_cast<double>(both) / static_cast<double>(fi->second + ti->second - both);
    best[f] = std::max(best[f], iou);
  }
  for (const auto& [l, n] : from) {
    weighted += static_cast<double>(n) * (best.count(l) ? best[l] : 0.0);
    total += static_cast<double>(n);
  }
  return total > 0 ? weighted / total : 0.0;
}

}  // namespace

SegmentationAgreement compareSegmentations(const io::LabelRaster& segmentation,
                                           const io::LabelRaster& reference, int min_pixels) {
  if (segmentation.width != reference.width || segmentation.height != reference.height ||
      segmentation.labels.size() != reference.labels.size())
    throw Error("compareSegmentations: the segmentation is " + std::to_string(segmentation.width) +
                " x " + std::to_string(segmentation.height) + ", the reference " +
                std::to_string(reference.width) + " x " + std::to_string(reference.height));
  const auto seg = counted(sizes(segmentation), min_pixels);
  const auto ref = counted(sizes(reference), min_pixels);
  std::map<std::pair<Label, Label>, std::size_t> overlap;  // (segment, reference region)
  for (std::size_t i = 0; i < segmentation.labels.size(); ++i) {
    const Label s = segmentation.labels[i], r = reference.labels[i];
    if (s > 0 && r > 0) ++overlap[{s, r}];
  }
  SegmentationAgreement a;
  a.segments = static_cast<int>(seg.size());
  a.reference_regions = static_cast<int>(ref.size());
  a.iou_reference = bestMatchIou(ref, seg, overlap, false);
  a.iou_segmentation = bestMatchIou(seg, ref, overlap, true);
  // The adjusted Rand index (Hubert and Arabie 1985) over the pixels in a counted region on
  // both sides: the contingency table is `overlap` restricted to counted labels.
  std::map<Label, double> row, col;
  double n = 0, sum_ij = 0;
  for (const auto& [key, both] : overlap) {
    if (!seg.count(key.first) || !ref.count(key.second)) continue;
    const double v = static_cast<double>(both);
    row[key.first] += v;
    col[key.second] += v;
    n += v;
    sum_ij += pairs(v);
  }
  a.pixels_compared = static_cast<std::size_t>(n);
  double sum_a = 0, sum_b = 0;
  for (const auto& [l, v] : row) sum_a += pairs(v);
  for (const auto& [l, v] : col) sum_b += pairs(v);
  const double expected = n > 1 ? sum_a * sum_b / pairs(n) : 0.0;
  const double max_index = 0.5 * (sum_a + sum_b);
  // Both sides one region (or nothing compared): identical partitions, index 1 by convention.
  a.ari = max_index - expected == 0 ? 1.0 : (sum_ij - expected) / (max_index - expected);
  return a;
}

}  // namespace asf::evaluation
