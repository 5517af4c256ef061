#pragma once
// The simulator's true world: a 2.5D occupancy grid (from a map image or a built-in room)
// where every obstacle cell is a vertical column standing on the floor (z = 0) with a height,
// and its clearance field. Used for laser simulation (the horizontal laser on the obstacles
// taller than its height, the tilted laser by ray casting over the height field) and for
// collision checks (every obstacle, whatever its height).
#include <asf/geometry.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace asf::sim2d {

/// Obstacle pixels whose gray level is nearest to `gray` (0..255) are `height` metres tall.
struct HeightClass {
  int gray = 0;
  double height = 0;
};

/// Parses "GRAY:HEIGHT, GRAY:HEIGHT, ..." (commas or semicolons between entries, blanks
/// allowed; empty or blank text = no classes). GRAY is an integer 0..255, HEIGHT a finite
/// number > 0 [m]; a gray level may appear once. Throws std::invalid_argument saying what is
/// wrong (without the key name) otherwise.
std::vector<HeightClass> parseHeightClasses(const std::string& text);

/// What a pixel of a map image is in the world.
enum class PixelClass : std::uint8_t { Free, Wall, Unknown };

/// Unknown pixels (a map_server map's gray between its thresholds) in the world: Wall, a wall;
/// Blocked, the robot cannot enter them and the lasers see through them (no echo); Free.
enum class UnknownCells { Blocked, Free, Wall };

struct ImageWorldOptions {
  std::string file;                   ///< PNG/PGM/...: dark = wall
  double resolution = 0.04;           ///< metres per pixel
  double origin_x = 0, origin_y = 0;  ///< world coordinates of the image's lower-left corner
  double occupied_threshold = 0.5;    ///< a pixel with 1 - gray/255 above this is a wall
  /// When set, the class of each gray level instead of occupied_threshold (a map_server map's
  /// rules: asf/io/occupancy_io.h's mapServerOccupancy).
  std::optional<std::array<PixelClass, 256>> classes;
  UnknownCells unknown = UnknownCells::Wall;
  int pad_wall_px = 0;  ///< wall of this many pixels added around the image
  /// The world is tiles x tiles copies of the image, every other one mirrored (horizontally
  /// in odd columns, vertically in odd rows) so the walls meet at the seams: bigger worlds of
  /// the same kind, for scaling measurements. The padding goes around the whole.
  int tiles = 1;
  /// Height of every obstacle pixel without classes, and of the padding frame [m].
  double wall_height = 2.0;
  /// When not empty, an obstacle pixel of gray level v is as tall as the class whose `gray`
  /// is nearest to v (a tie goes to the darker class).
  std::vector<HeightClass> height_classes;
};

class World {
 public:
  /// Loads an image; throws std::runtime_error naming the file when it can't be read.
  static World fromImage(const ImageWorldOptions& o);
  /// A closed rectangular room [0, width] x [0, height] whose walls are one cell thick,
  /// just outside it, `wall_height` tall.
  static World room(double width, double height, double resolution, double wall_height = 2.0);

  /// Every obstacle, whatever its height (collisions, ground truth); unknown cells (Blocked)
  /// hold 0.5, neither free nor occupied.
  const mrpt::maps::COccupancyGridMap2D& grid() const { return grid_; }
  double resolution() const { return grid_.getResolution(); }
  Box2 bounds() const;
  bool occupiedAt(double x, double y) const;  ///< outside the grid counts as occupied
  /// Height of the obstacle column at (x, y) [m]: 0 on free floor and outside the grid.
  double heightAt(double x, double y) const;
  /// Height of cell (cx, cy) (0: free); the cell must be inside the grid.
  float cellHeight(int cx, int cy) const {
    return heights_[static_cast<std::size_t>(cy) * grid_.getSizeX() + cx];
  }
  /// Number of obstacle cells no taller than z (invisible to a horizontal laser at z).
  std::size_t cellsNotTallerThan(double z) const;
  /// The grid of the obstacles strictly taller than z: what a horizontal laser at height z
  /// sees (unknown cells free: no echo). Null when every obstacle is taller than z and no
  /// cell is unknown: then it is `grid()` itself.
  std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> gridTallerThan(double z) const;
  /// Cells that are unknown and block the robot (UnknownCells::Blocked).
  std::size_t unknownCells() const { return unknown_cells_; }
  /// The centre of the free cell farthest from every wall and blocking unknown cell (the
  /// lowest row, then column, of the ties), and that distance [m]; nullopt without free cells.
  std::optional<std::pair<Point2, double>> farthestFromWalls() const;
  /// Distance from (x, y) to the nearest wall surface or blocking unknown cell [m] (0 inside
  /// one or outside).
  double clearance(double x, double y) const;
  /// True when a disc of `radius` moving straight from a to b touches a wall.
  bool sweepCollides(const Point2& a, const Point2& b, double radius) const;
  std::size_t wallCells() const { return wall_cells_; }
  double maxHeight() const { return max_height_; }

  /// The range of a ray from `origin` along the unit vector `dir` (world frame, z up) to the
  /// first surface of the height field: the floor z = 0 (everywhere, also outside the grid)
  /// or an obstacle column (its sides and its top; outside the grid there are none).
  /// Returns a negative value when nothing is hit within max_range.
  double castRay(const mrpt::math::TPoint3D& origin, const mrpt::math::TPoint3D& dir,
                 double max_range) const;

  /// Fills `scan` (its aperture, rightToLeft and sensorPose — the sensor's pose on the
  /// robot, any 3D pose — must be set) with `rays` exact ranges by castRay() from the robot at
  /// `robot` (on the floor, z = 0). Rays with no hit within scan.maxRange are invalid and read
  /// maxRange.
  void simulateScan3D(mrpt::obs::CObservation2DRangeScan& scan, const mrpt::poses::CPose2D& robot,
                      std::size_t rays) const;

 private:
  void finish();  // computes the clearance field from the grid
  mrpt::maps::COccupancyGridMap2D grid_;
  std::vector<float> heights_;    // per cell, 0 = free
  std::vector<float> clearance_;  // per cell, metres between cell centres
  std::size_t wall_cells_ = 0;
  std::size_t unknown_cells_ = 0;
  double max_height_ = 0;
};

}  // namespace asf::sim2d
