// Thesis Fig. 3.3: the Monte Carlo of place recognition at one node, drawn as SVG.
#include <asf/studies/recognition_figure.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

namespace asf::studies {

namespace {

/// A square panel mapping [cx - half, cx + half] x [cy - half, cy + half] to pixels.
struct Panel {
  double left, top, size, cx, cy, half;
  double px(double x) const { return left + (x - cx + half) / (2 * half) * size; }
  double py(double y) const { return top + (cy + half - y) / (2 * half) * size; }
  bool inside(double x, double y) const {
    return std::abs(x - cx) <= half && std::abs(y - cy) <= half;
  }
};

void frame(std::ostringstream& os, const Panel& p, const std::string& caption) {
  os << "<rect x='" << p.left << "' y='" << p.top << "' width='" << p.size << "' height='"
     << p.size << "' fill='white' stroke='#444'/>\n"
     << "<text x='" << p.left + p.size / 2 << "' y='" << p.top + p.size + 22
     << "' text-anchor='middle' font-size='13'>" << caption << "</text>\n";
}

void rect(std::ostringstream& os, const Panel& p, double x0, double y0, double x1, double y1,
          const char* style) {
  os << "<rect x='" << p.px(x0) << "' y='" << p.py(y1) << "' width='" << p.px(x1) - p.px(x0)
     << "' height='" << p.py(y0) - p.py(y1) << "' " << style << "/>\n";
}

/// Left panel: the local map, the node's scan, the node and the window of believed poses.
void mapPanel(std::ostringstream& os, const Panel& p, const planning::RecognitionTrial& t,
              const PoseNode& node, const planning::RecognitionMcOptions& o) {
  frame(os, p, "local map (grey), the node's scan (blue), window of believed positions");
  // One dot per pixel: the local map holds thousands of points.
  auto dots = [&](const std::vector<std::pair<float, float>>& pts, const char* style) {
    std::set<std::pair<int, int>> drawn;
    for (const auto& [x, y] : pts) {
      if (!p.inside(x, y)) continue;
      const auto px = std::make_pair(static_cast<int>(p.px(x)), static_cast<int>(p.py(y)));
      if (!drawn.insert(px).second) continue;
      os << "<circle cx='" << px.first << "' cy='" << px.second << "' " << style << "/>\n";
    }
  };
  dots(t.map_points, "r='0.9' fill='#999'");
  dots(t.scan_points, "r='1.2' fill='#1f5fbf'");
  const double x = node.pose.x(), y = node.pose.y(), phi = node.pose.phi();
  rect(os, p, x - o.half_x, y - o.half_y, x + o.half_x, y + o.half_y,
       "fill='none' stroke='black' stroke-dasharray='4 3'");
  os << "<circle cx='" << p.px(x) << "' cy='" << p.py(y) << "' r='4' fill='black'/>\n"
     << "<line x1='" << p.px(x) << "' y1='" << p.py(y) << "' x2='" << p.px(x + 0.8 * std::cos(phi))
     << "' y2='" << p.py(y + 0.8 * std::sin(phi)) << "' stroke='black' stroke-width='2'/>\n";
  // A 1 m scale bar.
  const double bx = p.cx - p.half + 0.1 * p.half, by = p.cy - p.half + 0.1 * p.half;
  os << "<line x1='" << p.px(bx) << "' y1='" << p.py(by) << "' x2='" << p.px(bx + 1)
     << "' y2='" << p.py(by) << "' stroke='black' stroke-width='2'/>\n"
     << "<text x='" << p.px(bx + 0.5) << "' y='" << p.py(by) - 5
     << "' text-anchor='middle' font-size='11'>1 m</text>\n";
}

/// Right panel: each sample's position error in the node's frame [cm].
void errorPanel(std::ostringstream& os, const Panel& p, const planning::RecognitionTrial& t,
                const PoseNode& node, const planning::RecognitionMcOptions& o) {
  frame(os, p, "ICP result - node, node frame [cm]: success (black), failure (red)");
  rect(os, p, -100 * o.success_xy, -100 * o.success_xy, 100 * o.success_xy, 100 * o.success_xy,
       "fill='#eee' stroke='black'");
  rect(os, p, -100 * o.half_x, -100 * o.half_y, 100 * o.half_x, 100 * o.half_y,
       "fill='none' stroke='#888' stroke-dasharray='4 3'");
  for (double v = -p.half; v <= p.half + 1e-9; v += p.half / 2) {
    os << "<text x='" << p.px(v) << "' y='" << p.top + p.size + 12
       << "' text-anchor='middle' font-size='10'>" << v << "</text>\n"
       << "<text x='" << p.left - 4 << "' y='" << p.py(v) + 3
       << "' text-anchor='end' font-size='10'>" << v << "</text>\n";
  }
  for (const planning::RecognitionSample& s : t.samples) {
    const mrpt::poses::CPose2D e = s.result - node.pose;  // node^-1 (+) result
    double x = 100 * e.x(), y = 100 * e.y();
    const bool clipped = !p.inside(x, y);
    x = std::clamp(x, p.cx - p.half, p.cx + p.half);
    y = std::clamp(y, p.cy - p.half, p.cy + p.half);
    const char* colour = s.success ? "black" : "#d62728";
    os << "<circle cx='" << p.px(x) << "' cy='" << p.py(y) << "' r='3' "
       << (clipped ? std::string("fill='none' stroke='") + colour + "'"
                   : std::string("fill='") + colour + "'")
       << "/>\n";
  }
}

}  // namespace

std::string recognitionScatterSvg(const planning::RecognitionTrial& t, const PoseNode& node,
                                  const planning::RecognitionMcOptions& o, const std::string& title) {
  const double size = 380, margin = 40;
  const double view = std::min(o.map_radius, 8.0);
  const Panel map{margin, 50, size, node.pose.x(), node.pose.y(), view};
  const double err_half = 100 * 1.5 * std::max({o.half_x, o.half_y, o.success_xy});
  const Panel err{2 * margin + size + 20, 50, size, 0, 0, err_half};
  std::size_t ok = 0, unaligned = 0;
  for (const auto& s : t.samples) {
    ok += s.success;
    unaligned += !s.aligned;
  }
  std::ostringstream os;
  os << std::fixed << std::setprecision(2);
  os << "<svg xmlns='http://www.w3.org/2000/svg' width='" << 3 * margin + 2 * size + 20
     << "' height='" << size + 110 << "' font-family='sans-serif'>\n"
     << "<rect width='100%' height='100%' fill='white'/>\n"
     << "<text x='" << margin << "' y='22' font-size='15'>" << title << "</text>\n"
     << "<text x='" << margin << "' y='40' font-size='12'>p_recognition = " << ok << " / "
     << t.samples.size() << " = " << t.p << "; window +-" << 100 * o.half_x << " cm, +-"
     << o.half_phi * 180 / M_PI << " deg; success within " << 100 * o.success_xy << " cm and "
     << o.success_phi * 180 / M_PI << " deg";
  if (unaligned) os << "; " << unaligned << " with too few rays left";
  os << "; open circles: beyond the panel</text>\n";
  mapPanel(os, map, t, node, o);
  errorPanel(os, err, t, node, o);
  os << "</svg>\n";
  return os.str();
}

}  // namespace asf::studies
