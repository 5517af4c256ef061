// CGAL-backed geometry of the `thesis` variant: hull, constrained Delaunay triangulation,
// point in polygon. The only translation unit of the plugin that includes CGAL (compile time).
#include "dude_thesis_geometry.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Convex_hull_traits_adapter_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>

namespace asf::dude::thesis::detail {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Pt = K::Point_2;
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact_predicates_tag: intersecting constraints (a simplified ring that crosses itself) are
// split at constructed points instead of failing.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

Pt pt(Vec2 v) { return Pt(v.x, v.y); }

}  // namespace

int Poly::addRing(const Ring& r) {
  int first = -1, last = -1;
  for (const Vec2& q : r) {
    const int id = add(q);
    if (first < 0) first = id;
    else {
      nx[last] = id;
      pv[id] = last;
    }
    last = id;
  }
  if (first >= 0) {
    nx[last] = first;
    pv[first] = last;
    heads.push_back(first);
  }
  return first;
}

std::vector<int> Poly::ring(int head) const {
  std::vector<int> out;
  int v = head;
  do {
    out.push_back(v);
    v = nx[v];
  } while (v != head && v >= 0 && out.size() <= p.size());
  return out;
}

Ring positions(const Poly& P, const std::vector<int>& ids) {
  Ring r;
  r.reserve(ids.size());
  for (int i : ids) r.push_back(P.p[i]);
  return r;
}

double dist2Seg(Vec2 s, Vec2 t, Vec2 q) {
  const double vx = t.x - s.x, vy = t.y - s.y;
  const double l2 = vx * vx + vy * vy;
  double u = l2 > 0 ? ((q.x - s.x) * vx + (q.y - s.y) * vy) / l2 : 0;
  u = std::clamp(u, 0.0, 1.0);
  return std::hypot(q.x - (s.x + u * vx), q.y - (s.y + u * vy));
}

double signedAreaIds(const Poly& P, const std::vector<int>& ids) {
  double a = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Vec2 p = P.p[ids[i]], q = P.p[ids[(i + 1) % ids.size()]];
    a += p.x * q.y - p.y * q.x;
  }
  return a / 2;
}

double angleAt(Vec2 a, Vec2 b, Vec2 c) {
  const double ux = a.x - b.x, uy = a.y - b.y, wx = c.x - b.x, wy = c.y - b.y;
  const double ang = std::atan2(std::abs(ux * wy - uy * wx), ux * wx + uy * wy);  // [0, pi]
  const CGAL::Orientation o = CGAL::orientation(pt(a), pt(b), pt(c));
  if (o == CGAL::COLLINEAR) return M_PI;
  return o == CGAL::LEFT_TURN ? ang : 2 * M_PI - ang;
}

std::vector<int> hullPositions(const std::vector<Vec2>& pts) {
  std::vector<Pt> P;
  P.reserve(pts.size());
  for (const Vec2& v : pts) P.push_back(pt(v));
  std::vector<std::size_t> idx(P.size()), out;
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  using Traits = CGAL::Convex_hull_traits_adapter_2<K, CGAL::Pointer_property_map<Pt>::type>;
  CGAL::convex_hull_2(idx.begin(), idx.end(), std::back_inserter(out),
                      Traits(CGAL::make_property_map(P)));
  std::vector<int> h(out.begin(), out.end());
  std::sort(h.begin(), h.end());
  return h;
}

namespace {
std::vector<int> allPositions(int n) {
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  return all;
}
}  // namespace

std::vector<int> approximate(const std::vector<Vec2>& pts, double tolerance) {
  const int n = static_cast<int>(pts.size());
  if (n <= 2) return allPositions(n);
  std::vector<char> keep(n, 0);
  keep[0] = keep[n - 1] = 1;
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    double best = -1;
    int at = -1;
    for (int i = a + 1; i < b; ++i) {
      const double d = dist2Seg(pts[a], pts[b], pts[i]);
      if (d > best) {
        best = d;
        at = i;
      }
    }
    if (at >= 0 && best > tolerance) {
      keep[at] = 1;
      stack.push_back({a, at});
      stack.push_back({at, b});
    }
  }
  std::vector<int> out;
  for (int i = 0; i < n; ++i)
    if (keep[i]) out.push_back(i);
  return out;
}

namespace {

/// Distance from q to the line through s and t (the reference measures to the line).
double dist2Line(Vec2 s, Vec2 t, Vec2 q) {
  const double vx = s.x - t.x, vy = s.y - t.y, n = std::hypot(vx, vy);
  if (n == 0) return 0;
  return std::abs(vy * (q.x - t.x) - vx * (q.y - t.y)) / n;
}

/// The position in [a, b] farthest from line a-b (strictly positive), else b.
int farthest(const std::vector<Vec2>& p, int a, int b) {
  double best = 0;
  int at = b;
  for (int i = a; i <= b; ++i) {
    const double d = dist2Line(p[a], p[b], p[i]);
    if (d > best) best = d, at = i;
  }
  return at;
}

struct Chain {
  int pm = 0, s = 0, e = 0;
  double dist = 0, nx = 0, ny = 0;  ///< distance so far; unit normal of its segment
  int pre = -1, next = -1;          ///< neighbouring chains
  double distance(const std::vector<Vec2>& p, int q) const {
    return std::abs((p[pm].x - p[q].x) * nx + (p[pm].y - p[q].y) * ny);
  }
};

/// Grows chain c by one vertex (reference `expand`); false when it cannot grow.
bool grow(const std::vector<Vec2>& p, std::vector<Chain>& ch, int c) {
  Chain& C = ch[c];
  const int n = static_cast<int>(p.size());
  const int t1 = C.s - 1, t2 = C.e + 1 < n ? C.e + 1 : -1;
  if (t1 < 0 && t2 < 0) return false;
  double d1 = 1e300, d2 = 1e300;
  bool up1 = false, up2 = false;
  if (t1 >= 0) {
    d1 = C.distance(p, t1);
    up1 = true;
    if (C.pre >= 0 && ch[C.pre].e == C.s) {  // touching the previous chain: take its end?
      const Chain& P = ch[C.pre];
      const double old_score = C.distance(p, P.e) + P.distance(p, P.e);
      const double new_score = C.distance(p, t1) + P.distance(p, t1);
      if (!(new_score < old_score) || P.e == P.pm) up1 = false;
    }
  }
  if (t2 >= 0) {
    d2 = C.distance(p, t2);
    up2 = true;
    if (C.next >= 0 && ch[C.next].s == C.e) {
      const Chain& N = ch[C.next];
      const double old_score = C.distance(p, N.s) + N.distance(p, N.s);
      const double new_score = C.distance(p, t2) + N.distance(p, t2);
      if (!(new_score < old_score) || N.s == N.pm) up2 = false;
    }
  }
  if (up1 && up2) (d1 < d2 ? up2 : up1) = false;
  if (up1) {
    if (C.pre >= 0 && ch[C.pre].e == C.s) {  // the previous chain gives up its end
      Chain& P = ch[C.pre];
      P.e = P.e - 1;
      P.dist = std::max(P.distance(p, P.s), P.distance(p, P.e));
    }
    C.dist = d1;
    C.s = t1;
    return true;
  }
  if (up2) {
    if (C.next >= 0 && ch[C.next].s == C.e) {
      Chain& N = ch[C.next];
      N.s = N.s + 1;
      N.dist = std::max(N.distance(p, N.s), N.distance(p, N.e));
    }
    C.dist = d2;
    C.e = t2;
    return true;
  }
  return false;
}

}  // namespace

std::vector<int> approximateChains(const std::vector<Vec2>& pts, double tolerance) {
  const int n = static_cast<int>(pts.size());
  if (n <= 2) return allPositions(n);
  std::vector<int> approx{0, n - 1};
  for (int round = 0; round < n; ++round) {
    // The vertex farthest from its segment joins the approximation.
    double max_d = -1;
    int max_v = -1, at = -1;
    for (std::size_t k = 0; k + 1 < approx.size(); ++k) {
      const int seed = farthest(pts, approx[k], approx[k + 1]);
      if (seed == approx[k] || seed == approx[k + 1]) continue;
      const double d = dist2Line(pts[approx[k]], pts[approx[k + 1]], pts[seed]);
      if (d > max_d) max_d = d, max_v = seed, at = static_cast<int>(k) + 1;
    }
    if (max_v >= 0) approx.insert(approx.begin() + at, max_v);
    std::vector<Chain> ch;
    for (std::size_t k = 0; k + 1 < approx.size(); ++k) {
      Chain c;
      c.pm = c.s = c.e = farthest(pts, approx[k], approx[k + 1]);
      const double vx = pts[approx[k + 1]].x - pts[approx[k]].x, vy = pts[approx[k + 1]].y - pts[approx[k]].y;
      const double len = std::hypot(vx, vy);
      c.nx = len > 0 ? vy / len : 0;
      c.ny = len > 0 ? -vx / len : 0;
      c.pre = static_cast<int>(ch.size()) - 1;
      if (c.pre >= 0) ch[c.pre].next = static_cast<int>(ch.size());
      ch.push_back(c);
    }
    // Grow the chain of least distance first (a min-heap, rebuilt after every growth as the
    // neighbours' distances change); a chain that cannot grow leaves the heap.
    std::vector<int> open(ch.size());
    for (std::size_t k = 0; k < ch.size(); ++k) open[k] = static_cast<int>(k);
    auto greater = [&](int a, int b) { return ch[a].dist > ch[b].dist; };
    std::make_heap(open.begin(), open.end(), greater);
    for (long guard = 0; !open.empty() && guard < 16L * n * static_cast<long>(ch.size()) + 64; ++guard) {
      std::pop_heap(open.begin(), open.end(), greater);
      const int best = open.back();
      open.pop_back();
      if (grow(pts, ch, best)) {
        open.push_back(best);
        std::make_heap(open.begin(), open.end(), greater);
      }
    }
    std::vector<int> next{ch.front().s};
    double error = 0;
    for (const Chain& c : ch) {
      next.push_back(c.e);
      error = std::max(error, c.dist);
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    approx = next;
    if (error < tolerance) break;
  }
  if (approx.front() != 0) approx.insert(approx.begin(), 0);
  if (approx.back() != n - 1) approx.push_back(n - 1);
  return approx;
}

std::vector<std::pair<int, int>> cdtFreeEdges(const Poly& P, const std::vector<std::vector<int>>& rings) {
  Cdt cdt;
  std::map<Cdt::Vertex_handle, int> id_of;  // vertices made at constraint crossings have none
  for (const auto& r : rings) {
    std::vector<Cdt::Vertex_handle> h;
    h.reserve(r.size());
    for (int id : r) {
      Cdt::Vertex_handle vh = cdt.insert(pt(P.p[id]));
      id_of.emplace(vh, id);  // a repeated position keeps its first id
      h.push_back(vh);
    }
    for (std::size_t i = 0; i < h.size(); ++i) {
      const auto a = h[i], b = h[(i + 1) % h.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  std::vector<std::pair<int, int>> out;
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e) {
    if (cdt.is_constrained(*e)) continue;
    const auto v1 = e->first->vertex(Cdt::cw(e->second));
    const auto v2 = e->first->vertex(Cdt::ccw(e->second));
    const auto i1 = id_of.find(v1), i2 = id_of.find(v2);
    if (i1 == id_of.end() || i2 == id_of.end()) continue;
    out.push_back({i1->second, i2->second});
  }
  return out;
}

struct InsideTest::Rings {
  std::vector<std::vector<Pt>> rings;
};

InsideTest::InsideTest(const Poly& P, const std::vector<std::vector<int>>& rings)
    : rings_(std::make_unique<Rings>()) {
  for (const auto& r : rings) {
    std::vector<Pt> ring;
    ring.reserve(r.size());
    for (int id : r) ring.push_back(pt(P.p[id]));
    rings_->rings.push_back(std::move(ring));
  }
}

InsideTest::~InsideTest() = default;

bool InsideTest::operator()(Vec2 q) const {
  const Pt Q = pt(q);
  for (std::size_t r = 0; r < rings_->rings.size(); ++r) {
    const auto& ring = rings_->rings[r];
    const CGAL::Bounded_side side = CGAL::bounded_side_2(ring.begin(), ring.end(), Q, K());
    if (r == 0 && side != CGAL::ON_BOUNDED_SIDE) return false;
    if (r > 0 && side != CGAL::ON_UNBOUNDED_SIDE) return false;
  }
  return true;
}

bool insidePolygon(const Poly& P, const std::vector<std::vector<int>>& rings, Vec2 q) {
  return InsideTest(P, rings)(q);
}

bool segmentsIntersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d, Vec2* at) {
  const K::Segment_2 s1(pt(a), pt(b)), s2(pt(c), pt(d));
  if (!CGAL::do_intersect(s1, s2)) return false;
  const auto x = CGAL::intersection(s1, s2);
  if (!x) return false;
  if (const Pt* p = boost::get<Pt>(&*x)) {
    *at = {p->x(), p->y()};
    return true;
  }
  if (const K::Segment_2* s = boost::get<K::Segment_2>(&*x)) {  // overlap: nearer end to a
    const Pt s0 = s->source(), s1e = s->target();
    const double d0 = std::hypot(s0.x() - a.x, s0.y() - a.y), d1 = std::hypot(s1e.x() - a.x, s1e.y() - a.y);
    const Pt& n = d0 <= d1 ? s0 : s1e;
    *at = {n.x(), n.y()};
    return true;
  }
  return false;
}

}  // namespace asf::dude::thesis::detail
