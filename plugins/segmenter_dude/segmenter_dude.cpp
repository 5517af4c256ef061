// segmenter_dude: contour-based topological segmentation (thesis ch. 4). Grid -> free mask
// -> contours with holes -> polygons in metres -> Dual-Space Decomposition (dude.h) ->
// pieces rasterized into a label image -> asf::regionsFromLabels.
// Incremental mode (thesis Algorithm 3): only regions touching the changed free space are
// merged with it and decomposed again; the others keep their cells, and so their ids.
#include "dude.h"
#include "dude_thesis.h"

#include <asf/errors.h>
#include <asf/segmenter.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <unordered_map>
#include <vector>

namespace {

using Grid = mrpt::maps::COccupancyGridMap2D;

struct Frame {
  int width = 0, height = 0;
  double resolution = 0, origin_x = 0, origin_y = 0;
};

class DudeSegmenter final : public asf::Segmenter {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    free_threshold_ = p.getDouble("free_threshold");
    occupied_threshold_ = p.getDouble("occupied_threshold");
    if (occupied_threshold_ < free_threshold_)
      p.fail("occupied_threshold", "must be >= free_threshold");
    gap_closing_ = p.getDouble("gap_closing");
    obstacle_dilation_ = p.getDouble("obstacle_dilation");
    simplify_tolerance_ = p.getDouble("simplify_tolerance");
    options_.max_concavity = p.getDouble("max_concavity");
    options_.min_hole_extent = p.getDouble("min_hole_extent");
    options_.resolve_radius = p.getDouble("resolve_radius");
    min_region_area_ = p.getDouble("min_region_area");
    min_component_area_ = p.getDouble("min_component_area");
    incremental_ = p.getBool("incremental");
    rebuild_full_fraction_ = p.getDouble("rebuild_full_fraction");
    max_cells_ = p.getInt("max_cells");
    merge_concavity_ = p.getDouble("merge_concavity");
    merge_min_border_ = p.getDouble("merge_min_border");
    thesis_ = p.getString("variant") == "thesis";
    thesis_options_.max_concavity = options_.max_concavity;
    thesis_options_.approximation = p.getString("approximation") == "douglas_peucker"
                                        ? asf::dude::thesis::Approximation::DouglasPeucker
                                        : asf::dude::thesis::Approximation::Chains;
    state_ = State{};
  }

  asf::Segmentation segment(const asf::GridMap& map, const asf::Segmentation* previous) override {
    asf::Segmentation out;
    out.map_version = map.version;
    if (!map.grid) return out;
    const Grid& grid = *map.grid;
    Frame f;
    f.width = static_cast<int>(grid.getSizeX());
    f.height = static_cast<int>(grid.getSizeY());
    // Checked before anything is allocated: the working images take ~12 bytes per cell.
    const std::int64_t cells = static_cast<std::int64_t>(f.width) * f.height;
    if (cells > max_cells_)
      throw asf::InputError("dude: the map has " + std::to_string(f.width) + " x " +
                            std::to_string(f.height) + " = " + std::to_string(cells) +
                            " cells, more than max_cells = " + std::to_string(max_cells_) +
                            " (raise [dude] max_cells, or use a coarser map)");
    f.resolution = grid.getResolution();
    f.origin_x = grid.getXMin();
    f.origin_y = grid.getYMin();
    out.labels.width = f.width;
    out.labels.height = f.height;
    out.labels.resolution = f.resolution;
    out.labels.origin_x = f.origin_x;
    out.labels.origin_y = f.origin_y;
    out.labels.labels.assign(static_cast<std::size_t>(f.width) * f.height, 0);
    if (f.width == 0 || f.height == 0) {
      state_ = State{};
      return out;
    }

    cv::Mat free, obstacle;
    thresholdGrid(grid, free, obstacle);

    cv::Mat labels, proc;  // provisional labels (CV_32S), decomposed free space
    int next_label = 1;
    const cv::Rect full(0, 0, f.width, f.height);
    cv::Rect work = full;  // where labels may change
    bool can_update = incremental_ && state_.valid && previous &&
                      previous->map_version == state_.version && alignState(f);
    // Cells whose free state changed since the last call (all cells without a comparable one).
    const std::int64_t changed =
        can_update ? cv::countNonZero(free != state_.free) : static_cast<std::int64_t>(f.width) * f.height;
    // A rebuilt map (loop closure: keyframes moved) stays incremental while the change is
    // local: regions far from it keep their cells.
    if (can_update && map.rebuilt &&
        changed > rebuild_full_fraction_ * std::max(1, cv::countNonZero(free)))
      can_update = false;
    if (can_update) {
      labels = updateIncrementally(free, obstacle, f, &next_label, &proc, &work);
    } else {
      proc = preprocess(free, obstacle, f.resolution);
      labels = cv::Mat(f.height, f.width, CV_32S, cv::Scalar(0));
      decomposeInto(proc, full, f, labels, &next_label);
    }
    const int first_fresh = can_update ? first_fresh_ : 1;
    if (work.area() > 0) {
      // Post-processing on the changed window only (the whole map in batch mode). Fresh
      // labels lie entirely inside it, so the steps that look at whole regions only
      // consider fresh ones in an update.
      cv::Mat lab_w = labels(work).clone(), free_w = free(work).clone();
      // The thesis variant keeps every piece DuDe makes, however small; only free components
      // below min_component_area are left out (the rooms variant drops small regions later).
      const int min_new_cells =
          thesis_ ? static_cast<int>(std::ceil(min_component_area_ / (f.resolution * f.resolution))) : 0;
      completeLabels(free_w, lab_w, &next_label, min_new_cells);
      if (!thesis_) {  // the published algorithm has no post-processing
        mergeSmallRegions(lab_w, next_label, f.resolution, first_fresh);
        mergeConvexNeighbours(lab_w, next_label, first_fresh, f);
      }
      lab_w.copyTo(labels(work));
    }

    asf::LabelImage& L = out.labels;
    for (int cy = 0; cy < f.height; ++cy) {
      const int* row = labels.ptr<int>(cy);
      std::copy(row, row + f.width, L.labels.begin() + static_cast<std::size_t>(cy) * f.width);
    }
    out = asf::regionsFromLabels(std::move(L), previous, &max_issued_, map.version,
                                 thesis_ ? 0.0 : min_component_area_);
    out.mode = can_update ? asf::Segmentation::Mode::Incremental : asf::Segmentation::Mode::Full;
    out.changed_cells = changed;
    if (incremental_) saveState(out, free, proc, f);
    else state_ = State{};
    MRPT_LOG_DEBUG_STREAM("dude: " << out.regions.size() << " regions ("
                                   << (can_update ? "incremental" : "full") << ")");
    return out;
  }

 private:
  struct State {
    bool valid = false;
    std::uint64_t version = 0;
    Frame frame;
    cv::Mat free, proc, ids;  ///< masks (CV_8U) and final region ids (CV_32S)
    std::map<int, cv::Rect> boxes;  ///< cell bounding box of every region
    int max_id = 0;
  };

  void thresholdGrid(const Grid& grid, cv::Mat& free, cv::Mat& obstacle) const {
    const int W = static_cast<int>(grid.getSizeX()), H = static_cast<int>(grid.getSizeY());
    free = cv::Mat(H, W, CV_8U, cv::Scalar(0));
    obstacle = cv::Mat(H, W, CV_8U, cv::Scalar(0));
    // MRPT cells hold p(free): occupancy = 1 - cell. A table over the raw log-odds cells
    // avoids a conversion per cell (the 8-bit cell type has 256 values).
    using Cell = Grid::cellType;
    const bool table = sizeof(Cell) == 1;
    unsigned char lut[256] = {};
    if (table)
      for (int v = -128; v < 128; ++v) {
        const double occ = 1.0 - Grid::l2p(static_cast<Cell>(v));
        lut[static_cast<unsigned char>(v)] =
            (occ < free_threshold_ ? 1 : 0) | (occ > occupied_threshold_ ? 2 : 0);
      }
    for (int cy = 0; cy < H; ++cy) {
      const Cell* row = grid.getRow(cy);
      unsigned char* fr = free.ptr<unsigned char>(cy);
      unsigned char* ob = obstacle.ptr<unsigned char>(cy);
      for (int cx = 0; cx < W; ++cx) {
        unsigned char c;
        if (table) {
          c = lut[static_cast<unsigned char>(row[cx])];
        } else {
          const double occ = 1.0 - Grid::l2p(row[cx]);
          c = (occ < free_threshold_ ? 1 : 0) | (occ > occupied_threshold_ ? 2 : 0);
        }
        fr[cx] = c & 1;
        ob[cx] = (c >> 1) & 1;
      }
    }
  }

  /// Free space the decomposition sees: gaps between obstacles narrower than gap_closing
  /// closed (closing of the obstacle mask), then obstacles grown by obstacle_dilation.
  cv::Mat preprocess(const cv::Mat& free, const cv::Mat& obstacle, double res) const {
    cv::Mat proc = free.clone();
    cv::Mat blocked = obstacle;
    const int gap_px = static_cast<int>(std::lround(gap_closing_ / res));
    if (gap_px >= 1) {
      const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(gap_px + 1, gap_px + 1));
      cv::morphologyEx(obstacle, blocked, cv::MORPH_CLOSE, k);
    }
    const int dil_px = static_cast<int>(std::lround(obstacle_dilation_ / res));
    if (dil_px >= 1) {
      const cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                                  cv::Size(2 * dil_px + 1, 2 * dil_px + 1));
      cv::dilate(blocked, blocked, k);
    }
    proc.setTo(0, blocked);
    return proc;
  }

  /// Decomposes every connected component of `mask` inside `roi` and paints its pieces into
  /// `labels` (same size as mask) with fresh labels, on cells of `mask` only.
  void decomposeInto(const cv::Mat& mask, cv::Rect roi, const Frame& f, cv::Mat& labels,
                     int* next_label) {
    cv::Mat sub = mask(roi).clone();
    std::vector<std::vector<cv::Point>> contours;
    std::vector<cv::Vec4i> hierarchy;
    cv::findContours(sub, contours, hierarchy, cv::RETR_TREE, cv::CHAIN_APPROX_SIMPLE);
    const double res = f.resolution;
    // The thesis variant takes the contours as traced (the reference simplifies them itself,
    // through its feature points); CHAIN_APPROX_SIMPLE only drops collinear cells.
    const double eps_px = thesis_ ? 0.0 : simplify_tolerance_ / res;
    const double min_px = min_component_area_ / (res * res);
    auto toMetres = [&](const std::vector<cv::Point>& c) {
      std::vector<cv::Point> s;
      if (eps_px > 0 && c.size() > 3)
        cv::approxPolyDP(c, s, eps_px, true);
      else
        s = c;
      asf::dude::Ring r;
      r.reserve(s.size());
      for (const cv::Point& p : s)
        r.push_back({f.origin_x + (roi.x + p.x + 0.5) * res, f.origin_y + (roi.y + p.y + 0.5) * res});
      return r;
    };
    std::vector<int> depth(contours.size(), -1);
    auto depthOf = [&](int i) {
      int d = 0;
      for (int p = hierarchy[i][3]; p >= 0; p = hierarchy[p][3]) ++d;
      return d;
    };
    cv::Mat piece_mask;
    std::size_t warnings = 0;
    std::string first_warning;
    for (int i = 0; i < static_cast<int>(contours.size()); ++i) {
      if (depthOf(i) % 2 != 0) continue;  // odd depth: a hole, handled with its parent
      if (std::abs(cv::contourArea(contours[i])) < min_px) continue;
      asf::dude::Shape shape;
      shape.outer = toMetres(contours[i]);
      for (int c = hierarchy[i][2]; c >= 0; c = hierarchy[c][0]) shape.holes.push_back(toMetres(contours[c]));
      const asf::dude::Result r = thesis_ ? asf::dude::thesis::decompose(shape, thesis_options_)
                                          : asf::dude::decompose(shape, options_);
      warnings += r.warnings.size();
      if (!r.warnings.empty() && first_warning.empty()) first_warning = r.warnings.front();
      for (const asf::dude::Shape& piece : r.pieces) {
        std::vector<std::vector<cv::Point>> polys;
        auto toPixels = [&](const asf::dude::Ring& ring) {
          std::vector<cv::Point> poly;
          poly.reserve(ring.size());
          // Sub-pixel vertices (8 fractional bits): cuts land where the geometry put them.
          for (const auto& v : ring)
            poly.emplace_back(
                static_cast<int>(std::lround(((v.x - f.origin_x) / res - 0.5 - roi.x) * 256)),
                static_cast<int>(std::lround(((v.y - f.origin_y) / res - 0.5 - roi.y) * 256)));
          return poly;
        };
        polys.push_back(toPixels(piece.outer));
        for (const auto& h : piece.holes) polys.push_back(toPixels(h));
        const int label = (*next_label)++;
        // Paint only inside the piece's bounding box (a full-image mask per piece is slow).
        cv::Rect pb;
        for (const auto& poly : polys)
          for (const cv::Point& q : poly) {
            const cv::Rect cell(q.x >> 8, q.y >> 8, 2, 2);
            pb = pb.area() == 0 ? cell : (pb | cell);
          }
        pb &= cv::Rect(0, 0, roi.width, roi.height);
        if (pb.area() == 0) continue;
        for (auto& poly : polys)
          for (cv::Point& q : poly) q -= cv::Point(pb.x * 256, pb.y * 256);
        piece_mask = cv::Mat::zeros(pb.size(), CV_8U);
        cv::fillPoly(piece_mask, polys, cv::Scalar(1), cv::LINE_8, 8);
        piece_mask &= sub(pb);
        labels(roi)(pb).setTo(label, piece_mask);
      }
    }
    if (warnings > 0)
      MRPT_LOG_WARN_STREAM("dude: " << warnings << " piece(s) kept undecomposed; first: "
                                    << first_warning);
  }

  /// Every free cell gets a label: cells left out by the polygons (simplification, grown
  /// obstacles, one-cell corridors) join the nearest labelled cell through free space;
  /// free components with no labelled cell at all become regions of their own, when they
  /// have at least `min_new_cells` cells (else they stay unlabelled).
  static void completeLabels(const cv::Mat& free, cv::Mat& labels, int* next_label,
                             int min_new_cells = 0) {
    const int W = free.cols, H = free.rows;
    std::deque<int> queue;
    for (int y = 0; y < H; ++y) {
      const unsigned char* fr = free.ptr<unsigned char>(y);
      int* lr = labels.ptr<int>(y);
      for (int x = 0; x < W; ++x)
        if (!fr[x]) lr[x] = 0;
    }
    int* L = labels.ptr<int>(0);
    const unsigned char* F = free.ptr<unsigned char>(0);
    // Seeds: labelled cells with an unlabelled free neighbour, in row-major order (the other
    // labelled cells would expand nothing: the result is that of seeding every one).
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int i = y * W + x;
        if (!F[i] || L[i] <= 0) continue;
        bool open = false;
        for (int dy = -1; dy <= 1 && !open; ++dy)
          for (int dx = -1; dx <= 1 && !open; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
            const int j = ny * W + nx;
            open = F[j] && L[j] == 0;
          }
        if (open) queue.push_back(i);
      }
    // Grows the queued cells' labels over unlabelled free cells; `visited` (if given) gets
    // every cell taken from the queue.
    auto bfs = [&](std::vector<int>* visited) {
      while (!queue.empty()) {
        const int i = queue.front();
        queue.pop_front();
        if (visited) visited->push_back(i);
        const int x = i % W, y = i / W;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
            const int j = ny * W + nx;
            if (F[j] && L[j] == 0) {
              L[j] = L[i];
              queue.push_back(j);
            }
          }
      }
    };
    bfs(nullptr);
    std::vector<int> component;
    for (int i = 0; i < W * H; ++i)
      if (F[i] && L[i] == 0) {
        L[i] = (*next_label)++;
        queue.push_back(i);
        component.clear();
        bfs(&component);
        if (static_cast<int>(component.size()) < min_new_cells)
          for (int c : component) L[c] = -1;  // too small: unlabelled (restored below)
      }
    for (int i = 0; i < W * H; ++i)
      if (L[i] < 0) L[i] = 0;
  }

  /// Regions below min_region_area join the neighbour they share the longest border with.
  void mergeSmallRegions(cv::Mat& labels, int next_label, double res, int first_fresh) const {
    if (min_region_area_ <= 0) return;
    const double cell = res * res;
    std::vector<long> count(next_label, 0);
    const int W = labels.cols, H = labels.rows;
    int* L = labels.ptr<int>(0);
    for (int i = 0; i < W * H; ++i) ++count[L[i]];
    std::vector<char> small(next_label, 0);
    bool any = false;
    for (int l = first_fresh; l < next_label; ++l)
      if (count[l] > 0 && count[l] * cell < min_region_area_) small[l] = any = 1;
    if (!any) return;
    // Border lengths between a small region and its neighbours (4-neighbourhood).
    std::unordered_map<long long, long> border;
    auto touch = [&](int a, int b) {
      if (a == b || a == 0 || b == 0) return;
      if (small[a]) ++border[static_cast<long long>(a) * next_label + b];
      if (small[b]) ++border[static_cast<long long>(b) * next_label + a];
    };
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int a = L[y * W + x];
        if (x + 1 < W) touch(a, L[y * W + x + 1]);
        if (y + 1 < H) touch(a, L[(y + 1) * W + x]);
      }
    std::vector<std::vector<std::pair<int, long>>> nb(next_label);
    for (const auto& [key, n] : border) nb[key / next_label].push_back({static_cast<int>(key % next_label), n});
    std::vector<int> parent(next_label);
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int a) {
      while (parent[a] != a) a = parent[a] = parent[parent[a]];
      return a;
    };
    std::vector<int> order;
    for (int l = 1; l < next_label; ++l)
      if (small[l]) order.push_back(l);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[a] < count[b]; });
    std::vector<long> size(count.begin(), count.end());
    for (int l : order) {
      const int root = find(l);
      if (size[root] * cell >= min_region_area_) continue;  // grew by earlier merges
      std::map<int, long> by_root;  // ordered: deterministic ties
      for (const auto& [m, n] : nb[l]) {
        const int r = find(m);
        if (r != root) by_root[r] += n;
      }
      int best = -1;
      long best_n = 0;
      for (const auto& [r, n] : by_root)
        if (n > best_n) best = r, best_n = n;
      if (best < 0) continue;
      parent[root] = best;
      size[best] += size[root];
    }
    for (int i = 0; i < W * H; ++i)
      if (L[i] > 0) L[i] = find(L[i]);
  }

  /// Room layer: neighbouring pieces whose union DuDe would not cut again (no reflex vertex
  /// deeper than merge_concavity, no hole wider than min_hole_extent) are merged, cheapest
  /// union first. Undoes cuts that were chosen for a pocket minimum resolved elsewhere
  /// (furniture corners). Only labels >= first_fresh are considered: regions kept by an
  /// incremental update keep their cells.
  void mergeConvexNeighbours(cv::Mat& labels, int next_label, int first_fresh, const Frame& f) const {
    if (merge_concavity_ <= 0) return;
    const int W = labels.cols, H = labels.rows;
    std::vector<cv::Rect> box(next_label);
    std::vector<char> present(next_label, 0);
    for (int y = 0; y < H; ++y) {
      const int* l = labels.ptr<int>(y);
      for (int x = 0; x < W; ++x) {
        const int v = l[x];
        if (v <= 0) continue;
        if (!present[v]) box[v] = cv::Rect(x, y, 1, 1), present[v] = 1;
        else box[v] |= cv::Rect(x, y, 1, 1);
      }
    }
    // Border lengths between labels (4-neighbourhood), kept up to date through merges.
    std::map<int, std::map<int, int>> adj;
    for (int y = 0; y < H; ++y) {
      const int* l = labels.ptr<int>(y);
      const int* below = y + 1 < H ? labels.ptr<int>(y + 1) : nullptr;
      for (int x = 0; x < W; ++x) {
        const int a = l[x];
        if (a <= 0) continue;
        if (x + 1 < W && l[x + 1] > 0 && l[x + 1] != a) ++adj[a][l[x + 1]], ++adj[l[x + 1]][a];
        if (below && below[x] > 0 && below[x] != a) ++adj[a][below[x]], ++adj[below[x]][a];
      }
    }
    const double res = f.resolution;
    // Pieces meeting along less than this are joined by a doorway-sized opening: kept apart
    // without the (costly) union test.
    const int min_border_px = std::max(3, static_cast<int>(std::lround(merge_min_border_ / res)));
    const double eps_px = simplify_tolerance_ / res;
    const double hole_px = (options_.min_hole_extent < 0 ? options_.max_concavity : options_.min_hole_extent) / res;
    // Concavity of the union of a and b (infinity: must stay apart).
    auto unionConcavity = [&](int a, int b) {
      const cv::Rect r = (box[a] | box[b]) + cv::Size(2, 2) - cv::Point(1, 1);
      cv::Mat m(r.size(), CV_8U, cv::Scalar(0));
      for (int y = 0; y < r.height; ++y) {
        const int yy = y + r.y;
        if (yy < 0 || yy >= H) continue;
        const int* l = labels.ptr<int>(yy);
        unsigned char* o = m.ptr<unsigned char>(y);
        for (int x = 0; x < r.width; ++x) {
          const int xx = x + r.x;
          if (xx >= 0 && xx < W && (l[xx] == a || l[xx] == b)) o[x] = 1;
        }
      }
      std::vector<std::vector<cv::Point>> contours;
      std::vector<cv::Vec4i> hierarchy;
      cv::findContours(m, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
      int outer = -1;
      double best = -1;
      for (int i = 0; i < static_cast<int>(contours.size()); ++i)
        if (hierarchy[i][3] < 0) {
          const double area = std::abs(cv::contourArea(contours[i]));
          if (area > best) best = area, outer = i;
        } else {
          const cv::Rect hb = cv::boundingRect(contours[i]);
          if (std::hypot(hb.width, hb.height) >= hole_px) return std::numeric_limits<double>::infinity();
        }
      if (outer < 0) return std::numeric_limits<double>::infinity();
      std::vector<cv::Point> poly;
      cv::approxPolyDP(contours[outer], poly, std::max(eps_px, 0.5), true);
      asf::dude::Ring ring;
      for (const cv::Point& p : poly) ring.push_back({p.x * res, p.y * res});
      ring = asf::dude::cleanRing(ring, true);
      if (ring.empty()) return std::numeric_limits<double>::infinity();
      return asf::dude::maxReflexConcavity(ring);
    };
    // Candidate pairs, evaluated lazily and kept sorted by union concavity.
    std::set<std::tuple<double, int, int>> queue;
    std::map<std::pair<int, int>, double> score;
    auto evaluate = [&](int a) {
      for (const auto& [b, n] : adj[a]) {
        if (n < min_border_px || a < first_fresh || b < first_fresh) continue;
        const auto key = std::minmax(a, b);
        if (score.count(key)) continue;
        const double c = unionConcavity(key.first, key.second);
        score[key] = c;
        if (c <= merge_concavity_) queue.insert({c, key.first, key.second});
      }
    };
    for (int a = 1; a < next_label; ++a)
      if (present[a]) evaluate(a);
    while (!queue.empty()) {
      const auto [c, a, b] = *queue.begin();
      queue.erase(queue.begin());
      if (!present[a] || !present[b]) continue;
      // a absorbs b (the smaller label stays: kept ids win over fresh ones).
      const cv::Rect r = box[b];
      for (int y = r.y; y < r.y + r.height; ++y) {
        int* l = labels.ptr<int>(y);
        for (int x = r.x; x < r.x + r.width; ++x)
          if (l[x] == b) l[x] = a;
      }
      box[a] |= box[b];
      present[b] = 0;
      for (const auto& [c, n] : adj[b]) {
        adj[c].erase(b);
        if (c == a) continue;
        adj[a][c] += n;
        adj[c][a] += n;
      }
      adj.erase(b);
      adj[a].erase(b);
      // Pairs involving a or b changed: drop their scores and evaluate a's again.
      for (auto it = score.begin(); it != score.end();)
        if (it->first.first == a || it->first.second == a || it->first.first == b || it->first.second == b) {
          queue.erase({it->second, it->first.first, it->first.second});
          it = score.erase(it);
        } else {
          ++it;
        }
      evaluate(a);
    }
  }

  // ---- incremental mode ---------------------------------------------------------------

  /// Brings the stored state into frame f (same resolution; the grid may have grown or
  /// moved by whole cells). False when that is impossible.
  bool alignState(const Frame& f) {
    const Frame& o = state_.frame;
    if (std::abs(o.resolution - f.resolution) > 1e-9 * f.resolution) return false;
    const double sx = (o.origin_x - f.origin_x) / f.resolution;
    const double sy = (o.origin_y - f.origin_y) / f.resolution;
    const int dx = static_cast<int>(std::lround(sx)), dy = static_cast<int>(std::lround(sy));
    if (std::abs(sx - dx) > 1e-3 || std::abs(sy - dy) > 1e-3) return false;
    if (dx == 0 && dy == 0 && o.width == f.width && o.height == f.height) return true;
    const cv::Rect old_in_new = cv::Rect(dx, dy, o.width, o.height) & cv::Rect(0, 0, f.width, f.height);
    auto move = [&](cv::Mat& m) {
      cv::Mat n(f.height, f.width, m.type(), cv::Scalar(0));
      if (old_in_new.area() > 0)
        m(old_in_new - cv::Point(dx, dy)).copyTo(n(old_in_new));
      m = n;
    };
    move(state_.free);
    move(state_.proc);
    move(state_.ids);
    state_.frame = f;
    return true;
  }

  void saveState(const asf::Segmentation& s, const cv::Mat& free, const cv::Mat& proc,
                 const Frame& f) {
    state_.valid = true;
    state_.version = s.map_version;
    state_.frame = f;
    state_.free = free;
    state_.proc = proc;
    state_.ids = cv::Mat(f.height, f.width, CV_32S);
    for (int cy = 0; cy < f.height; ++cy)
      std::copy(s.labels.labels.begin() + static_cast<std::size_t>(cy) * f.width,
                s.labels.labels.begin() + static_cast<std::size_t>(cy + 1) * f.width,
                state_.ids.ptr<int>(cy));
    // Region boxes from their outlines (through border cell centres), one cell of slack.
    state_.boxes.clear();
    state_.max_id = 0;
    const cv::Rect full(0, 0, f.width, f.height);
    for (const asf::Region& r : s.regions) {
      state_.max_id = std::max(state_.max_id, static_cast<int>(r.id));
      double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
      for (const asf::Point2& p : r.outer)
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
      if (r.outer.empty()) {
        state_.boxes[r.id] = full;  // unknown extent: the whole map
        continue;
      }
      const int cx0 = static_cast<int>(std::floor((x0 - f.origin_x) / f.resolution)) - 1;
      const int cy0 = static_cast<int>(std::floor((y0 - f.origin_y) / f.resolution)) - 1;
      const int cx1 = static_cast<int>(std::floor((x1 - f.origin_x) / f.resolution)) + 2;
      const int cy1 = static_cast<int>(std::floor((y1 - f.origin_y) / f.resolution)) + 2;
      state_.boxes[r.id] = cv::Rect(cv::Point(cx0, cy0), cv::Point(cx1 + 1, cy1 + 1)) & full;
    }
  }

  /// Algorithm 3: the regions touching the changed free space (contact by a one-cell
  /// dilation) are merged with it and decomposed again; the others keep their cells.
  /// Works in windows around the change; *work receives the window whose labels changed.
  cv::Mat updateIncrementally(const cv::Mat& free, const cv::Mat& obstacle, const Frame& f,
                              int* next_label, cv::Mat* proc_out, cv::Rect* work) {
    const cv::Rect full(0, 0, f.width, f.height);
    // Provisional labels: kept regions keep their previous id (ids above them are fresh).
    *next_label = state_.max_id + 1;
    first_fresh_ = *next_label;
    cv::Mat labels = state_.ids.clone();
    *work = cv::Rect();
    cv::Mat raw_diff = free != state_.free;
    cv::Mat& proc = *proc_out;
    proc = state_.proc.clone();
    if (cv::countNonZero(raw_diff) == 0) return labels;
    // Pre-processing again around the change only: the morphology reaches `margin` cells.
    const int margin = static_cast<int>(std::lround(gap_closing_ / f.resolution)) +
                       static_cast<int>(std::lround(obstacle_dilation_ / f.resolution)) + 2;
    const cv::Rect raw_box = cv::boundingRect(raw_diff);
    const cv::Rect pre_box = (raw_box + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) & full;
    const cv::Rect ext_box = (pre_box + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) & full;
    const cv::Mat local = preprocess(free(ext_box), obstacle(ext_box), f.resolution);
    local(pre_box - ext_box.tl()).copyTo(proc(pre_box));
    cv::Mat diff = raw_diff.clone();
    diff(pre_box) |= (proc(pre_box) != state_.proc(pre_box));
    const cv::Rect touch_box = (pre_box + cv::Size(2, 2) - cv::Point(1, 1)) & full;
    cv::Mat contact;
    cv::dilate(diff(touch_box), contact, cv::Mat::ones(3, 3, CV_8U));
    std::vector<char> affected(*next_label, 0);
    cv::Rect mod_box = cv::boundingRect(diff(pre_box)) + pre_box.tl();
    for (int y = 0; y < touch_box.height; ++y) {
      const unsigned char* c = contact.ptr<unsigned char>(y);
      const int* id = state_.ids.ptr<int>(y + touch_box.y) + touch_box.x;
      for (int x = 0; x < touch_box.width; ++x)
        if (c[x] && id[x] > 0 && !affected[id[x]]) {
          affected[id[x]] = 1;
          const auto it = state_.boxes.find(id[x]);
          mod_box |= it != state_.boxes.end() ? it->second : full;
        }
    }
    mod_box &= full;
    // Modifiable: the changed cells plus the cells of the affected regions.
    cv::Mat modifiable(f.height, f.width, CV_8U, cv::Scalar(0));
    for (int y = mod_box.y; y < mod_box.y + mod_box.height; ++y) {
      int* l = labels.ptr<int>(y);
      unsigned char* m = modifiable.ptr<unsigned char>(y);
      const unsigned char* d = diff.ptr<unsigned char>(y);
      for (int x = mod_box.x; x < mod_box.x + mod_box.width; ++x)
        if ((l[x] > 0 && affected[l[x]]) || d[x]) {
          m[x] = 1;
          l[x] = 0;
        }
    }
    cv::Mat mod_proc(f.height, f.width, CV_8U, cv::Scalar(0));
    mod_proc(mod_box) = modifiable(mod_box) & proc(mod_box);
    decomposeInto(mod_proc, mod_box, f, labels, next_label);
    *work = mod_box;
    return labels;
  }

  double free_threshold_ = 0.4, occupied_threshold_ = 0.6;
  double gap_closing_ = 0.1, obstacle_dilation_ = 0.0, simplify_tolerance_ = 0.1;
  double min_region_area_ = 1.0, min_component_area_ = 0.25;
  bool incremental_ = true;
  double rebuild_full_fraction_ = 0.25;
  std::int64_t max_cells_ = 100000000;
  double merge_concavity_ = 1.0, merge_min_border_ = 1.2;
  int first_fresh_ = 1;  ///< first provisional label of the current incremental update
  asf::dude::Options options_;
  bool thesis_ = false;  ///< variant = thesis: the reference's cuts, no post-processing
  asf::dude::thesis::Options thesis_options_;
  asf::RegionId max_issued_ = 0;
  State state_;
};

const asf::KeySpec kKeys[] = {
    asf::keyEnum("variant", "rooms", "rooms|thesis",
                 "thesis: DuDe as published and as the thesis ran it (the reference's pocket "
                 "minima, Delaunay diagonals, cut sets and knapsack selection; no "
                 "post-processing); rooms: asf's heuristic cuts plus the room layer (README)"),
    asf::keyDouble("max_concavity", "2.5",
                   "DuDe's one parameter: boundary points deeper than this below the convex "
                   "hull (through the bridge hierarchy) are resolved by cuts [m]",
                   0.01, 1e6),
    asf::keyEnum("approximation", "chains", "chains|douglas_peucker",
                 "variant = thesis: how boundary chains are simplified into feature points: "
                 "the reference's default (chains grown around the farthest vertices) or its "
                 "Douglas-Peucker option"),
    asf::keyDouble("free_threshold", "0.4",
                   "A cell is free when its occupancy probability (1 - MRPT cell value) is below this",
                   0.0, 1.0),
    asf::keyDouble("occupied_threshold", "0.6",
                   "A cell is an obstacle (grown by obstacle_dilation) when its occupancy "
                   "probability is above this; cells in between are unknown, never free",
                   0.0, 1.0),
    asf::keyDouble("gap_closing", "0.1",
                   "Gaps between obstacles narrower than this (cracks in walls) are closed "
                   "before the contours are traced (closing of the obstacle mask) [m]",
                   0.0, 10.0),
    asf::keyDouble("obstacle_dilation", "0.0",
                   "Obstacles grown by this before the contours are traced [m]; the cells "
                   "given up still get the label of the nearest region",
                   0.0, 10.0),
    asf::keyDouble("simplify_tolerance", "0.1",
                   "Douglas-Peucker tolerance of the contours [m]; 0 keeps every contour vertex",
                   0.0, 10.0),
    asf::keyDouble("min_hole_extent", "-1",
                   "Holes (obstacles inside free space) narrower than this are not cut to and "
                   "stay inside one region [m]; < 0: max_concavity",
                   -1.0, 1e6),
    asf::keyDouble("resolve_radius", "0.5",
                   "Pocket minima this close to a chosen cut's ends wait for the next round "
                   "(no parallel cuts a wall's width apart) [m]",
                   0.0, 1e6),
    asf::keyDouble("min_region_area", "1.0",
                   "Pieces smaller than this join the neighbour they share most border with [m^2]",
                   0.0, 1e9),
    asf::keyDouble("min_component_area", "0.25",
                   "Free components smaller than this are left unlabelled [m^2]", 0.0, 1e9),
    asf::keyDouble("merge_concavity", "1.0",
                   "Room layer: neighbouring pieces whose union has no reflex vertex deeper "
                   "than this are merged [m]; 0: off",
                   0.0, 1e6),
    asf::keyDouble("merge_min_border", "1.2",
                   "Room layer: only pieces sharing at least this much border are merge "
                   "candidates (a doorway is narrower) [m]",
                   0.0, 1e6),
    asf::keyBool("incremental", "true",
                 "Re-decompose only the regions touching changed free space (thesis Algorithm "
                 "3)"),
    asf::keyDouble("rebuild_full_fraction", "0.25",
                   "After a rebuilt map (a loop closure moved keyframes) the update stays "
                   "incremental unless more than this fraction of the free cells changed "
                   "state; 0: always segment a rebuilt map in full",
                   0.0, 1.0),
    asf::keyInt("max_cells", "100000000",
                "Largest map segmented (cells; about 12 bytes each while segmenting): a larger "
                "one is an input error naming its size (1e8: 500 m x 500 m at 5 cm)",
                1, 2e9),
};

}  // namespace

ASF_PLUGIN(DudeSegmenter, asf::PluginKind::Segmenter, "dude", "1.0.0",
           "Contour-based topological segmentation by Dual-Space Decomposition (nearly convex regions)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
