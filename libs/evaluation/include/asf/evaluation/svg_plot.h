#pragma once
/// \file svg_plot.h
/// Line plots as standalone SVG text (no dependency): what run reports and experiment
/// summaries draw (coverage vs distance, pose error vs distance, ...).
#include <string>
#include <utility>
#include <vector>

namespace asf::evaluation::plot {

struct Series {
  std::string label;
  std::vector<double> x, y;
  /// Optional band drawn under the line (e.g. mean +- std); empty or the size of x.
  std::vector<double> y_low, y_high;
  std::string color;  ///< CSS colour; empty: the palette's next colour
  bool dashed = false;
};

/// A plain line series (no band, palette colour).
inline Series series(std::string label, std::vector<double> x, std::vector<double> y) {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  return s;
}

struct Figure {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  int width = 640, height = 400;  ///< pixels
  bool y_from_zero = true;        ///< the y axis starts at 0 (else at the data minimum)
};

/// The figure as an SVG document (axes with "nice" ticks, labels, legend). Non-finite
/// points are skipped (a gap in the line); a figure without data gives a valid SVG that
/// says so.
std::string svg(const Figure& f);

/// Tick values covering [lo, hi]: a step of 1, 2 or 5 times a power of ten chosen so about
/// `target` intervals span the range, from the largest multiple of the step <= lo to the
/// smallest >= hi. A degenerate or non-finite range gives a small range around it.
std::vector<double> niceTicks(double lo, double hi, int target = 5);

/// Writes svg(f) to path; throws asf::Error naming the file when it cannot.
void writeSvg(const Figure& f, const std::string& path);

}  // namespace asf::evaluation::plot
