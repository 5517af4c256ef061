#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/evaluation/run_report.h>
#include <asf/evaluation/svg_plot.h>
#include <asf/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace asf::evaluation::plot {

namespace {

// Colour-blind friendly palette (Okabe & Ito), most distinct first.
const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                "#E69F00", "#56B4E9", "#000000", "#F0E442"};

// Text in SVG is escaped as in HTML.
std::string esc(const std::string& s) { return htmlEscape(s); }

/// A tick label with as many decimals as the step needs (0.25 never appears: steps are
/// 1, 2 or 5 times a power of ten).
std::string tickLabel(double v, double step) {
  if (std::fabs(v) < step * 1e-9) v = 0;  // no "-0"
  const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", std::min(decimals, 12), v);
  return b;
}

bool finite(double v) { return std::isfinite(v); }

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!finite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};

bool hasBand(const Series& s) {
  return !s.y_low.empty() && s.y_low.size() == s.x.size() && s.y_high.size() == s.x.size();
}

/// Runs of consecutive indices where `ok(i)` holds: the pieces of a line with gaps.
template <class Ok>
std::vector<std::pair<std::size_t, std::size_t>> runs(std::size_t n, Ok ok) {
  std::vector<std::pair<std::size_t, std::size_t>> r;
  std::size_t i = 0;
  while (i < n) {
    if (!ok(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && ok(j)) ++j;
    r.emplace_back(i, j);  // [i, j)
    i = j;
  }
  return r;
}

}  // namespace

std::vector<double> niceTicks(double lo, double hi, int target) {
  if (!finite(lo) || !finite(hi)) {
    if (finite(lo))
      hi = lo;
    else if (finite(hi))
      lo = hi;
    else
      lo = 0, hi = 1;
  }
  if (lo > hi) std::swap(lo, hi);
  if (hi - lo <= 1e-12 * std::max(1.0, std::fabs(lo))) {
    // One value: a range that shows it (0 alone gives [0, 1]).
    const double pad = lo == 0 ? 1 : std::fabs(lo) * 0.1;
    lo = lo == 0 ? 0 : lo - pad;
    hi = hi + pad;
  }
  const double raw = (hi - lo) / std::max(1, target);
  if (!finite(raw) || raw <= 0) return {lo, hi};
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  const double step = (n < 1.5 ? 1 : n < 3 ? 2 : n < 7 ? 5 : 10) * mag;
  const double k0 = std::floor(lo / step + 1e-9), k1 = std::ceil(hi / step - 1e-9);
  if (!finite(k0) || !finite(k1) || k1 - k0 > 1000) return {lo, hi};
  std::vector<double> t;
  // Multiples of the step (not accumulated sums), so 0.3 is 3 * 0.1, not 0.1 + 0.1 + 0.1.
  for (double k = k0; k <= k1; k += 1) t.push_back(k * step);
  if (t.size() < 2) t.push_back((k0 + 1) * step);
  return t;
}

namespace {

/// Where everything goes: the plot box, with the legend below it (entries flowing left to
/// right, so it never covers the data).
struct Layout {
  struct LegendItem {
    double x, y;
    std::size_t series;
  };
  double W = 0, H = 0, left = 70, right = 20, top = 16, bottom = 0, pw = 0, ph = 0;
  std::vector<LegendItem> legend;
};

Layout layoutOf(const Figure& f) {
  Layout L;
  L.W = std::max(f.width, 200);
  const double H0 = std::max(f.height, 150);
  L.top = f.title.empty() ? 16 : 36;
  double lx = L.left;
  int legend_rows = f.series.empty() ? 0 : 1;
  for (std::size_t i = 0; i < f.series.size(); ++i) {
    const double w = 34 + 7.0 * f.series[i].label.size() + 16;
    if (lx + w > L.W - L.right && lx > L.left) {
      lx = L.left;
      ++legend_rows;
    }
    L.legend.push_back({lx, (legend_rows - 1) * 18.0, i});
    lx += w;
  }
  const double legend_h = legend_rows * 18.0;
  L.H = H0 + legend_h;
  L.bottom = 46 + legend_h;
  L.pw = L.W - L.left - L.right;
  L.ph = L.H - L.top - L.bottom;
  return L;
}

/// The range of the finite data (lines and bands); false when no line has a finite point.
bool dataRange(const Figure& f, Range& xr, Range& yr) {
  bool any = false;
  for (const auto& s : f.series) {
    const bool band = hasBand(s);
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!finite(s.x[i])) continue;
      const double y = i < s.y.size() ? s.y[i] : NAN;
      if (finite(y)) {
        any = true;
        xr.add(s.x[i]);
        yr.add(y);
      }
      if (band && finite(s.y_low[i]) && finite(s.y_high[i])) {
        xr.add(s.x[i]);
        yr.add(s.y_low[i]);
        yr.add(s.y_high[i]);
      }
    }
  }
  return any;
}

/// The document, background, title, plot box and axis labels.
void writeFrame(std::ostringstream& o, const Figure& f, const Layout& L) {
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << L.W << "\" height=\"" << L.H
    << "\" viewBox=\"0 0 " << L.W << ' ' << L.H
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  if (!f.title.empty()) o << "<title>" << esc(f.title) << "</title>\n";
  o << "<rect x=\"0\" y=\"0\" width=\"" << L.W << "\" height=\"" << L.H << "\" fill=\"white\"/>\n";
  if (!f.title.empty())
    o << "<text x=\"" << formatFixed(L.W / 2, 1)
      << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\" "
      << "font-weight=\"bold\">" << esc(f.title) << "</text>\n";
  o << "<rect x=\"" << formatFixed(L.left, 1) << "\" y=\"" << formatFixed(L.top, 1) << "\" width=\""
    << formatFixed(L.pw, 1) << "\" height=\"" << formatFixed(L.ph, 1)
    << "\" fill=\"none\" stroke=\"#444\"/>\n";
  // Axis labels.
  o << "<text x=\"" << formatFixed(L.left + L.pw / 2, 1) << "\" y=\""
    << formatFixed(L.top + L.ph + 38, 1) << "\" text-anchor=\"middle\">" << esc(f.x_label)
    << "</text>\n";
  o << "<text transform=\"translate(16," << formatFixed(L.top + L.ph / 2, 1)
    << ") rotate(-90)\" text-anchor=\"middle\">" << esc(f.y_label) << "</text>\n";
}

/// Data to plot coordinates over the ticks' range.
struct Axes {
  std::vector<double> xt, yt;
  double x0, x1, y0, y1, xstep, ystep;
  const Layout& L;
  Axes(const Range& xr, const Range& yr, const Layout& layout)
      : xt(niceTicks(xr.lo, xr.hi)), yt(niceTicks(yr.lo, yr.hi)), L(layout) {
    x0 = xt.front(), x1 = xt.back(), y0 = yt.front(), y1 = yt.back();
    xstep = xt.size() > 1 ? xt[1] - xt[0] : 1;
    ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  }
  double px(double x) const { return L.left + (x - x0) / (x1 - x0) * L.pw; }
  double py(double y) const { return L.top + L.ph - (y - y0) / (y1 - y0) * L.ph; }
};

void writeGridAndTicks(std::ostringstream& o, const Axes& a) {
  const Layout& L = a.L;
  o << "<g stroke=\"#e4e4e4\">\n";
  for (double t : a.xt)
    o << "<line x1=\"" << formatFixed(a.px(t), 1) << "\" y1=\"" << formatFixed(L.top, 1)
      << "\" x2=\"" << formatFixed(a.px(t), 1) << "\" y2=\"" << formatFixed(L.top + L.ph, 1)
      << "\"/>\n";
  for (double t : a.yt)
    o << "<line x1=\"" << formatFixed(L.left, 1) << "\" y1=\"" << formatFixed(a.py(t), 1)
      << "\" x2=\"" << formatFixed(L.left + L.pw, 1) << "\" y2=\"" << formatFixed(a.py(t), 1)
      << "\"/>\n";
  o << "</g>\n<g fill=\"#333\">\n";
  for (double t : a.xt)
    o << "<text x=\"" << formatFixed(a.px(t), 1) << "\" y=\"" << formatFixed(L.top + L.ph + 16, 1)
      << "\" text-anchor=\"middle\">" << tickLabel(t, a.xstep) << "</text>\n";
  for (double t : a.yt)
    o << "<text x=\"" << formatFixed(L.left - 6, 1) << "\" y=\"" << formatFixed(a.py(t) + 4, 1)
      << "\" text-anchor=\"end\">" << tickLabel(t, a.ystep) << "</text>\n";
  o << "</g>\n";
}

void writeBand(std::ostringstream& o, const Series& s, const std::string& color, const Axes& a) {
  for (auto [b0, b1] : runs(s.x.size(), [&](std::size_t i) {
         return finite(s.x[i]) && finite(s.y_low[i]) && finite(s.y_high[i]);
       })) {
    o << "<polygon fill=\"" << esc(color) << "\" fill-opacity=\"0.18\" stroke=\"none\" "
      << "points=\"";
    for (std::size_t i = b0; i < b1; ++i)
      o << formatFixed(a.px(s.x[i]), 1) << ',' << formatFixed(a.py(s.y_high[i]), 1) << ' ';
    for (std::size_t i = b1; i-- > b0;)
      o << formatFixed(a.px(s.x[i]), 1) << ',' << formatFixed(a.py(s.y_low[i]), 1) << ' ';
    o << "\"/>\n";
  }
}

void writeLine(std::ostringstream& o, const Series& s, const std::string& color, const Axes& a) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const auto pieces = runs(n, [&](std::size_t i) { return finite(s.x[i]) && finite(s.y[i]); });
  std::ostringstream d;
  for (auto [b0, b1] : pieces) {
    if (b1 - b0 == 1) {  // an isolated point: a dot, a path of one point is invisible
      o << "<circle cx=\"" << formatFixed(a.px(s.x[b0]), 1) << "\" cy=\""
        << formatFixed(a.py(s.y[b0]), 1) << "\" r=\"2.5\" fill=\"" << esc(color) << "\"/>\n";
      continue;
    }
    for (std::size_t i = b0; i < b1; ++i)
      d << (i == b0 ? 'M' : 'L') << formatFixed(a.px(s.x[i]), 1) << ','
        << formatFixed(a.py(s.y[i]), 1) << ' ';
  }
  if (!d.str().empty())
    o << "<path fill=\"none\" stroke=\"" << esc(color) << "\" stroke-width=\"1.8\" "
      << "stroke-linejoin=\"round\"" << (s.dashed ? " stroke-dasharray=\"6 4\"" : "") << " d=\""
      << d.str() << "\"/>\n";
}

/// Legend swatches in the lines' colours.
void writeLegend(std::ostringstream& o, const Figure& f, const Layout& L,
                 const std::vector<std::string>& colors) {
  for (const auto& it : L.legend) {
    const Series& s = f.series[it.series];
    const double y = L.top + L.ph + 46 + it.y + 4;
    if (hasBand(s))
      o << "<rect x=\"" << formatFixed(it.x, 1) << "\" y=\"" << formatFixed(y - 6, 1)
        << "\" width=\"26\" "
        << "height=\"12\" fill=\"" << esc(colors[it.series]) << "\" fill-opacity=\"0.18\"/>\n";
    o << "<line x1=\"" << formatFixed(it.x, 1) << "\" y1=\"" << formatFixed(y, 1) << "\" x2=\""
      << formatFixed(it.x + 26, 1) << "\" y2=\"" << formatFixed(y, 1) << "\" stroke=\""
      << esc(colors[it.series]) << "\" stroke-width=\"2\""
      << (s.dashed ? " stroke-dasharray=\"6 4\"" : "") << "/>\n";
    o << "<text x=\"" << formatFixed(it.x + 32, 1) << "\" y=\"" << formatFixed(y + 4, 1) << "\">"
      << esc(s.label) << "</text>\n";
  }
}

/// No data: a note in the box, and the legend still names the series.
void writeNoData(std::ostringstream& o, const Figure& f, const Layout& L) {
  o << "<text x=\"" << formatFixed(L.left + L.pw / 2, 1) << "\" y=\""
    << formatFixed(L.top + L.ph / 2, 1)
    << "\" text-anchor=\"middle\" font-size=\"16\" fill=\"#888\">no data</text>\n";
  for (const auto& it : L.legend) {
    const double y = L.top + L.ph + 46 + it.y + 4;
    o << "<text x=\"" << formatFixed(it.x + 32, 1) << "\" y=\"" << formatFixed(y + 4, 1)
      << "\" fill=\"#888\">" << esc(f.series[it.series].label) << "</text>\n";
  }
}

}  // namespace

std::string svg(const Figure& f) {
  const Layout L = layoutOf(f);
  Range xr, yr;
  const bool any = dataRange(f, xr, yr);
  std::ostringstream o;
  writeFrame(o, f, L);
  if (!any) {
    writeNoData(o, f, L);
    o << "</svg>\n";
    return o.str();
  }
  if (f.y_from_zero) yr.add(0);
  const Axes a(xr, yr, L);
  writeGridAndTicks(o, a);
  std::size_t pal = 0;
  std::vector<std::string> colors;
  for (const auto& s : f.series)
    colors.push_back(s.color.empty() ? kPalette[pal++ % (sizeof kPalette / sizeof *kPalette)]
                                     : s.color);
  // Bands first, so every line is drawn over every band.
  for (std::size_t k = 0; k < f.series.size(); ++k)
    if (hasBand(f.series[k])) writeBand(o, f.series[k], colors[k], a);
  for (std::size_t k = 0; k < f.series.size(); ++k) writeLine(o, f.series[k], colors[k], a);
  writeLegend(o, f, L, colors);
  o << "</svg>\n";
  return o.str();
}

void writeSvg(const Figure& f, const std::string& path) {
  writeFileAtomically(path, svg(f), "plot");
}

}  // namespace asf::evaluation::plot
