#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/io/image_io.h>
#include <asf/evaluation/map_views.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "region_render.h"

namespace asf::evaluation {

using render::MapImage;

namespace {

void writeBgr(const std::string& path, const cv::Mat& img) {
  io::writeBgrImage(path, img.cols, img.rows, img.ptr());
}

}  // namespace

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
    writeBgr(prefix + "regions.png", regions.img);
  }
  drawPath(m);
  for (const auto& n : graph.nodes)
    cv::circle(m.img, m.px(n.pose.x(), n.pose.y()), 2, {0, 0, 220}, -1);
  writeBgr(prefix + "map.png", m.img);
}

namespace {

/// The timeline's picture at full resolution: regions (or the grid), path, topological graph,
/// goal and robot; `graph` (optional) drawn before the robot.
MapImage renderFrame(const GridMap& map, const Segmentation& seg, const TopoGraph& topo,
                     const PoseGraph* graph, const std::vector<mrpt::poses::CPose2D>& path,
                     const mrpt::poses::CPose2D& robot, const Point2* goal) {
  MapImage m = render::renderGrid(*map.grid);
  if (!seg.labels.labels.empty()) render::drawRegions(m, seg.labels);
  for (std::size_t i = 1; i < path.size(); ++i)
    cv::line(m.img, m.px(path[i - 1].x(), path[i - 1].y()), m.px(path[i].x(), path[i].y()),
             {200, 80, 0}, 1, cv::LINE_AA);
  render::drawTopology(m, topo);
  if (graph) {
    for (const PoseEdge& e : graph->edges) {
      if (e.from >= graph->size() || e.to >= graph->size()) continue;
      const auto &a = graph->nodes[e.from].pose, &b = graph->nodes[e.to].pose;
      const bool loop = e.kind == EdgeKind::LoopClosure;
      cv::line(m.img, m.px(a.x(), a.y()), m.px(b.x(), b.y()),
               loop ? cv::Scalar(200, 0, 200) : cv::Scalar(90, 90, 90), loop ? 2 : 1, cv::LINE_AA);
    }
    for (const PoseNode& n : graph->nodes)
      cv::circle(m.img, m.px(n.pose.x(), n.pose.y()), 1, {60, 60, 60}, -1);
  }
  const int r = std::max(4, static_cast<int>(0.4 / m.res));  // large enough to see scaled down
  if (goal) cv::drawMarker(m.img, m.px(goal->x, goal->y), {0, 140, 0}, cv::MARKER_CROSS, 4 * r, 3);
  cv::circle(m.img, m.px(robot.x(), robot.y()), r, {0, 0, 220}, -1, cv::LINE_AA);
  return m;
}

void shrink(cv::Mat& img, int max_side) {
  const int side = std::max(img.cols, img.rows);
  if (max_side > 0 && side > max_side) {
    const double f = static_cast<double>(max_side) / side;
    cv::resize(img, img, cv::Size(), f, f, cv::INTER_AREA);
  }
}

}  // namespace

void writeTimelineFrame(const std::string& file, const GridMap& map, const Segmentation& seg,
                        const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
                        const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side) {
  if (!map.grid) return;
  MapImage m = renderFrame(map, seg, topo, nullptr, path, robot, goal);
  shrink(m.img, max_side);
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", m.img, png)) throw Error(file + ": cannot encode");
  writeFileAtomically(file, std::string(png.begin(), png.end()));
}

ViewImage renderLiveView(const GridMap& map, const Segmentation& seg, const TopoGraph& topo,
                         const PoseGraph& graph, const std::vector<mrpt::poses::CPose2D>& path,
                         const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side) {
  ViewImage out;
  if (!map.grid) return out;
  MapImage m = renderFrame(map, seg, topo, &graph, path, robot, goal);
  shrink(m.img, max_side);
  const cv::Mat bgr = m.img.isContinuous() ? m.img : m.img.clone();
  out.width = bgr.cols;
  out.height = bgr.rows;
  out.bgr.assign(bgr.data, bgr.data + static_cast<std::size_t>(bgr.cols) * bgr.rows * 3);
  return out;
}

void writeViewPng(const std::string& file, const ViewImage& image) {
  const cv::Mat m(image.height, image.width, CV_8UC3, const_cast<unsigned char*>(image.bgr.data()));
  std::vector<unsigned char> png;
  if (image.bgr.size() != static_cast<std::size_t>(image.width) * image.height * 3 ||
      !cv::imencode(".png", m, png))
    throw Error(file + ": cannot encode");
  writeFileAtomically(file, std::string(png.begin(), png.end()));
}

void writeGridPng(const std::string& file, const GridMap& map) {
  const MapImage m = render::renderGrid(*map.grid);
  writeBgr(file, m.img);
}

}  // namespace asf::evaluation
