// The cut sets of one round of DuDe 2D (the reference's c_cutset, build_cutsets): per pocket
// minimum, the single diagonals and pairs of diagonals that resolve it (residual concavity
// below tau on every side), typed and weighted as the reference does.
#include "dude_thesis_round.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace asf::dude::thesis::detail {
namespace {

double cutsetWeight(const RoundState& st, const CutSet& c) {
  const auto conc = [&](int x) { return st.info[x].concavity; };
  const auto len = [&](const std::pair<int, int>& d) {
    return std::hypot(st.P->p[d.first].x - st.P->p[d.second].x, st.P->p[d.first].y - st.P->p[d.second].y);
  };
  const double my = conc(c.v);
  const int o1 = c.diagonals.front().second;
  const double l1 = len(c.diagonals.front());
  if (c.diagonals.size() == 1) {
    if (c.resolves == 2) return (my + conc(o1)) / l1;
    if (c.resolves == 1) return (my + (c.type == CutSet::SinglePM ? conc(o1) / 2 : 0)) / l1;
    return (my / 2 + (c.type == CutSet::SinglePM ? conc(o1) / 2 : 0)) / l1;  // resolves 0
  }
  const int o2 = c.diagonals.back().second;
  const double l = l1 + len(c.diagonals.back());
  if (c.resolves == 3) return ((my + conc(o1)) + (my + conc(o2))) / l;
  if (c.resolves == 2) {
    double w = my;
    if (st.info[o1].isPM() && resolves(st, o1, c.v)) {
      w += conc(o1);
      if (c.type == CutSet::DoublePMPM) w += conc(o2) / 2;
    } else {
      w += conc(o2);
      if (c.type == CutSet::DoublePMPM) w += conc(o1) / 2;
    }
    return w / l;
  }
  double w = my;
  if (c.type == CutSet::DoublePMPM) w += conc(o1) / 2 + conc(o2) / 2;
  else if (c.type == CutSet::DoublePMTip) w += (st.info[o1].isPM() ? conc(o1) : conc(o2)) / 2;
  return w / l;
}

/// Two diagonals (v,o1), (v,o2) together resolve v (reference is_resolving with two cuts).
bool resolvesPair(const RoundState& st, int v, int o1, int o2) {
  if (!st.info[v].isPM()) return true;
  const Poly& P = *st.P;
  const Vec2 v0 = P.p[v], v1 = P.p[st.info[v].pre_feature], v2 = P.p[st.info[v].next_feature];
  const Vec2 a = P.p[o1], b = P.p[o2];
  const double a1 = angleAt(v1, v0, a), a2 = angleAt(a, v0, b), a3 = angleAt(b, v0, v2);
  if (a1 < M_PI && a2 < M_PI && a3 < M_PI) return true;
  if (a1 >= M_PI && dist2Seg(v1, a, v0) > st.tau) return false;
  if (a2 >= M_PI && dist2Seg(a, b, v0) > st.tau) return false;
  if (a3 >= M_PI && dist2Seg(b, v2, v0) > st.tau) return false;
  return true;
}

/// The cut set of diagonals (v, o) for o in `others` (one or two), typed by which ends are
/// pocket minima, with the minima it resolves and its weight.
CutSet makeCutSet(const RoundState& st, int v, const std::vector<int>& others) {
  CutSet c;
  c.v = v;
  for (int o : others) c.diagonals.push_back({v, o});
  const bool pm1 = st.info[others.front()].isPM();
  if (others.size() == 1) {
    c.type = pm1 ? CutSet::SinglePM : CutSet::SingleTip;
    c.resolves = pm1 && resolves(st, others[0], v) ? 2 : 1;
  } else {
    const bool pm2 = st.info[others.back()].isPM();
    c.type = pm1 && pm2 ? CutSet::DoublePMPM : (pm1 || pm2 ? CutSet::DoublePMTip : CutSet::DoubleTipTip);
    if (c.type == CutSet::DoublePMPM) {
      const bool r1 = resolves(st, others[0], v), r2 = resolves(st, others[1], v);
      c.resolves = r1 && r2 ? 3 : (r1 || r2 ? 2 : 1);
    } else if (c.type == CutSet::DoublePMTip) {
      const int pm = pm1 ? others[0] : others[1];
      c.resolves = resolves(st, pm, v) ? 2 : 1;
    }
  }
  c.weight = cutsetWeight(st, c);
  return c;
}

}  // namespace

bool resolves(const RoundState& st, int v, int o) {
  if (!st.info[v].isPM()) return true;
  const Poly& P = *st.P;
  const Vec2 v0 = P.p[v], v1 = P.p[st.info[v].pre_feature], v2 = P.p[st.info[v].next_feature];
  const Vec2 q = P.p[o];
  const double a1 = angleAt(v1, v0, q), a2 = angleAt(q, v0, v2);
  if (a1 < M_PI && a2 < M_PI) return true;
  if (a1 >= M_PI && dist2Seg(v1, q, v0) > st.tau) return false;
  if (a2 >= M_PI && dist2Seg(v2, q, v0) > st.tau) return false;
  return true;
}

/// Cut sets of pocket minimum v (reference build_cutsets, residual-concavity version).
void buildCutsets(RoundState& st, int v) {
  const Poly& P = *st.P;
  const VertexInfo& I = st.info[v];
  const Vec2 start = P.p[I.pre_feature], end = P.p[I.next_feature], at = P.p[v];
  const double total = angleAt(start, at, end);
  std::vector<std::pair<double, int>> ang;
  for (int o : st.diagonals[v]) {
    const double a = angleAt(start, at, P.p[o]);
    if (a <= total) ang.push_back({a, o});
  }
  std::sort(ang.begin(), ang.end());
  const auto len = [&](int o) { return std::hypot(P.p[o].x - at.x, P.p[o].y - at.y); };
  const int n = static_cast<int>(ang.size());
  std::vector<char> single(n, 0);
  std::vector<CutSet> out;
  CutSet best_tip;
  double shortest_tip = 1e300;
  for (int i = 0; i < n; ++i) {
    const int o = ang[i].second;
    if (!resolves(st, v, o) || !holeDiagonalValid(st, v, o)) continue;
    single[i] = 1;
    CutSet c = makeCutSet(st, v, {o});
    if (c.type == CutSet::SinglePM) out.push_back(c);
    else if (len(o) < shortest_tip) shortest_tip = len(o), best_tip = c;
  }
  if (best_tip.v >= 0) out.push_back(best_tip);
  CutSet best_pmtip, best_tiptip;
  double short_pmtip = 1e300, short_tiptip = 1e300;
  for (int i = 0; i < n; ++i) {
    if (single[i]) continue;
    for (int j = i + 1; j < n; ++j) {
      if (single[j]) continue;
      const int o1 = ang[i].second, o2 = ang[j].second;
      if (!resolvesPair(st, v, o1, o2)) continue;
      CutSet c = makeCutSet(st, v, {o1, o2});
      const double l = len(o1) + len(o2);
      if (c.type == CutSet::DoublePMPM) out.push_back(c);
      else if (c.type == CutSet::DoublePMTip) {
        if (c.resolves == 2) out.push_back(c);
        else if (l < short_pmtip) short_pmtip = l, best_pmtip = c;
      } else if (l < short_tiptip) short_tiptip = l, best_tiptip = c;
    }
  }
  if (best_pmtip.v >= 0) out.push_back(best_pmtip);
  if (best_tiptip.v >= 0) out.push_back(best_tiptip);
  if (out.empty()) {  // nothing resolves v: the best single diagonal, credited one less
    CutSet best;
    double best_w = -1e300;
    for (int i = 0; i < n; ++i) {
      CutSet c = makeCutSet(st, v, {ang[i].second});
      c.resolves -= 1;
      c.weight = cutsetWeight(st, c);
      if (c.weight > best_w) best_w = c.weight, best = c;
    }
    if (best.v >= 0) out.push_back(best);
  }
  st.cutsets[v] = out;
  st.all_cutsets.insert(st.all_cutsets.end(), out.begin(), out.end());
}

}  // namespace asf::dude::thesis::detail
