#pragma once
/// \file segment_world.h
/// A 2D world of wall segments with exact ray casting: the ground truth of the
/// `segment_world` source and the synthetic input of tests and the conformance kit.
#include <asf/geometry.h>

#include <string>
#include <vector>

namespace asf::mapping {

struct Segment {
  Point2 a, b;
};

class SegmentWorld {
 public:
  SegmentWorld() = default;
  explicit SegmentWorld(std::vector<Segment> walls) : walls_(std::move(walls)) {}

  /// Parses "x1 y1 x2 y2; x1 y1 x2 y2; ..." (metres). Throws asf::ConfigError on bad text.
  static SegmentWorld parse(const std::string& text);
  /// Axis-aligned rectangle [x0,x1] x [y0,y1] as four walls.
  static SegmentWorld rectangle(double x0, double y0, double x1, double y1);
  /// Two rooms side by side (each w x h, total 2w x h, lower-left at the origin), joined by
  /// a door of width `door` in the middle of the shared wall.
  static SegmentWorld twoRooms(double w, double h, double door);

  const std::vector<Segment>& walls() const { return walls_; }
  void add(const Segment& s) { walls_.push_back(s); }

  /// Distance from (x, y) along direction `angle` (radians, world frame) to the nearest
  /// wall, or `max_range` if none is closer. Exact (no discretization).
  double castRay(double x, double y, double angle, double max_range) const;
  /// True if the straight segment p -> q comes closer than `clearance` to any wall.
  bool collides(const Point2& p, const Point2& q, double clearance) const;
  /// Bounding box of all walls.
  Box2 bounds() const;

 private:
  std::vector<Segment> walls_;
};

}  // namespace asf::mapping
