// The generalized Voronoi graph of an occupancy grid (raster: clearance by exact distance
// transform, Guo-Hall thinning, corner spurs pruned) and the virtual edges it adds to a pose graph
// in a partially explored map (thesis section 3.6).
#include <asf/errors.h>
#include <asf/planning/voronoi_graph.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>
#include <queue>
#include <set>
#include <string>
#include <tuple>

namespace asf::planning {

namespace {

// The 8-neighbourhood in ring order (E, NE, N, NW, W, SW, S, SE), rows growing with the
// index: even entries are the 4-neighbours.
constexpr int kRingDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kRingDy[8] = {0, -1, -1, -1, 0, 1, 1, 1};

struct Ring {
  int offset[8];
  explicit Ring(int w) {
    for (int k = 0; k < 8; ++k) offset[k] = kRingDy[k] * w + kRingDx[k];
  }
};

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

std::size_t Gvg::junctions() const {
  return static_cast<std::size_t>(std::count_if(vertices.begin(), vertices.end(),
                                                [](const Vertex& v) { return v.degree >= 3; }));
}
std::size_t Gvg::ends() const {
  return static_cast<std::size_t>(std::count_if(vertices.begin(), vertices.end(),
                                                [](const Vertex& v) { return v.degree == 1; }));
}
Eigen::Vector2d Gvg::cellCentre(int index) const {
  return {origin_x + (index % width + 0.5) * resolution,
          origin_y + (index / width + 0.5) * resolution};
}

namespace {

/// Padded working raster: cell (cx, cy) of the grid is (cx + 1, cy + 1) here.
struct Work {
  int W = 0, H = 0;                ///< padded size
  std::vector<std::uint8_t> free;  ///< p(free) > threshold
  std::vector<std::uint8_t> skel;
  int padded(int grid_index, int grid_w) const {
    return (grid_index / grid_w + 1) * W + grid_index % grid_w + 1;
  }
  int unpadded(int i, int grid_w) const { return (i / W - 1) * grid_w + i % W - 1; }
};

/// Kept end points also grow the medial axis' branches into convex corners of the free
/// space (a room's corners, the two corners closing a dead-end corridor). Such a branch ends
/// inside the junction's own clearance disc: a dead-end branch whose end lies within
/// kSpurRatio x the junction's clearance of the junction is removed (repeatedly, as removing
/// one may turn a junction into part of another branch). A real dead-end corridor reaches
/// farther than that.
constexpr double kSpurRatio = 1.5;

void pruneCornerSpurs(std::vector<std::uint8_t>& s, const std::vector<float>& D, int W, int H) {
  const Ring ring(W);
  const int N = W * H;
  auto degree = [&](int i) {
    int n = 0;
    for (int k = 0; k < 8; ++k) n += s[i + ring.offset[k]];
    return n;
  };
  for (int round = 0; round < 1000; ++round) {
    bool changed = false;
    for (int e = 0; e < N; ++e) {
      if (!s[e] || degree(e) != 1) continue;
      std::vector<int> branch{e};
      int prev = -1, cur = e, junction = -1;
      while (junction < 0) {
        int next = -1;
        for (int k = 0; k < 8 && next < 0; ++k) {
          const int j = cur + ring.offset[k];
          if (s[j] && j != prev) next = j;
        }
        if (next < 0) break;  // an isolated segment: the whole component
        const int d = degree(next);
        if (d >= 3) {
          junction = next;
          break;
        }
        if (d != 2) break;
        branch.push_back(next);
        prev = cur;
        cur = next;
      }
      if (junction < 0) continue;
      const double dx = e % W - junction % W, dy = e / W - junction / W;
      if (std::hypot(dx, dy) <= kSpurRatio * D[junction]) {
        for (int c : branch) s[c] = 0;
        changed = true;
      }
    }
    if (!changed) break;
  }
  (void)H;
}

/// The free cells and the pruned medial axis of the cells farther than the clearance from
/// every non-free cell centre, on the padded raster.
void skeletonCells(const mrpt::maps::COccupancyGridMap2D& grid, const GvgOptions& o, const Gvg& out,
                   Work& w) {
  const int N = w.W * w.H;
  w.free.assign(N, 0);
  cv::Mat free255(w.H, w.W, CV_8U, cv::Scalar(0));
  for (int cy = 0; cy < out.height; ++cy)
    for (int cx = 0; cx < out.width; ++cx)
      if (grid.getCell(cx, cy) > o.free_threshold) {
        const int i = (cy + 1) * w.W + cx + 1;
        w.free[i] = 1;
        free255.data[i] = 255;
      }
  cv::Mat d0;
  cv::distanceTransform(free255, d0, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  // Traversable: farther than the clearance from every non-free cell centre.
  const double limit = o.clearance / out.resolution;
  cv::Mat core(w.H, w.W, CV_8U, cv::Scalar(0));
  for (int i = 0; i < N; ++i)
    if (w.free[i] && d0.ptr<float>()[i] > limit) core.data[i] = 255;
  cv::Mat d1;
  cv::distanceTransform(core, d1, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  std::vector<float> clearance(d1.ptr<float>(), d1.ptr<float>() + N);
  cv::Mat thin;
  cv::ximgproc::thinning(core, thin, cv::ximgproc::THINNING_GUOHALL);
  w.skel.assign(N, 0);
  for (int i = 0; i < N; ++i) w.skel[i] = thin.data[i] ? 1 : 0;
  pruneCornerSpurs(w.skel, clearance, w.W, w.H);
}

/// The readable graph's vertices: 8-connected clusters of skeleton cells of degree != 2.
/// Returns each padded cell's vertex (-1: none); fills the skeleton image and its count.
std::vector<int> clusterVertices(const Work& w, const Ring& ring, Gvg& out) {
  const int N = w.W * w.H;
  out.skeleton.assign(static_cast<std::size_t>(out.width) * out.height, 0);
  std::vector<int> deg(N, 0), vertex(N, -1);
  for (int i = 0; i < N; ++i) {
    if (!w.skel[i]) continue;
    out.skeleton[w.unpadded(i, out.width)] = 1;
    ++out.skeleton_cells;
    for (int k = 0; k < 8; ++k) deg[i] += w.skel[i + ring.offset[k]];
  }
  for (int i = 0; i < N; ++i) {
    if (!w.skel[i] || deg[i] == 2 || vertex[i] >= 0) continue;
    const int id = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back();
    std::vector<int> stack{i};
    vertex[i] = id;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      out.vertices[id].cells.push_back(w.unpadded(c, out.width));
      for (int k = 0; k < 8; ++k) {
        const int j = c + ring.offset[k];
        if (w.skel[j] && deg[j] != 2 && vertex[j] < 0) {
          vertex[j] = id;
          stack.push_back(j);
        }
      }
    }
    std::sort(out.vertices[id].cells.begin(), out.vertices[id].cells.end());
  }
  return vertex;
}

void addSkeletonEdge(const Work& w, Gvg& out, int va, const std::vector<int>& cells, int vb) {
  Gvg::Edge e;
  e.a = va;
  e.b = vb;
  for (std::size_t t = 1; t < cells.size(); ++t) {
    const int a = cells[t - 1], b = cells[t];
    e.length +=
        (a - b == 1 || b - a == 1 || a - b == w.W || b - a == w.W ? 1.0 : M_SQRT2) * out.resolution;
  }
  // A two-cell detour around a junction's own cells is thinning residue, not a loop.
  if (va == vb && cells.size() < 5) return;
  for (int c : cells) e.cells.push_back(w.unpadded(c, out.width));
  ++out.vertices[va].degree;
  ++out.vertices[vb].degree;
  out.edges.push_back(std::move(e));
}

/// The edges: chains of degree-2 cells from a vertex to a vertex (`visited` marks their
/// cells).
void traceEdges(const Work& w, const Ring& ring, const std::vector<int>& vertex,
                std::vector<std::uint8_t>& visited, Gvg& out) {
  const int N = w.W * w.H;
  for (int i = 0; i < N; ++i) {
    if (!w.skel[i] || vertex[i] < 0) continue;
    for (int k = 0; k < 8; ++k) {
      const int q = i + ring.offset[k];
      if (!w.skel[q] || vertex[q] >= 0 || visited[q]) continue;
      std::vector<int> cells{i, q};
      visited[q] = 1;
      int prev = i, cur = q, end = -1;
      while (end < 0) {
        int next = -1;
        for (int kk = 0; kk < 8 && next < 0; ++kk) {
          const int j = cur + ring.offset[kk];
          if (w.skel[j] && j != prev && !(vertex[j] >= 0 && cells.size() == 2 && j == i) &&
              (vertex[j] >= 0 || !visited[j]))
            next = j;
        }
        if (next < 0) break;  // cannot happen on a thin skeleton; dropped
        cells.push_back(next);
        if (vertex[next] >= 0) {
          end = next;
        } else {
          visited[next] = 1;
          prev = cur;
          cur = next;
        }
      }
      if (end >= 0) addSkeletonEdge(w, out, vertex[i], cells, vertex[end]);
    }
  }
}

/// Closed loops without any vertex: one vertex on the loop (its smallest cell).
void closeLoops(const Work& w, const Ring& ring, std::vector<int>& vertex,
                std::vector<std::uint8_t>& visited, Gvg& out) {
  const int N = w.W * w.H;
  for (int i = 0; i < N; ++i) {
    if (!w.skel[i] || vertex[i] >= 0 || visited[i]) continue;
    const int id = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back();
    out.vertices[id].cells = {w.unpadded(i, out.width)};
    vertex[i] = id;
    std::vector<int> cells{i};
    int prev = -1, cur = i;
    while (true) {
      int next = -1;
      for (int k = 0; k < 8 && next < 0; ++k) {
        const int j = cur + ring.offset[k];
        if (w.skel[j] && j != prev && !visited[j] && (j != i || cells.size() > 2)) next = j;
      }
      if (next < 0) break;
      cells.push_back(next);
      if (next == i) break;
      visited[next] = 1;
      prev = cur;
      cur = next;
    }
    visited[i] = 1;
    if (cells.size() > 2 && cells.back() == i) addSkeletonEdge(w, out, id, cells, id);
  }
}

Work skeletonOf(const GridMap& map, const GvgOptions& o, Gvg& out) {
  if (!map.grid) throw Error("GVG: the map has no grid");
  if (!(o.free_threshold >= 0 && o.free_threshold < 1))
    throw Error("GVG: free_threshold must be in [0, 1)");
  if (!(o.clearance >= 0)) throw Error("GVG: clearance must be >= 0");
  const auto& grid = *map.grid;
  out.width = static_cast<int>(grid.getSizeX());
  out.height = static_cast<int>(grid.getSizeY());
  out.resolution = grid.getResolution();
  out.origin_x = grid.getXMin();
  out.origin_y = grid.getYMin();
  Work w;
  w.W = out.width + 2;
  w.H = out.height + 2;
  skeletonCells(grid, o, out, w);
  const Ring ring(w.W);
  std::vector<int> vertex = clusterVertices(w, ring, out);
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(w.W) * w.H, 0);
  traceEdges(w, ring, vertex, visited, out);
  closeLoops(w, ring, vertex, visited, out);
  for (auto& v : out.vertices) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int cell : v.cells) c += out.cellCentre(cell);
    v.position = c / static_cast<double>(v.cells.size());
  }
  return w;
}

Eigen::Matrix3d rot3(double phi) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const double c = std::cos(phi), s = std::sin(phi);
  R.topLeftCorner<2, 2>() << c, -s, s, c;
  return R;
}

/// Covariance of driving `length` from `from` to `to` (see VirtualEdge), in from's frame.
Eigen::Matrix3d driveCovariance(const mrpt::poses::CPose2D& from, const mrpt::poses::CPose2D& to,
                                double length, const VirtualEdgeOptions& o) {
  mrpt::poses::CPose2D d = to - from;
  d.normalizePhi();
  const double bearing = std::hypot(d.x(), d.y()) > 1e-9 ? std::atan2(d.y(), d.x()) : 0.0;
  Eigen::Matrix3d c;
  if (o.odometry_step > 0 && length > o.odometry_step) {
    // Equal increments, each with the model's covariance, composed (first order).
    const double n = std::ceil(length / o.odometry_step);
    const mrpt::poses::CPose2D inc(length / n, 0, d.phi() / n);
    const Eigen::Matrix3d ci = o.odometry.covariance(inc);
    mrpt::poses::CPose2D acc;
    Eigen::Matrix3d acc_cov = Eigen::Matrix3d::Zero();
    for (int k = 0; k < static_cast<int>(n); ++k) {
      Eigen::Matrix3d next;
      acc = composeWithCov(acc, acc_cov, inc, ci, next);
      acc_cov = next;
    }
    c = o.covariance_scale * acc_cov;
  } else {
    c = o.covariance_scale * o.odometry.covariance(mrpt::poses::CPose2D(length, 0, d.phi()));
  }
  const Eigen::Matrix3d R = rot3(bearing);
  Eigen::Matrix3d r = R * c * R.transpose();
  return 0.5 * (r + r.transpose());
}

double stepLength(int k, double res) { return (k % 2 ? M_SQRT2 : 1.0) * res; }

/// Attaches each node to the skeleton: a geodesic search through free cells from the node's
/// cell, up to attach_radius (attach_cell, attach_distance, attached).
void attachNodes(const PoseGraph& g, const Work& w, const Ring& ring, double attach_radius,
                 VirtualEdges& out) {
  const Gvg& gvg = out.gvg;
  const double res = gvg.resolution;
  const std::size_t n = g.size();
  out.attach_cell.assign(n, -1);
  out.attach_distance.assign(n, kInf);
  std::vector<double> dist(static_cast<std::size_t>(w.W) * w.H, kInf);
  std::vector<int> touched;
  using Item = std::pair<double, int>;
  for (std::size_t v = 0; v < n; ++v) {
    const auto& p = g.nodes[v].pose;
    const double fx = (p.x() - gvg.origin_x) / res, fy = (p.y() - gvg.origin_y) / res;
    if (!(fx >= 0 && fy >= 0 && fx < gvg.width && fy < gvg.height)) continue;
    const int src = (static_cast<int>(fy) + 1) * w.W + static_cast<int>(fx) + 1;
    for (int c : touched) dist[c] = kInf;
    touched.clear();
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    dist[src] = 0;
    touched.push_back(src);
    open.emplace(0.0, src);
    while (!open.empty()) {
      const auto [d, c] = open.top();
      open.pop();
      if (d > dist[c]) continue;
      if (w.skel[c]) {
        out.attach_cell[v] = w.unpadded(c, gvg.width);
        out.attach_distance[v] = d;
        ++out.attached;
        break;
      }
      for (int k = 0; k < 8; ++k) {
        const int j = c + ring.offset[k];
        if (!w.free[j]) continue;  // the node's own cell may be non-free; the rest may not
        if (k % 2) {               // no diagonal squeeze between two non-free cells
          const int a = c + ring.offset[k - 1], b = c + ring.offset[(k + 1) % 8];
          if (!w.free[a] && !w.free[b]) continue;
        }
        const double nd = d + stepLength(k, res);
        if (nd > attach_radius + 1e-9 || nd >= dist[j]) continue;
        if (dist[j] == kInf) touched.push_back(j);
        dist[j] = nd;
        open.emplace(nd, j);
      }
    }
  }
}

/// Candidate pairs of attached nodes and their length along the skeleton: nodes sharing an
/// attach cell (a port; its representative is the node with the shortest leg, then the
/// smallest id), and ports whose regions along the skeleton touch.
std::map<std::pair<NodeId, NodeId>, double> skeletonPairs(const Work& w, const Ring& ring,
                                                          const VirtualEdges& out) {
  const Gvg& gvg = out.gvg;
  const double res = gvg.resolution;
  const int N = w.W * w.H;
  std::map<int, std::vector<NodeId>> port_nodes;  // padded cell -> nodes
  for (std::size_t v = 0; v < out.attach_cell.size(); ++v)
    if (out.attach_cell[v] >= 0)
      port_nodes[w.padded(out.attach_cell[v], gvg.width)].push_back(static_cast<NodeId>(v));
  std::vector<int> port_cell;
  std::vector<NodeId> rep;
  std::map<std::pair<NodeId, NodeId>, double> skel_len;
  for (const auto& [cell, nodes] : port_nodes) {
    NodeId r = nodes[0];
    for (NodeId v : nodes)
      if (out.attach_distance[v] < out.attach_distance[r]) r = v;
    port_cell.push_back(cell);
    rep.push_back(r);
    for (NodeId v : nodes)
      if (v != r) skel_len[{std::min(v, r), std::max(v, r)}] = 0;
  }
  // Regions of the ports along the skeleton; ports whose regions touch are joined.
  std::vector<double> sd(N, kInf);
  std::vector<int> owner(N, -1);
  std::priority_queue<std::tuple<double, int, int>, std::vector<std::tuple<double, int, int>>,
                      std::greater<>>
      open;
  for (std::size_t p = 0; p < port_cell.size(); ++p) {
    sd[port_cell[p]] = 0;
    owner[port_cell[p]] = static_cast<int>(p);
    open.emplace(0.0, static_cast<int>(p), port_cell[p]);
  }
  while (!open.empty()) {
    const auto [d, p, c] = open.top();
    open.pop();
    if (d > sd[c] || owner[c] != p) continue;
    for (int k = 0; k < 8; ++k) {
      const int j = c + ring.offset[k];
      if (!w.skel[j]) continue;
      const double nd = d + stepLength(k, res);
      if (nd < sd[j] || (nd == sd[j] && p < owner[j])) {
        sd[j] = nd;
        owner[j] = p;
        open.emplace(nd, p, j);
      }
    }
  }
  for (int c = 0; c < N; ++c) {
    if (!w.skel[c] || owner[c] < 0) continue;
    for (int k = 0; k < 4; ++k) {  // each adjacency once
      const int j = c + ring.offset[k];
      if (!w.skel[j] || owner[j] < 0 || owner[j] == owner[c]) continue;
      const NodeId a = rep[owner[c]], b = rep[owner[j]];
      const std::pair<NodeId, NodeId> key{std::min(a, b), std::max(a, b)};
      const double len = sd[c] + stepLength(k, res) + sd[j];
      auto it = skel_len.find(key);
      if (it == skel_len.end())
        skel_len.emplace(key, len);
      else
        it->second = std::min(it->second, len);
    }
  }
  return skel_len;
}

/// The pose graph's own connections: direct edges, and a Dijkstra (metres between node
/// positions) bounded by a length.
class GraphDistance {
 public:
  explicit GraphDistance(const PoseGraph& g) : g_(g), adj_(g.size()), gd_(g.size(), kInf) {
    const std::size_t n = g.size();
    for (const auto& e : g.edges) {
      if (e.from == e.to || e.from >= n || e.to >= n) continue;
      adj_[e.from].push_back(e.to);
      adj_[e.to].push_back(e.from);
      direct_.insert({std::min(e.from, e.to), std::max(e.from, e.to)});
    }
  }
  bool direct(const std::pair<NodeId, NodeId>& key) const { return direct_.count(key) > 0; }
  /// True if b is within `bound` metres of a through the graph.
  bool within(NodeId a, NodeId b, double bound) {
    for (NodeId v : touched_) gd_[v] = kInf;
    touched_.clear();
    std::priority_queue<std::pair<double, NodeId>, std::vector<std::pair<double, NodeId>>,
                        std::greater<>>
        open;
    gd_[a] = 0;
    touched_.push_back(a);
    open.emplace(0.0, a);
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > gd_[v]) continue;
      if (v == b) return true;
      for (NodeId u : adj_[v]) {
        const double nd = d + planar(v, u);
        if (nd > bound || nd >= gd_[u]) continue;
        if (gd_[u] == kInf) touched_.push_back(u);
        gd_[u] = nd;
        open.emplace(nd, u);
      }
    }
    return false;
  }

 private:
  double planar(NodeId a, NodeId b) const {
    return std::hypot(g_.nodes[a].pose.x() - g_.nodes[b].pose.x(),
                      g_.nodes[a].pose.y() - g_.nodes[b].pose.y());
  }
  const PoseGraph& g_;
  std::vector<std::vector<NodeId>> adj_;
  std::set<std::pair<NodeId, NodeId>> direct_;
  std::vector<double> gd_;
  std::vector<NodeId> touched_;
};

}  // namespace

Gvg computeGvg(const GridMap& map, const GvgOptions& o) {
  Gvg out;
  skeletonOf(map, o, out);
  return out;
}

VirtualEdges computeVirtualEdges(const PoseGraph& g, const GridMap& map,
                                 const VirtualEdgeOptions& o) {
  if (!(o.attach_radius >= 0)) throw Error("virtual edges: attach_radius must be >= 0");
  if (!(o.detour >= 1)) throw Error("virtual edges: detour must be >= 1");
  if (!(o.covariance_scale > 0)) throw Error("virtual edges: covariance_scale must be > 0");
  if (!(o.odometry_step >= 0)) throw Error("virtual edges: odometry_step must be >= 0");
  VirtualEdges out;
  const Work w = skeletonOf(map, o.gvg, out.gvg);
  const Ring ring(w.W);
  attachNodes(g, w, ring, o.attach_radius, out);
  const auto skel_len = skeletonPairs(w, ring, out);
  out.candidates = skel_len.size();
  // A pair the pose graph already joins directly, or within `detour` times the virtual
  // edge's length, needs no virtual edge.
  GraphDistance graph(g);
  for (const auto& [key, sl] : skel_len) {
    const auto [a, b] = key;
    if (graph.direct(key)) continue;
    VirtualEdge e;
    e.a = a;
    e.b = b;
    e.skeleton_length = sl;
    e.length = out.attach_distance[a] + sl + out.attach_distance[b];
    if (graph.within(a, b, o.detour * e.length + 1e-9)) continue;
    e.covariance_ab = driveCovariance(g.nodes[a].pose, g.nodes[b].pose, e.length, o);
    e.covariance_ba = driveCovariance(g.nodes[b].pose, g.nodes[a].pose, e.length, o);
    out.edges.push_back(e);
  }
  return out;
}

}  // namespace asf::planning
