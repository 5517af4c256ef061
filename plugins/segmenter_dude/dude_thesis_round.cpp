// One round of DuDe 2D on one piece, as the reference (c_dude::build) computes it: bridges,
// pockets and their recursive decomposition, pocket minima, hole minima, feature points,
// diagonals from two constrained Delaunay triangulations, cut sets per pocket minimum (built in
// dude_thesis_cutsets.cpp).
#include "dude_thesis_round.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace asf::dude::thesis::detail {
namespace {

constexpr int kMaxPocketDepth = 12;

/// Bridge-pocket (reference c_BPC): the outer ring's chain s..e (ring order) outside the hull.
struct Bpc {
  int s = -1, e = -1;
  std::vector<int> kids;         ///< sub-bridges directly below this one
  std::vector<int> bridge_ends;  ///< ends of every sub-bridge found in the pocket
  std::vector<int> concavities;  ///< pocket minima
};

struct OuterRing {
  std::vector<int> ids;
  std::map<int, int> pos;  // vertex id -> position in ids
  int n() const { return static_cast<int>(ids.size()); }
  int dist(int a, int b) const { return ((pos.at(b) - pos.at(a)) % n() + n()) % n(); }
  /// u in the chain a.next .. b (inclusive)?
  bool inChain(int a, int b, int u) const {
    const auto it = pos.find(u);
    if (it == pos.end()) return false;
    const int du = dist(a, u);
    return du > 0 && du <= dist(a, b);
  }
  std::vector<int> chain(int a, int b) const {  // a .. b inclusive
    std::vector<int> c;
    for (int i = pos.at(a);; i = (i + 1) % n()) {
      c.push_back(ids[i]);
      if (ids[i] == b || static_cast<int>(c.size()) > n()) break;
    }
    return c;
  }
};

struct Builder {
  const Poly& P;
  double tau;
  bool chains;  ///< approximation: the reference's chains, else Douglas-Peucker
  int depth;
  RoundState& st;
  OuterRing outer;
  std::vector<Bpc> bpcs;
  std::vector<int> top;  // top-level bridges

  double chainArea(const std::vector<int>& c) const { return signedAreaIds(P, c); }
  std::vector<int> approx(const std::vector<Vec2>& pts, double tolerance) const {
    return chains ? approximateChains(pts, tolerance) : approximate(pts, tolerance);
  }

  /// Kid bridges of a pocket: the cuts DuDe finds in the pocket polygon (reference
  /// decompose_bridge), nested by containment (reorganize_kids / insert2tree).
  void decomposePocket(int b) {
    const std::vector<int> chain = outer.chain(bpcs[b].s, bpcs[b].e);
    double deepest = 0;
    for (int v : chain) deepest = std::max(deepest, dist2Seg(P.p[bpcs[b].s], P.p[bpcs[b].e], P.p[v]));
    // A pocket shallower than tau can hold no pocket minimum at any level (the minima are
    // finally measured against this bridge): its sub-bridges are not computed.
    if (deepest < tau || depth >= kMaxPocketDepth || chain.size() < 4) return;
    Poly pocket;
    Ring r;
    std::vector<int> map_back;
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      r.push_back(P.p[*it]);
      map_back.push_back(*it);
    }
    pocket.addRing(r);
    RoundState sub;
    const auto cuts = roundCuts(pocket, tau, chains, false, depth + 1, &sub);
    std::vector<std::pair<int, int>> ranges;  // (start pos, end pos) from s
    std::vector<int> kid_ids;
    for (const auto& [x, y] : cuts) {
      int a = map_back[x], c = map_back[y];
      if (outer.dist(bpcs[b].s, a) > outer.dist(bpcs[b].s, c)) std::swap(a, c);
      if (P.nx[a] == c || a == c) continue;
      if (std::abs(chainArea(outer.chain(a, c))) <= 1e-10) continue;
      Bpc kid;
      kid.s = a;
      kid.e = c;
      bpcs[b].bridge_ends.push_back(a);
      bpcs[b].bridge_ends.push_back(c);
      bpcs.push_back(kid);
      kid_ids.push_back(static_cast<int>(bpcs.size()) - 1);
    }
    // Smallest pockets first, each inserted under the deepest bridge containing it.
    std::stable_sort(kid_ids.begin(), kid_ids.end(), [&](int x, int y) {
      return outer.dist(bpcs[x].s, bpcs[x].e) < outer.dist(bpcs[y].s, bpcs[y].e);
    });
    for (int k : kid_ids) insertKid(b, k);
  }

  bool contains(int outer_b, int inner_b) const {
    const int s = bpcs[outer_b].s;
    const int a0 = outer.dist(s, bpcs[inner_b].s), a1 = outer.dist(s, bpcs[inner_b].e);
    return a1 <= outer.dist(s, bpcs[outer_b].e) && a0 <= a1;
  }

  void insertKid(int parent, int k) {
    std::vector<int> keep;
    for (int c : bpcs[parent].kids) {
      if (contains(c, k)) {
        insertKid(c, k);
        return;
      }
    }
    for (int c : bpcs[parent].kids) {
      if (contains(k, c)) bpcs[k].kids.push_back(c);
      else keep.push_back(c);
    }
    keep.push_back(k);
    bpcs[parent].kids = keep;
  }

  /// Pocket minima of bridge b (reference determineConcavity): salient vertices of the hull of
  /// the pocket (sub-pockets with minima excluded) at least tau from the bridge, filtered.
  void concavity(int b) {
    Bpc& B = bpcs[b];
    std::vector<int> pms;
    std::set<int> kid_interior, kid_ends_with_pm, kid_ends;
    for (int k : B.kids) {
      concavity(k);
      for (int v : bpcs[k].concavities) pms.push_back(v);
      kid_ends.insert(bpcs[k].s);
      kid_ends.insert(bpcs[k].e);
      if (bpcs[k].concavities.empty()) continue;
      kid_ends_with_pm.insert(bpcs[k].s);
      kid_ends_with_pm.insert(bpcs[k].e);
      const auto c = outer.chain(bpcs[k].s, bpcs[k].e);
      for (std::size_t i = 1; i + 1 < c.size(); ++i) kid_interior.insert(c[i]);
    }
    std::vector<int> vlist;
    for (int v : outer.chain(B.s, B.e))
      if (!kid_interior.count(v) || v == B.s || v == B.e) vlist.push_back(v);
    std::vector<Vec2> pts;
    for (int v : vlist) pts.push_back(P.p[v]);
    std::vector<int> hull = hullPositions(pts);
    if (hull.empty() || hull.front() != 0) hull.insert(hull.begin(), 0);
    if (hull.back() != static_cast<int>(vlist.size()) - 1) hull.push_back(static_cast<int>(vlist.size()) - 1);
    std::vector<Vec2> hpts;
    for (int h : hull) hpts.push_back(pts[h]);
    for (int a : approx(hpts, tau - tau / 4)) {
      const int v = vlist[hull[a]];
      if (v == B.s || v == B.e || kid_ends_with_pm.count(v)) continue;
      if (dist2Seg(P.p[B.s], P.p[B.e], P.p[v]) < tau) continue;
      st.info[v].bpc = b;
      pms.push_back(v);
    }
    // Minima of this bridge too close to the line through their neighbouring features are
    // dropped (reference: distance to the segment of the features around it > tau / 2).
    std::set<int> flagged(kid_ends.begin(), kid_ends.end());
    flagged.insert(pms.begin(), pms.end());
    std::vector<int> features{B.s};
    for (int v : outer.chain(B.s, B.e))
      if (v != B.s && v != B.e && flagged.count(v)) features.push_back(v);
    features.push_back(B.e);
    for (std::size_t i = 1; i + 1 < features.size(); ++i) {
      const int v = features[i];
      if (st.info[v].bpc < 0) continue;
      if (st.info[v].bpc != b) {
        B.concavities.push_back(v);
      } else if (dist2Seg(P.p[features[i - 1]], P.p[features[i + 1]], P.p[v]) > tau / 2) {
        B.concavities.push_back(v);
      }
    }
  }

  void buildOuter() {
    outer.ids = P.ring(P.heads[0]);
    for (int i = 0; i < outer.n(); ++i) outer.pos[outer.ids[i]] = i;
    if (outer.n() <= 3) return;
    std::vector<Vec2> pts;
    for (int v : outer.ids) pts.push_back(P.p[v]);
    const std::vector<int> hull = hullPositions(pts);
    for (std::size_t i = 0; i < hull.size(); ++i) {
      const int s = outer.ids[hull[i]], e = outer.ids[hull[(i + 1) % hull.size()]];
      if (s == e || P.nx[s] == e) continue;
      if (std::abs(chainArea(outer.chain(s, e))) <= 1e-10) continue;
      Bpc b;
      b.s = s;
      b.e = e;
      bpcs.push_back(b);
      const int id = static_cast<int>(bpcs.size()) - 1;
      top.push_back(id);
      decomposePocket(id);
      concavity(id);
      // determine_PM: the minima's concavity is their distance to this (hull) bridge.
      std::vector<int> kept;
      for (int v : bpcs[id].concavities) {
        const double c = dist2Seg(P.p[s], P.p[e], P.p[v]);
        if (c < tau) continue;
        st.info[v].concavity = c;
        kept.push_back(v);
      }
      bpcs[id].concavities = kept;
    }
  }

  /// Holes (reference decompose_hole, convex case): the diameter pair are the hole's minima,
  /// with the diameter as concavity; a hole narrower than tau is dropped.
  void buildHole(int head, std::vector<int>* pms, std::set<int>* features) {
    const std::vector<int> ids = P.ring(head);
    std::vector<Vec2> pts;
    for (int v : ids) pts.push_back(P.p[v]);
    const std::vector<int> hull = hullPositions(pts);
    double diam = -1;
    int m1 = -1, m2 = -1;
    for (std::size_t i = 0; i < hull.size(); ++i)
      for (std::size_t j = i + 1; j < hull.size(); ++j) {
        const double d = std::hypot(pts[hull[i]].x - pts[hull[j]].x, pts[hull[i]].y - pts[hull[j]].y);
        if (d > diam) {
          diam = d;
          m1 = hull[i];
          m2 = hull[j];
        }
      }
    if (m1 < 0 || diam < tau) {
      st.ignored_holes.push_back(head);
      return;
    }
    const int n = static_cast<int>(ids.size());
    const int a = ids[m1], c = ids[m2];
    for (int v : {a, c}) {
      st.info[v].concavity = diam;
      st.info[v].hole = head;
      pms->push_back(v);
      features->insert(v);
    }
    int added = 2;
    double far = -1;
    int far_v = -1;
    for (auto [from, to] : {std::pair<int, int>{m1, m2}, std::pair<int, int>{m2, m1}}) {
      std::vector<int> chain;
      for (int i = from;; i = (i + 1) % n) {
        chain.push_back(i);
        if (i == to) break;
      }
      std::vector<Vec2> cp;
      for (int i : chain) cp.push_back(pts[i]);
      for (int k : approx(cp, tau)) {
        const int v = ids[chain[k]];
        if (v == a || v == c) continue;
        const double conc = dist2Seg(P.p[a], P.p[c], P.p[v]);
        st.info[v].concavity = conc;
        st.info[v].hole = head;
        if (conc > tau) pms->push_back(v);
        features->insert(v);
        ++added;
      }
      for (int i : chain) {
        const double d = dist2Seg(P.p[a], P.p[c], pts[i]);
        if (d > far) {
          far = d;
          far_v = ids[i];
        }
      }
    }
    if (added < 3 && far_v >= 0) features->insert(far_v);
  }

  /// Feature points of the outer ring outside the pockets (reference collectConvexFeatPnts /
  /// collectOutConvexFeatPnts).
  void outerFeatures(std::set<int>* features) {
    for (int b : top) {
      features->insert(bpcs[b].s);
      features->insert(bpcs[b].e);
      for (int v : bpcs[b].concavities) features->insert(v);
      for (int v : bpcs[b].bridge_ends) features->insert(v);
    }
    auto addApprox = [&](const std::vector<int>& chain, double tol) {
      std::vector<Vec2> cp;
      for (int v : chain) cp.push_back(P.p[v]);
      for (int k : approx(cp, tol)) features->insert(chain[k]);
    };
    if (top.empty()) {  // convex outer ring with holes: its diameter pair and approximations
      const std::vector<int> hull = hullPositions([&] {
        std::vector<Vec2> pts;
        for (int v : outer.ids) pts.push_back(P.p[v]);
        return pts;
      }());
      double diam = -1;
      int a = -1, c = -1;
      for (std::size_t i = 0; i < hull.size(); ++i)
        for (std::size_t j = i + 1; j < hull.size(); ++j) {
          const double d = std::hypot(P.p[outer.ids[hull[i]]].x - P.p[outer.ids[hull[j]]].x,
                                      P.p[outer.ids[hull[i]]].y - P.p[outer.ids[hull[j]]].y);
          if (d > diam) {
            diam = d;
            a = outer.ids[hull[i]];
            c = outer.ids[hull[j]];
          }
        }
      if (a < 0) return;
      addApprox(outer.chain(a, c), tau);
      addApprox(outer.chain(c, a), tau);
      return;
    }
    std::vector<int> sorted = top;
    std::sort(sorted.begin(), sorted.end(), [&](int x, int y) {
      return outer.pos.at(bpcs[x].s) < outer.pos.at(bpcs[y].s);
    });
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const int from = bpcs[sorted[i]].e, to = bpcs[sorted[(i + 1) % sorted.size()]].s;
      const std::vector<int> run = outer.chain(from, to);
      if (run.size() > 2) addApprox(run, tau - tau / 4);
      else features->insert(run.begin(), run.end());
    }
  }
};

/// Reference is_bridge_breaking: a diagonal must leave the pocket of its end's bridge.
bool breaksBridge(const RoundState& st, const OuterRing& outer, const std::vector<Bpc>& bpcs, int u, int v) {
  const VertexInfo &a = st.info[u], &b = st.info[v];
  if (a.bpc < 0 && b.bpc < 0 && a.hole < 0 && b.hole < 0) return false;
  if (a.bpc == b.bpc && a.hole == b.hole) return false;
  if (a.bpc >= 0 && b.bpc < 0 && outer.inChain(bpcs[a.bpc].s, bpcs[a.bpc].e, v)) return false;
  if (a.bpc < 0 && b.bpc >= 0 && outer.inChain(bpcs[b.bpc].s, bpcs[b.bpc].e, u)) return false;
  return true;
}

bool adjacent(const Poly& P, int a, int b) { return P.nx[a] == b || P.nx[b] == a; }

/// Reference checkCutSkinny: the ends are close along the boundary (2 tau one way, 3 tau back).
bool skinny(const Poly& P, int a, int b, double tau) {
  if (a == b) return true;
  for (auto [from, to, limit] : {std::tuple<int, int, double>{a, b, 2 * tau}, {b, a, 3 * tau}}) {
    double acc = 0;
    int cur = from;
    for (std::size_t guard = 0; acc < limit && guard <= P.p.size(); ++guard) {
      const int nxt = P.nx[cur];
      acc += std::hypot(P.p[nxt].x - P.p[cur].x, P.p[nxt].y - P.p[cur].y);
      if (nxt == to) return true;
      cur = nxt;
    }
  }
  return false;
}

/// Reference resolveIntersectedCuts: a cut that crosses the boundary is moved to the nearer end
/// of the first edge it crosses; then cuts between neighbours, repeated and skinny cuts go.
void clipCuts(const Poly& P, const std::vector<std::vector<int>>& rings, double tau,
              std::vector<std::pair<int, int>>* cuts) {
  const InsideTest inside(P, rings);
  for (auto& [a, b] : *cuts) {
    const Vec2 A = P.p[a], B = P.p[b];
    double da = 1e300, db = 1e300;
    int ea = -1, eb = -1;
    Vec2 xa{}, xb{};
    for (const auto& r : rings)
      for (std::size_t i = 0; i < r.size(); ++i) {
        const int u = r[i], w = r[(i + 1) % r.size()];
        Vec2 x;
        if (!segmentsIntersect(A, B, P.p[u], P.p[w], &x)) continue;
        const double dA = std::hypot(x.x - A.x, x.y - A.y), dB = std::hypot(x.x - B.x, x.y - B.y);
        if (dA < 1e-8 || dB < 1e-8) continue;
        if (dA < da) da = dA, ea = u, xa = x;
        if (dB < db) db = dB, eb = u, xb = x;
      }
    if (ea < 0) continue;
    auto nearerEnd = [&](int u, Vec2 from) {
      const int w = P.nx[u];
      return std::hypot(P.p[u].x - from.x, P.p[u].y - from.y) <= std::hypot(P.p[w].x - from.x, P.p[w].y - from.y) ? u : w;
    };
    const bool a_in = inside({(xa.x + A.x) / 2, (xa.y + A.y) / 2});
    const bool b_in = inside({(xb.x + B.x) / 2, (xb.y + B.y) / 2});
    if (a_in && (!b_in || da > db)) b = nearerEnd(ea, A);
    else if (b_in) a = nearerEnd(eb, B);
  }
  std::vector<std::pair<int, int>> kept;
  for (const auto& [a, b] : *cuts) {
    if (a == b || adjacent(P, a, b) || skinny(P, a, b, tau)) continue;
    const bool dup = std::any_of(kept.begin(), kept.end(), [&](const auto& k) {
      return (k.first == a && k.second == b) || (k.first == b && k.second == a);
    });
    if (!dup) kept.push_back({a, b});
  }
  *cuts = kept;
}

}  // namespace

/// Reference isHoleDiagonalValid: from a hole feature, not to a vertex of the same hole between
/// it and its neighbouring features.
bool holeDiagonalValid(const RoundState& st, int u, int v) {
  int m = -1, o = -1;
  if (st.info[u].hole >= 0 && st.info[u].feature) m = u, o = v;
  else if (st.info[v].hole >= 0 && st.info[v].feature) m = v, o = u;
  if (m < 0) return true;
  const Poly& P = *st.P;
  for (int w = P.pv[m]; w != m; w = P.pv[w]) {
    if (w == o) return false;
    if (w == st.info[m].pre_feature) break;
  }
  for (int w = P.nx[m]; w != m; w = P.nx[w]) {
    if (w == o) return false;
    if (w == st.info[m].next_feature) break;
  }
  return true;
}

std::vector<std::pair<int, int>> roundCuts(const Poly& P, double tau, bool chains, bool clip,
                                           int depth, RoundState* stp) {
  RoundState& st = *stp;
  st = RoundState{};
  st.P = &P;
  st.tau = tau;
  st.info.assign(P.p.size(), VertexInfo{});
  st.diagonals.assign(P.p.size(), {});
  st.cutsets.assign(P.p.size(), {});
  if (P.heads.empty()) return {};
  Builder b{P, tau, chains, depth, st, {}, {}, {}};
  b.buildOuter();
  if (b.top.empty() && P.heads.size() == 1) return {};  // convex enough
  std::set<int> features;
  std::vector<int> hole_pms;
  for (std::size_t h = 1; h < P.heads.size(); ++h) b.buildHole(P.heads[h], &hole_pms, &features);
  b.outerFeatures(&features);
  std::set<int> pm_set(hole_pms.begin(), hole_pms.end());
  for (int t : b.top) pm_set.insert(b.bpcs[t].concavities.begin(), b.bpcs[t].concavities.end());
  st.pms.assign(pm_set.begin(), pm_set.end());
  if (st.pms.empty()) return {};

  // Simplified polygon (feature points only) and the reduced one (all vertices); rings with
  // fewer than three features are left out of both, as in the reference.
  std::vector<std::vector<int>> simplified, reduced, kept_rings;
  for (int head : P.heads) {
    if (std::find(st.ignored_holes.begin(), st.ignored_holes.end(), head) != st.ignored_holes.end()) continue;
    const std::vector<int> ring = P.ring(head);
    kept_rings.push_back(ring);
    std::vector<int> s;
    for (int v : ring)
      if (features.count(v)) s.push_back(v);
    if (s.size() < 3) continue;
    for (std::size_t i = 0; i < s.size(); ++i) {
      st.info[s[i]].feature = true;
      st.info[s[i]].pre_feature = s[(i + s.size() - 1) % s.size()];
      st.info[s[i]].next_feature = s[(i + 1) % s.size()];
    }
    simplified.push_back(s);
    reduced.push_back(ring);
  }
  if (simplified.empty()) return {};
  for (const auto* rings : {&simplified, &reduced}) {
    const InsideTest inside(P, *rings);
    for (const auto& [u, v] : cdtFreeEdges(P, *rings)) {
      if (!holeDiagonalValid(st, u, v) || !breaksBridge(st, b.outer, b.bpcs, u, v)) continue;
      const Vec2 mid{(P.p[u].x + P.p[v].x) / 2, (P.p[u].y + P.p[v].y) / 2};
      if (!inside(mid)) continue;
      for (auto [x, y] : {std::pair<int, int>{u, v}, std::pair<int, int>{v, u}}) {
        auto& d = st.diagonals[x];
        if (std::find(d.begin(), d.end(), y) == d.end()) d.push_back(y);
      }
    }
  }
  for (int v : st.pms)
    if (!st.diagonals[v].empty() && st.info[v].feature) buildCutsets(st, v);
  std::vector<std::pair<int, int>> cuts = selectCuts(st);
  if (clip) clipCuts(P, kept_rings, tau, &cuts);
  return cuts;
}

}  // namespace asf::dude::thesis::detail
