// Exhaustive search of traversals of a graph (thesis figs. 5.6-5.10) and its plot.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/graph/information.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

namespace asf::graph {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

void checkExhaustiveOptions(const Multigraph& g, const ExhaustiveOptions& o) {
  if (g.n < 1 || g.n > 250) throw InputError("exhaustive search: needs 1..250 nodes");
  if (o.max_d < 1 || o.max_d > 250) throw InputError("exhaustive search: max_d must be 1..250");
  if (o.start < -1 || o.start >= g.n)
    throw InputError("exhaustive search: start node " + std::to_string(o.start + 1) +
                     " is not a node");
  for (double p : o.criteria)
    if (std::isnan(p) || p > 1) throw InputError("exhaustive search: criterion p must be <= 1");
}

/// Scores each layer's edge-count vectors (one byte per edge) by every criterion into r.
void scoreLayer(const Multigraph& g, const ExhaustiveOptions& o, int di,
                const std::unordered_set<std::string>& counts, ExhaustiveResult& r) {
  const int m = g.m();
  const int nc = static_cast<int>(o.criteria.size());
  for (const std::string& key : counts) {
    VectorXd x(m);
    for (int j = 0; j < m; ++j) x[j] = static_cast<unsigned char>(key[j]);
    if (!supportConnected(g, x)) continue;
    const VectorXd mu = reducedSpectrum(g, x);
    for (int c = 0; c < nc; ++c) {
      const double v = std::max(0.0, powerMean(mu, o.criteria[c]));
      if (v > r.information(di, c)) {
        r.information(di, c) = v;
        r.best[di][c] = x;
      }
    }
  }
  const int d = di + 1;
  r.rate.row(di) = r.information.row(di) / d;
  r.d.push_back(d);
  r.candidates.push_back(counts.size());
}

/// Compositions of d into m parts, by extending those of d-1 with one more edge.
void searchMultisets(const Multigraph& g, const ExhaustiveOptions& o, ExhaustiveResult& r) {
  const int m = g.m();
  std::unordered_set<std::string> layer{std::string(m, '\0')};
  for (int d = 1; d <= o.max_d; ++d) {
    std::unordered_set<std::string> next;
    for (const std::string& s : layer)
      for (int j = 0; j < m; ++j) {
        std::string t = s;
        ++t[j];
        next.insert(std::move(t));
        if (next.size() > o.max_states)
          throw Error("exhaustive search: more than " + std::to_string(o.max_states) +
                      " multisets at d = " + std::to_string(d));
      }
    layer.swap(next);
    scoreLayer(g, o, d - 1, layer, r);
  }
}

/// Walks: state = [start, end, counts...]; the start only matters for closed walks.
void searchWalks(const Multigraph& g, const ExhaustiveOptions& o, ExhaustiveResult& r) {
  const int m = g.m();
  const bool closed = o.kind == TraversalKind::ClosedWalk;
  const auto inc = g.incidence();
  std::unordered_set<std::string> layer;
  for (int s = 0; s < g.n; ++s) {
    if (o.start >= 0 && s != o.start) continue;
    std::string st(2 + m, '\0');
    st[0] = static_cast<char>(closed ? s : 0);
    st[1] = static_cast<char>(s);
    layer.insert(st);
  }
  for (int d = 1; d <= o.max_d; ++d) {
    std::unordered_set<std::string> next;
    for (const std::string& s : layer) {
      const int at = static_cast<unsigned char>(s[1]);
      for (int j : inc[at]) {
        std::string t = s;
        t[1] = static_cast<char>(g.edges[j].u == at ? g.edges[j].v : g.edges[j].u);
        ++t[2 + j];
        next.insert(std::move(t));
      }
      if (next.size() > o.max_states)
        throw Error("exhaustive search: more than " + std::to_string(o.max_states) +
                    " walk states at d = " + std::to_string(d));
    }
    layer.swap(next);
    std::unordered_set<std::string> counts;
    for (const std::string& s : layer) {
      if (closed && s[0] != s[1]) continue;
      counts.insert(s.substr(2));
    }
    scoreLayer(g, o, d - 1, counts, r);
  }
}

}  // namespace

ExhaustiveResult exhaustiveSearch(const Multigraph& g, const ExhaustiveOptions& o) {
  checkExhaustiveOptions(g, o);
  const int m = g.m();
  ExhaustiveResult r;
  r.criteria = o.criteria;
  const int nc = static_cast<int>(o.criteria.size());
  r.information = MatrixXd::Zero(o.max_d, nc);
  r.rate = MatrixXd::Zero(o.max_d, nc);
  r.best.assign(o.max_d, std::vector<VectorXd>(nc, VectorXd::Zero(m)));
  if (o.kind == TraversalKind::Multiset)
    searchMultisets(g, o, r);
  else
    searchWalks(g, o, r);
  return r;
}

void writeExhaustiveSvg(const ExhaustiveResult& r, const std::string& path,
                        const std::string& title, const std::vector<double>& optimum) {
  static const char* kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                  "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
  const double W = 900, Hh = 380, pw = 380, ph = 260, top = 60, gapx = 70;
  const int nd = static_cast<int>(r.d.size()), nc = static_cast<int>(r.criteria.size());
  auto esc = [](const std::string& s) {
    std::string o;
    for (char ch : s) {
      if (ch == '<') o += "&lt;";
      else if (ch == '>') o += "&gt;";
      else if (ch == '&') o += "&amp;";
      else o += ch;
    }
    return o;
  };
  std::ostringstream os;
  os << std::setprecision(5);
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << Hh
     << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"white\"/>\n<text x=\""
     << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << esc(title)
     << "</text>\n";
  for (int panel = 0; panel < 2; ++panel) {
    const MatrixXd& Y = panel == 0 ? r.information : r.rate;
    double ymax = Y.size() ? Y.maxCoeff() : 1;
    if (panel == 1)
      for (double v : optimum) ymax = std::max(ymax, v);
    if (!(ymax > 0)) ymax = 1;
    ymax *= 1.05;
    const double x0 = gapx + panel * (pw + gapx), y0 = top + ph;
    const double dmax = nd ? r.d.back() : 1;
    auto X = [&](double d) { return x0 + pw * d / dmax; };
    auto Yp = [&](double v) { return y0 - ph * v / ymax; };
    os << "<rect x=\"" << x0 << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
       << "\" fill=\"none\" stroke=\"black\"/>\n";
    os << "<text x=\"" << x0 + pw / 2 << "\" y=\"" << top - 8 << "\" text-anchor=\"middle\">"
       << (panel == 0 ? "best information ||L(x)||_p" : "best information rate ||L(x)||_p / d")
       << "</text>\n<text x=\"" << x0 + pw / 2 << "\" y=\"" << y0 + 34
       << "\" text-anchor=\"middle\">traversals d</text>\n";
    for (int tk = 0; tk <= 4; ++tk) {
      const double v = ymax * tk / 4;
      os << "<line x1=\"" << x0 - 4 << "\" x2=\"" << x0 << "\" y1=\"" << Yp(v) << "\" y2=\""
         << Yp(v) << "\" stroke=\"black\"/><text x=\"" << x0 - 6 << "\" y=\"" << Yp(v) + 4
         << "\" text-anchor=\"end\">" << v << "</text>\n";
    }
    const int step = std::max(1, nd / 12);
    for (int i = 0; i < nd; i += step)
      os << "<text x=\"" << X(r.d[i]) << "\" y=\"" << y0 + 16 << "\" text-anchor=\"middle\">"
         << r.d[i] << "</text>\n";
    for (int c = 0; c < nc; ++c) {
      const char* col = kColors[c % 8];
      os << "<polyline fill=\"none\" stroke=\"" << col << "\" stroke-width=\"2\" points=\"";
      for (int i = 0; i < nd; ++i) os << X(r.d[i]) << "," << Yp(Y(i, c)) << " ";
      os << "\"/>\n";
      for (int i = 0; i < nd; ++i)
        os << "<circle cx=\"" << X(r.d[i]) << "\" cy=\"" << Yp(Y(i, c)) << "\" r=\"2.5\" fill=\""
           << col << "\"/>\n";
      if (panel == 1 && c < static_cast<int>(optimum.size()))
        os << "<line x1=\"" << x0 << "\" x2=\"" << x0 + pw << "\" y1=\"" << Yp(optimum[c])
           << "\" y2=\"" << Yp(optimum[c]) << "\" stroke=\"" << col
           << "\" stroke-dasharray=\"6,4\"/>\n";
      if (panel == 0)
        os << "<text x=\"" << x0 + 10 << "\" y=\"" << top + 18 + 16 * c << "\" fill=\"" << col
           << "\">" << esc(criterionName(r.criteria[c])) << "</text>\n";
    }
  }
  if (!optimum.empty())
    os << "<text x=\"" << W - 20 << "\" y=\"" << Hh - 12
       << "\" text-anchor=\"end\">dashed: relaxed optimum (max over the simplex)</text>\n";
  os << "</svg>\n";
  writeFileAtomically(path, os.str(), "SVG");
}

}  // namespace asf::graph
