#include <asf/errors.h>
#include <asf/segmentation.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <unordered_map>

namespace asf {

RegionId LabelImage::atPoint(double x, double y) const {
  if (resolution <= 0) return 0;
  const int cx = static_cast<int>(std::floor((x - origin_x) / resolution));
  const int cy = static_cast<int>(std::floor((y - origin_y) / resolution));
  if (cx < 0 || cy < 0 || cx >= width || cy >= height) return 0;
  return at(cx, cy);
}

const Region* Segmentation::find(RegionId id) const {
  for (const auto& r : regions)
    if (r.id == id) return &r;
  return nullptr;
}

namespace {

struct Provisional {
  RegionId label = 0;  // provisional label
  RegionId id = 0;     // final id
  long cells = 0;
  double sx = 0, sy = 0;  // sums of cell indices, for the centroid
  int min_x = 0, min_y = 0, max_x = -1, max_y = -1;
};

// Outer boundary and holes of the cells labelled `label`, through the centres of border cells.
void boundary(const LabelImage& L, const Provisional& p, Region& r) {
  const int bw = p.max_x - p.min_x + 1, bh = p.max_y - p.min_y + 1;
  cv::Mat mask(bh + 2, bw + 2, CV_8U, cv::Scalar(0));  // one-cell zero border
  for (int y = 0; y < bh; ++y)
    for (int x = 0; x < bw; ++x)
      if (L.at(p.min_x + x, p.min_y + y) == p.label) mask.at<uchar>(y + 1, x + 1) = 255;
  std::vector<std::vector<cv::Point>> cs;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(mask, cs, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE,
                   cv::Point(p.min_x - 1, p.min_y - 1));
  auto toPolygon = [&](const std::vector<cv::Point>& c) {
    Polygon poly;
    poly.reserve(c.size());
    for (const auto& q : c)
      poly.push_back({L.origin_x + (q.x + 0.5) * L.resolution,
                      L.origin_y + (q.y + 0.5) * L.resolution});
    return poly;
  };
  // Holes belong to the outer contour they sit in; keep the largest piece and its holes.
  int best = -1;
  double best_area = -1;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    if (hierarchy[i][3] >= 0) continue;
    const double a = std::abs(cv::contourArea(cs[i]));
    if (a > best_area || best < 0) {
      best_area = a;
      best = static_cast<int>(i);
    }
  }
  if (best < 0) return;
  r.outer = toPolygon(cs[static_cast<std::size_t>(best)]);
  if (polygonArea(r.outer) < 0) std::reverse(r.outer.begin(), r.outer.end());
  for (std::size_t i = 0; i < cs.size(); ++i) {
    if (hierarchy[i][3] != best) continue;
    Polygon h = toPolygon(cs[i]);
    if (polygonArea(h) > 0) std::reverse(h.begin(), h.end());
    r.holes.push_back(std::move(h));
  }
}

}  // namespace

Segmentation regionsFromLabels(LabelImage L, const Segmentation* previous, RegionId* max_issued,
                               std::uint64_t map_version, double min_area) {
  if (L.width < 0 || L.height < 0 ||
      L.labels.size() != static_cast<std::size_t>(L.width) * static_cast<std::size_t>(L.height))
    throw Error("regionsFromLabels: label image has " + std::to_string(L.labels.size()) +
                " cells, expected " + std::to_string(L.width) + " x " + std::to_string(L.height));
  Segmentation out;
  out.map_version = map_version;
  const double cell_area = L.resolution * L.resolution;

  // Labels come in long runs along rows: remember the last look-up instead of hashing every
  // cell (this function runs on every incremental map update).
  std::unordered_map<RegionId, std::size_t> index;
  std::vector<Provisional> prov;
  RegionId run_label = 0;
  std::size_t run_index = 0;
  for (int cy = 0; cy < L.height; ++cy) {
    const RegionId* row = L.labels.data() + static_cast<std::size_t>(cy) * L.width;
    for (int cx = 0; cx < L.width; ++cx) {
      const RegionId l = row[cx];
      if (l <= 0) continue;
      if (l != run_label || prov.empty()) {
        auto [it, fresh] = index.emplace(l, prov.size());
        if (fresh) {
          Provisional p;
          p.label = l;
          p.min_x = p.max_x = cx;
          p.min_y = p.max_y = cy;
          prov.push_back(p);
        }
        run_label = l;
        run_index = it->second;
      }
      Provisional& p = prov[run_index];
      ++p.cells;
      p.sx += cx;
      p.sy += cy;
      if (cx < p.min_x) p.min_x = cx;
      if (cx > p.max_x) p.max_x = cx;
      if (cy > p.max_y) p.max_y = cy;  // rows ascend: min_y is the first row seen
    }
  }
  auto indexOf = [&](RegionId l) {
    if (l != run_label) {
      run_label = l;
      run_index = index.at(l);
    }
    return run_index;
  };

  // Drop small regions.
  std::vector<char> keep(prov.size(), 1);
  bool dropped = false;
  for (std::size_t i = 0; i < prov.size(); ++i)
    if (prov[i].cells * cell_area < min_area) keep[i] = 0, dropped = true;
  if (dropped)
    for (auto& l : L.labels)
      if (l > 0 && !keep[indexOf(l)]) l = 0;

  // Reuse ids by largest overlap with the previous segmentation.
  RegionId issued = max_issued ? *max_issued : 0;
  std::vector<std::map<RegionId, long>> overlap;
  bool same_raster = false;
  if (previous) {
    for (const auto& r : previous->regions) issued = std::max(issued, r.id);
    const LabelImage& P = previous->labels;
    // Same raster (the usual case): compare cell by cell, no coordinate conversion.
    same_raster = P.width == L.width && P.height == L.height &&
                             P.resolution == L.resolution && P.origin_x == L.origin_x &&
                             P.origin_y == L.origin_y && P.labels.size() == L.labels.size();
    overlap.assign(prov.size(), {});
    // Counted per run of equal (new, old) label pairs, not per cell.
    RegionId pair_new = 0, pair_old = 0;
    long pair_n = 0;
    auto flush = [&] {
      if (pair_n > 0) overlap[indexOf(pair_new)][pair_old] += pair_n;
      pair_n = 0;
    };
    for (int cy = 0; cy < L.height; ++cy)
      for (int cx = 0; cx < L.width; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cy) * L.width + cx;
        const RegionId l = L.labels[c];
        if (l <= 0) continue;
        const RegionId old = same_raster ? P.labels[c]
                                         : P.atPoint(L.origin_x + (cx + 0.5) * L.resolution,
                                                     L.origin_y + (cy + 0.5) * L.resolution);
        if (old <= 0) continue;
        if (l != pair_new || old != pair_old) {
          flush();
          pair_new = l;
          pair_old = old;
        }
        ++pair_n;
      }
    flush();
    std::vector<std::tuple<long, std::size_t, RegionId>> pairs;  // overlap, region, old id
    for (std::size_t i = 0; i < prov.size(); ++i)
      if (keep[i])
        for (const auto& [id, n] : overlap[i]) pairs.emplace_back(n, i, id);
    // Largest overlap first; ties by smaller provisional index, then smaller id.
    std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
      if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
      if (std::get<1>(a) != std::get<1>(b)) return std::get<1>(a) < std::get<1>(b);
      return std::get<2>(a) < std::get<2>(b);
    });
    std::map<RegionId, bool> used;
    for (const auto& [n, i, id] : pairs) {
      if (prov[i].id != 0 || used[id]) continue;
      prov[i].id = id;
      used[id] = true;
    }
  }
  for (std::size_t i = 0; i < prov.size(); ++i)
    if (keep[i] && prov[i].id == 0) prov[i].id = ++issued;
  if (max_issued) *max_issued = issued;

  for (std::size_t i = 0; i < prov.size(); ++i) {
    if (!keep[i]) continue;
    const Provisional& p = prov[i];
    Region r;
    r.id = p.id;
    r.area = static_cast<double>(p.cells) * cell_area;
    r.centroid = {L.origin_x + (p.sx / p.cells + 0.5) * L.resolution,
                  L.origin_y + (p.sy / p.cells + 0.5) * L.resolution};
    // A region whose cells are exactly those of the previous region with its id (same
    // raster, full overlap, same count) keeps its boundary: most regions on an incremental
    // update, and the per-region contour tracing is the costly part here.
    const Region* old = same_raster ? previous->find(p.id) : nullptr;
    if (old && overlap[i].count(p.id) && overlap[i].at(p.id) == p.cells &&
        std::llround(old->area / cell_area) == p.cells) {
      r.outer = old->outer;
      r.holes = old->holes;
    } else {
      boundary(L, p, r);
    }
    out.regions.push_back(std::move(r));
  }
  // Final ids into the image.
  for (auto& l : L.labels)
    if (l > 0) l = prov[indexOf(l)].id;
  std::sort(out.regions.begin(), out.regions.end(),
            [](const Region& a, const Region& b) { return a.id < b.id; });
  out.labels = std::move(L);
  return out;
}

}  // namespace asf
