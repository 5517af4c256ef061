// `thesis` variant driver: the reference's cut selection (c_knapsack), the application of
// cuts by splicing ring vertices (c_dude_use::decomposePolygonUsingCuts) and the rounds
// (iterativeDecompose), plus the public entry points of dude_thesis.h.
#include "dude_thesis.h"

#include "dude_thesis_round.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace asf::dude::thesis {
namespace detail {
namespace {

using Diag = std::pair<int, int>;

bool sameDiag(const Diag& a, const Diag& b) {
  return (a.first == b.first && a.second == b.second) || (a.first == b.second && a.second == b.first);
}

/// Reference c_cutset::operator==: the same diagonals.
bool sameSet(const CutSet& a, const CutSet& b) {
  if (a.diagonals.size() != b.diagonals.size()) return false;
  if (a.diagonals.size() == 1) return sameDiag(a.diagonals[0], b.diagonals[0]);
  return (sameDiag(a.diagonals[0], b.diagonals[0]) && sameDiag(a.diagonals[1], b.diagonals[1])) ||
         (sameDiag(a.diagonals[0], b.diagonals[1]) && sameDiag(a.diagonals[1], b.diagonals[0]));
}

struct Selector {
  Selector(RoundState& state, const std::vector<CutSet>& cutsets) : st(state), sets(cutsets) {}
  RoundState& st;
  const std::vector<CutSet>& sets;

  /// `other`, whose diagonal d ends at mine.v, conflicts when mine.v could use the same set.
  bool conflictVia(const CutSet& mine, const CutSet& other, const Diag& d) const {
    const int end = d.first == other.v ? d.second : d.first;
    if (end != mine.v) return false;
    for (const CutSet& c : st.cutsets[mine.v])
      if (sameSet(c, other)) return true;
    return false;
  }

  /// Reference c_cutset::conflict.
  bool conflict(const CutSet& mine, const CutSet& other) const {
    if (other.v == mine.v) return true;
    const std::size_t no = other.diagonals.size(), nm = mine.diagonals.size();
    if (no == 2 && nm == 2) return false;
    if (no == 1 && nm == 1 && sameDiag(other.diagonals[0], mine.diagonals[0])) return false;
    if (no == 1 && nm == 2 &&
        (sameDiag(other.diagonals[0], mine.diagonals[0]) || sameDiag(other.diagonals[0], mine.diagonals[1])))
      return false;
    if (no == 2 && nm == 1 &&
        (sameDiag(mine.diagonals[0], other.diagonals[0]) || sameDiag(mine.diagonals[0], other.diagonals[1])))
      return false;
    if (conflictVia(mine, other, other.diagonals.front())) return true;
    if (conflictVia(other, mine, mine.diagonals.front())) return true;
    if (no == 2 && conflictVia(mine, other, other.diagonals.back())) return true;
    if (nm == 2 && conflictVia(other, mine, mine.diagonals.back())) return true;
    return false;
  }

  struct Cell {
    std::vector<int> sets;
    double score = 0;
    int cuts = 0;  ///< distinct diagonals of the sets
  };

  /// conflicts[i][m]: conflict(sets[i], sets[m]), computed once (the table asks it often).
  std::vector<std::vector<char>> conflicts;
  std::vector<std::vector<int>> diag_ids;  ///< per set: ids of its diagonals (distinct pairs)
  mutable std::vector<int> stamp;          ///< per diagonal id: last count pass that saw it
  mutable int pass = 0;

  void precompute() {
    const std::size_t M = sets.size();
    conflicts.assign(M, std::vector<char>(M, 0));
    for (std::size_t i = 0; i < M; ++i)
      for (std::size_t m = 0; m < M; ++m) conflicts[i][m] = conflict(sets[i], sets[m]) ? 1 : 0;
    std::map<std::pair<int, int>, int> ids;
    diag_ids.assign(M, {});
    for (std::size_t m = 0; m < M; ++m)
      for (const Diag& d : sets[m].diagonals)
        diag_ids[m].push_back(ids.emplace(std::minmax(d.first, d.second), static_cast<int>(ids.size())).first->second);
    stamp.assign(ids.size(), -1);
  }

  void add(Cell& c, int m) const {
    std::vector<int> next{m};
    for (int i : c.sets)
      if (!conflicts[i][m]) next.push_back(i);
    c.sets = std::move(next);
    c.score = 0;
    c.cuts = 0;
    ++pass;
    for (int i : c.sets) {
      c.score += sets[i].weight;
      for (int d : diag_ids[i])
        if (stamp[d] != pass) stamp[d] = pass, ++c.cuts;
    }
  }

  /// Reference c_knapsack::build: capacity (number of cuts) grows until the best score of the
  /// last column stalls over three capacities; each row iterates until stable.
  Cell knapsack() const {
    const int M = static_cast<int>(sets.size());
    int N = 1;
    for (const CutSet& c : sets) N += static_cast<int>(c.diagonals.size());
    // A set has at most two cuts, so row n reads rows n, n-1 and n-2 only: three rows kept.
    std::vector<std::vector<Cell>> rows(3, std::vector<Cell>(M));
    auto row = [&](int n) -> std::vector<Cell>& { return rows[n % 3]; };
    int last = 0;
    for (int n = 1; n < N; ++n) {
      last = n;
      row(n).assign(M, Cell{});
      bool stable = true;
      int iteration = 0;
      do {
        stable = true;
        for (int m = 0; m < M; ++m) {
          const double old = row(n)[m].score;
          update(row, n, m, iteration);
          if (row(n)[m].score != old) stable = false;
        }
        ++iteration;
        // The reference makes at least three passes; a pass after the first that changes
        // nothing leaves the next one the same input, so the third would change nothing.
      } while ((!stable || iteration < 2) && iteration < 64);
      if (n >= 3 && row(n)[M - 1].score == row(n - 1)[M - 1].score &&
          row(n)[M - 1].score == row(n - 2)[M - 1].score)
        break;
    }
    return row(last)[M - 1];
  }

  /// Score and cut count of `c` plus set m, as add() would compute them (same summation
  /// order, so comparisons are unchanged), without building the cell.
  void evaluate(const Cell& c, int m, double* score, int* cuts) const {
    ++pass;
    double sc = sets[m].weight;
    int n = 0;
    for (int d : diag_ids[m])
      if (stamp[d] != pass) stamp[d] = pass, ++n;
    for (int i : c.sets) {
      if (conflicts[i][m]) continue;
      sc += sets[i].weight;
      for (int d : diag_ids[i])
        if (stamp[d] != pass) stamp[d] = pass, ++n;
    }
    *score = sc;
    *cuts = n;
  }

  template <class Rows>
  void update(Rows& row, int n, int m, int iteration) const {
    const int size = static_cast<int>(sets[m].diagonals.size());
    if (m == 0 && iteration == 0) {
      if (n >= size) add(row(n)[0], m);
      return;
    }
    const int M = static_cast<int>(sets.size());
    const int m1 = m > 0 ? m - 1 : M - 1;
    double best_score = -1e300;
    int best_k = -1;
    for (int k = n; k >= std::max(0, n - size); --k) {
      double score;
      int cuts;
      evaluate(row(k)[m1], m, &score, &cuts);
      if (cuts > n) continue;
      if (score > best_score) best_score = score, best_k = k;
    }
    if (row(n)[m1].score > best_score) {
      row(n)[m] = row(n)[m1];
    } else {
      Cell c = row(best_k)[m1];
      add(c, m);
      row(n)[m] = std::move(c);
    }
  }

  /// Pocket minima a set resolves (reference collect_resolvable_vertex).
  std::vector<int> resolved(const CutSet& c) const {
    std::vector<int> r{c.v};
    if (c.resolves <= 1) return r;
    if (c.type == CutSet::SinglePM) r.push_back(c.diagonals[0].second);
    if (c.type == CutSet::DoublePMPM || c.type == CutSet::DoublePMTip)
      for (const Diag& d : c.diagonals)
        if (st.info[d.second].isPM() && resolves(st, d.second, c.v)) r.push_back(d.second);
    return r;
  }

  /// Reference c_knapsack::getOptimalCuts: redundant sets removed, missing minima given their
  /// best set, the union of the remaining diagonals returned.
  std::vector<Diag> optimalCuts() const {
    if (sets.empty()) return {};
    const Cell cell = knapsack();
    std::vector<CutSet> all;
    for (std::size_t i = 0; i < cell.sets.size(); ++i) {
      bool dup = false;
      for (std::size_t j = i + 1; j < cell.sets.size(); ++j)
        if (sameSet(sets[cell.sets[i]], sets[cell.sets[j]])) dup = true;
      if (!dup) all.push_back(sets[cell.sets[i]]);
    }
    std::map<int, std::vector<int>> by_vertex;
    for (std::size_t i = 0; i < all.size(); ++i)
      for (int v : resolved(all[i])) by_vertex[v].push_back(static_cast<int>(i));
    std::vector<char> flag(all.size(), 0);  // 1: keep, 2: removed
    auto valid = [&](const std::vector<int>& ids) {
      int n = 0;
      for (int i : ids) n += flag[i] != 2;
      return n;
    };
    auto removable = [&](int id) {
      for (int v : resolved(all[id]))
        if (valid(by_vertex[v]) < 2) return false;
      return true;
    };
    for (int v : st.pms)
      if (by_vertex[v].size() == 1) flag[by_vertex[v].front()] = 1;
    std::vector<CutSet> missing;
    for (int v : st.pms) {
      const std::vector<int>& ids = by_vertex[v];
      if (ids.empty()) {
        const auto& own = st.cutsets[v];
        const auto best = std::max_element(own.begin(), own.end(),
                                           [](const CutSet& a, const CutSet& b) { return a.weight < b.weight; });
        if (best != own.end()) missing.push_back(*best);
        continue;
      }
      if (ids.size() < 2) continue;
      const int remaining = valid(ids);
      std::vector<int> candidates;
      for (int i : ids)
        if (flag[i] == 0) candidates.push_back(i);
      if (remaining <= 1 || candidates.empty()) continue;
      if (remaining > static_cast<int>(candidates.size())) {
        for (int i : candidates)
          if (removable(i)) flag[i] = 2;
      } else {
        int best = candidates.front();
        for (int i : candidates)
          if (all[i].weight > all[best].weight) best = i;
        for (int i : candidates) {
          if (i == best) flag[i] = 1;
          else if (removable(i)) flag[i] = 2;
        }
      }
    }
    Cell final_cell;
    std::vector<CutSet> kept;
    for (std::size_t i = 0; i < all.size(); ++i)
      if (flag[i] == 1) kept.push_back(all[i]);
    kept.insert(kept.end(), missing.begin(), missing.end());
    std::map<std::pair<int, int>, Diag> u;
    for (const CutSet& c : kept)
      for (const Diag& d : c.diagonals) u.emplace(std::minmax(d.first, d.second), d);
    std::vector<Diag> out;
    for (const auto& [k, d] : u) out.push_back(d);
    return out;
  }
};

/// Interior wedge test at ring vertex c: is direction d strictly inside the interior angle?
/// (angleAt measures clockwise from its first ray, the interior from the previous vertex.)
bool inWedge(const Poly& P, int c, Vec2 d) {
  const Vec2 at = P.p[c], n = P.p[P.nx[c]], p = P.p[P.pv[c]];
  const double total = angleAt(p, at, n);
  const double dir = angleAt(p, at, {at.x + d.x, at.y + d.y});
  return dir > 1e-12 && dir < total - 1e-12;
}

/// Applies cuts (ends given as positions of vertices of P) by splicing: at each end the
/// vertex (or copy made by an earlier cut) whose interior wedge holds the cut is used.
/// Returns the resulting pieces as polygons with holes; *applied counts the cuts applied.
std::vector<Poly> applyCuts(Poly P, const std::vector<Cut>& cuts, int* applied) {
  std::map<std::pair<double, double>, std::vector<int>> at;  // position -> vertices there
  for (int i = 0; i < static_cast<int>(P.p.size()); ++i) at[{P.p[i].x, P.p[i].y}].push_back(i);
  *applied = 0;
  for (const Cut& c : cuts) {
    const Vec2 d{c.b.x - c.a.x, c.b.y - c.a.y};
    int a = -1, b = -1;
    for (int ca : at[{c.a.x, c.a.y}])
      if (inWedge(P, ca, d)) a = ca;
    for (int cb : at[{c.b.x, c.b.y}])
      if (inWedge(P, cb, {-d.x, -d.y})) b = cb;
    if (a < 0 || b < 0 || a == b) continue;  // no longer a diagonal (an earlier cut took it)
    const int an = P.nx[a], bn = P.nx[b];
    const int a2 = P.add(P.p[a]), b2 = P.add(P.p[b]);
    at[{c.a.x, c.a.y}].push_back(a2);
    at[{c.b.x, c.b.y}].push_back(b2);
    P.nx[a] = b2, P.pv[b2] = a, P.nx[b2] = bn, P.pv[bn] = b2;
    P.nx[b] = a2, P.pv[a2] = b, P.nx[a2] = an, P.pv[an] = a2;
    ++*applied;
  }
  std::vector<std::vector<int>> outers, holes;
  std::vector<double> outer_area;
  std::vector<char> seen(P.p.size(), 0);
  for (int v = 0; v < static_cast<int>(P.p.size()); ++v) {
    if (seen[v] || P.nx[v] < 0) continue;
    std::vector<int> r = P.ring(v);
    for (int x : r) seen[x] = 1;
    const double a = signedAreaIds(P, r);
    if (std::abs(a) <= 1e-12) continue;
    if (a > 0) outers.push_back(r), outer_area.push_back(a);
    else holes.push_back(r);
  }
  std::vector<Poly> pieces(outers.size());
  for (std::size_t i = 0; i < outers.size(); ++i) pieces[i].addRing(positions(P, outers[i]));
  for (const auto& h : holes) {
    // The hole goes to the smallest piece containing a point just inside its first edge's
    // outer side (hole rings run clockwise: the polygon's interior is on their left).
    const Vec2 a = P.p[h[0]], b = P.p[h[1 % h.size()]];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len <= 0) continue;
    const Vec2 q{(a.x + b.x) / 2 - (b.y - a.y) / len * 1e-6, (a.y + b.y) / 2 + (b.x - a.x) / len * 1e-6};
    int best = -1;
    for (std::size_t i = 0; i < outers.size(); ++i) {
      Poly one;
      one.addRing(positions(P, outers[i]));
      if (insidePolygon(one, {one.ring(one.heads[0])}, q) && (best < 0 || outer_area[i] < outer_area[best]))
        best = static_cast<int>(i);
    }
    if (best >= 0) pieces[best].addRing(positions(P, h));
  }
  return pieces;
}

Shape toShape(const Poly& P) {
  Shape s;
  for (std::size_t r = 0; r < P.heads.size(); ++r) {
    Ring ring = positions(P, P.ring(P.heads[r]));
    if (r == 0) s.outer = ring;
    else s.holes.push_back(ring);
  }
  return s;
}

bool fromShape(const Shape& shape, Poly* P) {
  const Ring outer = cleanRing(shape.outer, true, 1e-12);
  if (outer.size() < 3) return false;
  P->addRing(outer);
  for (const Ring& h : shape.holes) {
    const Ring hole = cleanRing(h, false, 1e-12);
    if (hole.size() >= 3) P->addRing(hole);
  }
  return true;
}

}  // namespace

std::vector<std::pair<int, int>> selectCuts(RoundState& st) {
  Selector s(st, st.all_cutsets);
  s.precompute();
  return s.optimalCuts();
}

}  // namespace detail

Result decompose(const Shape& shape, const Options& options) {
  using namespace detail;
  Result result;
  Poly P;
  if (!fromShape(shape, &P)) return result;
  std::vector<Poly> todo{P};
  int rounds = 0;
  while (!todo.empty()) {
    if (++rounds > options.max_rounds ||
        static_cast<int>(todo.size() + result.pieces.size()) > options.max_pieces) {
      std::ostringstream w;
      w << "dude(thesis): limit reached (" << options.max_rounds << " rounds / " << options.max_pieces
        << " pieces); " << todo.size() << " piece(s) kept as they are";
      result.warnings.push_back(w.str());
      for (const Poly& q : todo) result.pieces.push_back(toShape(q));
      break;
    }
    std::vector<Poly> next;
    for (const Poly& piece : todo) {
      RoundState st;
      const auto cuts = roundCuts(piece, options.max_concavity,
                                  options.approximation == Approximation::Chains, /*clip=*/true, 0, &st);
      Poly kept = piece;
      if (!st.ignored_holes.empty()) {  // the reference drops holes narrower than tau
        kept = Poly{};
        for (int head : piece.heads)
          if (std::find(st.ignored_holes.begin(), st.ignored_holes.end(), head) == st.ignored_holes.end())
            kept.addRing(positions(piece, piece.ring(head)));
      }
      if (cuts.empty()) {
        result.pieces.push_back(toShape(kept));
        continue;
      }
      std::vector<Cut> at_positions;
      for (const auto& [a, b] : cuts) at_positions.push_back({piece.p[a], piece.p[b]});
      int applied = 0;
      std::vector<Poly> parts = applyCuts(kept, at_positions, &applied);
      if (applied == 0) {  // guards against a round that would repeat forever
        result.pieces.push_back(toShape(kept));
        result.warnings.push_back("dude(thesis): no cut of a piece could be applied; kept whole");
        continue;
      }
      result.cuts.insert(result.cuts.end(), at_positions.begin(), at_positions.end());
      for (Poly& q : parts) next.push_back(std::move(q));
    }
    todo = std::move(next);
  }
  return result;
}

RoundReport analyzeRound(const Shape& shape, double max_concavity, Approximation approximation) {
  using namespace detail;
  RoundReport rep;
  Poly P;
  if (!fromShape(shape, &P)) return rep;
  RoundState st;
  const auto cuts = roundCuts(P, max_concavity, approximation == Approximation::Chains, true, 0, &st);
  for (int v : st.pms) {
    rep.pocket_minima.push_back(P.p[v]);
    rep.concavities.push_back(st.info[v].concavity);
  }
  for (int v = 0; v < static_cast<int>(st.info.size()); ++v)
    if (st.info[v].feature) rep.features.push_back(P.p[v]);
  std::set<std::pair<int, int>> seen;
  for (int v = 0; v < static_cast<int>(st.diagonals.size()); ++v)
    for (int o : st.diagonals[v])
      if (seen.insert(std::minmax(v, o)).second && (st.info[v].isPM() || st.info[o].isPM()))
        rep.diagonals.push_back({P.p[v], P.p[o]});
  for (const auto& [a, b] : cuts) rep.cuts.push_back({P.p[a], P.p[b]});
  return rep;
}

}  // namespace asf::dude::thesis
