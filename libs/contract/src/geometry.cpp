#include <asf/geometry.h>

namespace asf {

double polygonArea(const Polygon& p) {
  double a = 0;
  for (std::size_t i = 0, n = p.size(); i < n; ++i) {
    const Point2& u = p[i];
    const Point2& v = p[(i + 1) % n];
    a += u.x * v.y - v.x * u.y;
  }
  return 0.5 * a;
}

Point2 polygonCentroid(const Polygon& p) {
  const double a = polygonArea(p);
  Point2 c;
  if (p.empty()) return c;
  if (a == 0) {  // degenerate: vertex mean
    for (const auto& q : p) c.x += q.x, c.y += q.y;
    c.x /= p.size(), c.y /= p.size();
    return c;
  }
  for (std::size_t i = 0, n = p.size(); i < n; ++i) {
    const Point2& u = p[i];
    const Point2& v = p[(i + 1) % n];
    const double cr = u.x * v.y - v.x * u.y;
    c.x += (u.x + v.x) * cr;
    c.y += (u.y + v.y) * cr;
  }
  c.x /= 6 * a, c.y /= 6 * a;
  return c;
}

}  // namespace asf
