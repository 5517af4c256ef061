#include <asf/mapping/topo_builder.h>
#include <mrpt/maps/COccupancyGridMap2D.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace asf::mapping {

namespace detail {
using Key = std::pair<RegionId, RegionId>;  // (a, b), a < b, or (a, kUnexplored)

/// The cells along one border (a region pair) or frontier (a region and unknown space).
struct BorderAcc {
  int cells = 0;
  /// Region pairs: sums of (cx + nx + 1) and (cy + ny + 1) over the cell pairs, i.e. twice
  /// the border midpoint in cells (integers: stripes add up exactly in any order).
  long long twice_x = 0, twice_y = 0;
  std::vector<Point2> border;       // cells on the side of the key's first region
  std::vector<int> frontier_cells;  // frontier keys: label-image index of each border cell
};
using BorderMap = std::map<Key, BorderAcc>;

/// One stripe of label rows: its borders, and every grid lookup it made (label-image cell
/// index, whether it was unknown), which is all it read of the grid.
struct BorderStripe {
  BorderMap acc;
  std::vector<std::pair<int, char>> probes;
};

/// The borders of the last update in stripes of rows: an update recomputes a stripe only
/// when its labels (or those of the rows next to it) changed, or one of its grid lookups
/// answers differently now; then the stripes are added up in row order.
struct TopoBorderCache {
  bool valid = false;
  int width = 0, height = 0;
  double resolution = 0, origin_x = 0, origin_y = 0;
  std::vector<BorderStripe> stripes;
};

TopoBorderCacheHolder::TopoBorderCacheHolder() = default;
TopoBorderCacheHolder::~TopoBorderCacheHolder() = default;
TopoBorderCacheHolder::TopoBorderCacheHolder(const TopoBorderCacheHolder& o)
    : cache_(o.cache_ ? std::make_unique<TopoBorderCache>(*o.cache_) : nullptr) {}
TopoBorderCacheHolder& TopoBorderCacheHolder::operator=(const TopoBorderCacheHolder& o) {
  if (this != &o) cache_ = o.cache_ ? std::make_unique<TopoBorderCache>(*o.cache_) : nullptr;
  return *this;
}
TopoBorderCacheHolder::TopoBorderCacheHolder(TopoBorderCacheHolder&&) noexcept = default;
TopoBorderCacheHolder& TopoBorderCacheHolder::operator=(TopoBorderCacheHolder&&) noexcept = default;
TopoBorderCache& TopoBorderCacheHolder::get() {
  if (!cache_) cache_ = std::make_unique<TopoBorderCache>();
  return *cache_;
}
void TopoBorderCacheHolder::reset() { cache_.reset(); }

}  // namespace detail
using detail::BorderAcc;
using detail::BorderMap;
using detail::BorderStripe;
using detail::Key;
using detail::TopoBorderCache;

namespace {
const KeySpec kTopoKeys[] = {
    keyDouble("min_border_width", "0.3",
              "Two regions are joined when their shared free border is at least this wide [m]", 0.0,
              100.0),
    keyDouble("min_frontier_width", "0.5",
              "A region gets a frontier edge when it borders unknown space along a stretch of "
              "adjacent cells at least this wide [m]; shorter stretches are ignored",
              0.0, 100.0),
    keyDouble("unknown_band", "0.02",
              "A cell is unknown when its probability differs from 0.5 by less than this", 0.0,
              0.5),
};

Key edgeKey(RegionId a, RegionId b) {
  if (b == kUnexplored || a == kUnexplored) return {a == kUnexplored ? b : a, kUnexplored};
  return a < b ? Key{a, b} : Key{b, a};
}

/// Is label-image cell (cx, cy) unknown on the grid (off the grid counts as unknown; no
/// grid: never)?
struct UnknownProbe {
  const LabelImage& L;
  const mrpt::maps::COccupancyGridMap2D* grid;
  double band;
  bool operator()(int cx, int cy) const {
    if (!grid) return false;
    const double x = L.origin_x + (cx + 0.5) * L.resolution;
    const double y = L.origin_y + (cy + 0.5) * L.resolution;
    const int gx = grid->x2idx(x), gy = grid->y2idx(y);
    if (gx < 0 || gy < 0 || gx >= static_cast<int>(grid->getSizeX()) ||
        gy >= static_cast<int>(grid->getSizeY()))
      return true;  // beyond the grid: never observed
    return std::abs(grid->getCell(gx, gy) - 0.5) < band;
  }
};

/// Rows [y0, y1) of the borders between two regions and the frontiers of a region (cells
/// next to unknown or unlabelled space whose grid cell is unknown, or off the grid), from
/// the label image. A row's result depends on its own labels, those of the rows next to it
/// and the grid lookups recorded in `out.probes`.
void accumulateBorders(const LabelImage& L, const UnknownProbe& unknown, int y0, int y1,
                       BorderStripe& out) {
  auto cellX = [&](double cx) { return L.origin_x + (cx + 0.5) * L.resolution; };
  auto cellY = [&](double cy) { return L.origin_y + (cy + 0.5) * L.resolution; };
  BorderMap& acc = out.acc;
  for (int cy = y0; cy < y1; ++cy)
    for (int cx = 0; cx < L.width; ++cx) {
      const RegionId a = L.at(cx, cy);
      if (a <= 0) continue;
      bool frontier = false;
      const int nb[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
      for (const auto& d : nb) {
        const int nx = cx + d[0], ny = cy + d[1];
        const bool inside = nx >= 0 && ny >= 0 && nx < L.width && ny < L.height;
        const RegionId b = inside ? L.at(nx, ny) : 0;
        if (b > 0 && b != a && (d[0] + d[1]) > 0) {  // each pair of cells once
          const Key k = edgeKey(a, b);
          auto& s = acc[k];
          ++s.cells;
          s.twice_x += cx + nx + 1;
          s.twice_y += cy + ny + 1;
          if (k.first == a)
            s.border.push_back({cellX(cx), cellY(cy)});
          else
            s.border.push_back({cellX(nx), cellY(ny)});
        }
        if (b == 0 && !inside) frontier = true;
        if (b == 0 && inside) {
          const bool u = unknown(nx, ny);
          out.probes.emplace_back(ny * L.width + nx, u);
          frontier |= u;
        }
      }
      if (frontier) {
        auto& s = acc[edgeKey(a, kUnexplored)];
        ++s.cells;
        s.border.push_back({cellX(cx), cellY(cy)});
        s.frontier_cells.push_back(cy * L.width + cx);
      }
    }
}

constexpr int kStripeRows = 16;

/// Which stripes of the new label image `L` need recomputing: all when the cache cannot be
/// compared (first call, other image geometry); else those next to a row whose labels
/// differ from `old`, and those with a grid lookup that now answers differently (checked
/// every time: a few thousand lookups, and right even for a grid changed in place).
std::vector<char> dirtyStripes(const TopoBorderCache& c, const LabelImage& old, const LabelImage& L,
                               const UnknownProbe& unknown) {
  const int n = (L.height + kStripeRows - 1) / kStripeRows;
  const bool same_image = c.valid && c.width == L.width && c.height == L.height &&
                          c.resolution == L.resolution && c.origin_x == L.origin_x &&
                          c.origin_y == L.origin_y && old.width == L.width &&
                          old.height == L.height && static_cast<int>(c.stripes.size()) == n;
  if (!same_image) return std::vector<char>(n, 1);
  std::vector<char> dirty(n, 0);
  for (int y = 0; y < L.height; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * L.width;
    if (std::equal(L.labels.begin() + row, L.labels.begin() + row + L.width,
                   old.labels.begin() + row))
      continue;
    for (int r = std::max(y - 1, 0); r <= std::min(y + 1, L.height - 1); ++r)
      dirty[r / kStripeRows] = 1;  // its stripe and those reading it as a neighbour
  }
  for (int i = 0; i < n; ++i) {
    if (dirty[i]) continue;
    for (const auto& [cell, was] : c.stripes[i].probes)
      if (unknown(cell % L.width, cell / L.width) != static_cast<bool>(was)) {
        dirty[i] = 1;
        break;
      }
  }
  return dirty;
}

/// The borders and frontiers of label image `L` (the previous one `old`) on `map`: the stripes
/// of the cache `c` that changed are recomputed, then all are added up in row order (the same
/// as one pass over the image).
BorderMap borders(TopoBorderCache& c, const LabelImage& old, const LabelImage& L,
                  const GridMap& map, double unknown_band) {
  const UnknownProbe unknown{L, map.grid.get(), unknown_band};
  const std::vector<char> dirty = dirtyStripes(c, old, L, unknown);
  c.stripes.resize(dirty.size());
  for (std::size_t i = 0; i < dirty.size(); ++i) {
    if (!dirty[i]) continue;
    c.stripes[i] = BorderStripe{};
    const int y0 = static_cast<int>(i) * kStripeRows;
    accumulateBorders(L, unknown, y0, std::min(y0 + kStripeRows, L.height), c.stripes[i]);
  }
  c.valid = true;
  c.width = L.width;
  c.height = L.height;
  c.resolution = L.resolution;
  c.origin_x = L.origin_x;
  c.origin_y = L.origin_y;
  BorderMap acc;
  for (const BorderStripe& stripe : c.stripes)
    for (const auto& [k, s] : stripe.acc) {
      BorderAcc& t = acc[k];
      t.cells += s.cells;
      t.twice_x += s.twice_x;
      t.twice_y += s.twice_y;
      t.border.insert(t.border.end(), s.border.begin(), s.border.end());
      t.frontier_cells.insert(t.frontier_cells.end(), s.frontier_cells.begin(),
                              s.frontier_cells.end());
    }
  return acc;
}

}  // namespace

void TopoBuilder::keepWideFrontiers(std::vector<int>& cells, int width, double resolution,
                                    std::vector<Point2>& border) const {
  // A region borders unknown space "over a width" along a stretch of adjacent frontier
  // cells (8-neighbours); scattered single cells along a wall's blurred edge add up to a
  // width but are no place to explore from.
  std::unordered_map<int, int> at;  // cell index -> position in `cells`
  for (std::size_t i = 0; i < cells.size(); ++i) at.emplace(cells[i], static_cast<int>(i));
  std::vector<char> kept(cells.size(), 0), seen(cells.size(), 0);
  std::vector<int> stack, piece;
  const int min_cells = static_cast<int>(std::ceil(min_frontier_width_ / resolution - 1e-9));
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (seen[i]) continue;
    piece.clear();
    stack.assign(1, static_cast<int>(i));
    seen[i] = 1;
    while (!stack.empty()) {
      const int j = stack.back();
      stack.pop_back();
      piece.push_back(j);
      const int cx = cells[j] % width, cy = cells[j] / width;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!dx && !dy) continue;
          const int nx = cx + dx, ny = cy + dy;
          if (nx < 0 || nx >= width || ny < 0) continue;
          auto it = at.find(ny * width + nx);
          if (it == at.end() || seen[it->second]) continue;
          seen[it->second] = 1;
          stack.push_back(it->second);
        }
    }
    if (static_cast<int>(piece.size()) >= min_cells)
      for (int j : piece) kept[j] = 1;
  }
  std::vector<Point2> b;
  std::vector<int> c;
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (kept[i]) {
      b.push_back(border[i]);
      c.push_back(cells[i]);
    }
  border.swap(b);
  cells.swap(c);
}

const KeySpec* TopoBuilder::keys(std::size_t& n) {
  n = std::size(kTopoKeys);
  return kTopoKeys;
}

void TopoBuilder::configure(const Params& p) {
  min_border_width_ = p.getDouble("min_border_width");
  min_frontier_width_ = p.getDouble("min_frontier_width");
  unknown_band_ = p.getDouble("unknown_band");
  borders_.reset();
}

void TopoBuilder::update(const Segmentation& seg, const GridMap& map, const PoseGraph* history) {
  // Carry over what persists by region id / region pair.
  std::map<RegionId, TopoNode> old_nodes;
  for (const auto& n : graph_.nodes) old_nodes[n.region] = n;
  std::map<Key, std::vector<Traversal>> old_trav;
  std::map<RegionId, Key> old_entrance;
  for (const auto& e : graph_.edges) old_trav[edgeKey(e.a, e.b)] = e.traversals;
  for (const auto& n : graph_.nodes)
    if (n.entrance_edge >= 0 && n.entrance_edge < static_cast<int>(graph_.edges.size()))
      old_entrance[n.region] =
          edgeKey(graph_.edges[n.entrance_edge].a, graph_.edges[n.entrance_edge].b);

  const LabelImage& L = seg.labels;
  BorderMap acc = borders(borders_.get(), seg_.labels, L, map, unknown_band_);
  seg_ = seg;

  TopoGraph g;
  g.current = graph_.current;
  for (const auto& r : seg.regions) {
    TopoNode n;
    n.region = r.id;
    n.centroid = r.centroid;
    n.area = r.area;
    auto it = old_nodes.find(r.id);
    if (it != old_nodes.end()) n.visited = it->second.visited;
    g.nodes.push_back(n);
  }
  TopoNode unexplored;
  unexplored.region = kUnexplored;
  g.nodes.push_back(unexplored);
  for (auto& [k, s] : acc) {
    const bool is_frontier = k.second == kUnexplored;
    if (is_frontier) keepWideFrontiers(s.frontier_cells, L.width, L.resolution, s.border);
    if (is_frontier) {
      // Width, midpoint from the stretches kept.
      s.cells = static_cast<int>(s.border.size());
      if (s.cells == 0) continue;
    }
    const double width = s.cells * L.resolution;
    if (width < (is_frontier ? min_frontier_width_ : min_border_width_)) continue;
    TopoEdge e;
    e.a = k.first;
    e.b = k.second;
    e.width = width;
    if (is_frontier) {
      double sx = 0, sy = 0;
      for (const Point2& b : s.border) sx += b.x, sy += b.y;
      e.midpoint = {sx / s.cells, sy / s.cells};
    } else {
      e.midpoint = {L.origin_x + L.resolution * static_cast<double>(s.twice_x) / (2.0 * s.cells),
                    L.origin_y + L.resolution * static_cast<double>(s.twice_y) / (2.0 * s.cells)};
    }
    e.border = s.border;
    auto t = old_trav.find(k);
    if (t != old_trav.end()) e.traversals = t->second;
    g.edges.push_back(e);
  }
  for (auto& n : g.nodes) {
    auto it = old_entrance.find(n.region);
    if (it == old_entrance.end()) continue;
    for (std::size_t i = 0; i < g.edges.size(); ++i)
      if (edgeKey(g.edges[i].a, g.edges[i].b) == it->second) n.entrance_edge = static_cast<int>(i);
  }
  if (!g.node(g.current)) g.current = 0;
  graph_ = std::move(g);
  if (history) replay(*history);
}

void TopoBuilder::replay(const PoseGraph& history) {
  for (auto& e : graph_.edges) e.traversals.clear();
  for (auto& n : graph_.nodes) {
    n.visited = false;
    n.entrance_edge = -1;
  }
  std::map<Key, int> edge_of;
  for (std::size_t i = 0; i < graph_.edges.size(); ++i)
    edge_of[edgeKey(graph_.edges[i].a, graph_.edges[i].b)] = static_cast<int>(i);

  struct Sample {
    double x, y, t;
  };
  std::vector<Sample> path;
  const double t0 = history.nodes.empty() ? 0 : history.nodes.front().timestamp;
  for (const PoseNode& n : history.nodes)
    path.push_back({n.pose.x(), n.pose.y(), n.timestamp - t0});
  if (have_robot_) path.push_back({robot_x_, robot_y_, robot_t_});

  const double step = 0.5 * (seg_.labels.resolution > 0 ? seg_.labels.resolution : 0.05);
  RegionId last = 0;
  auto visit = [&](double x, double y, double t) {
    const RegionId r = seg_.labels.atPoint(x, y);
    if (r <= 0 || r == last) return;
    TopoNode* to = graph_.node(r);
    if (!to) return;
    int edge = -1;
    if (last > 0) {
      auto it = edge_of.find(edgeKey(last, r));
      if (it != edge_of.end()) {
        edge = it->second;
        TopoEdge& e = graph_.edges[edge];
        e.traversals.push_back({e.a == last, t});
      }
    }
    // The entrance edge is that of the first arrival; the region of the start has none.
    if (!to->visited && last > 0) to->entrance_edge = edge;
    to->visited = true;
    last = r;
  };
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i == 0) {
      visit(path[0].x, path[0].y, path[0].t);
      continue;
    }
    const Sample& a = path[i - 1];
    const Sample& b = path[i];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int k = 1; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      visit(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.t + f * (b.t - a.t));
    }
  }
  graph_.current = last;
}

void TopoBuilder::observeRobot(double x, double y, double t) {
  have_robot_ = true;
  robot_x_ = x;
  robot_y_ = y;
  robot_t_ = t;
  const RegionId r = seg_.labels.atPoint(x, y);
  if (r <= 0 || r == graph_.current) return;
  const RegionId from = graph_.current;
  int edge = -1;
  if (from > 0) {
    for (std::size_t i = 0; i < graph_.edges.size(); ++i)
      if (edgeKey(graph_.edges[i].a, graph_.edges[i].b) == edgeKey(from, r)) {
        edge = static_cast<int>(i);
        graph_.edges[i].traversals.push_back({graph_.edges[i].a == from, t});
      }
  }
  if (TopoNode* n = graph_.node(r)) {
    if (!n->visited) n->entrance_edge = edge;
    n->visited = true;
  }
  graph_.current = r;
}

}  // namespace asf::mapping
