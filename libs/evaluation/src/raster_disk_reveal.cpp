// asf::RasterDiskReveal: the thesis' incremental protocol (disks revealed along a raster).
#include <asf/errors.h>
#include <asf/evaluation/segmentation_eval.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>

#include "reveal_map.h"

namespace asf::evaluation {

using Grid = mrpt::maps::COccupancyGridMap2D;

struct RasterDiskReveal::State {
  RasterDiskOptions opt;
  int W = 0, H = 0;
  double res = 0;
  std::vector<std::uint8_t> truth_free;  // image orientation, 1 = free
  std::vector<std::uint8_t> known;       // 1 = revealed
  std::size_t free_total = 0, free_revealed = 0, disks = 0;
  bool finished = false;
  std::shared_ptr<Grid> grid;
  GridMap map;

  /// Reveals the disk centred on pixel (cx, cy): appends the newly revealed pixels and
  /// extends `changed` by the map-frame box of the disk's part on the image (if any).
  void reveal(int cx, int cy, std::vector<int>& revealed, Box2& changed) {
    const int r = opt.radius_px;
    const long r2 = static_cast<long>(r) * r;
    const int y0 = std::max(0, cy - r), y1 = std::min(H - 1, cy + r);
    const int x0 = std::max(0, cx - r), x1 = std::min(W - 1, cx + r);
    if (x0 > x1 || y0 > y1) return;
    changed.extend(x0 * res, (H - 1 - y1) * res);  // grid rows run bottom-up
    changed.extend((x1 + 1) * res, (H - y0) * res);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const long dx = x - cx, dy = y - cy;
        if (dx * dx + dy * dy > r2) continue;
        const std::size_t i = static_cast<std::size_t>(y) * W + x;
        if (known[i]) continue;
        known[i] = 1;
        free_revealed += truth_free[i];
        revealed.push_back(static_cast<int>(i));
      }
  }

};

RasterDiskReveal::RasterDiskReveal(const io::GrayImage& image, double resolution,
                                   const RasterDiskOptions& options, int free_threshold)
    : s_(std::make_unique<State>()) {
  State& s = *s_;
  if (!(resolution > 0)) throw Error("RasterDiskReveal: resolution must be > 0");
  if (options.radius_px < 0) throw Error("RasterDiskReveal: radius_px must be >= 0");
  if (options.step_px < 1) throw Error("RasterDiskReveal: step_px must be >= 1");
  s.opt = options;
  s.W = image.width;
  s.H = image.height;
  s.res = resolution;
  const std::size_t N = static_cast<std::size_t>(s.W) * s.H;
  s.truth_free.assign(N, 0);
  s.known.assign(N, 0);
  for (int r = 0; r < s.H; ++r)
    for (int c = 0; c < s.W; ++c)
      if (image.at(c, r) >= free_threshold) {
        s.truth_free[static_cast<std::size_t>(r) * s.W + c] = 1;
        ++s.free_total;
      }
  s.finished = s.W == 0 || s.H == 0;
}

RasterDiskReveal::~RasterDiskReveal() = default;

bool RasterDiskReveal::step() {
  State& s = *s_;
  // Pixels revealed since the last published map, and the union of their disks' boxes (the
  // disks before it may have revealed too few free pixels in all to be published).
  std::vector<int> revealed;
  Box2 changed;
  while (!s.finished) {
    const long along = static_cast<long>(s.opt.step_px) * static_cast<long>(s.disks);
    const int x = static_cast<int>(along % s.W);
    const long y = static_cast<long>(s.opt.step_px) * (along / s.W);
    s.reveal(x, static_cast<int>(std::min<long>(y, s.H + s.opt.radius_px + 1)), revealed, changed);
    ++s.disks;
    // The author's loop stops after the first centre below the image (x is always inside).
    if (y > s.H) s.finished = true;
    if (s.free_revealed > s.opt.min_free_px) {
      detail::publishReveal(s.grid, s.map, s.W, s.H, s.res, revealed,
                            [&](int i) { return s.truth_free[i] != 0; }, changed);
      return true;
    }
  }
  return false;
}

const GridMap& RasterDiskReveal::map() const { return s_->map; }
double RasterDiskReveal::coverage() const {
  return s_->free_total ? static_cast<double>(s_->free_revealed) / s_->free_total : 0;
}
std::size_t RasterDiskReveal::disks() const { return s_->disks; }

}  // namespace asf::evaluation
