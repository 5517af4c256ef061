// segmenter_free_components: one region per connected component of free cells. An honest,
// trivial segmentation (no rooms, no doors) until a real segmenter (DuDe) lands.
#include <asf/errors.h>
#include <asf/segmenter.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <tuple>
#include <vector>

namespace {

class FreeComponentsSegmenter final : public asf::Segmenter {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    free_threshold_ = p.getDouble("free_threshold");
    connectivity_ = static_cast<int>(p.getInt("connectivity"));
    if (connectivity_ != 4 && connectivity_ != 8) p.fail("connectivity", "must be 4 or 8");
    min_area_ = p.getDouble("min_area");
  }

  asf::Segmentation segment(const asf::GridMap& map, const asf::Segmentation* previous) override {
    asf::Segmentation out;
    out.map_version = map.version;
    if (!map.grid) return out;
    const auto& grid = *map.grid;
    const int W = static_cast<int>(grid.getSizeX()), H = static_cast<int>(grid.getSizeY());
    const double res = grid.getResolution(), x0 = grid.getXMin(), y0 = grid.getYMin();
    asf::LabelImage& L = out.labels;
    L.width = W;
    L.height = H;
    L.resolution = res;
    L.origin_x = x0;
    L.origin_y = y0;
    L.labels.assign(static_cast<std::size_t>(W) * H, 0);
    if (W == 0 || H == 0) return out;

    cv::Mat free(H, W, CV_8U, cv::Scalar(0));  // row = cy
    for (int cy = 0; cy < H; ++cy)
      for (int cx = 0; cx < W; ++cx)
        // MRPT cells hold p(free) (0 = occupied, 1 = empty, 0.5 = unknown).
        if (1.0 - grid.getCell(cx, cy) < free_threshold_) free.at<uchar>(cy, cx) = 1;
    cv::Mat comp, stats, centroids;
    const int n = cv::connectedComponentsWithStats(free, comp, stats, centroids, connectivity_,
                                                   CV_32S);
    const double cell_area = res * res;

    struct Comp {
      int cv_label;
      std::vector<std::pair<int, int>> cells;
      asf::RegionId id = 0;
    };
    std::vector<Comp> comps;
    std::vector<int> comp_of(static_cast<std::size_t>(n), -1);
    for (int k = 1; k < n; ++k) {
      if (stats.at<int>(k, cv::CC_STAT_AREA) * cell_area < min_area_) continue;
      comp_of[static_cast<std::size_t>(k)] = static_cast<int>(comps.size());
      comps.push_back(Comp{k, {}, 0});
    }
    for (int cy = 0; cy < H; ++cy)
      for (int cx = 0; cx < W; ++cx) {
        const int k = comp.at<int>(cy, cx);
        if (k > 0 && comp_of[static_cast<std::size_t>(k)] >= 0)
          comps[static_cast<std::size_t>(comp_of[static_cast<std::size_t>(k)])].cells.emplace_back(
              cx, cy);
      }

    assignIds(comps, previous, x0, y0, res);

    for (const Comp& c : comps) {
      asf::Region r;
      r.id = c.id;
      r.area = static_cast<double>(c.cells.size()) * cell_area;
      double sx = 0, sy = 0;
      for (const auto& [cx, cy] : c.cells) {
        L.labels[static_cast<std::size_t>(cy) * W + cx] = c.id;
        sx += x0 + (cx + 0.5) * res;
        sy += y0 + (cy + 0.5) * res;
      }
      r.centroid = {sx / c.cells.size(), sy / c.cells.size()};
      contours(comp, c.cv_label, stats, x0, y0, res, r);
      out.regions.push_back(std::move(r));
    }
    std::sort(out.regions.begin(), out.regions.end(),
              [](const asf::Region& a, const asf::Region& b) { return a.id < b.id; });
    MRPT_LOG_DEBUG_STREAM("free_components: " << out.regions.size() << " regions ("
                                              << (n - 1 - static_cast<int>(comps.size()))
                                              << " components below min_area)");
    return out;
  }

 private:
  // Greedy largest-overlap matching with the previous segmentation, then fresh ids.
  template <class Comp>
  void assignIds(std::vector<Comp>& comps, const asf::Segmentation* previous, double x0,
                 double y0, double res) {
    if (previous) {
      for (const auto& r : previous->regions) max_issued_ = std::max(max_issued_, r.id);
      std::vector<std::tuple<long, std::size_t, asf::RegionId>> pairs;  // overlap, comp, id
      for (std::size_t i = 0; i < comps.size(); ++i) {
        std::map<asf::RegionId, long> overlap;
        for (const auto& [cx, cy] : comps[i].cells) {
          const asf::RegionId id =
              previous->labels.atPoint(x0 + (cx + 0.5) * res, y0 + (cy + 0.5) * res);
          if (id > 0) ++overlap[id];
        }
        for (const auto& [id, count] : overlap) pairs.emplace_back(count, i, id);
      }
      // Largest overlap first; ties broken by smaller component index, then smaller id.
      std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
        if (std::get<0>(a) != std::get<0>(b)) return std::get<0>(a) > std::get<0>(b);
        if (std::get<1>(a) != std::get<1>(b)) return std::get<1>(a) < std::get<1>(b);
        return std::get<2>(a) < std::get<2>(b);
      });
      std::map<asf::RegionId, bool> used;
      for (const auto& [count, i, id] : pairs) {
        if (comps[i].id != 0 || used[id]) continue;
        comps[i].id = id;
        used[id] = true;
      }
    }
    for (auto& c : comps)
      if (c.id == 0) c.id = ++max_issued_;
  }

  // Outer boundary and holes of one component, through the centres of its border cells.
  static void contours(const cv::Mat& comp, int label, const cv::Mat& stats, double x0,
                       double y0, double res, asf::Region& r) {
    const int bx = stats.at<int>(label, cv::CC_STAT_LEFT), by = stats.at<int>(label, cv::CC_STAT_TOP);
    const int bw = stats.at<int>(label, cv::CC_STAT_WIDTH);
    const int bh = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    cv::Mat mask(bh + 2, bw + 2, CV_8U, cv::Scalar(0));  // 1-cell zero border
    for (int y = 0; y < bh; ++y)
      for (int x = 0; x < bw; ++x)
        if (comp.at<int>(by + y, bx + x) == label) mask.at<uchar>(y + 1, x + 1) = 255;
    std::vector<std::vector<cv::Point>> cs;
    std::vector<cv::Vec4i> hierarchy;
    cv::findContours(mask, cs, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE,
                     cv::Point(bx - 1, by - 1));
    auto toPolygon = [&](const std::vector<cv::Point>& c) {
      asf::Polygon p;
      p.reserve(c.size());
      for (const auto& q : c) p.push_back({x0 + (q.x + 0.5) * res, y0 + (q.y + 0.5) * res});
      return p;
    };
    double best = -1;
    for (std::size_t i = 0; i < cs.size(); ++i) {
      asf::Polygon p = toPolygon(cs[i]);
      const double a = asf::polygonArea(p);
      if (hierarchy[i][3] < 0) {  // top level: outer boundary (one per component)
        if (a < 0) std::reverse(p.begin(), p.end());
        if (std::abs(a) > best) {
          best = std::abs(a);
          r.outer = std::move(p);
        }
      } else {  // hole: clockwise
        if (a > 0) std::reverse(p.begin(), p.end());
        r.holes.push_back(std::move(p));
      }
    }
  }

  double free_threshold_ = 0.4;
  int connectivity_ = 8;
  double min_area_ = 0.25;
  asf::RegionId max_issued_ = 0;
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("free_threshold", "0.4",
                   "A cell is free when its occupancy probability (1 - MRPT cell value) is below this", 0.0, 1.0),
    asf::keyInt("connectivity", "8", "Cell neighbourhood of a component: 4 or 8", 4, 8),
    asf::keyDouble("min_area", "0.25", "Components smaller than this are dropped [m^2]", 0,
                   1e9),
};

}  // namespace

ASF_PLUGIN(FreeComponentsSegmenter, asf::PluginKind::Segmenter, "free_components", "1.0.0",
           "One region per connected component of free cells (trivial reference segmenter)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
