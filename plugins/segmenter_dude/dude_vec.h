#pragma once
// Private to asf_dude: 2D vector arithmetic and angles of the `rooms` decomposition (dude.cpp,
// dude_candidates.cpp, dude_concavity.cpp).
#include <cmath>
#include <cstddef>

#include "dude.h"

namespace asf::dude::detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = 1e-9;  // distances [m] below this are "the same point"

inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
inline double orient(Vec2 o, Vec2 a, Vec2 b) { return cross(a - o, b - o); }
inline bool same(Vec2 a, Vec2 b) { return norm(a - b) <= kEps; }

/// Distance from p to segment ab; *t receives the parameter of the closest point.
inline double distToSegment(Vec2 p, Vec2 a, Vec2 b, double* t) {
  const Vec2 ab = b - a;
  const double l2 = dot(ab, ab);
  double s = l2 > 0 ? dot(p - a, ab) / l2 : 0;
  s = std::clamp(s, 0.0, 1.0);
  if (t) *t = s;
  return norm(p - (a + s * ab));
}

/// Angle of direction d measured counter-clockwise from direction ref, in [0, 2 pi).
inline double ccwAngle(Vec2 ref, Vec2 d) {
  double a = std::atan2(cross(ref, d), dot(ref, d));
  if (a < 0) a += 2 * kPi;
  return a;
}

/// Interior angle at ring[i] (interior on the left of the ring's direction).
inline double interiorAngle(const Ring& r, std::size_t i) {
  const std::size_t n = r.size();
  const Vec2 cur = r[i], prev = r[(i + n - 1) % n], next = r[(i + 1) % n];
  return ccwAngle(next - cur, prev - cur);
}

}  // namespace asf::dude::detail
