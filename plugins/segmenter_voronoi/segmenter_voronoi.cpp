// segmenter_voronoi: room segmentation on the generalized Voronoi graph of free space (Thrun
// 1998; Bormann et al., ICRA 2016), the baseline segmenter. Algorithm: voronoi_segmentation.h.
#include <asf/errors.h>
#include <asf/mapping/region_labels.h>
#include <asf/segmenter.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "voronoi_segmentation.h"

namespace {

constexpr double kDegToRad = M_PI / 180.0;

class VoronoiSegmenter final : public asf::Segmenter {
 public:
  void configure(const asf::Params& p, const asf::PluginContext&) override {
    free_threshold_ = p.getDouble("free_threshold");
    robot_radius_ = p.getDouble("robot_radius");
    prune_length_ = p.getDouble("prune_length");
    neighborhood_ = p.getDouble("critical_neighborhood");
    min_rise_ = p.getDouble("min_clearance_rise");
    min_cut_angle_ = p.getDouble("min_cut_angle");
    max_cut_length_ = p.getDouble("max_cut_length");
    max_furniture_area_ = p.getDouble("max_furniture_area");
    min_room_area_ = p.getDouble("min_room_area");
    max_merge_area_ = p.getDouble("max_merge_area");
    merge_border_ratio_ = p.getDouble("merge_border_ratio");
    min_area_ = p.getDouble("min_area");
    if (max_merge_area_ < min_room_area_)
      p.fail("max_merge_area", "must not be below min_room_area (" +
                                   std::to_string(min_room_area_) + " m^2)");
  }

  asf::Segmentation segment(const asf::GridMap& map, const asf::Segmentation* previous) override {
    asf::Segmentation out;
    out.map_version = map.version;
    if (!map.grid) return out;
    const auto& grid = *map.grid;
    const int W = static_cast<int>(grid.getSizeX()), H = static_cast<int>(grid.getSizeY());
    const double res = grid.getResolution();
    asf::LabelImage L;
    L.width = W;
    L.height = H;
    L.resolution = res;
    L.origin_x = grid.getXMin();
    L.origin_y = grid.getYMin();
    L.labels.assign(static_cast<std::size_t>(W) * H, 0);
    if (W == 0 || H == 0) return asf::mapping::regionsFromLabels(std::move(L), previous, &max_issued_, map.version);

    cv::Mat free(H, W, CV_8U, cv::Scalar(0));  // row = cy
    int n_free = 0;
    for (int cy = 0; cy < H; ++cy)
      for (int cx = 0; cx < W; ++cx)
        // MRPT cells hold p(free) (0 = occupied, 1 = empty, 0.5 = unknown).
        if (1.0 - grid.getCell(cx, cy) < free_threshold_) {
          free.at<uchar>(cy, cx) = 1;
          ++n_free;
        }
    if (n_free > 0) {
      asf::voronoi::Options o;
      const double cell_area = res * res;
      o.robot_radius = robot_radius_ / res;
      o.prune_length = prune_length_ / res;
      o.neighborhood = std::max(1, static_cast<int>(std::lround(neighborhood_ / res)));
      o.min_rise = min_rise_;
      o.min_cut_angle = min_cut_angle_ * kDegToRad;
      o.max_cut_length = max_cut_length_ / res;
      o.max_furniture_area = max_furniture_area_ / cell_area;
      o.min_room_area = min_room_area_ / cell_area;
      o.max_merge_area = max_merge_area_ / cell_area;
      o.merge_border_ratio = merge_border_ratio_;
      asf::voronoi::Stats st;
      const cv::Mat labels = asf::voronoi::segmentFreeSpace(free, o, &st);
      for (int cy = 0; cy < H; ++cy)
        std::copy_n(labels.ptr<int>(cy), W, &L.labels[static_cast<std::size_t>(cy) * W]);
      MRPT_LOG_DEBUG_STREAM("voronoi: skeleton " << st.skeleton_cells << " cells, "
                                                 << st.critical_points << " critical points, "
                                                 << st.cuts << " cuts, " << st.components
                                                 << " components, " << st.regions << " regions");
    }
    out = asf::mapping::regionsFromLabels(std::move(L), previous, &max_issued_, map.version, min_area_);
    out.mode = asf::Segmentation::Mode::Full;  // always the whole map
    return out;
  }

 private:
  double free_threshold_ = 0.4, robot_radius_ = 0.3, prune_length_ = 0.5, neighborhood_ = 1.5;
  double min_cut_angle_ = 120, max_cut_length_ = 4, min_room_area_ = 1.5, max_merge_area_ = 12.5;
  double merge_border_ratio_ = 0.2, min_area_ = 0.25, max_furniture_area_ = 0.2, min_rise_ = 0.1;
  asf::RegionId max_issued_ = 0;
};

const asf::KeySpec kKeys[] = {
    asf::keyDouble("free_threshold", "0.4",
                   "A cell is free when its occupancy probability (1 - MRPT cell value) is below this",
                   0.0, 1.0),
    asf::keyDouble("robot_radius", "0.3",
                   "Free space is opened with a disc of this radius before building the graph: "
                   "gaps narrower than twice it do not connect rooms [m]; 0 = off",
                   0.0, 10.0),
    asf::keyDouble("prune_length", "0.5",
                   "Dead-end branches of the Voronoi graph shorter than this are removed [m]", 0.0,
                   100.0),
    asf::keyDouble("critical_neighborhood", "1.5",
                   "A critical point has the least clearance within this distance along its "
                   "branch of the graph, on both sides [m]",
                   0.0, 100.0),
    asf::keyDouble("min_clearance_rise", "0.1",
                   "Within critical_neighborhood the clearance must grow on both sides of a critical "
                   "point by this fraction (and by one cell): dents in corridor walls are no doors",
                   0.0, 10.0),
    asf::keyDouble("min_cut_angle", "120",
                   "Least angle at a critical point between its two basis points (nearest "
                   "obstacles) for a cut line [deg]",
                   0.0, 180.0),
    asf::keyDouble("max_cut_length", "4.0", "Cut lines (door widths) longer than this are not drawn [m]",
                   0.0, 1e6),
    asf::keyDouble("max_furniture_area", "0.2",
                   "Obstacles (8-connected) smaller than this count as furniture: no cut line "
                   "ends on them [m^2]; 0 = off (cuts as published)",
                   0.0, 1e9),
    asf::keyDouble("min_room_area", "1.5",
                   "Regions smaller than this merge into the neighbour with the longest shared "
                   "border [m^2]",
                   0.0, 1e9),
    asf::keyDouble("max_merge_area", "12.5",
                   "Regions smaller than this merge into a neighbour sharing at least "
                   "merge_border_ratio of their perimeter [m^2]",
                   0.0, 1e9),
    asf::keyDouble("merge_border_ratio", "0.2",
                   "Fraction of a region's perimeter shared with one neighbour that merges them "
                   "(for regions below max_merge_area)",
                   0.0, 1.0),
    asf::keyDouble("min_area", "0.25",
                   "Regions still smaller than this after merging (isolated pockets) are dropped [m^2]",
                   0.0, 1e9),
};

}  // namespace

ASF_PLUGIN(VoronoiSegmenter, asf::PluginKind::Segmenter, "voronoi", "1.0.0",
           "Room segmentation on the generalized Voronoi graph (Bormann et al. 2016)",
           asf::ThreadSafety::ThreadCompatible, kKeys)
