#include "region_render.h"

#include <asf/evaluation/run_report.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <cmath>
#include <iomanip>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace asf::evaluation {

using Grid = mrpt::maps::COccupancyGridMap2D;

namespace render {

cv::Vec3b regionColour(RegionId id) {
  // Distinct, deterministic colours from the id (golden-ratio hue walk).
  const double h = std::fmod(id * 0.618033988749895, 1.0) * 180.0;
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(h, 140, 230)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

MapImage renderGrid(const Grid& g) {
  MapImage m;
  m.x0 = g.getXMin(), m.y0 = g.getYMin(), m.res = g.getResolution();
  const int w = static_cast<int>(g.getSizeX()), h = static_cast<int>(g.getSizeY());
  m.img = cv::Mat(h, w, CV_8UC3);
  for (int cy = 0; cy < h; ++cy)
    for (int cx = 0; cx < w; ++cx) {
      const auto v = static_cast<unsigned char>(255.0 * g.getCell(cx, cy));  // p(free)
      m.img.at<cv::Vec3b>(h - 1 - cy, cx) = {v, v, v};
    }
  return m;
}

void drawRegions(MapImage& m, const LabelImage& labels) {
  std::map<RegionId, cv::Vec3b> colours;  // one HSV conversion per region, not per cell
  for (int cy = 0; cy < labels.height; ++cy)
    for (int cx = 0; cx < labels.width; ++cx) {
      const RegionId r = labels.at(cx, cy);
      if (r <= 0) continue;
      const auto p = m.px(labels.origin_x + (cx + 0.5) * labels.resolution,
                          labels.origin_y + (cy + 0.5) * labels.resolution);
      if (p.x < 0 || p.y < 0 || p.x >= m.img.cols || p.y >= m.img.rows) continue;
      auto it = colours.find(r);
      if (it == colours.end()) it = colours.emplace(r, regionColour(r)).first;
      m.img.at<cv::Vec3b>(p) = it->second;
    }
}

void drawTopology(MapImage& m, const TopoGraph& topo) {
  for (const auto& e : topo.edges) {
    const TopoNode* a = topo.node(e.a);
    const cv::Point mid = m.px(e.midpoint.x, e.midpoint.y);
    if (e.frontier()) {
      cv::circle(m.img, mid, 3, {0, 0, 255}, -1);
      if (a) cv::line(m.img, m.px(a->centroid.x, a->centroid.y), mid, {0, 0, 200}, 1);
    } else if (const TopoNode* b = topo.node(e.b); a && b) {
      cv::line(m.img, m.px(a->centroid.x, a->centroid.y), mid, {40, 40, 40}, 1);
      cv::line(m.img, mid, m.px(b->centroid.x, b->centroid.y), {40, 40, 40}, 1);
    }
  }
  for (const auto& n : topo.nodes)
    if (n.region > 0) cv::circle(m.img, m.px(n.centroid.x, n.centroid.y), 4, {0, 0, 0}, -1);
}

void drawRegionIds(MapImage& m, const Segmentation& seg) {
  for (const auto& r : seg.regions) {
    const std::string text = std::to_string(r.id);
    cv::Point p = m.px(r.centroid.x, r.centroid.y) + cv::Point(5, -5);
    // White halo under black text: readable on any region colour.
    cv::putText(m.img, text, p, cv::FONT_HERSHEY_SIMPLEX, 0.4, {255, 255, 255}, 3, cv::LINE_AA);
    cv::putText(m.img, text, p, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
  }
}

std::string topologySvg(const MapImage& m, const cv::Mat& background, const TopoGraph& topo,
                        const std::vector<Point2>& path) {
  std::vector<unsigned char> png;
  cv::imencode(".png", background, png);
  std::ostringstream os;
  os << std::fixed << std::setprecision(1);
  const int W = background.cols, H = background.rows;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
     << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\">\n"
     << "<image width=\"" << W << "\" height=\"" << H << "\" href=\"data:image/png;base64,"
     << report::base64(std::string(png.begin(), png.end())) << "\"/>\n";
  auto at = [&](const Point2& p) {
    const cv::Point q = m.px(p.x, p.y);
    std::ostringstream o;
    o << std::fixed << std::setprecision(1) << q.x + 0.5 << "," << q.y + 0.5;
    return o.str();
  };
  if (path.size() > 1) {
    os << "<polyline fill=\"none\" stroke=\"#0050c8\" stroke-width=\"1\" stroke-opacity=\"0.7\" "
          "points=\"";
    for (const Point2& p : path) os << at(p) << " ";
    os << "\"/>\n";
  }
  for (const auto& e : topo.edges) {
    const TopoNode* a = topo.node(e.a);
    if (!a) continue;
    if (e.frontier()) {
      os << "<polyline fill=\"none\" stroke=\"#d00000\" stroke-width=\"1.5\" points=\""
         << at(a->centroid) << " " << at(e.midpoint) << "\"/>\n";
      continue;
    }
    const TopoNode* b = topo.node(e.b);
    if (!b) continue;
    os << "<polyline fill=\"none\" stroke=\"#202020\" stroke-width=\"1.5\" points=\""
       << at(a->centroid) << " " << at(e.midpoint) << " " << at(b->centroid) << "\"/>\n";
    const cv::Point q = m.px(e.midpoint.x, e.midpoint.y);
    os << "<text x=\"" << q.x + 3 << "\" y=\"" << q.y - 3 << "\" font-size=\"9\" fill=\"#202020\">"
       << e.traversals.size() << "</text>\n";
  }
  for (const auto& n : topo.nodes) {
    if (n.region <= 0) continue;
    const cv::Point q = m.px(n.centroid.x, n.centroid.y);
    os << "<circle cx=\"" << q.x + 0.5 << "\" cy=\"" << q.y + 0.5 << "\" r=\"4\" fill=\""
       << (n.visited ? "#000000" : "#ffffff") << "\" stroke=\"#000000\"/>\n";
    if (n.region == topo.current)
      os << "<circle cx=\"" << q.x + 0.5 << "\" cy=\"" << q.y + 0.5
         << "\" r=\"7\" fill=\"none\" stroke=\"#0050c8\" stroke-width=\"2\"/>\n";
    os << "<text x=\"" << q.x + 6 << "\" y=\"" << q.y - 6
       << "\" font-size=\"10\" stroke=\"#ffffff\" stroke-width=\"3\" paint-order=\"stroke\">"
       << n.region << "</text>\n";
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace render

}  // namespace asf::evaluation
