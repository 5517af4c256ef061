#include "sim2d_world.h"

#include <asf/text.h>
#include <mrpt/img/CImage.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>

namespace asf::sim2d {

namespace {}  // namespace

std::vector<HeightClass> parseHeightClasses(const std::string& text) {
  std::vector<HeightClass> out;
  if (trim(text).empty()) return out;
  std::set<int> seen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find_first_of(",;", start);
    const std::string entry =
        trim(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    start = end == std::string::npos ? text.size() + 1 : end + 1;
    const std::string where = "entry '" + entry + "'";
    if (entry.empty())
      throw std::invalid_argument(
          "empty entry; expected GRAY:HEIGHT[, GRAY:HEIGHT...], e.g. "
          "'0:2.0, 100:0.25'");
    const std::size_t colon = entry.find(':');
    if (colon == std::string::npos || entry.find(':', colon + 1) != std::string::npos)
      throw std::invalid_argument(where + ": expected GRAY:HEIGHT, e.g. '100:0.25'");
    const std::string g = trim(entry.substr(0, colon)), h = trim(entry.substr(colon + 1));
    char* rest = nullptr;
    const long gray = g.empty() ? -1 : std::strtol(g.c_str(), &rest, 10);
    if (g.empty() || *rest != '\0' || gray < 0 || gray > 255)
      throw std::invalid_argument(where + ": the gray level '" + g +
                                  "' is not an integer in 0..255");
    const double height = h.empty() ? NAN : std::strtod(h.c_str(), &rest);
    if (h.empty() || *rest != '\0' || !std::isfinite(height) || height <= 0)
      throw std::invalid_argument(where + ": the height '" + h + "' is not a number > 0 (metres)");
    if (!seen.insert(static_cast<int>(gray)).second)
      throw std::invalid_argument(where + ": gray level " + g + " appears twice");
    out.push_back({static_cast<int>(gray), height});
  }
  return out;
}

World World::fromImage(const ImageWorldOptions& o) {
  mrpt::img::CImage img;
  std::error_code ec;
  if (std::filesystem::exists(o.file, ec) && std::filesystem::file_size(o.file, ec) == 0 && !ec)
    throw std::runtime_error(o.file + ": the map image is an empty file");
  bool read = false;
  try {  // MRPT and OpenCV throw (with a call trace, without the file) on damaged images
    read = img.loadFromFile(o.file, 0 /*grayscale*/);
  } catch (const std::exception&) {
    read = false;
  }
  if (!read)
    throw std::runtime_error(o.file +
                             ": cannot read the map image (missing, damaged or not an image)");
  const int iw = static_cast<int>(img.getWidth()), ih = static_cast<int>(img.getHeight());
  if (iw < 2 || ih < 2) throw std::runtime_error(o.file + ": map image is smaller than 2x2 px");
  if (o.tiles < 1) throw std::runtime_error(o.file + ": tiles must be at least 1");
  // The tiled image's size, and the source pixel of one of its pixels (mirrored tiles).
  const int w = iw * o.tiles, h = ih * o.tiles;
  auto source = [&](int col, int row) {
    const int tc = col / iw, tr = row / ih;
    int c = col % iw, r = row % ih;
    if (tc % 2) c = iw - 1 - c;
    if (tr % 2) r = ih - 1 - r;
    return img.at<std::uint8_t>(static_cast<unsigned>(c), static_cast<unsigned>(r));
  };
  const int pad = o.pad_wall_px;
  const double res = o.resolution;
  // Height of each gray level: the nearest class (a tie goes to the darker one).
  std::array<float, 256> height_of{};
  for (int v = 0; v < 256; ++v) {
    height_of[v] = static_cast<float>(o.wall_height);
    int best = 1000, best_gray = 1000;
    for (const auto& c : o.height_classes) {
      const int d = std::abs(c.gray - v);
      if (d < best || (d == best && c.gray < best_gray)) {
        best = d;
        best_gray = c.gray;
        height_of[v] = static_cast<float>(c.height);
      }
    }
  }
  World world;
  world.grid_.setSize(
      static_cast<float>(o.origin_x - pad * res), static_cast<float>(o.origin_x + (w + pad) * res),
      static_cast<float>(o.origin_y - pad * res), static_cast<float>(o.origin_y + (h + pad) * res),
      static_cast<float>(res), 1.0f);
  auto& g = world.grid_;
  const int sx = static_cast<int>(g.getSizeX()), sy = static_cast<int>(g.getSizeY());
  world.heights_.assign(static_cast<std::size_t>(sx) * sy, 0.f);
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const int col = cx - pad, row_from_bottom = cy - pad;
      PixelClass c = PixelClass::Wall;  // the padding frame
      float height = static_cast<float>(o.wall_height);
      if (col >= 0 && col < w && row_from_bottom >= 0 && row_from_bottom < h) {
        // Image rows go top-down, grid rows bottom-up.
        const auto v = source(col, h - 1 - row_from_bottom);
        c = o.classes
                ? (*o.classes)[v]
                : (1.0 - v / 255.0 > o.occupied_threshold ? PixelClass::Wall : PixelClass::Free);
        height = height_of[v];
        if (c == PixelClass::Unknown && o.unknown != UnknownCells::Blocked) {
          c = o.unknown == UnknownCells::Wall ? PixelClass::Wall : PixelClass::Free;
          height = static_cast<float>(o.wall_height);
        }
      } else if (pad == 0) {
        c = PixelClass::Free;
      }
      // MRPT: cell value = p(free); unknown 0.5
      g.setCell(cx, cy, c == PixelClass::Wall ? 0.0f : c == PixelClass::Free ? 1.0f : 0.5f);
      world.heights_[static_cast<std::size_t>(cy) * sx + cx] = c == PixelClass::Wall ? height : 0.f;
    }
  world.finish();
  return world;
}

World World::room(double width, double height, double resolution, double wall_height) {
  World world;
  auto& g = world.grid_;
  g.setSize(static_cast<float>(-resolution), static_cast<float>(width + resolution),
            static_cast<float>(-resolution), static_cast<float>(height + resolution),
            static_cast<float>(resolution), 1.0f);
  const int sx = static_cast<int>(g.getSizeX()), sy = static_cast<int>(g.getSizeY());
  world.heights_.assign(static_cast<std::size_t>(sx) * sy, 0.f);
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const bool wall = cx == 0 || cy == 0 || cx == sx - 1 || cy == sy - 1;
      g.setCell(cx, cy, wall ? 0.0f : 1.0f);
      world.heights_[static_cast<std::size_t>(cy) * sx + cx] =
          wall ? static_cast<float>(wall_height) : 0.f;
    }
  world.finish();
  return world;
}

void World::finish() {
  const int sx = static_cast<int>(grid_.getSizeX()), sy = static_cast<int>(grid_.getSizeY());
  cv::Mat1b free_mask(sy, sx);
  wall_cells_ = 0;
  unknown_cells_ = 0;
  max_height_ = 0;
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const float p = grid_.getCell(cx, cy);
      const bool wall = p < 0.25f, unknown = !wall && p < 0.75f;
      free_mask(cy, cx) = wall || unknown ? 0 : 255;  // unknown cells block the robot too
      wall_cells_ += wall;
      unknown_cells_ += unknown;
      if (wall) max_height_ = std::max(max_height_, static_cast<double>(cellHeight(cx, cy)));
    }
  cv::Mat1f dist;
  // Distance (in cells) from each free cell centre to the nearest wall cell centre.
  cv::distanceTransform(free_mask, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  clearance_.assign(static_cast<std::size_t>(sx) * sy, 0.f);
  const float res = grid_.getResolution();
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx)
      clearance_[static_cast<std::size_t>(cy) * sx + cx] =
          wall_cells_ + unknown_cells_ ? dist(cy, cx) * res : 1e9f;
}

std::optional<std::pair<Point2, double>> World::farthestFromWalls() const {
  const int sx = static_cast<int>(grid_.getSizeX()), sy = static_cast<int>(grid_.getSizeY());
  int best = -1;
  for (int k = 0; k < sx * sy; ++k)
    if (grid_.getCell(k % sx, k / sx) >= 0.75f &&
        (best < 0 ||
         clearance_[static_cast<std::size_t>(k)] > clearance_[static_cast<std::size_t>(best)]))
      best = k;
  if (best < 0) return std::nullopt;
  const Point2 c{grid_.idx2x(best % sx), grid_.idx2y(best / sx)};
  return std::make_pair(c, clearance(c.x, c.y));
}

Box2 World::bounds() const {
  return {grid_.getXMin(), grid_.getYMin(), grid_.getXMax(), grid_.getYMax()};
}

bool World::occupiedAt(double x, double y) const {
  const int cx = grid_.x2idx(x), cy = grid_.y2idx(y);
  if (cx < 0 || cy < 0 || cx >= static_cast<int>(grid_.getSizeX()) ||
      cy >= static_cast<int>(grid_.getSizeY()))
    return true;
  return grid_.getCell(cx, cy) < 0.25f;
}

double World::heightAt(double x, double y) const {
  const int cx = grid_.x2idx(x), cy = grid_.y2idx(y);
  if (cx < 0 || cy < 0 || cx >= static_cast<int>(grid_.getSizeX()) ||
      cy >= static_cast<int>(grid_.getSizeY()))
    return 0;
  return cellHeight(cx, cy);
}

std::size_t World::cellsNotTallerThan(double z) const {
  // Heights are stored as floats: compare as floats, so that a box of height z is "not
  // taller" than a laser at z.
  const float zf = static_cast<float>(z);
  std::size_t n = 0;
  for (float h : heights_) n += h > 0 && h <= zf;
  return n;
}

std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> World::gridTallerThan(double z) const {
  if (cellsNotTallerThan(z) == 0 && unknown_cells_ == 0) return nullptr;
  const float zf = static_cast<float>(z);
  auto g = std::make_shared<mrpt::maps::COccupancyGridMap2D>(grid_);
  const int sx = static_cast<int>(grid_.getSizeX()), sy = static_cast<int>(grid_.getSizeY());
  for (int cy = 0; cy < sy; ++cy)
    for (int cx = 0; cx < sx; ++cx) {
      const float h = cellHeight(cx, cy);
      // Low obstacles and unknown cells (laserScanSimulator stops at p(free) <= 0.5): no echo.
      if ((h > 0 && h <= zf) || (h == 0 && grid_.getCell(cx, cy) < 0.75f)) g->setCell(cx, cy, 1.0f);
    }
  return g;
}

double World::castRay(const mrpt::math::TPoint3D& o, const mrpt::math::TPoint3D& d,
                      double max_range) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // The floor: z = 0 everywhere.
  double t_floor = kInf;
  if (o.z <= 0) {
    t_floor = 0;
  } else if (d.z < 0) {
    t_floor = -o.z / d.z;
  }
  const double t_end = std::min(t_floor, max_range);
  const auto hit = [&](double t) { return t <= max_range ? t : -1.0; };
  if (wall_cells_ == 0 || t_end <= 0) return hit(t_floor);

  // The part of the ray inside the grid's box (slab method on x and y).
  const double res = grid_.getResolution();
  const double x0 = grid_.getXMin(), y0 = grid_.getYMin();
  const int sx = static_cast<int>(grid_.getSizeX()), sy = static_cast<int>(grid_.getSizeY());
  const double x1 = x0 + sx * res, y1 = y0 + sy * res;
  double t_in = 0, t_out = t_end;
  const auto slab = [&](double p, double dp, double lo, double hi) {
    if (std::abs(dp) < 1e-15) {
      if (p < lo || p >= hi) t_out = -1;  // parallel to the slab and outside it
      return;
    }
    double a = (lo - p) / dp, b = (hi - p) / dp;
    if (a > b) std::swap(a, b);
    t_in = std::max(t_in, a);
    t_out = std::min(t_out, b);
  };
  slab(o.x, d.x, x0, x1);
  slab(o.y, d.y, y0, y1);
  if (t_out < t_in) return hit(t_floor);  // the ray misses the grid before the floor

  // Amanatides & Woo traversal of the cells the ray's ground track crosses, from t_in.
  const double px = o.x + d.x * t_in, py = o.y + d.y * t_in;
  int cx = std::clamp(static_cast<int>(std::floor((px - x0) / res)), 0, sx - 1);
  int cy = std::clamp(static_cast<int>(std::floor((py - y0) / res)), 0, sy - 1);
  const int step_x = d.x > 0 ? 1 : -1, step_y = d.y > 0 ? 1 : -1;
  double t_max_x = kInf, t_max_y = kInf, t_delta_x = kInf, t_delta_y = kInf;
  if (std::abs(d.x) >= 1e-15) {
    t_max_x = (x0 + (cx + (d.x > 0 ? 1 : 0)) * res - o.x) / d.x;
    t_delta_x = res / std::abs(d.x);
  }
  if (std::abs(d.y) >= 1e-15) {
    t_max_y = (y0 + (cy + (d.y > 0 ? 1 : 0)) * res - o.y) / d.y;
    t_delta_y = res / std::abs(d.y);
  }
  double t = t_in;
  while (true) {
    const double t_exit = std::min({t_max_x, t_max_y, t_out});
    const float h = cellHeight(cx, cy);
    const double z = o.z + d.z * t;
    if (h > 0) {
      if (z <= h) return hit(t);  // the column's side (or the ray starts inside it)
      if (d.z < 0) {
        const double t_top = (h - o.z) / d.z;
        if (t_top <= t_exit) return hit(t_top);  // comes down on the column's top
      }
    } else if (d.z >= 0 && z > max_height_) {
      return -1;  // level or rising above every obstacle: nothing more to hit
    }
    if (t_exit >= t_out) break;
    if (t_max_x < t_max_y) {
      cx += step_x;
      t = t_max_x;
      t_max_x += t_delta_x;
    } else {
      cy += step_y;
      t = t_max_y;
      t_max_y += t_delta_y;
    }
    if (cx < 0 || cy < 0 || cx >= sx || cy >= sy) break;
  }
  return hit(t_floor);
}

void World::simulateScan3D(mrpt::obs::CObservation2DRangeScan& scan,
                           const mrpt::poses::CPose2D& robot, std::size_t rays) const {
  const mrpt::poses::CPose3D sensor = mrpt::poses::CPose3D(robot) + scan.sensorPose;
  const auto& R = sensor.getRotationMatrix();
  const mrpt::math::TPoint3D o(sensor.x(), sensor.y(), sensor.z());
  scan.resizeScan(rays);
  for (std::size_t i = 0; i < rays; ++i) {
    const double a = scan.getScanAngle(i), c = std::cos(a), s = std::sin(a);
    // The ray's direction: the sensor's x-y plane, rotated into the world.
    const mrpt::math::TPoint3D d(R(0, 0) * c + R(0, 1) * s, R(1, 0) * c + R(1, 1) * s,
                                 R(2, 0) * c + R(2, 1) * s);
    const double r = castRay(o, d, scan.maxRange);
    const bool valid = r > 0;
    scan.setScanRange(i, static_cast<float>(valid ? r : scan.maxRange));
    scan.setScanRangeValidity(i, valid);
  }
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
