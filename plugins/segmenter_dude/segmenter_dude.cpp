// segmenter_dude: contour-based topological segmentation (thesis ch. 4). Grid -> free mask
// -> contours with holes -> polygons in metres -> Dual-Space Decomposition (dude.h) ->
// pieces rasterized into a label image -> asf::mapping::regionsFromLabels.
// Incremental mode (thesis Algorithm 3): only regions touching the changed free space are
// merged with it and decomposed again; the others keep their cells, and so their ids.
#include "dude.h"
#include "dude_raster.h"
#include "dude_reference_change.h"
#include "dude_thesis.h"
#include "segmenter_dude_keys.h"

#include <asf/errors.h>
#include <asf/mapping/region_labels.h>
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
    reference_rule_ = p.getString("change_rule") == "reference";
    new_space_side_ = p.getDouble("new_space_side");
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
    if (f.width == 0 || f.height == 0) {
      state_ = State{};
      out.labels = emptyLabels(f);
      return out;
    }
    if (incremental_ && state_.valid && previous && previous->map_version == state_.version) {
      try {
        if (reference_rule_ ? updateByReference(map, grid, f, out) : update(map, grid, f, out))
          return out;
      } catch (...) {
        state_ = State{};  // half-updated: the next call starts afresh
        throw;
      }
    }
    segmentFull(map, grid, f, previous, out);
    return out;
  }

 private:
  struct State {
    bool valid = false;
    std::uint64_t version = 0;
    Frame frame;
    cv::Mat free, obstacle, proc;  ///< masks (CV_8U) of the last call
    cv::Mat outline;  ///< change_rule = reference: the regions' cells, no longer free ones too
    asf::Segmentation last;         ///< its result: labels hold the final region ids
    asf::RegionBoxes boxes;         ///< cell box of every region of `last`
    int max_id = 0;
  };

  static asf::LabelImage emptyLabels(const Frame& f) {
    asf::LabelImage L;
    L.width = f.width;
    L.height = f.height;
    L.resolution = f.resolution;
    L.origin_x = f.origin_x;
    L.origin_y = f.origin_y;
    L.labels.assign(static_cast<std::size_t>(f.width) * f.height, 0);
    return L;
  }

  /// The whole map: thresholds, pre-processing, decomposition, post-processing.
  void segmentFull(const asf::GridMap& map, const Grid& grid, const Frame& f,
                   const asf::Segmentation* previous, asf::Segmentation& out) {
    const cv::Rect full(0, 0, f.width, f.height);
    cv::Mat free, obstacle;
    thresholdGrid(grid, full, free, obstacle);
    // Cells whose free state changed since the last call (all cells without a comparable one).
    const bool comparable = state_.valid && previous && previous->map_version == state_.version &&
                            state_.frame.width == f.width && state_.frame.height == f.height;
    const std::int64_t changed = comparable ? cv::countNonZero(free != state_.free)
                                            : static_cast<std::int64_t>(f.width) * f.height;
    cv::Mat proc = preprocess(free, obstacle, f.resolution);
    cv::Mat labels(f.height, f.width, CV_32S, cv::Scalar(0));
    int next_label = 1;
    decomposeInto(proc, cv::Point(0, 0), f, labels, &next_label);
    postProcess(free, labels, &next_label, 1, f.resolution);
    out.labels = emptyLabels(f);
    std::copy(labels.ptr<int>(0), labels.ptr<int>(0) + out.labels.labels.size(),
              out.labels.labels.begin());
    asf::RegionBoxes boxes;
    out = asf::mapping::regionsFromLabels(std::move(out.labels), previous, &max_issued_, map.version,
                                 thesis_ ? 0.0 : min_component_area_, &boxes);
    out.mode = asf::Segmentation::Mode::Full;
    out.changed_cells = changed;
    if (!incremental_) {
      state_ = State{};
      return;
    }
    state_.valid = true;
    state_.version = map.version;
    state_.frame = f;
    state_.free = free;
    state_.obstacle = obstacle;
    state_.proc = proc;
    state_.outline.release();  // the reference rule starts again from the labels
    state_.last = out;
    state_.boxes = std::move(boxes);
    state_.max_id = out.regions.empty() ? 0 : out.regions.back().id;
  }

  /// Post-processing of a window of provisional labels (the whole map in batch mode). In
  /// an update fresh labels (>= first_fresh) lie entirely inside the window, so the steps
  /// that look at whole regions only consider fresh ones.
  void postProcess(const cv::Mat& free, cv::Mat& labels, int* next_label, int first_fresh,
                   double res) const {
    // The thesis variant keeps every piece DuDe makes, however small; only free components
    // below min_component_area are left out (the rooms variant drops small regions later).
    const int min_new_cells =
        thesis_ ? static_cast<int>(std::ceil(min_component_area_ / (res * res))) : 0;
    asf::dude::raster::completeLabels(free, labels, next_label, min_new_cells);
    if (thesis_) return;  // the published algorithm has no post-processing
    asf::dude::raster::mergeSmallRegions(labels, *next_label, res, first_fresh, min_region_area_);
    asf::dude::raster::RoomLayerOptions room;
    room.merge_concavity = merge_concavity_;
    room.merge_min_border = merge_min_border_;
    room.simplify_tolerance = simplify_tolerance_;
    room.min_hole_extent =
        options_.min_hole_extent < 0 ? options_.max_concavity : options_.min_hole_extent;
    asf::dude::raster::mergeConvexNeighbours(labels, *next_label, first_fresh, res, room);
  }

  /// Free and obstacle masks (CV_8U, 0/1) of the cells in `box`.
  void thresholdGrid(const Grid& grid, cv::Rect box, cv::Mat& free, cv::Mat& obstacle) const {
    free = cv::Mat(box.height, box.width, CV_8U, cv::Scalar(0));
    obstacle = cv::Mat(box.height, box.width, CV_8U, cv::Scalar(0));
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
    for (int y = 0; y < box.height; ++y) {
      const Cell* row = grid.getRow(box.y + y) + box.x;
      unsigned char* fr = free.ptr<unsigned char>(y);
      unsigned char* ob = obstacle.ptr<unsigned char>(y);
      for (int cx = 0; cx < box.width; ++cx) {
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
    cv::Mat blocked = obstacle.clone();  // its own buffer: the closing below writes into it
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

  /// Decomposes every connected component of `mask` and paints its pieces into `labels`
  /// (same size as mask) with fresh labels, on cells of `mask` only. Both are the window of
  /// the frame whose top-left cell is `roi`.
  void decomposeInto(const cv::Mat& mask, cv::Point roi, const Frame& f, cv::Mat& labels,
                     int* next_label) {
    const cv::Mat& sub = mask;
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
        pb &= cv::Rect(0, 0, mask.cols, mask.rows);
        if (pb.area() == 0) continue;
        for (auto& poly : polys)
          for (cv::Point& q : poly) q -= cv::Point(pb.x * 256, pb.y * 256);
        piece_mask = cv::Mat::zeros(pb.size(), CV_8U);
        cv::fillPoly(piece_mask, polys, cv::Scalar(1), cv::LINE_8, 8);
        piece_mask &= sub(pb);
        labels(pb).setTo(label, piece_mask);
      }
    }
    if (warnings > 0)
      MRPT_LOG_WARN_STREAM("dude: " << warnings << " piece(s) kept undecomposed; first: "
                                    << first_warning);
  }

  // ---- incremental mode (thesis Algorithm 3) ------------------------------------------

  /// Brings the stored state into frame f (same resolution; the grid may have grown or
  /// moved by whole cells, keeping every old cell). False when that is impossible; *moved
  /// says whether the frame changed.
  bool alignState(const Frame& f, bool* moved) {
    const Frame& o = state_.frame;
    *moved = false;
    if (std::abs(o.resolution - f.resolution) > 1e-9 * f.resolution) return false;
    const double sx = (o.origin_x - f.origin_x) / f.resolution;
    const double sy = (o.origin_y - f.origin_y) / f.resolution;
    const int dx = static_cast<int>(std::lround(sx)), dy = static_cast<int>(std::lround(sy));
    if (std::abs(sx - dx) > 1e-3 || std::abs(sy - dy) > 1e-3) return false;
    if (dx == 0 && dy == 0 && o.width == f.width && o.height == f.height) return true;
    const cv::Rect old_in_new(dx, dy, o.width, o.height);
    if ((old_in_new & cv::Rect(0, 0, f.width, f.height)) != old_in_new) return false;
    *moved = true;
    auto move = [&](cv::Mat& m) {
      cv::Mat n(f.height, f.width, m.type(), cv::Scalar(0));
      m.copyTo(n(old_in_new));
      m = n;
    };
    move(state_.free);
    move(state_.obstacle);
    move(state_.proc);
    if (!state_.outline.empty()) move(state_.outline);
    asf::LabelImage& L = state_.last.labels;
    asf::LabelImage shifted = emptyLabels(f);
    for (int y = 0; y < o.height; ++y)
      std::copy(L.labels.begin() + static_cast<std::size_t>(y) * o.width,
                L.labels.begin() + static_cast<std::size_t>(y + 1) * o.width,
                shifted.labels.begin() + static_cast<std::size_t>(y + dy) * f.width + dx);
    L = std::move(shifted);
    for (auto& [id, box] : state_.boxes) box.x += dx, box.y += dy;
    state_.frame = f;
    return true;
  }

  static cv::Rect grow(cv::Rect r, int by, const cv::Rect& limit) {
    return (r + cv::Size(2 * by, 2 * by) - cv::Point(by, by)) & limit;
  }

  /// Algorithm 3: the regions touching the changed free space (contact by a one-cell
  /// dilation) are merged with it and decomposed again; the others keep their cells. Every
  /// step works in windows around the change: thresholds (the map's `changed` box when it is
  /// the next version), pre-processing, decomposition, post-processing and the region
  /// measures (asf::mapping::regionsFromLabelsInWindow). False: segment the whole map instead.
  bool update(const asf::GridMap& map, const Grid& grid, const Frame& f, asf::Segmentation& out) {
    bool moved = false;
    if (!alignState(f, &moved)) return false;
    const cv::Rect full(0, 0, f.width, f.height);
    cv::Rect dirty = full;  // cells whose grid value may have changed
    // The map's `changed` box, when it is the next version (an empty box says nothing).
    if (!moved && !map.rebuilt && map.version == state_.version + 1 && !map.changed.empty()) {
      auto cell = [&](double x, double y) {
        return cv::Point(static_cast<int>(std::floor((x - f.origin_x) / f.resolution)),
                         static_cast<int>(std::floor((y - f.origin_y) / f.resolution)));
      };
      const cv::Point lo = cell(map.changed.min_x, map.changed.min_y);
      const cv::Point hi = cell(map.changed.max_x, map.changed.max_y) + cv::Point(1, 1);
      dirty = grow(cv::Rect(lo, hi), 1, full);
      // A box off the grid changed nothing: one cell keeps the steps below non-empty.
      if (dirty.area() == 0) dirty = cv::Rect(0, 0, 1, 1);
    }
    cv::Mat free_d, obstacle_d;
    thresholdGrid(grid, dirty, free_d, obstacle_d);
    const cv::Mat free_diff = free_d != state_.free(dirty);
    const cv::Mat input_diff = free_diff | (obstacle_d != state_.obstacle(dirty));
    const std::int64_t changed = cv::countNonZero(free_diff);
    // A rebuilt map (loop closure: keyframes moved) stays incremental while the change is
    // local: regions far from it keep their cells. (A rebuilt map is thresholded in full.)
    if (map.rebuilt && changed > rebuild_full_fraction_ * std::max(1, cv::countNonZero(free_d)))
      return false;
    free_d.copyTo(state_.free(dirty));
    obstacle_d.copyTo(state_.obstacle(dirty));

    int next_label = state_.max_id + 1;  // provisional: kept regions keep their ids
    const int first_fresh = next_label;
    cv::Rect work;  // where labels change
    cv::Mat lab_w;
    const cv::Rect raw_box = cv::boundingRect(input_diff) + dirty.tl();
    if (raw_box.area() > 0) {
      work = redecompose(f, free_diff, dirty, raw_box, &next_label, &lab_w);
      if (work.area() > 0) postProcess(state_.free(work).clone(), lab_w, &next_label, first_fresh, f.resolution);
    }
    commitWindow(map.version, f, work, lab_w, changed, out);
    return true;
  }

  /// The labels of window `work` replaced by `lab_w`: the regions measured again there, the
  /// others kept (ids included), and the result stored as the state for the next update.
  void commitWindow(std::uint64_t version, const Frame& f, const cv::Rect& work,
                    const cv::Mat& lab_w, std::int64_t changed, asf::Segmentation& out) {
    asf::LabelImage L = state_.last.labels;
    for (int y = 0; y < work.height; ++y)
      std::copy(lab_w.ptr<int>(y), lab_w.ptr<int>(y) + work.width,
                L.labels.begin() + static_cast<std::size_t>(work.y + y) * f.width + work.x);
    out = asf::mapping::regionsFromLabelsInWindow(std::move(L), state_.last, state_.boxes,
                                         {work.x, work.y, work.width, work.height}, &max_issued_,
                                         version, thesis_ ? 0.0 : min_component_area_);
    out.mode = asf::Segmentation::Mode::Incremental;
    out.changed_cells = changed;
    state_.version = version;
    state_.last.regions = out.regions;
    state_.last.labels.labels = out.labels.labels;  // same size: no allocation
    state_.last.map_version = version;
    state_.max_id = out.regions.empty() ? 0 : out.regions.back().id;
  }

  /// change_rule = reference (dude_reference_change.h): the regions keep their outlines (in
  /// state_.outline, cells that are no longer free included); the blobs of new free space the
  /// rule keeps are decomposed again with the regions they touch. The result labels free cells
  /// only (the contract). Works on the whole frame. False: segment the whole map instead.
  bool updateByReference(const asf::GridMap& map, const Grid& grid, const Frame& f,
                         asf::Segmentation& out) {
    bool moved = false;
    if (!alignState(f, &moved)) return false;
    const cv::Rect full(0, 0, f.width, f.height);
    cv::Mat free, obstacle;
    thresholdGrid(grid, full, free, obstacle);
    const std::int64_t changed = cv::countNonZero(free != state_.free);
    if (map.rebuilt && changed > rebuild_full_fraction_ * std::max(1, cv::countNonZero(free)))
      return false;
    state_.free = free;
    state_.obstacle = obstacle;
    state_.proc = preprocess(free, obstacle, f.resolution);
    const cv::Mat last(f.height, f.width, CV_32S, state_.last.labels.labels.data());
    if (state_.outline.size() != last.size()) state_.outline = last.clone();
    cv::Mat outline = state_.outline.clone();
    const int side = static_cast<int>(new_space_side_ / f.resolution);  // rounded down, as the author's
    const auto change = asf::dude::incremental::referenceChange(state_.proc, outline, side);
    if (change.box.area() > 0) {
      const cv::Rect work = grow(change.box, 1, full);
      cv::Mat lab_w = outline(work).clone();  // continuous, as completeLabels needs
      const cv::Mat redo = change.redo(work);
      lab_w.setTo(0, redo);
      int next_label = state_.max_id + 1;
      const int first_fresh = next_label;
      decomposeInto(state_.proc(work) & redo, work.tl(), f, lab_w, &next_label);
      // Post-processing over the cells decomposed again only: the kept regions' cells count
      // as free (completeLabels clears labels elsewhere), the dropped blobs stay out.
      const cv::Mat keep = (free(work) & redo) | ((lab_w > 0) & (redo == 0));
      postProcess(keep & 1, lab_w, &next_label, first_fresh, f.resolution);
      lab_w.copyTo(outline(work));
    }
    cv::Mat clipped = outline.clone();
    clipped.setTo(0, free == 0);
    const cv::Rect window = cv::boundingRect(clipped != last);
    commitWindow(map.version, f, window, clipped(window), changed, out);
    // The next outline: the result's ids, and the stable cells no longer free outside `redo`
    // (free cells the result left out, a region below min_component_area, are no region's).
    const cv::Mat result(f.height, f.width, CV_32S, out.labels.labels.data());
    cv::Mat kept_outline = (result == 0) & (outline > 0) & (free == 0);
    if (!change.redo.empty()) kept_outline &= (change.redo == 0);
    result.copyTo(state_.outline);
    outline.copyTo(state_.outline, kept_outline);
    return true;
  }

  /// Pre-processes around the input change `raw_box`, finds the regions touching the
  /// changed free space, clears them and decomposes them with the change. Returns the
  /// window whose labels changed (empty: none) and its provisional labels in *lab_w.
  cv::Rect redecompose(const Frame& f, const cv::Mat& free_diff, const cv::Rect& dirty,
                       const cv::Rect& raw_box, int* next_label, cv::Mat* lab_w) {
    const cv::Rect full(0, 0, f.width, f.height);
    // The morphology reaches `margin` cells.
    const int margin = static_cast<int>(std::lround(gap_closing_ / f.resolution)) +
                       static_cast<int>(std::lround(obstacle_dilation_ / f.resolution)) + 2;
    const cv::Rect pre_box = grow(raw_box, margin, full);
    const cv::Rect ext_box = grow(pre_box, margin, full);
    const cv::Mat local = preprocess(state_.free(ext_box), state_.obstacle(ext_box), f.resolution);
    const cv::Mat proc_pre = local(pre_box - ext_box.tl());
    // Changed cells: free state or pre-processed free state.
    cv::Mat diff = proc_pre != state_.proc(pre_box);
    const cv::Rect fd = (raw_box & dirty) - dirty.tl();
    diff(fd + dirty.tl() - pre_box.tl()) |= free_diff(fd);
    proc_pre.copyTo(state_.proc(pre_box));
    const cv::Rect diff_box = cv::boundingRect(diff);
    if (diff_box.area() == 0) return cv::Rect();
    const cv::Rect touch_box = grow(diff_box + pre_box.tl(), 1, full);
    cv::Mat diff_touch(touch_box.size(), CV_8U, cv::Scalar(0)), contact;
    diff(diff_box).copyTo(diff_touch(diff_box + pre_box.tl() - touch_box.tl()));
    cv::dilate(diff_touch, contact, cv::Mat::ones(3, 3, CV_8U));
    const asf::LabelImage& ids = state_.last.labels;
    std::unordered_map<int, char> affected;
    cv::Rect mod_box = diff_box + pre_box.tl();
    for (int y = 0; y < touch_box.height; ++y) {
      const unsigned char* c = contact.ptr<unsigned char>(y);
      const asf::RegionId* id = ids.labels.data() + static_cast<std::size_t>(y + touch_box.y) * f.width + touch_box.x;
      for (int x = 0; x < touch_box.width; ++x)
        if (c[x] && id[x] > 0 && affected.emplace(id[x], 1).second) {
          const auto it = state_.boxes.find(id[x]);
          mod_box |= it != state_.boxes.end()
                         ? cv::Rect(it->second.x, it->second.y, it->second.width, it->second.height)
                         : full;
        }
    }
    mod_box &= full;
    // Modifiable: the changed cells plus the cells of the affected regions.
    *lab_w = cv::Mat(mod_box.size(), CV_32S);
    cv::Mat mod_proc(mod_box.size(), CV_8U, cv::Scalar(0));
    for (int y = 0; y < mod_box.height; ++y) {
      const asf::RegionId* src = ids.labels.data() + static_cast<std::size_t>(y + mod_box.y) * f.width + mod_box.x;
      int* l = lab_w->ptr<int>(y);
      unsigned char* m = mod_proc.ptr<unsigned char>(y);
      const unsigned char* p = state_.proc.ptr<unsigned char>(y + mod_box.y) + mod_box.x;
      const int yd = y + mod_box.y - pre_box.y;
      const unsigned char* d = yd >= 0 && yd < pre_box.height ? diff.ptr<unsigned char>(yd) : nullptr;
      for (int x = 0; x < mod_box.width; ++x) {
        const int xd = x + mod_box.x - pre_box.x;
        const bool changed_cell = d && xd >= 0 && xd < pre_box.width && d[xd];
        if ((src[x] > 0 && affected.count(src[x])) || changed_cell) {
          l[x] = 0;
          m[x] = p[x];
        } else {
          l[x] = src[x];
        }
      }
    }
    decomposeInto(mod_proc, mod_box.tl(), f, *lab_w, next_label);
    return mod_box;
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
  bool reference_rule_ = false;  ///< change_rule = reference (dude_reference_change.h)
  double new_space_side_ = 0.5;
  asf::dude::thesis::Options thesis_options_;
  asf::RegionId max_issued_ = 0;
  State state_;
};

}  // namespace

ASF_PLUGIN(DudeSegmenter, asf::PluginKind::Segmenter, "dude", "1.0.0",
           "Contour-based topological segmentation by Dual-Space Decomposition (nearly convex regions)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
