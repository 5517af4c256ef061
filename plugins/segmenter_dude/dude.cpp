// Dual-Space Decomposition, implemented from the paper's description (Liu, Xi, Lien 2014) and
// the thesis' outline. One round on a piece:
//   hull -> pockets and bridges -> concavity through the bridge hierarchy -> pocket minima
//   (deepest reflex vertex of every pocket, when deeper than tau) -> candidate cuts per
//   minimum -> greedy selection by resolved concavity / length -> split -> next round.
// Holes wider than tau are first bridged to the outer ring (shortest visible segment), which
// turns their far side into a pocket that the rounds then resolve.
// The candidate cuts at a pocket minimum are generated in dude_candidates.cpp.
#include "dude.h"

#include <algorithm>
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <sstream>

#include "dude_candidates.h"
#include "dude_concavity.h"
#include "dude_vec.h"

namespace asf::dude {

using namespace detail;

namespace {

namespace bg = boost::geometry;
using BgPoint = bg::model::d2::point_xy<double>;
using BgRing = bg::model::ring<BgPoint, /*clockwise=*/false, /*closed=*/false>;

/// Proper crossing (or overlap) of segments ab and cd, sharing end points allowed.
bool segmentsConflict(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Ring r{c, d};
  // blockedBy treats the 2-point ring as edges c->d and d->c: the same segment twice.
  return blockedBy(r, a, b);
}

/// Inserts the edge points of `ends` into the ring; returns the ring position of each end.
std::vector<int> insertEnds(Ring& r, const std::vector<End>& ends,
                            std::vector<int>* vertex_pos = nullptr) {
  const int n = static_cast<int>(r.size());
  std::vector<std::vector<std::pair<double, int>>> on_edge(n);
  for (int k = 0; k < static_cast<int>(ends.size()); ++k)
    if (ends[k].vertex < 0) on_edge[ends[k].edge].push_back({ends[k].t, k});
  std::vector<int> pos(ends.size(), -1);
  Ring out;
  out.reserve(n + ends.size());
  std::vector<int> newpos(n);
  for (int i = 0; i < n; ++i) {
    newpos[i] = static_cast<int>(out.size());
    out.push_back(r[i]);
    auto& list = on_edge[i];
    std::stable_sort(list.begin(), list.end());
    for (const auto& [t, k] : list) {
      if (same(out.back(), ends[k].p)) {
        pos[k] = static_cast<int>(out.size()) - 1;
        continue;
      }
      pos[k] = static_cast<int>(out.size());
      out.push_back(ends[k].p);
    }
  }
  for (int k = 0; k < static_cast<int>(ends.size()); ++k)
    if (ends[k].vertex >= 0) pos[k] = newpos[ends[k].vertex];
  if (vertex_pos) *vertex_pos = std::move(newpos);
  r = std::move(out);
  return pos;
}

bool pointInRing(Vec2 p, const Ring& r) {
  BgRing br;
  br.reserve(r.size());
  for (const Vec2& v : r) br.push_back(BgPoint(v.x, v.y));
  return bg::within(BgPoint(p.x, p.y), br);
}

double ringDiameter(const Ring& r) {
  std::vector<Vec2> pts(r.begin(), r.end());
  const std::vector<int> h = hullPositions(pts);
  double d = 0;
  for (std::size_t a = 0; a < h.size(); ++a)
    for (std::size_t b = a + 1; b < h.size(); ++b) d = std::max(d, norm(r[h[a]] - r[h[b]]));
  return d;
}

class Decomposer {
 public:
  Decomposer(const Options& o, Result& res) : opt_(o), res_(res) {
    tau_ = opt_.max_concavity;
    min_hole_ = opt_.min_hole_extent < 0 ? tau_ : opt_.min_hole_extent;
  }

  void run(const Shape& shape) {
    Work w;
    w.outer = cleanRing(shape.outer, true);
    if (w.outer.empty()) return;
    std::vector<Ring> big;
    for (const Ring& h0 : shape.holes) {
      Ring h = cleanRing(h0, false);
      if (h.empty()) continue;
      if (ringDiameter(h) >= min_hole_)
        big.push_back(std::move(h));
      else
        w.holes.push_back(std::move(h));
    }
    // Largest first, so the result does not depend on the input order of equal holes.
    std::stable_sort(big.begin(), big.end(), [](const Ring& a, const Ring& b) {
      return std::abs(signedArea(a)) > std::abs(signedArea(b));
    });
    bridgeHoles(w, big);
    std::vector<Work> stack{std::move(w)};
    while (!stack.empty()) {
      Work cur = std::move(stack.back());
      stack.pop_back();
      if (cur.round >= opt_.max_rounds ||
          static_cast<int>(res_.pieces.size() + stack.size()) >= opt_.max_pieces) {
        warn("decomposition limit reached (rounds or pieces); piece kept whole");
        emit(cur);
        continue;
      }
      std::vector<Work> parts;
      if (!decomposeOnce(cur, parts)) {
        emit(cur);
        continue;
      }
      for (auto it = parts.rbegin(); it != parts.rend(); ++it) stack.push_back(std::move(*it));
    }
  }

 private:
  void warn(const std::string& s) { res_.warnings.push_back(s); }

  void emit(const Work& w) {
    Shape s;
    s.outer = w.outer;
    s.holes = w.holes;
    res_.pieces.push_back(std::move(s));
  }

  /// Joins each hole to the outer ring (or to holes already joined) with the shortest
  /// segment that stays inside the polygon; the outer ring then runs around the hole.
  void bridgeHoles(Work& w, std::vector<Ring>& holes) {
    while (!holes.empty()) {
      double best = std::numeric_limits<double>::infinity();
      int best_h = -1, best_v = -1;
      End best_e;
      for (int h = 0; h < static_cast<int>(holes.size()); ++h) {
        const Ring& hole = holes[h];
        for (int v = 0; v < static_cast<int>(hole.size()); ++v) {
          const Vec2 p = hole[v];
          // A few nearest points of the outer ring, closest first, until one is visible.
          std::vector<std::pair<double, End>> near;
          const int n = static_cast<int>(w.outer.size());
          for (int k = 0; k < n; ++k) {
            double t = 0;
            const Vec2 a = w.outer[k], b = w.outer[(k + 1) % n];
            const double d = distToSegment(p, a, b, &t);
            if (d >= best) continue;
            End e;
            if (t <= 1e-6) {
              e.vertex = k;
              e.p = a;
            } else if (t >= 1 - 1e-6) {
              e.vertex = (k + 1) % n;
              e.p = b;
            } else {
              e.edge = k;
              e.t = t;
              e.p = a + t * (b - a);
            }
            near.push_back({d, e});
          }
          std::stable_sort(near.begin(), near.end(),
                           [](const auto& x, const auto& y) { return x.first < y.first; });
          if (near.size() > 4) near.resize(4);
          for (const auto& [d, e] : near) {
            if (d >= best) break;
            if (holeBridgeValid(w, holes, h, v, e)) {
              best = d;
              best_h = h;
              best_v = v;
              best_e = e;
              break;
            }
          }
        }
      }
      if (best_h < 0) {
        warn("a hole could not be joined to the boundary; kept as an obstacle");
        for (Ring& h : holes) w.holes.push_back(std::move(h));
        return;
      }
      const Ring hole = std::move(holes[best_h]);
      holes.erase(holes.begin() + best_h);
      const std::vector<int> pos = insertEnds(w.outer, {best_e});
      const int j = pos[0];
      Ring merged;
      merged.reserve(w.outer.size() + hole.size() + 2);
      for (int k = 0; k <= j; ++k) merged.push_back(w.outer[k]);
      const int m = static_cast<int>(hole.size());
      for (int k = 0; k <= m; ++k) merged.push_back(hole[(best_v + k) % m]);
      for (int k = j; k < static_cast<int>(w.outer.size()); ++k) merged.push_back(w.outer[k]);
      res_.cuts.push_back({hole[best_v], w.outer[j]});
      w.outer = std::move(merged);
    }
  }

  bool holeBridgeValid(const Work& w, const std::vector<Ring>& holes, int h, int v,
                       const End& e) const {
    const Ring& hole = holes[h];
    const Vec2 p = hole[v], q = e.p;
    const Vec2 d = q - p;
    if (norm(d) <= kEps) return false;
    // At the hole vertex: the bridge leaves into the free side (left of the clockwise hole).
    const int m = static_cast<int>(hole.size());
    const double interior = interiorAngle(hole, v);
    const double rel = ccwAngle(hole[(v + 1) % m] - p, d);
    if (rel <= 1e-6 || rel >= interior - 1e-6) return false;
    const Ring& r = w.outer;
    const int n = static_cast<int>(r.size());
    if (e.vertex >= 0) {
      const double int_j = interiorAngle(r, e.vertex);
      const double rel_j = ccwAngle(r[(e.vertex + 1) % n] - q, p - q);
      if (rel_j <= 1e-6 || rel_j >= int_j - 1e-6) return false;
    } else {
      const Vec2 u = r[e.edge], vv = r[(e.edge + 1) % n];
      if (cross(vv - u, p - q) <= 1e-9 * norm(vv - u) * norm(p - q)) return false;
    }
    if (blockedBy(r, p, q)) return false;
    for (const Ring& o : holes)
      if (blockedBy(o, p, q)) return false;
    for (const Ring& o : w.holes)
      if (blockedBy(o, p, q)) return false;
    return true;
  }

  /// One round: false when the piece is final (no pocket minimum, or none can be cut).
  bool decomposeOnce(Work& w, std::vector<Work>& parts) {
    Ring& r = w.outer;
    const int n = static_cast<int>(r.size());
    if (n < 4) return false;
    const Concavity c = analyse(r);
    std::vector<char> reflex(n, 0);
    for (int i = 0; i < n; ++i) reflex[i] = interiorAngle(r, i) > kPi + 1e-6;
    const std::vector<int> pms = pocketMinima(c, reflex);
    if (pms.empty()) return false;
    std::vector<int> reflex_list;
    for (int i = 0; i < n; ++i)
      if (reflex[i]) reflex_list.push_back(i);
    std::vector<Candidate> cands;
    for (int pm : pms)
      addCandidates(w, c, reflex, reflex_list, pm, tau_, opt_.angle_tolerance, cands);
    if (cands.empty()) {
      std::ostringstream s;
      s << "no valid cut for " << pms.size() << " pocket minima (max concavity "
        << c.value[pms.front()] << "); piece kept whole";
      warn(s.str());
      return false;
    }
    std::stable_sort(cands.begin(), cands.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    const std::vector<Candidate> chosen = chooseCuts(r, cands, pms);
    // Apply: insert edge end points, then split the ring along each cut in turn.
    std::vector<End> ends;
    for (const Candidate& cd : chosen) ends.push_back(cd.end);
    Ring ring = r;
    std::vector<int> vertex_pos;
    const std::vector<int> endpos = insertEnds(ring, ends, &vertex_pos);
    std::vector<std::vector<int>> pieces = splitAlongCuts(r, ring, chosen, vertex_pos, endpos);
    if (pieces.size() == 1) return failSplit("cuts could not be applied");
    return assemblePieces(w, ring, pieces, parts);
  }

  /// Pocket minima: the deepest reflex vertex (above tau) of every pocket of the hierarchy,
  /// in vertex order.
  std::vector<int> pocketMinima(const Concavity& c, const std::vector<char>& reflex) const {
    std::vector<int> deepest(c.pockets, -1);
    for (std::size_t i = 0; i < reflex.size(); ++i) {
      if (!reflex[i] || c.pocket[i] < 0 || c.value[i] <= tau_) continue;
      int& d = deepest[c.pocket[i]];
      if (d < 0 || c.value[i] > c.value[d]) d = static_cast<int>(i);
    }
    std::vector<int> pms;
    for (int d : deepest)
      if (d >= 0) pms.push_back(d);
    std::sort(pms.begin(), pms.end());
    return pms;
  }

  /// Greedy: best score first, each minimum once, no crossing cuts.
  std::vector<Candidate> chooseCuts(const Ring& r, const std::vector<Candidate>& cands,
                                    const std::vector<int>& pms) const {
    std::vector<char> resolved(r.size(), 0);
    std::vector<Candidate> chosen;
    for (const Candidate& cd : cands) {
      if (resolved[cd.pm]) continue;
      const Vec2 a = r[cd.pm], b = cd.end.p;
      bool conflict = false;
      for (const Candidate& o : chosen) {
        const Vec2 oa = r[o.pm], ob = o.end.p;
        if ((same(a, oa) && same(b, ob)) || (same(a, ob) && same(b, oa)) ||
            segmentsConflict(a, b, oa, ob)) {
          conflict = true;
          break;
        }
      }
      if (conflict) continue;
      chosen.push_back(cd);
      resolved[cd.pm] = 1;
      if (cd.other_pm >= 0) resolved[cd.other_pm] = 1;
      for (int pm : pms)
        if (norm(r[pm] - a) <= opt_.resolve_radius || norm(r[pm] - b) <= opt_.resolve_radius)
          resolved[pm] = 1;
    }
    return chosen;
  }

  /// The pieces (positions in `ring`, the ring with the cuts' end points inserted) after
  /// splitting along each chosen cut in turn; the cuts applied are recorded.
  std::vector<std::vector<int>> splitAlongCuts(const Ring& r, const Ring& ring,
                                               const std::vector<Candidate>& chosen,
                                               const std::vector<int>& vertex_pos,
                                               const std::vector<int>& endpos) {
    std::vector<std::vector<int>> pieces(1);
    pieces[0].resize(ring.size());
    std::iota(pieces[0].begin(), pieces[0].end(), 0);
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const int pa = vertex_pos[chosen[k].pm], pb = endpos[k];
      if (pa == pb) continue;
      bool done = false;
      for (std::size_t pi = 0; pi < pieces.size() && !done; ++pi) {
        auto& pc = pieces[pi];
        auto ia = std::find(pc.begin(), pc.end(), pa);
        auto ib = std::find(pc.begin(), pc.end(), pb);
        if (ia == pc.end() || ib == pc.end()) continue;
        std::size_t a = ia - pc.begin(), b = ib - pc.begin();
        if (a > b) std::swap(a, b);
        if (b - a < 2 || a + pc.size() - b < 2) break;  // along an edge: nothing to split
        std::vector<int> A(pc.begin() + a, pc.begin() + b + 1);
        std::vector<int> B(pc.begin() + b, pc.end());
        B.insert(B.end(), pc.begin(), pc.begin() + a + 1);
        pc = std::move(A);
        pieces.push_back(std::move(B));
        done = true;
      }
      if (done) res_.cuts.push_back({r[chosen[k].pm], chosen[k].end.p});
    }
    return pieces;
  }

  /// The pieces as rings, checked (orientation, area adding up), with the holes kept whole
  /// placed in the piece that contains them.
  bool assemblePieces(Work& w, const Ring& ring, const std::vector<std::vector<int>>& pieces,
                      std::vector<Work>& parts) {
    const double parent_area = signedArea(w.outer);
    double total = 0;
    std::vector<Work> out;
    for (const auto& pc : pieces) {
      Ring pr;
      pr.reserve(pc.size());
      for (int p : pc) pr.push_back(ring[p]);
      const double a = signedArea(pr);
      if (a <= 0) return failSplit("a cut produced an inverted piece");
      Work piece;
      piece.outer = cleanRing(pr, true);
      piece.round = w.round + 1;
      total += a;
      if (!piece.outer.empty()) out.push_back(std::move(piece));
    }
    if (std::abs(total - parent_area) > 1e-6 * std::max(1.0, parent_area))
      return failSplit("pieces do not add up to the polygon (self-intersecting boundary?)");
    for (Ring& h : w.holes) {
      bool placed = false;
      for (Work& p : out)
        if (pointInRing(h.front(), p.outer)) {
          p.holes.push_back(h);
          placed = true;
          break;
        }
      if (!placed && !out.empty()) out.front().holes.push_back(h);
    }
    for (Work& p : out) parts.push_back(std::move(p));
    return true;
  }

  bool failSplit(const std::string& why) {
    warn(why + "; piece kept whole");
    return false;
  }

  const Options& opt_;
  Result& res_;
  double tau_ = 2.5, min_hole_ = 2.5;
};

}  // namespace

double signedArea(const Ring& r) {
  double a = 0;
  const std::size_t n = r.size();
  for (std::size_t i = 0; i < n; ++i) a += cross(r[i], r[(i + 1) % n]);
  return a / 2;
}

Ring cleanRing(const Ring& in, bool ccw, double eps) {
  Ring r;
  r.reserve(in.size());
  for (const Vec2& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    if (!r.empty() && norm(p - r.back()) <= eps) continue;
    r.push_back(p);
  }
  while (r.size() > 1 && norm(r.front() - r.back()) <= eps) r.pop_back();
  // Collinear vertices and spikes (the boundary turning back on itself) carry no area.
  auto degenerate = [&](Vec2 a, Vec2 b, Vec2 c) {
    const double l1 = norm(b - a), l2 = norm(c - b);
    if (l1 <= eps || l2 <= eps) return true;
    return std::abs(orient(a, b, c)) <= 1e-9 * l1 * l2;
  };
  bool changed = true;
  while (changed && r.size() >= 3) {
    changed = false;
    Ring s;
    s.reserve(r.size());
    for (const Vec2& p : r) {
      while (s.size() >= 2 && degenerate(s[s.size() - 2], s.back(), p)) {
        s.pop_back();
        changed = true;
      }
      s.push_back(p);
    }
    // Close the loop: the joint between the last and first vertices.
    while (s.size() >= 3 && degenerate(s[s.size() - 2], s.back(), s.front())) {
      s.pop_back();
      changed = true;
    }
    while (s.size() >= 3 && degenerate(s.back(), s.front(), s[1])) {
      s.erase(s.begin());
      changed = true;
    }
    r = std::move(s);
  }
  if (r.size() < 3) return {};
  const double a = signedArea(r);
  if (std::abs(a) <= eps * eps) return {};
  if ((a > 0) != ccw) std::reverse(r.begin(), r.end());
  return r;
}

std::vector<double> concavities(const Ring& ccw_ring) { return analyse(ccw_ring).value; }

double maxReflexConcavity(const Ring& r) {
  const Concavity c = analyse(r);
  double m = 0;
  for (std::size_t i = 0; i < r.size(); ++i)
    if (interiorAngle(r, i) > kPi + 1e-6) m = std::max(m, c.value[i]);
  return m;
}

Result decompose(const Shape& shape, const Options& options) {
  Result res;
  Options o = options;
  if (!(o.max_concavity > 0)) o.max_concavity = 2.5;
  Decomposer d(o, res);
  d.run(shape);
  return res;
}

}  // namespace asf::dude
