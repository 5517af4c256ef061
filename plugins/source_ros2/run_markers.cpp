// A run as rviz markers (run_markers.h).
#include "run_markers.h"

#include <asf/pose_graph.h>
#include <asf/segmentation.h>
#include <asf/topo_graph.h>

#include <cmath>

namespace asf::ros2live {

namespace {

using ros2::Marker;

Marker base(const ros2::Stamp& stamp, const std::string& frame, const char* ns, int id,
            std::int32_t type) {
  Marker m;
  m.stamp = stamp;
  m.frame_id = frame;
  m.ns = ns;
  m.id = id;
  m.type = type;
  return m;
}

// A colour per region id, spread around the hue circle (golden angle).
std::array<float, 4> regionColour(int id) {
  const double h = std::fmod(id * 137.508, 360.0) / 60.0;
  const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x; break;
  }
  return {static_cast<float>(0.2 + 0.8 * r), static_cast<float>(0.2 + 0.8 * g),
          static_cast<float>(0.2 + 0.8 * b), 1.0f};
}

std::array<double, 3> at(double x, double y, double z = 0) { return {x, y, z}; }

void addPoseGraph(const PoseGraph& g, const ros2::Stamp& s, const std::string& f,
                  std::vector<Marker>& out) {
  Marker nodes = base(s, f, "pose_graph_nodes", 0, Marker::Points);
  nodes.scale = {0.06, 0.06, 0};
  nodes.color = {0.1f, 0.1f, 0.1f, 1};
  for (const PoseNode& n : g.nodes) nodes.points.push_back(at(n.pose.x(), n.pose.y()));
  Marker edges = base(s, f, "pose_graph_edges", 0, Marker::LineList);
  edges.scale = {0.01, 0, 0};
  edges.color = {0.5f, 0.5f, 0.5f, 1};
  Marker loops = base(s, f, "loop_closures", 0, Marker::LineList);
  loops.scale = {0.02, 0, 0};
  loops.color = {0.9f, 0.1f, 0.1f, 1};
  for (const PoseEdge& e : g.edges) {
    if (e.from >= g.nodes.size() || e.to >= g.nodes.size()) continue;
    Marker& m = e.kind == EdgeKind::LoopClosure ? loops : edges;
    m.points.push_back(at(g.nodes[e.from].pose.x(), g.nodes[e.from].pose.y()));
    m.points.push_back(at(g.nodes[e.to].pose.x(), g.nodes[e.to].pose.y()));
  }
  out.push_back(std::move(nodes));
  out.push_back(std::move(edges));
  out.push_back(std::move(loops));
}

void addRegions(const Segmentation& seg, const ros2::Stamp& s, const std::string& f,
                std::vector<Marker>& out) {
  for (const Region& r : seg.regions) {
    Marker outline = base(s, f, "regions", r.id, Marker::LineStrip);
    outline.scale = {0.04, 0, 0};
    outline.color = regionColour(r.id);
    for (const Point2& p : r.outer) outline.points.push_back(at(p.x, p.y));
    if (!r.outer.empty()) outline.points.push_back(at(r.outer.front().x, r.outer.front().y));
    out.push_back(std::move(outline));
    Marker label = base(s, f, "region_labels", r.id, Marker::Text);
    label.pose.tx = r.centroid.x, label.pose.ty = r.centroid.y, label.pose.tz = 0.3;
    label.scale = {0, 0, 0.4};
    label.color = regionColour(r.id);
    label.text = std::to_string(r.id);
    out.push_back(std::move(label));
  }
}

void addTopology(const TopoGraph& t, const ros2::Stamp& s, const std::string& f,
                 std::vector<Marker>& out) {
  Marker nodes = base(s, f, "topology_nodes", 0, Marker::SphereList);
  nodes.scale = {0.3, 0.3, 0.3};
  nodes.color = {0.1f, 0.3f, 0.9f, 1};
  for (const TopoNode& n : t.nodes)
    if (n.region != kUnexplored) nodes.points.push_back(at(n.centroid.x, n.centroid.y, 0.1));
  Marker edges = base(s, f, "topology_edges", 0, Marker::LineList);
  edges.scale = {0.05, 0, 0};
  edges.color = {0.1f, 0.3f, 0.9f, 1};
  Marker frontiers = base(s, f, "frontiers", 0, Marker::Points);
  frontiers.scale = {0.2, 0.2, 0};
  frontiers.color = {1.0f, 0.6f, 0.0f, 1};
  for (const TopoEdge& e : t.edges) {
    const TopoNode* a = t.node(e.a);
    if (!a) continue;
    if (e.frontier()) {
      frontiers.points.push_back(at(e.midpoint.x, e.midpoint.y, 0.1));
      continue;
    }
    const TopoNode* b = t.node(e.b);
    if (!b) continue;
    // Through the border's middle: the way the robot passes between the two regions.
    for (const Point2* p : {&a->centroid, &e.midpoint, &e.midpoint, &b->centroid})
      edges.points.push_back(at(p->x, p->y, 0.1));
  }
  out.push_back(std::move(nodes));
  out.push_back(std::move(edges));
  out.push_back(std::move(frontiers));
}

}  // namespace

std::vector<Marker> runMarkers(const RunView& v, const ros2::Stamp& stamp, const std::string& frame) {
  std::vector<Marker> out;
  Marker clear = base(stamp, frame, "", 0, Marker::Points);
  clear.action = Marker::DeleteAll;
  out.push_back(clear);
  Marker robot = base(stamp, frame, "robot", 0, Marker::Arrow);
  robot.pose = ros2::transformFromPose(v.robot);
  robot.scale = {0.5, 0.1, 0.1};
  robot.color = {0.0f, 0.4f, 1.0f, 1};
  out.push_back(robot);
  if (v.goal) {
    Marker goal = base(stamp, frame, "goal", 0, Marker::Sphere);
    goal.pose.tx = v.goal->x, goal.pose.ty = v.goal->y;
    goal.scale = {0.3, 0.3, 0.3};
    goal.color = {0.1f, 0.8f, 0.1f, 1};
    out.push_back(goal);
  }
  if (v.graph) addPoseGraph(*v.graph, stamp, frame, out);
  if (v.segmentation) addRegions(*v.segmentation, stamp, frame, out);
  if (v.topo) addTopology(*v.topo, stamp, frame, out);
  return out;
}

}  // namespace asf::ros2live
