#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/map_views.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "region_render.h"

namespace asf {

using render::MapImage;

void writeMapViews(const std::string& prefix, const PoseGraph& graph, const GridMap& map,
                   const Segmentation& seg, const TopoGraph& topo,
                   const std::vector<mrpt::poses::CPose2D>& path) {
  if (!map.grid) return;
  MapImage m = render::renderGrid(*map.grid);
  auto drawPath = [&](MapImage& img) {
    for (std::size_t i = 1; i < path.size(); ++i)
      cv::line(img.img, img.px(path[i - 1].x(), path[i - 1].y()), img.px(path[i].x(), path[i].y()),
               {200, 80, 0}, 1, cv::LINE_AA);
  };
  if (!seg.labels.labels.empty()) {
    MapImage regions{m.img.clone(), m.x0, m.y0, m.res};
    render::drawRegions(regions, seg.labels);
    // topology.svg: the regions as the background, graph and trajectory as vectors.
    std::vector<Point2> pts;
    pts.reserve(path.size());
    for (const auto& p : path) pts.push_back({p.x(), p.y()});
    writeFileAtomically(prefix + "topology.svg",
                        render::topologySvg(regions, regions.img, topo, pts));
    drawPath(regions);
    render::drawTopology(regions, topo);
    if (!cv::imwrite(prefix + "regions.png", regions.img))
      throw Error(prefix + "regions.png: cannot write");
  }
  drawPath(m);
  for (const auto& n : graph.nodes)
    cv::circle(m.img, m.px(n.pose.x(), n.pose.y()), 2, {0, 0, 220}, -1);
  if (!cv::imwrite(prefix + "map.png", m.img)) throw Error(prefix + "map.png: cannot write");
}

void writeTimelineFrame(const std::string& file, const GridMap& map, const Segmentation& seg,
                        const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                        const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side) {
  if (!map.grid) return;
  MapImage m = render::renderGrid(*map.grid);
  if (!seg.labels.labels.empty()) render::drawRegions(m, seg.labels);
  for (std::size_t i = 1; i < path.size(); ++i)
    cv::line(m.img, m.px(path[i - 1].x(), path[i - 1].y()), m.px(path[i].x(), path[i].y()),
             {200, 80, 0}, 1, cv::LINE_AA);
  render::drawTopology(m, topo);
  const int r = std::max(4, static_cast<int>(0.4 / m.res));  // large enough to see scaled down
  if (goal) cv::drawMarker(m.img, m.px(goal->x, goal->y), {0, 140, 0}, cv::MARKER_CROSS, 4 * r, 3);
  cv::circle(m.img, m.px(robot.x(), robot.y()), r, {0, 0, 220}, -1, cv::LINE_AA);
  const int side = std::max(m.img.cols, m.img.rows);
  if (max_side > 0 && side > max_side) {
    const double f = static_cast<double>(max_side) / side;
    cv::resize(m.img, m.img, cv::Size(), f, f, cv::INTER_AREA);
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", m.img, png)) throw Error(file + ": cannot encode");
  writeFileAtomically(file, std::string(png.begin(), png.end()));
}

void writeGridPng(const std::string& file, const GridMap& map) {
  const MapImage m = render::renderGrid(*map.grid);
  if (!cv::imwrite(file, m.img)) throw Error("cannot write");
}

}  // namespace asf
