#pragma once
// The simulator's true world: a binary occupancy grid (from a map image or a built-in room)
// and its clearance field, used for laser simulation and collision checks.
#include <asf/geometry.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <string>
#include <vector>

namespace asf::sim2d {

struct ImageWorldOptions {
  std::string file;                ///< PNG/PGM/...: dark = wall
  double resolution = 0.04;        ///< metres per pixel
  double origin_x = 0, origin_y = 0;  ///< world coordinates of the image's lower-left corner
  double occupied_threshold = 0.5;  ///< a pixel with 1 - gray/255 above this is a wall
  int pad_wall_px = 0;             ///< wall of this many pixels added around the image
};

class World {
 public:
  /// Loads an image; throws std::runtime_error naming the file when it can't be read.
  static World fromImage(const ImageWorldOptions& o);
  /// A closed rectangular room [0, width] x [0, height] whose walls are one cell thick,
  /// just outside it.
  static World room(double width, double height, double resolution);

  const mrpt::maps::COccupancyGridMap2D& grid() const { return grid_; }
  double resolution() const { return grid_.getResolution(); }
  Box2 bounds() const;
  bool occupiedAt(double x, double y) const;  ///< outside the grid counts as occupied
  /// Distance from (x, y) to the nearest wall surface [m] (0 inside a wall or outside).
  double clearance(double x, double y) const;
  /// True when a disc of `radius` moving straight from a to b touches a wall.
  bool sweepCollides(const Point2& a, const Point2& b, double radius) const;
  std::size_t wallCells() const { return wall_cells_; }

 private:
  void finish();  // computes the clearance field from the grid
  mrpt::maps::COccupancyGridMap2D grid_;
  std::vector<float> clearance_;  // per cell, metres between cell centres
  std::size_t wall_cells_ = 0;
};

}  // namespace asf::sim2d
