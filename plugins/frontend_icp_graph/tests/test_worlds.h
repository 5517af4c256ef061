#pragma once
// Small line-segment worlds for the loop-search tests: a room without symmetry and a corridor
// of identical doors; sampled as point sets, or seen by a ray-cast 360-degree laser.
#include <array>
#include <cmath>
#include <vector>

namespace asf_test_worlds {

struct World {
  std::vector<std::array<double, 4>> segments;  ///< x0 y0 x1 y1
  void add(double x0, double y0, double x1, double y1) { segments.push_back({x0, y0, x1, y1}); }
};

/// A 6 m x 4 m room with a pillar, a niche and a shelf: no symmetry.
inline World room() {
  World w;
  const double p[][4] = {{0, 0, 6, 0},         {6, 0, 6, 1.5},     {6, 1.5, 6.8, 1.5},
                         {6.8, 1.5, 6.8, 2.5}, {6.8, 2.5, 6, 2.5}, {6, 2.5, 6, 4},
                         {6, 4, 0, 4},         {0, 4, 0, 0},       {2, 1, 2.4, 1},
                         {2.4, 1, 2.4, 1.4},   {2.4, 1.4, 2, 1.4}, {2, 1.4, 2, 1},
                         {3.5, 3.2, 4.7, 3.5}};
  for (const auto& s : p) w.add(s[0], s[1], s[2], s[3]);
  return w;
}

/// A corridor 2 m wide along x, with a door (a 0.8 m gap) in the upper wall every 3 m and a
/// 0.4 m deep niche in the lower wall every 3 m.
inline World doors(double length) {
  World w;
  for (double x = 0; x < length; x += 3.0) {
    w.add(x, 2, x + 2.2, 2);
    w.add(x, 0, x + 1.0, 0);
    w.add(x + 1.0, 0, x + 1.0, -0.4);
    w.add(x + 1.0, -0.4, x + 1.6, -0.4);
    w.add(x + 1.6, -0.4, x + 1.6, 0);
    w.add(x + 1.6, 0, x + 3.0, 0);
  }
  return w;
}

/// Points along every segment, `spacing` apart (both ends included).
inline void sample(const World& w, double spacing, std::vector<float>& x, std::vector<float>& y) {
  for (const auto& s : w.segments) {
    const int n = std::max(1, static_cast<int>(std::hypot(s[2] - s[0], s[3] - s[1]) / spacing));
    for (int i = 0; i <= n; ++i) {
      x.push_back(static_cast<float>(s[0] + (s[2] - s[0]) * i / n));
      y.push_back(static_cast<float>(s[1] + (s[3] - s[1]) * i / n));
    }
  }
}

/// Range of the nearest segment along the ray from (px, py) in direction `a`, or max_range.
inline double castRay(const World& w, double px, double py, double a, double max_range) {
  const double dx = std::cos(a), dy = std::sin(a);
  double best = max_range;
  for (const auto& s : w.segments) {
    // p + t d = s0 + u (s1 - s0)
    const double ex = s[2] - s[0], ey = s[3] - s[1];
    const double den = dx * ey - dy * ex;
    if (std::abs(den) < 1e-12) continue;
    const double qx = s[0] - px, qy = s[1] - py;
    const double t = (qx * ey - qy * ex) / den, u = (qx * dy - qy * dx) / den;
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

}  // namespace asf_test_worlds
