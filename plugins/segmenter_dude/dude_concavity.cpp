// Concavity through the bridge hierarchy (Liu, Xi, Lien 2014), for the `rooms` decomposition.
#include "dude_concavity.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "dude_vec.h"

namespace asf::dude::detail {

/// Strict convex hull (Andrew's monotone chain) of pts; positions into pts, ascending.
/// Hand-written because the decomposition needs vertex positions, which Boost's convex_hull
/// (it returns points) does not give.
std::vector<int> hullPositions(const std::vector<Vec2>& pts) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return pts[a].x < pts[b].x || (pts[a].x == pts[b].x && pts[a].y < pts[b].y);
  });
  if (n < 3) return order;
  std::vector<int> h(2 * n);
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 && orient(pts[h[k - 2]], pts[h[k - 1]], pts[order[i]]) <= 0) --k;
    h[k++] = order[i];
  }
  for (int i = n - 2, lo = k + 1; i >= 0; --i) {
    while (k >= lo && orient(pts[h[k - 2]], pts[h[k - 1]], pts[order[i]]) <= 0) --k;
    h[k++] = order[i];
  }
  h.resize(std::max(k - 1, 0));
  std::sort(h.begin(), h.end());
  h.erase(std::unique(h.begin(), h.end()), h.end());
  return h;
}

namespace {

constexpr int kMaxPocketDepth = 48;  // bridge hierarchy depth (deeper: plain distance)

/// Adds to `hull` (ascending positions) the points lying on the hull edges between
/// consecutive hull positions (and, when cyclic, between the last and the first).
std::vector<int> withCollinear(const std::vector<Vec2>& pts, const std::vector<int>& hull,
                               bool cyclic) {
  if (hull.size() < 2) return hull;
  const int n = static_cast<int>(pts.size());
  std::vector<int> out;
  out.reserve(hull.size());
  const std::size_t pairs = cyclic ? hull.size() : hull.size() - 1;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    out.push_back(hull[k]);
    if (k >= pairs) continue;
    const int h0 = hull[k];
    const int h1 = k + 1 < hull.size() ? hull[k + 1] : hull[0] + n;
    for (int p = h0 + 1; p < h1; ++p)
      if (distToSegment(pts[p % n], pts[h0], pts[h1 % n], nullptr) <= kEps) out.push_back(p % n);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Concavity of the vertices strictly inside `chain` (ring positions from one bridge end to
/// the other), whose bridge ends have concavity ca and cb.
void analysePocket(const Ring& r, const std::vector<int>& chain, double ca, double cb, int depth,
                   Concavity& c) {
  const int node = c.pockets++;
  const int m = static_cast<int>(chain.size());
  const Vec2 a = r[chain.front()], b = r[chain.back()];
  std::vector<Vec2> pts(m);
  for (int i = 0; i < m; ++i) pts[i] = r[chain[i]];
  // Concavity of a point seen from this pocket: distance to the bridge plus the concavity
  // of the bridge where the point projects (interpolated between its ends).
  auto through = [&](int pos) {
    double t = 0;
    const double d = distToSegment(pts[pos], a, b, &t);
    return d + ca + (cb - ca) * t;
  };
  std::vector<int> hull = hullPositions(pts);
  hull.push_back(0);
  hull.push_back(m - 1);
  // Chain points touching the bridge are on the hull too (they split the pocket).
  for (int p = 1; p + 1 < m; ++p)
    if (distToSegment(pts[p], a, b, nullptr) <= kEps) hull.push_back(p);
  std::sort(hull.begin(), hull.end());
  hull.erase(std::unique(hull.begin(), hull.end()), hull.end());
  hull = withCollinear(pts, hull, false);
  auto concAt = [&](int pos) {
    if (pos == 0) return ca;
    if (pos == m - 1) return cb;
    return c.value[chain[pos]];
  };
  for (int h : hull)
    if (h != 0 && h != m - 1) {
      c.value[chain[h]] = through(h);
      c.pocket[chain[h]] = node;
    }
  for (std::size_t k = 0; k + 1 < hull.size(); ++k) {
    const int h0 = hull[k], h1 = hull[k + 1];
    if (h1 - h0 < 2) continue;
    if (depth >= kMaxPocketDepth) {
      for (int p = h0 + 1; p < h1; ++p) {
        c.value[chain[p]] = through(p);
        c.pocket[chain[p]] = node;
      }
      continue;
    }
    std::vector<int> sub(chain.begin() + h0, chain.begin() + h1 + 1);
    analysePocket(r, sub, concAt(h0), concAt(h1), depth + 1, c);
  }
}

}  // namespace

Concavity analyse(const Ring& r) {
  const int n = static_cast<int>(r.size());
  Concavity c;
  c.value.assign(n, 0.0);
  c.pocket.assign(n, -1);
  if (n < 4) return c;
  const std::vector<int> hull = withCollinear(r, hullPositions(r), true);
  if (hull.size() < 3) return c;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const int h0 = hull[k];
    const int h1 = k + 1 < hull.size() ? hull[k + 1] : hull[0] + n;
    if (h1 - h0 < 2) continue;
    std::vector<int> chain;
    chain.reserve(h1 - h0 + 1);
    for (int p = h0; p <= h1; ++p) chain.push_back(p % n);
    analysePocket(r, chain, 0.0, 0.0, 1, c);
  }
  return c;
}

}  // namespace asf::dude::detail
