#pragma once
/// \file geometry.h
/// Small geometric value types in metres, map frame.
#include <vector>

namespace asf {

struct Point2 {
  double x = 0, y = 0;
};

/// Closed polygon, vertices in order (counter-clockwise for outer boundaries), no repeat
/// of the first vertex at the end.
using Polygon = std::vector<Point2>;

/// Axis-aligned box; empty() when min > max.
struct Box2 {
  double min_x = 1, min_y = 1, max_x = 0, max_y = 0;
  bool empty() const { return min_x > max_x || min_y > max_y; }
  void extend(double x, double y) {
    if (empty()) { min_x = max_x = x; min_y = max_y = y; return; }
    if (x < min_x) min_x = x;
    if (x > max_x) max_x = x;
    if (y < min_y) min_y = y;
    if (y > max_y) max_y = y;
  }
};

/// Signed area (positive when counter-clockwise) and centroid of a simple polygon.
double polygonArea(const Polygon& p);
Point2 polygonCentroid(const Polygon& p);

}  // namespace asf
