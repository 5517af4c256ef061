// Candidate cuts of the `rooms` decomposition at a pocket minimum (see dude_candidates.h): to
// the nearest reflex vertices, along the minimum's two edges continued and to the nearest
// boundary points, each kept when it runs inside the polygon and resolves the minimum.
#include "dude_candidates.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "dude_vec.h"

namespace asf::dude::detail {

bool blockedBy(const Ring& ring, Vec2 p, Vec2 q) {
  const double len = norm(q - p);
  if (len <= kEps) return true;
  const double minx = std::min(p.x, q.x) - kEps, maxx = std::max(p.x, q.x) + kEps;
  const double miny = std::min(p.y, q.y) - kEps, maxy = std::max(p.y, q.y) + kEps;
  const std::size_t n = ring.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 u = ring[k], v = ring[(k + 1) % n];
    if (std::max(u.x, v.x) < minx || std::min(u.x, v.x) > maxx || std::max(u.y, v.y) < miny ||
        std::min(u.y, v.y) > maxy)
      continue;
    const double du = orient(p, q, u) / len, dv = orient(p, q, v) / len;
    // A vertex lying on the open segment pq: grazing a corner counts as blocked.
    for (const Vec2 w : {u, v}) {
      const double dw = orient(p, q, w) / len;
      if (std::abs(dw) <= 1e-7 && !same(w, p) && !same(w, q)) {
        const double s = dot(w - p, q - p) / (len * len);
        if (s > 1e-9 && s < 1 - 1e-9) return true;
      }
    }
    if ((du > 1e-7 && dv < -1e-7) || (du < -1e-7 && dv > 1e-7)) {
      const double el = norm(v - u);
      if (el <= kEps) continue;
      const double dp = orient(u, v, p) / el, dq = orient(u, v, q) / el;
      if ((dp > 1e-7 && dq < -1e-7) || (dp < -1e-7 && dq > 1e-7)) return true;
    }
  }
  return false;
}

namespace {

/// Checks that the cut from ring vertex i to `e` runs inside the polygon; fills the angles
/// it leaves at vertex i (a0: between the next edge and the cut; a1: the rest).
bool validCut(const Work& w, int i, const End& e, double* a0, double* a1) {
  const Ring& r = w.outer;
  const int n = static_cast<int>(r.size());
  const Vec2 p = r[i], q = e.p;
  const Vec2 d = q - p;
  if (norm(d) <= kEps) return false;
  const Vec2 next = r[(i + 1) % n] - p;
  const double interior = interiorAngle(r, i);
  const double rel = ccwAngle(next, d);
  if (rel <= 1e-6 || rel >= interior - 1e-6) return false;
  if (a0) *a0 = rel;
  if (a1) *a1 = interior - rel;
  if (e.vertex >= 0) {
    if (e.vertex == i) return false;
    const double int_j = interiorAngle(r, e.vertex);
    const double rel_j = ccwAngle(r[(e.vertex + 1) % n] - q, p - q);
    if (rel_j <= 1e-6 || rel_j >= int_j - 1e-6) return false;
  } else {
    const Vec2 u = r[e.edge], v = r[(e.edge + 1) % n];
    if (cross(v - u, p - q) <= 1e-9 * norm(v - u) * norm(p - q)) return false;  // from the left
  }
  if (blockedBy(r, p, q)) return false;
  for (const Ring& h : w.holes)
    if (blockedBy(h, p, q)) return false;
  return true;
}

/// First boundary point hit by the ray from ring vertex i along direction dir.
bool castRay(const Ring& r, int i, Vec2 dir, End* hit) {
  const int n = static_cast<int>(r.size());
  const Vec2 p = r[i];
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    if (k == i || k1 == i) continue;
    const Vec2 u = r[k], v = r[k1];
    const Vec2 ev = v - u;
    const double den = cross(dir, ev);
    if (std::abs(den) <= 1e-12) continue;
    const Vec2 w = u - p;
    const double s = cross(w, ev) / den;   // along the ray
    const double t = cross(w, dir) / den;  // along the edge
    if (s <= 1e-9 || t < -1e-9 || t > 1 + 1e-9 || s >= best) continue;
    best = s;
    hit->p = p + s * dir;
    if (t <= 1e-6 || norm(hit->p - u) <= kEps) {
      hit->vertex = k;
      hit->p = u;
    } else if (t >= 1 - 1e-6 || norm(hit->p - v) <= kEps) {
      hit->vertex = k1;
      hit->p = v;
    } else {
      hit->vertex = -1;
      hit->edge = k;
      hit->t = t;
    }
  }
  return std::isfinite(best);
}

/// Ends at the reflex vertices nearest to pocket minimum pm (doorway to doorway), at most a
/// few, nearest first.
std::vector<End> nearReflexEnds(const Ring& r, const std::vector<int>& reflex_list, int pm) {
  const Vec2 p = r[pm];
  std::vector<std::pair<double, int>> near;
  for (int j : reflex_list)
    if (j != pm) near.push_back({norm(r[j] - p), j});
  const std::size_t kNearReflex = 12;
  if (near.size() > kNearReflex) {
    std::nth_element(near.begin(), near.begin() + kNearReflex, near.end());
    near.resize(kNearReflex);
  }
  std::sort(near.begin(), near.end());
  std::vector<End> ends;
  for (const auto& [d, j] : near) {
    End e;
    e.vertex = j;
    e.p = r[j];
    ends.push_back(e);
  }
  return ends;
}

/// Ends where the two edges meeting at pocket minimum pm, continued past it (walls continued),
/// first hit the boundary.
std::vector<End> wallExtensionEnds(const Ring& r, int pm) {
  const int n = static_cast<int>(r.size());
  const Vec2 p = r[pm];
  const Vec2 prev = r[(pm + n - 1) % n], next = r[(pm + 1) % n];
  std::vector<End> ends;
  for (const Vec2 dir : {p - prev, p - next}) {
    const double l = norm(dir);
    if (l <= kEps) continue;
    End e;
    if (castRay(r, pm, (1.0 / l) * dir, &e)) ends.push_back(e);
  }
  return ends;
}

/// Ends at the boundary points nearest to pocket minimum pm (shortest way across), one per
/// edge, at most a few, nearest first.
std::vector<End> nearestBoundaryEnds(const Ring& r, int pm) {
  const int n = static_cast<int>(r.size());
  const Vec2 p = r[pm];
  std::vector<std::pair<double, End>> closest;
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    if (k == pm || k1 == pm) continue;
    double t = 0;
    const Vec2 a = r[k], b = r[k1];
    const double d = distToSegment(p, a, b, &t);
    End e;
    if (t <= 1e-6) {
      e.vertex = k;
      e.p = a;
    } else if (t >= 1 - 1e-6) {
      e.vertex = k1;
      e.p = b;
    } else {
      e.edge = k;
      e.t = t;
      e.p = a + t * (b - a);
    }
    closest.push_back({d, e});
  }
  const std::size_t kNearEdges = 4;
  if (closest.size() > kNearEdges) {
    std::nth_element(closest.begin(), closest.begin() + kNearEdges, closest.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    closest.resize(kNearEdges);
  }
  std::stable_sort(closest.begin(), closest.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<End> ends;
  for (const auto& [d, e] : closest) ends.push_back(e);
  return ends;
}

}  // namespace

void addCandidates(const Work& w, const Concavity& c, const std::vector<char>& reflex,
                   const std::vector<int>& reflex_list, int pm, double tau,
                   double angle_tolerance, std::vector<Candidate>& out) {
  const Ring& r = w.outer;
  const int n = static_cast<int>(r.size());
  const Vec2 p = r[pm];
  const double limit = kPi + angle_tolerance;
  auto consider = [&](const End& e) {
    double a0 = 0, a1 = 0;
    if (!validCut(w, pm, e, &a0, &a1)) return;
    if (a0 > limit || a1 > limit) return;  // does not resolve the minimum
    Candidate cd;
    cd.pm = pm;
    cd.end = e;
    cd.length = norm(e.p - p);
    double gain = c.value[pm];
    if (e.vertex >= 0 && reflex[e.vertex] && c.value[e.vertex] > tau) {
      // The far end is a minimum too: count it when the cut also resolves it there.
      const double int_j = interiorAngle(r, e.vertex);
      const double rel_j = ccwAngle(r[(e.vertex + 1) % n] - e.p, p - e.p);
      if (rel_j <= limit && int_j - rel_j <= limit) {
        gain += c.value[e.vertex];
        cd.other_pm = e.vertex;
      }
    }
    cd.score = gain / std::max(cd.length, 1e-6);
    out.push_back(cd);
  };
  for (const End& e : nearReflexEnds(r, reflex_list, pm)) consider(e);
  for (const End& e : wallExtensionEnds(r, pm)) consider(e);
  for (const End& e : nearestBoundaryEnds(r, pm)) consider(e);
}

}  // namespace asf::dude::detail
