// Expected-uncertainty planning (thesis chapter 3): the best path by a criterion (planBest),
// the planner plugins' shared class and the plan drawing.
#include <asf/errors.h>
#include <asf/planning/expected_uncertainty.h>
#include <asf/params.h>
#include <asf/planning/place_recognition.h>
#include <asf/io/image_io.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <queue>
#include <set>
#include <sstream>
#include <unordered_map>

#include "path_index.h"

namespace asf::planning {

using Mat3 = Eigen::Matrix3d;
using mrpt::poses::CPose2D;
using namespace detail;

// ---------------------------------------------------------------------------------------

namespace {

struct Scored {
  double cost, distance;
  std::size_t index;
  std::string label;
};

/// Why a request cannot be planned under criterion c; empty when it can.
std::string requestProblem(const PlanRequest& req, Criterion c) {
  if (!req.graph) return "no pose graph given";
  const PoseGraph& g = *req.graph;
  if (req.start >= g.size() || req.goal >= g.size())
    return "node " + std::to_string(req.start >= g.size() ? req.start : req.goal) +
           " does not exist (the graph has " + std::to_string(g.size()) + " nodes)";
  if (c != Criterion::Distance && (!req.marginals || req.marginals->node.size() != g.size()))
    return std::string(criterionName(c)) +
           " needs the node marginal covariances (none given, or not one per node)";
  return "";
}

/// The cheapest; costs within tie_tolerance (relative) of it are equally good, and the
/// shortest of those (metres, then fewer nodes, then the first found) is chosen.
const Scored& pickBest(const std::vector<Scored>& scored,
                       const std::vector<std::vector<NodeId>>& paths, double tie_tolerance) {
  double best = scored[0].cost;
  for (const auto& sc : scored) best = std::min(best, sc.cost);
  const double limit = best + tie_tolerance * std::abs(best);
  const Scored* pick = nullptr;
  for (const auto& sc : scored) {
    if (!(sc.cost <= limit)) continue;
    const auto& p = paths[sc.index];
    if (!pick || sc.distance < pick->distance ||
        (sc.distance == pick->distance && p.size() < paths[pick->index].size()))
      pick = &sc;
  }
  return *pick;
}

/// What limited the search or the evaluation, for the planner's warning.
std::string searchNote(const PathSearchResult& paths, const PathSearchOptions& search,
                       bool out_of_time, std::size_t evaluated, std::size_t missing) {
  std::string note;
  if (paths.timed_out)
    note += "path search stopped by the time budget (" + std::to_string(search.max_seconds) +
            " s) after " + std::to_string(paths.paths.size()) + " paths; the best may be missing. ";
  else if (paths.capped)
    note += "path search capped at " + std::to_string(search.max_paths) +
            " paths (reduced graph: " + std::to_string(paths.reduced_nodes) + " vertices, " +
            std::to_string(paths.reduced_edges) + " edges); the best may be missing. ";
  else if (paths.fell_back)
    note += "enumeration given up past " + std::to_string(search.max_paths) + " simple routes or " +
            std::to_string(std::max<std::size_t>(64 * search.max_paths, 4096)) +
            " expansions (reduced graph: " + std::to_string(paths.reduced_nodes) + " vertices, " +
            std::to_string(paths.reduced_edges) + " edges): Yen's " +
            std::to_string(search.k_paths) + " shortest routes (and " +
            std::to_string(paths.diverse_added) + " of the penalty method) evaluated instead. ";
  if (out_of_time)
    note += "time budget of " + std::to_string(search.max_seconds) + " s spent after " +
            std::to_string(evaluated) + " of " + std::to_string(paths.paths.size()) +
            " candidate paths; the best may be missing. ";
  if (missing)
    note += std::to_string(missing) +
            " relocalization queries lacked a cross-covariance block (treated as zero).";
  return note;
}

}  // namespace

PlanResult planBest(const PlanRequest& req, Criterion c, const CriterionOptions& o,
                    const PathSearchOptions& search, std::string* note) {
  PlanResult res;
  res.criterion = criterionName(c);
  res.reason = requestProblem(req, c);
  if (!res.reason.empty()) return res;
  const PoseGraph& g = *req.graph;
  const bool needs_marginals = c != Criterion::Distance;
  // Partially explored maps: the virtual edges of the map's GVG.
  std::vector<VirtualEdge> virtual_edges;
  std::string voronoi_note;
  if (search.voronoi_edges) {
    if (req.map && req.map->grid) {
      // How many were found is not a warning: `asf plan --json` reports it (virtual_edges).
      virtual_edges = computeVirtualEdges(g, *req.map, search.voronoi).edges;
    } else {
      voronoi_note = "voronoi_edges: the request has no map; pose-graph edges only. ";
    }
  }
  const PathSearchResult paths = searchPaths(g, req.start, req.goal, search, &virtual_edges);
  if (paths.paths.empty()) {
    res.reason = "node " + std::to_string(req.goal) + " is not connected to node " +
                 std::to_string(req.start);
    return res;
  }
  const EdgeIndex index(g);
  const VirtualIndex vindex(&virtual_edges);
  // Thesis eq. 3.25: with virtual edges, expected uncertainty weighs E[C] by the distance.
  const bool by_distance = search.voronoi_edges && c == Criterion::ExpectedUncertainty;
  std::size_t missing = 0, evaluated = 0;
  const auto t0 = std::chrono::steady_clock::now();
  bool out_of_time = false;
  std::vector<Scored> scored;
  for (std::size_t i = 0; i < paths.paths.size(); ++i) {
    const auto& p = paths.paths[i];
    if (search.max_seconds > 0 && evaluated > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
            search.max_seconds) {
      out_of_time = true;
      break;
    }
    ++evaluated;
    const PathModel model =
        makePathModel(g, index, needs_marginals ? req.marginals : nullptr, p, &vindex);
    PathCost pc = evaluatePath(c, model, o);
    missing += pc.missing_cross;
    const double distance = pathLength(model);
    if (by_distance) {
      pc.cost *= distance;
      pc.label = "distance*" + pc.label;
    }
    scored.push_back({pc.cost, distance, i, pc.label});
  }
  if (!scored.empty()) {
    const Scored& pick = pickBest(scored, paths.paths, o.tie_tolerance);
    res.found = true;
    res.cost = pick.cost;
    res.nodes = paths.paths[pick.index];
    res.criterion = pick.label;
  }
  if (note) *note = voronoi_note + searchNote(paths, search, out_of_time, evaluated, missing);
  return res;
}

// ---------------------------------------------------------------------------------------

void renderPlan(const std::string& png, const PoseGraph& g, const Marginals* marginals,
                const std::vector<NodeId>& path, const RenderOptions& o) {
  cv::Mat img;
  std::function<cv::Point(double, double)> px;
  double px_per_m = 1;
  if (!o.map_png.empty()) {
    io::GrayImage gray = io::readGrayImage(o.map_png);  // formats checked, errors name the file
    const cv::Mat map(gray.height, gray.width, CV_8U, gray.pixels.data());
    cv::cvtColor(map, img, cv::COLOR_GRAY2BGR);
    px_per_m = 1.0 / o.map_resolution;
    const int h = img.rows;
    const double ox = o.map_origin_x, oy = o.map_origin_y;
    px = [=](double x, double y) {
      return cv::Point(static_cast<int>(std::lround((x - ox) * px_per_m)),
                       static_cast<int>(std::lround(h - (y - oy) * px_per_m)));
    };
  } else {
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (!g.empty()) {
      x0 = x1 = g.nodes[0].pose.x();
      y0 = y1 = g.nodes[0].pose.y();
      for (const auto& v : g.nodes) {
        x0 = std::min(x0, v.pose.x()), x1 = std::max(x1, v.pose.x());
        y0 = std::min(y0, v.pose.y()), y1 = std::max(y1, v.pose.y());
      }
    }
    const double span = std::max({x1 - x0, y1 - y0, 1e-3});
    const int margin = 30;
    px_per_m = (o.max_size - 2 * margin) / span;
    const int w = static_cast<int>((x1 - x0) * px_per_m) + 2 * margin;
    const int h = static_cast<int>((y1 - y0) * px_per_m) + 2 * margin;
    img = cv::Mat(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
    px = [=](double x, double y) {
      return cv::Point(static_cast<int>(std::lround(margin + (x - x0) * px_per_m)),
                       static_cast<int>(std::lround(h - margin - (y - y0) * px_per_m)));
    };
  }
  auto at = [&](NodeId v) { return px(g.nodes[v].pose.x(), g.nodes[v].pose.y()); };
  for (const auto& e : g.edges) {
    if (e.from >= g.size() || e.to >= g.size()) continue;
    const cv::Scalar colour =
        e.kind == EdgeKind::LoopClosure ? cv::Scalar(120, 200, 120) : cv::Scalar(160, 160, 160);
    cv::line(img, at(e.from), at(e.to), colour, 1, cv::LINE_AA);
  }
  if (o.ellipses && marginals && marginals->node.size() == g.size()) {
    for (std::size_t v = 0; v < g.size(); ++v) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(marginals->node[v].topLeftCorner<2, 2>());
      const Eigen::Vector2d ev = es.eigenvalues().cwiseMax(0.0);
      const Eigen::Vector2d major = es.eigenvectors().col(1);
      // 3-sigma axes; image y points down, hence the negated angle.
      const double angle = -std::atan2(major.y(), major.x()) * 180.0 / M_PI;
      const cv::Size axes(static_cast<int>(3 * std::sqrt(ev(1)) * px_per_m) + 1,
                          static_cast<int>(3 * std::sqrt(ev(0)) * px_per_m) + 1);
      cv::ellipse(img, at(static_cast<NodeId>(v)), axes, angle, 0, 360, cv::Scalar(230, 180, 120),
                  1, cv::LINE_AA);
    }
  }
  for (std::size_t v = 0; v < g.size(); ++v)
    cv::circle(img, at(static_cast<NodeId>(v)), 2, cv::Scalar(90, 90, 90), cv::FILLED);
  for (std::size_t t = 1; t < path.size(); ++t)
    if (path[t] < g.size() && path[t - 1] < g.size())
      cv::line(img, at(path[t - 1]), at(path[t]), cv::Scalar(0, 0, 220), 3, cv::LINE_AA);
  if (!path.empty() && path.front() < g.size() && path.back() < g.size()) {
    cv::circle(img, at(path.front()), 7, cv::Scalar(0, 170, 0), cv::FILLED);
    cv::circle(img, at(path.back()), 7, cv::Scalar(200, 60, 0), cv::FILLED);
  }
  bool ok = false;
  try {
    ok = cv::imwrite(png, img);
  } catch (const cv::Exception& e) {
    throw Error(png + ": cannot write the image: " + e.what());
  }
  if (!ok) throw Error(png + ": cannot write the image");
}

void CriterionPlanner::configure(const Params& params, const PluginContext& ctx) {
  options_ = criterionOptionsFrom(params, ctx.seed);
  search_ = pathSearchOptionsFrom(params);
}

PathSearchOptions pathSearchOptionsFrom(const Params& params) {
  PathSearchOptions o;
  if (params.has("search")) {
    const std::string m = params.getString("search");
    bool ok = false;
    for (SearchMethod v : {SearchMethod::Auto, SearchMethod::All, SearchMethod::Yen})
      if (m == searchMethodName(v)) {
        o.method = v;
        ok = true;
      }
    if (!ok) params.fail("search", "expected auto, all or yen");
  }
  if (params.has("max_paths")) o.max_paths = static_cast<std::size_t>(params.getInt("max_paths"));
  if (params.has("k_paths")) o.k_paths = static_cast<std::size_t>(params.getInt("k_paths"));
  if (params.has("diverse_paths"))
    o.diverse_paths = static_cast<std::size_t>(params.getInt("diverse_paths"));
  if (params.has("diverse_penalty")) o.diverse_penalty = params.getDouble("diverse_penalty");
  if (params.has("reduce")) o.reduce = params.getBool("reduce");
  if (params.has("merge_radius")) o.merge_radius = params.getDouble("merge_radius");
  if (params.has("add_shortest")) o.add_shortest = params.getBool("add_shortest");
  if (params.has("max_seconds")) o.max_seconds = params.getDouble("max_seconds");
  if (params.has("voronoi_edges")) o.voronoi_edges = params.getBool("voronoi_edges");
  if (params.has("voronoi_free_threshold"))
    o.voronoi.gvg.free_threshold = params.getDouble("voronoi_free_threshold");
  if (params.has("voronoi_clearance"))
    o.voronoi.gvg.clearance = params.getDouble("voronoi_clearance");
  if (params.has("voronoi_attach_radius"))
    o.voronoi.attach_radius = params.getDouble("voronoi_attach_radius");
  if (params.has("voronoi_detour")) o.voronoi.detour = params.getDouble("voronoi_detour");
  if (params.has("voronoi_cov_scale"))
    o.voronoi.covariance_scale = params.getDouble("voronoi_cov_scale");
  if (params.has("voronoi_odometry_step"))
    o.voronoi.odometry_step = params.getDouble("voronoi_odometry_step");
  if (!(o.voronoi.gvg.free_threshold >= 0 && o.voronoi.gvg.free_threshold < 1))
    params.fail("voronoi_free_threshold", "expected a value in [0, 1)");
  if (!(o.voronoi.detour >= 1)) params.fail("voronoi_detour", "expected a value >= 1");
  if (!(o.voronoi.covariance_scale > 0)) params.fail("voronoi_cov_scale", "expected > 0");
  return o;
}

PlanResult CriterionPlanner::plan(const PlanRequest& req) {
  std::string note;
  PlanResult r;
  CriterionOptions options = options_;
  if (options_.recognition_samples > 0 && req.graph) {
    // Place recognition by Monte Carlo for the nodes the file does not give, once per
    // graph revision (the local maps move with the optimized poses).
    if (req.graph->revision != recognition_revision_) {
      recognition_.clear();
      recognition_revision_ = req.graph->revision;
    }
    RecognitionMcOptions mc;
    mc.samples = options_.recognition_samples;
    mc.half_x = options_.reloc.half_x;
    mc.half_y = options_.reloc.half_y;
    mc.half_phi = options_.reloc.half_phi;
    mc.map_radius = options_.recognition_map_radius;
    mc.seed = options_.reloc.seed;
    std::size_t computed = 0;
    for (const PoseNode& n : req.graph->nodes) {
      if (!n.scan || options_.reloc.p_recognition_by_node.count(n.id)) continue;
      if (!recognition_.count(n.id)) {
        recognition_[n.id] = recognitionProbability(*req.graph, n.id, mc);
        ++computed;
      }
      options.reloc.p_recognition_by_node[n.id] = recognition_[n.id];
    }
    if (computed)
      MRPT_LOG_INFO_STREAM("place recognition by Monte Carlo: " << computed << " nodes x "
                                                                << mc.samples << " ICP samples");
  }
  try {
    r = planBest(req, criterion_, options, search_, &note);
  } catch (const Error& e) {  // e.g. a marginal block of the wrong size
    r = PlanResult{};
    r.criterion = criterionName(criterion_);
    r.reason = e.what();
  }
  if (!note.empty()) MRPT_LOG_WARN_STREAM(note);
  return r;
}

}  // namespace asf::planning
