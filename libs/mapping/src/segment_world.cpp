// SegmentWorld: walls as line segments, exact ray casting and clearance checks.
#include <asf/errors.h>
#include <asf/mapping/segment_world.h>
#include <asf/text.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace asf::mapping {
namespace {

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

/// Distance from point p to segment [a, b].
double pointSegmentDistance(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = 0;
  if (len2 > 0) t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

int orientation(const Point2& a, const Point2& b, const Point2& c) {
  const double v = cross(b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y);
  return (v > 0) - (v < 0);
}

bool onSegment(const Point2& a, const Point2& b, const Point2& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

/// True if the closed segments [p1, p2] and [q1, q2] share a point.
bool segmentsIntersect(const Point2& p1, const Point2& p2, const Point2& q1, const Point2& q2) {
  const int o1 = orientation(p1, p2, q1), o2 = orientation(p1, p2, q2);
  const int o3 = orientation(q1, q2, p1), o4 = orientation(q1, q2, p2);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && onSegment(p1, p2, q1)) return true;
  if (o2 == 0 && onSegment(p1, p2, q2)) return true;
  if (o3 == 0 && onSegment(q1, q2, p1)) return true;
  if (o4 == 0 && onSegment(q1, q2, p2)) return true;
  return false;
}

double segmentSegmentDistance(const Point2& p1, const Point2& p2, const Point2& q1,
                              const Point2& q2) {
  if (segmentsIntersect(p1, p2, q1, q2)) return 0;
  return std::min({pointSegmentDistance(p1, q1, q2), pointSegmentDistance(p2, q1, q2),
                   pointSegmentDistance(q1, p1, p2), pointSegmentDistance(q2, p1, p2)});
}

bool parseNumber(const std::string& tok, double& out) {
  if (tok.empty()) return false;
  const char* s = tok.c_str();
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s, &end);
  return end == s + tok.size() && errno == 0 && std::isfinite(out);
}

}  // namespace

SegmentWorld SegmentWorld::parse(const std::string& text) {
  std::vector<Segment> walls;
  std::size_t start = 0;
  int index = 0;
  while (start <= text.size()) {
    std::size_t end = text.find(';', start);
    if (end == std::string::npos) end = text.size();
    const std::string item = trim(text.substr(start, end - start));
    start = end + 1;
    ++index;
    if (item.empty()) continue;  // allows "a; b;" and blank text
    std::string spaced = item;
    std::replace(spaced.begin(), spaced.end(), ',', ' ');
    std::istringstream in(spaced);
    std::vector<double> v;
    std::string tok;
    while (in >> tok) {
      double d = 0;
      if (!parseNumber(tok, d))
        throw ConfigError("wall " + std::to_string(index) + " '" + item + "': '" + tok +
                          "' is not a finite number (expected 'x1 y1 x2 y2' in metres)");
      v.push_back(d);
    }
    if (v.size() != 4)
      throw ConfigError("wall " + std::to_string(index) + " '" + item + "': expected 4 numbers " +
                        "'x1 y1 x2 y2', got " + std::to_string(v.size()));
    if (v[0] == v[2] && v[1] == v[3])
      throw ConfigError("wall " + std::to_string(index) + " '" + item +
                        "': both ends are the same point (zero-length wall)");
    walls.push_back(Segment{{v[0], v[1]}, {v[2], v[3]}});
  }
  return SegmentWorld(std::move(walls));
}

SegmentWorld SegmentWorld::rectangle(double x0, double y0, double x1, double y1) {
  if (!(x1 > x0) || !(y1 > y0)) throw Error("SegmentWorld::rectangle: need x0 < x1 and y0 < y1");
  return SegmentWorld({Segment{{x0, y0}, {x1, y0}}, Segment{{x1, y0}, {x1, y1}},
                       Segment{{x1, y1}, {x0, y1}}, Segment{{x0, y1}, {x0, y0}}});
}

SegmentWorld SegmentWorld::twoRooms(double w, double h, double door) {
  if (!(w > 0) || !(h > 0))
    throw Error("SegmentWorld::twoRooms: room width and height must be positive");
  if (!(door >= 0) || !(door < h))
    throw Error("SegmentWorld::twoRooms: door width must be in [0, room height)");
  SegmentWorld world = rectangle(0, 0, 2 * w, h);
  const double lo = 0.5 * (h - door), hi = 0.5 * (h + door);
  if (door == 0) {
    world.add(Segment{{w, 0}, {w, h}});
  } else {
    world.add(Segment{{w, 0}, {w, lo}});
    world.add(Segment{{w, hi}, {w, h}});
  }
  return world;
}

double SegmentWorld::castRay(double x, double y, double angle, double max_range) const {
  const double dx = std::cos(angle), dy = std::sin(angle);
  double best = max_range;
  for (const Segment& s : walls_) {
    const double ex = s.b.x - s.a.x, ey = s.b.y - s.a.y;  // wall direction
    const double wx = s.a.x - x, wy = s.a.y - y;          // ray origin -> wall start
    const double denom = cross(dx, dy, ex, ey);
    if (denom != 0) {
      // origin + t d = a + u e  ->  t = (w x e) / (d x e), u = (w x d) / (d x e)
      const double t = cross(wx, wy, ex, ey) / denom;
      const double u = cross(wx, wy, dx, dy) / denom;
      if (t >= 0 && u >= 0 && u <= 1 && t < best) best = t;
    } else if (cross(wx, wy, dx, dy) == 0) {
      // Collinear: the ray hits the nearest point of the wall that lies ahead.
      const double ta = wx * dx + wy * dy;
      const double tb = (s.b.x - x) * dx + (s.b.y - y) * dy;
      double t;
      if (ta >= 0 && tb >= 0)
        t = std::min(ta, tb);
      else if (ta <= 0 && tb <= 0)
        continue;  // wholly behind
      else
        t = 0;  // the origin is on the wall
      if (t < best) best = t;
    }
  }
  return best;
}

bool SegmentWorld::collides(const Point2& p, const Point2& q, double clearance) const {
  for (const Segment& s : walls_)
    if (segmentSegmentDistance(p, q, s.a, s.b) < clearance) return true;
  return false;
}

Box2 SegmentWorld::bounds() const {
  Box2 b;
  for (const Segment& s : walls_) {
    b.extend(s.a.x, s.a.y);
    b.extend(s.b.x, s.b.y);
  }
  return b;
}

}  // namespace asf::mapping
