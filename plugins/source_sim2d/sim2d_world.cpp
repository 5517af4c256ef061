#include "sim2d_world.h"

#include <mrpt/img/CImage.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace asf::sim2d {

World World::fromImage(const ImageWorldOptions& o) {
  mrpt::img::CImage img;
  if (!img.loadFromFile(o.file, 0 /*grayscale*/))
    throw std::runtime_error(o.file + ": cannot read the map image");
  const int w = static_cast<int>(img.getWidth()), h = static_cast<int>(img.getHeight());
  if (w < 2 || h < 2) throw std::runtime_error(o.file + ": map image is smaller than 2x2 px");
  const int pad = o.pad_wall_px;
  const double res = o.resolution;
  World world;
  world.grid_.setSize(static_cast<float>(o.origin_x - pad * res),
                      static_cast<float>(o.origin_x + (w + pad) * res),
                      static_cast<float>(o.origin_y - pad * res),
                      static_cast<float>(o.origin_y + (h + pad) * res), static_cast<float>(res),
                      1.0f);
  auto& g = world.grid_;
  const int sx = static_cast<int>(g.getSizeX()), sy = static_cast<int>(g.getSizeY());
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const int col = cx - pad, row_from_bottom = cy - pad;
      bool wall = true;  // the padding frame
      if (col >= 0 && col < w && row_from_bottom >= 0 && row_from_bottom < h) {
        // Image rows go top-down, grid rows bottom-up.
        const auto v = img.at<std::uint8_t>(static_cast<unsigned>(col),
                                            static_cast<unsigned>(h - 1 - row_from_bottom));
        wall = 1.0 - v / 255.0 > o.occupied_threshold;
      } else if (pad == 0) {
        wall = false;
      }
      g.setCell(cx, cy, wall ? 0.0f : 1.0f);  // MRPT: cell value = p(free)
    }
  world.finish();
  return world;
}

World World::room(double width, double height, double resolution) {
  World world;
  auto& g = world.grid_;
  g.setSize(static_cast<float>(-resolution), static_cast<float>(width + resolution),
            static_cast<float>(-resolution), static_cast<float>(height + resolution),
            static_cast<float>(resolution), 1.0f);
  const int sx = static_cast<int>(g.getSizeX()), sy = static_cast<int>(g.getSizeY());
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const bool wall = cx == 0 || cy == 0 || cx == sx - 1 || cy == sy - 1;
      g.setCell(cx, cy, wall ? 0.0f : 1.0f);
    }
  world.finish();
  return world;
}

void World::finish() {
  const int sx = static_cast<int>(grid_.getSizeX()), sy = static_cast<int>(grid_.getSizeY());
  cv::Mat1b free_mask(sy, sx);
  wall_cells_ = 0;
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const bool wall = grid_.getCell(cx, cy) < 0.5f;
      free_mask(cy, cx) = wall ? 0 : 255;
      wall_cells_ += wall;
    }
  cv::Mat1f dist;
  // Distance (in cells) from each free cell centre to the nearest wall cell centre.
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  clearance_.assign(static_cast<std::size_t>(sx) * sy, 0.f);
  const float res = grid_.getResolution();
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx)
      clearance_[static_cast<std::size_t>(cy) * sx + cx] =
          wall_cells_ ? dist(cy, cx) * res : 1e9f;
}

Box2 World::bounds() const {
  return {grid_.getXMin(), grid_.getYMin(), grid_.getXMax(), grid_.getYMax()};
}

bool World::occupiedAt(double x, double y) const {
  const int cx = grid_.x2idx(x), cy = grid_.y2idx(y);
  if (cx < 0 || cy < 0 || cx >= static_cast<int>(grid_.getSizeX()) ||
      cy >= static_cast<int>(grid_.getSizeY()))
    return true;
  return grid_.getCell(cx, cy) < 0.5f;
}

double World::clearance(double x, double y) const {
  const int cx = grid_.x2idx(x), cy = grid_.y2idx(y);
  const int sx = static_cast<int>(grid_.getSizeX());
  if (cx < 0 || cy < 0 || cx >= sx || cy >= static_cast<int>(grid_.getSizeY())) return 0;
  // Centre-to-centre distance minus half a cell: the wall cell's surface.
  const double c = clearance_[static_cast<std::size_t>(cy) * sx + cx];
  return std::max(0.0, c - 0.5 * grid_.getResolution());
}

bool World::sweepCollides(const Point2& a, const Point2& b, double radius) const {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const double step = 0.5 * grid_.getResolution();
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    if (clearance(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)) < radius) return true;
  }
  return false;
}

}  // namespace asf::sim2d
