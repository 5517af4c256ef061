// segmenter_free_components: one region per connected component of free cells. An honest,
// trivial segmentation (no rooms, no doors) until a real segmenter (DuDe) lands.
#include <asf/errors.h>
#include <asf/mapping/region_labels.h>
#include <asf/segmenter.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
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
    cv::Mat comp;
    const int n = cv::connectedComponents(free, comp, connectivity_, CV_32S);
    for (int cy = 0; cy < H; ++cy)
      for (int cx = 0; cx < W; ++cx)
        L.labels[static_cast<std::size_t>(cy) * W + cx] = comp.at<int>(cy, cx);
    out = asf::mapping::regionsFromLabels(std::move(L), previous, &max_issued_, map.version, min_area_);
    out.mode = asf::Segmentation::Mode::Full;  // always the whole map
    MRPT_LOG_DEBUG_STREAM("free_components: " << out.regions.size() << " regions ("
                                              << (n - 1 - static_cast<int>(out.regions.size()))
                                              << " components below min_area)");
    return out;
  }

 private:
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
