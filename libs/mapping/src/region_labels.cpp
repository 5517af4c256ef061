#include <asf/errors.h>
#include <asf/mapping/region_labels.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <unordered_map>

namespace asf::mapping {

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
      poly.push_back(
          {L.origin_x + (q.x + 0.5) * L.resolution, L.origin_y + (q.y + 0.5) * L.resolution});
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

bool sameRaster(const LabelImage& a, const LabelImage& b) {
  return a.width == b.width && a.height == b.height && a.resolution == b.resolution &&
         a.origin_x == b.origin_x && a.origin_y == b.origin_y && a.labels.size() == b.labels.size();
}

void checkSize(const LabelImage& L, const char* who) {
  if (L.width < 0 || L.height < 0 ||
      L.labels.size() != static_cast<std::size_t>(L.width) * static_cast<std::size_t>(L.height))
    throw Error(std::string(who) + ": label image has " + std::to_string(L.labels.size()) +
                " cells, expected " + std::to_string(L.width) + " x " + std::to_string(L.height));
}

/// Statistics of provisional labels, in order of first appearance (row-major).
struct Tally {
  std::unordered_map<RegionId, std::size_t> index;
  std::vector<Provisional> prov;
  // Labels come in long runs along rows: remember the last look-up instead of hashing every
  // cell (this runs on every incremental map update).
  RegionId run_label = 0;
  std::size_t run_index = 0;

  std::size_t indexOf(RegionId l) {
    if (l != run_label || prov.empty()) {
      run_label = l;
      run_index = index.at(l);
    }
    return run_index;
  }

  /// Adds the cells of `box` whose label l > 0 satisfies counted(l) (asked once per run).
  template <class Counted>
  void add(const LabelImage& L, const CellBox& box, Counted counted) {
    RegionId last = 0;
    bool last_counted = false;
    Provisional* p = nullptr;
    for (int cy = box.y; cy < box.y + box.height; ++cy) {
      const RegionId* row = L.labels.data() + static_cast<std::size_t>(cy) * L.width;
      for (int cx = box.x; cx < box.x + box.width; ++cx) {
        const RegionId l = row[cx];
        if (l <= 0) continue;
        if (l != last) {
          last = l;
          last_counted = counted(l);
          p = nullptr;
          if (!last_counted) continue;
          auto [it, fresh] = index.emplace(l, prov.size());
          if (fresh) {
            Provisional q;
            q.label = l;
            q.min_x = q.max_x = cx;
            q.min_y = q.max_y = cy;
            prov.push_back(q);
          }
          p = &prov[it->second];
        }
        if (!last_counted) continue;
        ++p->cells;
        p->sx += cx;
        p->sy += cy;
        if (cx < p->min_x) p->min_x = cx;
        if (cx > p->max_x) p->max_x = cx;
        if (cy > p->max_y) p->max_y = cy;  // rows ascend: min_y is the first row seen
      }
    }
    run_label = 0;
  }
};

/// Cells of each tallied label per previous id, over `box` (counted per run of equal
/// (new, old) label pairs, not per cell).
std::vector<std::map<RegionId, long>> overlaps(const LabelImage& L, const LabelImage& P,
                                               bool same_raster, const CellBox& box, Tally& t) {
  std::vector<std::map<RegionId, long>> overlap(t.prov.size());
  RegionId pair_new = 0, pair_old = 0;
  long pair_n = 0;
  auto flush = [&] {
    if (pair_n > 0) overlap[t.indexOf(pair_new)][pair_old] += pair_n;
    pair_n = 0;
  };
  RegionId last = 0;
  bool tallied = false;
  for (int cy = box.y; cy < box.y + box.height; ++cy)
    for (int cx = box.x; cx < box.x + box.width; ++cx) {
      const std::size_t c = static_cast<std::size_t>(cy) * L.width + cx;
      const RegionId l = L.labels[c];
      if (l <= 0) continue;
      if (l != last) last = l, tallied = t.index.count(l) > 0;
      if (!tallied) continue;
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
  return overlap;
}

/// Final ids: previous ids by largest overlap, greedily (largest overlap first; ties by
/// smaller provisional index, then smaller id), each at most once; fresh ids above `issued`
/// for the others, in provisional order.
void assignIds(std::vector<Provisional>& prov, const std::vector<char>& keep,
               const std::vector<std::map<RegionId, long>>& overlap, RegionId& issued) {
  std::vector<std::tuple<long, std::size_t, RegionId>> pairs;  // overlap, region, old id
  for (std::size_t i = 0; i < overlap.size(); ++i)
    if (keep[i])
      for (const auto& [id, n] : overlap[i]) pairs.emplace_back(n, i, id);
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
    if (std::get<1>(a) != std::get<1>(b)) return std::get<1>(a) < std::get<1>(b);
    return std::get<2>(a) < std::get<2>(b);
  });
  std::unordered_map<RegionId, bool> used;
  for (const auto& [n, i, id] : pairs) {
    if (prov[i].id != 0 || used[id]) continue;
    prov[i].id = id;
    used[id] = true;
  }
  for (std::size_t i = 0; i < prov.size(); ++i)
    if (keep[i] && prov[i].id == 0) prov[i].id = ++issued;
}

/// Region of provisional label p (final labels not yet written into L).
Region makeRegion(const LabelImage& L, const Provisional& p, const Segmentation* previous,
                  bool same_raster, const std::map<RegionId, long>& overlap) {
  const double cell_area = L.resolution * L.resolution;
  Region r;
  r.id = p.id;
  r.area = static_cast<double>(p.cells) * cell_area;
  r.centroid = {L.origin_x + (p.sx / p.cells + 0.5) * L.resolution,
                L.origin_y + (p.sy / p.cells + 0.5) * L.resolution};
  // A region whose cells are exactly those of the previous region with its id (same
  // raster, full overlap, same count) keeps its boundary: most regions on an incremental
  // update, and the per-region contour tracing is the costly part here.
  const Region* old = same_raster && previous ? previous->find(p.id) : nullptr;
  const auto it = overlap.find(p.id);
  if (old && it != overlap.end() && it->second == p.cells &&
      std::llround(old->area / cell_area) == p.cells) {
    r.outer = old->outer;
    r.holes = old->holes;
  } else {
    boundary(L, p, r);
  }
  return r;
}

CellBox boxOf(const Provisional& p) {
  return {p.min_x, p.min_y, p.max_x - p.min_x + 1, p.max_y - p.min_y + 1};
}

CellBox unite(const CellBox& a, const CellBox& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  const int x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const int x1 = std::max(a.x + a.width, b.x + b.width),
            y1 = std::max(a.y + a.height, b.y + b.height);
  return {x0, y0, x1 - x0, y1 - y0};
}

CellBox clip(const CellBox& a, int width, int height) {
  const int x0 = std::max(a.x, 0), y0 = std::max(a.y, 0);
  const int x1 = std::min(a.x + a.width, width), y1 = std::min(a.y + a.height, height);
  if (x1 <= x0 || y1 <= y0) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace

Segmentation regionsFromLabels(LabelImage L, const Segmentation* previous, RegionId* max_issued,
                               std::uint64_t map_version, double min_area, RegionBoxes* boxes) {
  checkSize(L, "regionsFromLabels");
  Segmentation out;
  out.map_version = map_version;
  const double cell_area = L.resolution * L.resolution;
  const CellBox all{0, 0, L.width, L.height};
  Tally t;
  t.add(L, all, [](RegionId) { return true; });
  std::vector<Provisional>& prov = t.prov;

  // Drop small regions.
  std::vector<char> keep(prov.size(), 1);
  bool dropped = false;
  for (std::size_t i = 0; i < prov.size(); ++i)
    if (prov[i].cells * cell_area < min_area) keep[i] = 0, dropped = true;
  if (dropped)
    for (auto& l : L.labels)
      if (l > 0 && !keep[t.indexOf(l)]) l = 0;

  // Reuse ids by largest overlap with the previous segmentation.
  RegionId issued = max_issued ? *max_issued : 0;
  std::vector<std::map<RegionId, long>> overlap(prov.size());
  bool same_raster = false;
  if (previous) {
    for (const auto& r : previous->regions) issued = std::max(issued, r.id);
    // Same raster (the usual case): compare cell by cell, no coordinate conversion.
    same_raster = sameRaster(previous->labels, L);
    overlap = overlaps(L, previous->labels, same_raster, all, t);
  }
  assignIds(prov, keep, overlap, issued);
  if (max_issued) *max_issued = issued;

  if (boxes) boxes->clear();
  for (std::size_t i = 0; i < prov.size(); ++i) {
    if (!keep[i]) continue;
    out.regions.push_back(makeRegion(L, prov[i], previous, same_raster, overlap[i]));
    if (boxes) (*boxes)[prov[i].id] = boxOf(prov[i]);
  }
  // Final ids into the image.
  for (auto& l : L.labels)
    if (l > 0) l = prov[t.indexOf(l)].id;
  std::sort(out.regions.begin(), out.regions.end(),
            [](const Region& a, const Region& b) { return a.id < b.id; });
  out.labels = std::move(L);
  return out;
}

Segmentation regionsFromLabelsInWindow(LabelImage L, const Segmentation& previous,
                                       RegionBoxes& boxes, CellBox window, RegionId* max_issued,
                                       std::uint64_t map_version, double min_area) {
  checkSize(L, "regionsFromLabelsInWindow");
  const LabelImage& P = previous.labels;
  auto full = [&] {
    return regionsFromLabels(std::move(L), &previous, max_issued, map_version, min_area, &boxes);
  };
  if (!sameRaster(P, L) || boxes.size() != previous.regions.size()) return full();
  window = clip(window, L.width, L.height);
  // Touched labels: those with a cell in the window, before or after. Every other region
  // kept all its cells (outside the window nothing changed), its id and its outline.
  std::unordered_map<RegionId, char> touched;
  for (int cy = window.y; cy < window.y + window.height; ++cy) {
    const std::size_t row = static_cast<std::size_t>(cy) * L.width;
    RegionId last_l = 0, last_p = 0;
    for (int cx = window.x; cx < window.x + window.width; ++cx) {
      const RegionId l = L.labels[row + cx], p = P.labels[row + cx];
      if (l > 0 && l != last_l) touched.emplace(l, 1), last_l = l;
      if (p > 0 && p != last_p) touched.emplace(p, 1), last_p = p;
    }
  }
  // Every cell of a touched label lies in the window or in its previous region's box.
  CellBox span = window;
  for (const auto& [id, unused] : touched) {
    const auto it = boxes.find(id);
    if (it != boxes.end()) {
      span = unite(span, it->second);
    } else if (previous.find(id)) {
      return full();  // a region without a box: the boxes are not previous'
    }
  }
  span = clip(span, L.width, L.height);

  Segmentation out;
  out.map_version = map_version;
  const double cell_area = L.resolution * L.resolution;
  Tally t;
  t.add(L, span, [&](RegionId l) { return touched.count(l) > 0; });
  std::vector<Provisional>& prov = t.prov;
  std::vector<char> keep(prov.size(), 1);
  for (std::size_t i = 0; i < prov.size(); ++i)
    if (prov[i].cells * cell_area < min_area) keep[i] = 0;
  RegionId issued = max_issued ? *max_issued : 0;
  for (const auto& r : previous.regions) issued = std::max(issued, r.id);
  std::vector<std::map<RegionId, long>> overlap = overlaps(L, P, true, span, t);
  assignIds(prov, keep, overlap, issued);
  if (max_issued) *max_issued = issued;

  // Untouched regions as they were; touched ones measured again.
  for (const Region& r : previous.regions)
    if (!touched.count(r.id)) out.regions.push_back(r);
  for (const auto& [id, unused] : touched) boxes.erase(id);
  for (std::size_t i = 0; i < prov.size(); ++i) {
    if (!keep[i]) continue;
    out.regions.push_back(makeRegion(L, prov[i], &previous, true, overlap[i]));
    boxes[prov[i].id] = boxOf(prov[i]);
  }
  for (int cy = span.y; cy < span.y + span.height; ++cy) {
    RegionId* row = L.labels.data() + static_cast<std::size_t>(cy) * L.width;
    for (int cx = span.x; cx < span.x + span.width; ++cx) {
      RegionId& l = row[cx];
      if (l <= 0) continue;
      const auto it = t.index.find(l);
      if (it != t.index.end()) l = keep[it->second] ? prov[it->second].id : 0;
    }
  }
  std::sort(out.regions.begin(), out.regions.end(),
            [](const Region& a, const Region& b) { return a.id < b.id; });
  out.labels = std::move(L);
  return out;
}

}  // namespace asf::mapping
