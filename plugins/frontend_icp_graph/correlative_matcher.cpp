#include "correlative_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>

namespace asf::icp_graph {

namespace {
/// Cell buffers of grids this thread no longer uses.
std::vector<std::vector<float>>& bufferPool() {
  thread_local std::vector<std::vector<float>> pool;
  return pool;
}

/// Level h of the max-pooled grids (width x height cells each) from level h - 1, s = 2^(h-1):
/// [i, i + 2^h) is [i, i + s) and [i + s, i + 2s). Beyond the grid counts as 0, which every
/// value is at least: a max over fewer cells there.
void poolLevel(const std::vector<float>& prev, std::vector<float>& cur, int width, int height,
               int s) {
  const int inner = std::max(0, width - s);  // columns whose right neighbour is inside
  for (int j = 0; j < height; ++j) {
    const float* a = prev.data() + static_cast<std::size_t>(j) * width;
    const float* b = j + s < height ? a + static_cast<std::size_t>(s) * width : nullptr;
    float* out = cur.data() + static_cast<std::size_t>(j) * width;
    if (b) {
      for (int i = 0; i < inner; ++i)
        out[i] = std::max(std::max(a[i], a[i + s]), std::max(b[i], b[i + s]));
      for (int i = inner; i < width; ++i) out[i] = std::max(a[i], b[i]);
    } else {
      for (int i = 0; i < inner; ++i) out[i] = std::max(a[i], a[i + s]);
      for (int i = inner; i < width; ++i) out[i] = a[i];
    }
  }
}

}  // namespace

LikelihoodGrid::~LikelihoodGrid() {
  auto& pool = bufferPool();
  for (auto& v : level_)
    if (pool.size() < 16) pool.push_back(std::move(v));
}

LikelihoodGrid::LikelihoodGrid(Points2 ref, double resolution, double sigma, int levels,
                               double margin, const std::array<double, 4>* cover)
    : res_(resolution) {
  if (!(resolution > 0) || !(sigma > 0) || levels < 1 || levels > 16)
    throw std::invalid_argument("LikelihoodGrid: resolution and sigma must be > 0, levels 1..16");
  const int reach = static_cast<int>(std::ceil(3 * sigma / res_));
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const double x = ref.x[i], y = ref.y[i];
    if (i == 0 || x < xmin) xmin = x;
    if (i == 0 || x > xmax) xmax = x;
    if (i == 0 || y < ymin) ymin = y;
    if (i == 0 || y > ymax) ymax = y;
  }
  // Below the grid at() says 0, so a pooled cell left of or under the grid must cover only
  // empty cells: the points start 2^(levels-1) cells in (plus the kernel and the margin).
  const int pad = reach + static_cast<int>(std::ceil(std::max(0.0, margin) / res_)) + 1;
  const int low = pad + (1 << (levels - 1));
  x0_ = xmin - low * res_;
  y0_ = ymin - low * res_;
  w_ = static_cast<int>(std::ceil((xmax - xmin) / res_)) + low + pad + 1;
  h_ = static_cast<int>(std::ceil((ymax - ymin) / res_)) + low + pad + 1;
  if (cover) {  // whole cells added on each side, the lattice unchanged
    const auto cells = [&](double d) { return std::max(0, static_cast<int>(std::ceil(d / res_))); };
    const int left = cells(x0_ - (*cover)[0]), below = cells(y0_ - (*cover)[1]);
    x0_ -= left * res_, y0_ -= below * res_;
    w_ += left, h_ += below;
    w_ = std::max(w_, cellX((*cover)[2]) + 1);
    h_ = std::max(h_, cellY((*cover)[3]) + 1);
  }
  if (static_cast<double>(w_) * h_ > 64e6)
    throw std::invalid_argument("LikelihoodGrid: more than 64 million cells");
  level_.resize(static_cast<std::size_t>(levels));
  auto& pool = bufferPool();
  for (std::size_t h = 0; h < level_.size(); ++h) {
    auto& v = level_[h];
    if (!pool.empty()) v = std::move(pool.back()), pool.pop_back();
    if (h == 0)
      v.assign(static_cast<std::size_t>(w_) * h_, 0.f);
    else
      v.resize(static_cast<std::size_t>(w_) * h_);  // every cell written below
  }
  std::vector<float>& l0 = level_[0];
  const double inv2s2 = 1.0 / (2 * sigma * sigma), cut2 = 9 * sigma * sigma;
  // exp(-(dx^2 + dy^2) / 2s^2) as the product of its x and y factors: 2 (2 reach + 1)
  // exponentials per point instead of (2 reach + 1)^2.
  std::vector<double> ex(static_cast<std::size_t>(2 * reach + 1)), ey(ex.size()), dx2(ex.size());
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const int ci = cellX(ref.x[k]), cj = cellY(ref.y[k]);
    for (int o = -reach; o <= reach; ++o) {
      const double dx = x0_ + (ci + o + 0.5) * res_ - ref.x[k];
      const double dy = y0_ + (cj + o + 0.5) * res_ - ref.y[k];
      dx2[static_cast<std::size_t>(o + reach)] = dx * dx;
      ex[static_cast<std::size_t>(o + reach)] = std::exp(-dx * dx * inv2s2);
      ey[static_cast<std::size_t>(o + reach)] = std::exp(-dy * dy * inv2s2);
    }
    for (int b = 0; b <= 2 * reach; ++b) {
      const int j = cj - reach + b;
      const double dy = y0_ + (j + 0.5) * res_ - ref.y[k];
      float* row = l0.data() + static_cast<std::size_t>(j) * w_ + (ci - reach);
      for (int a = 0; a <= 2 * reach; ++a) {
        if (dx2[static_cast<std::size_t>(a)] + dy * dy > cut2) continue;
        const float v =
            static_cast<float>(ex[static_cast<std::size_t>(a)] * ey[static_cast<std::size_t>(b)]);
        row[a] = std::max(row[a], v);
      }
    }
  }
  // Each level from the last.
  for (int h = 1; h < levels; ++h)
    poolLevel(level_[static_cast<std::size_t>(h - 1)], level_[static_cast<std::size_t>(h)], w_, h_,
              1 << (h - 1));
}

int LikelihoodGrid::cellX(double x) const { return static_cast<int>(std::floor((x - x0_) / res_)); }
int LikelihoodGrid::cellY(double y) const { return static_cast<int>(std::floor((y - y0_) / res_)); }

namespace {

/// One grid cell hit by a scan and how many of its points fall in it.
struct Cell {
  int i, j;
  double n;
};

/// A scan's points as grid cells at one heading (consecutive points in one cell as one entry
/// with their count: near points of a dense scan share cells), with their bounding box and the
/// number of points.
struct Cells {
  std::vector<Cell> ij;
  double points = 0;
  int imin = 0, imax = -1, jmin = 0, jmax = -1;
};

/// The scan's points at heading phi and translation t, as grid cells.
Cells cellsAt(const LikelihoodGrid& g, Points2 scan, double phi, double tx, double ty) {
  const double c = std::cos(phi), s = std::sin(phi);
  Cells cells;
  cells.points = static_cast<double>(scan.size());
  cells.ij.reserve(scan.size());
  for (std::size_t k = 0; k < scan.size(); ++k) {
    const int i = g.cellX(c * scan.x[k] - s * scan.y[k] + tx);
    const int j = g.cellY(s * scan.x[k] + c * scan.y[k] + ty);
    if (k == 0) cells.imin = cells.imax = i, cells.jmin = cells.jmax = j;
    cells.imin = std::min(cells.imin, i), cells.imax = std::max(cells.imax, i);
    cells.jmin = std::min(cells.jmin, j), cells.jmax = std::max(cells.jmax, j);
    if (!cells.ij.empty() && cells.ij.back().i == i && cells.ij.back().j == j)
      cells.ij.back().n += 1;
    else
      cells.ij.push_back({i, j, 1});
  }
  return cells;
}

/// Mean level-h value of the points' cells moved by (dx, dy): the score of a pose (h = 0) or
/// the bound of a block of poses (h > 0). Summed in the cells' order either way, so the two
/// paths agree to the bit.
double meanAt(const LikelihoodGrid& g, int h, const Cells& cells, int dx, int dy) {
  if (cells.ij.empty()) return 0;
  double sum = 0;
  const int w = g.width();
  if (cells.imin + dx >= 0 && cells.jmin + dy >= 0 && cells.imax + dx < w &&
      cells.jmax + dy < g.height()) {
    const float* v = g.data(h) + static_cast<std::ptrdiff_t>(dy) * w + dx;
    for (const Cell& c : cells.ij) sum += c.n * v[static_cast<std::ptrdiff_t>(c.j) * w + c.i];
  } else {
    for (const Cell& c : cells.ij) sum += c.n * g.at(h, c.i + dx, c.j + dy);
  }
  return sum / cells.points;
}

struct Node {
  int k, dx, dy, h;
  double bound;
};

/// The bounds of `n` level-h blocks of one heading's cells (a heading's coarsest blocks, or
/// a block's children): meanAt for each, in one pass over the cells when every moved cell lies
/// inside the grid (the reads of a cell are then near one another; the same sums in the same
/// order, so equal to meanAt to the bit), else block by block.
void blockBounds(const LikelihoodGrid& g, int h, const Cells& cells, Node* nodes, std::size_t n) {
  constexpr std::size_t kMax = 256;
  const int w = g.width();
  int dx0 = 0, dx1 = 0, dy0 = 0, dy1 = 0;
  for (std::size_t r = 0; r < n; ++r) {
    if (r == 0 || nodes[r].dx < dx0) dx0 = nodes[r].dx;
    if (r == 0 || nodes[r].dx > dx1) dx1 = nodes[r].dx;
    if (r == 0 || nodes[r].dy < dy0) dy0 = nodes[r].dy;
    if (r == 0 || nodes[r].dy > dy1) dy1 = nodes[r].dy;
  }
  const bool inside = !cells.ij.empty() && cells.imin + dx0 >= 0 && cells.jmin + dy0 >= 0 &&
                      cells.imax + dx1 < w && cells.jmax + dy1 < g.height();
  if (!inside || n > kMax) {
    for (std::size_t r = 0; r < n; ++r)
      nodes[r].bound = meanAt(g, h, cells, nodes[r].dx, nodes[r].dy);
    return;
  }
  std::array<std::ptrdiff_t, kMax> off;
  std::array<double, kMax> sum;
  for (std::size_t r = 0; r < n; ++r) {
    off[r] = static_cast<std::ptrdiff_t>(nodes[r].dy) * w + nodes[r].dx;
    sum[r] = 0;
  }
  const float* v = g.data(h);
  for (const Cell& c : cells.ij) {
    const float* p = v + static_cast<std::ptrdiff_t>(c.j) * w + c.i;
    for (std::size_t r = 0; r < n; ++r) sum[r] += c.n * p[off[r]];
  }
  for (std::size_t r = 0; r < n; ++r) nodes[r].bound = sum[r] / cells.points;
}

/// Depth-first branch and bound: children best-first, pruned by the best score found so far.
class Search {
 public:
  Search(const LikelihoodGrid& g, const std::vector<Cells>& cells, int window, Eigen::Vector2d ex,
         double ex_r)
      : g_(g), cells_(cells), w_(window), ex_(std::move(ex)), ex_r_(ex_r) {}

  /// `roots` sorted by byBound.
  void run(const std::vector<Node>& roots, double min_score) {
    best_score_ = min_score;
    if (!roots.empty() && roots.front().h == 0) scored_ += roots.size();
    for (const Node& n : roots) visit(n);
  }
  static bool byBound(const Node& a, const Node& b) {
    if (a.bound != b.bound) return a.bound > b.bound;
    return std::tie(a.k, a.dx, a.dy) < std::tie(b.k, b.dx, b.dy);  // deterministic ties
  }
  bool found() const { return found_; }
  const Node& best() const { return best_; }
  double bestScore() const { return best_score_; }
  std::size_t scored() const { return scored_; }

 private:
  /// Whether every translation of the block lies inside the excluded disc (it is convex).
  bool excluded(int dx, int dy, int size) const {
    if (ex_r_ <= 0) return false;
    const double r = g_.resolution();
    for (int cx : {dx, dx + size - 1})
      for (int cy : {dy, dy + size - 1})
        if ((Eigen::Vector2d(cx * r, cy * r) - ex_).norm() >= ex_r_) return false;
    return true;
  }
  void visit(const Node& n) {
    if (n.bound < best_score_ || (found_ && n.bound == best_score_)) return;
    if (excluded(n.dx, n.dy, 1 << n.h)) return;
    if (n.h == 0) {
      best_ = n;
      best_score_ = n.bound;
      found_ = true;
      return;
    }
    const int s = 1 << (n.h - 1);
    std::array<Node, 4> kids;
    int nkids = 0;
    for (int ox : {0, s})
      for (int oy : {0, s}) {
        const int dx = n.dx + ox, dy = n.dy + oy;
        if (dx <= w_ && dy <= w_) kids[nkids++] = {n.k, dx, dy, n.h - 1, 0.0};
      }
    blockBounds(g_, n.h - 1, cells_[n.k], kids.data(), static_cast<std::size_t>(nkids));
    if (n.h == 1) scored_ += static_cast<std::size_t>(nkids);  // a leaf's bound is its score
    // Best first (insertion sort of at most 4: no allocation, the order std::sort would give
    // under this strict total order).
    for (int a = 1; a < nkids; ++a)
      for (int b = a; b > 0 && byBound(kids[b], kids[b - 1]); --b) std::swap(kids[b], kids[b - 1]);
    for (int c = 0; c < nkids; ++c) visit(kids[c]);
  }

  const LikelihoodGrid& g_;
  const std::vector<Cells>& cells_;
  int w_;
  Eigen::Vector2d ex_;
  double ex_r_;
  Node best_{0, 0, 0, 0, 0};
  double best_score_ = 0;
  bool found_ = false;
  std::size_t scored_ = 0;
};

}  // namespace

double correlativeScore(const LikelihoodGrid& grid, Points2 scan, const Eigen::Vector3d& pose) {
  return meanAt(grid, 0, cellsAt(grid, scan, pose.z(), pose.x(), pose.y()), 0, 0);
}

struct CorrelativeSearch::Impl {
  Impl(const LikelihoodGrid& g, const Eigen::Vector3d& q) : grid(g), guess(q) {}
  const LikelihoodGrid& grid;
  Eigen::Vector3d guess;
  double step = 0;
  int nk = 0, w = 0;
  std::size_t lattice = 0;
  std::vector<Cells> cells;  ///< per heading guess.z() + (k - nk) step
  std::vector<Node> roots;   ///< the coarsest blocks, sorted by Search::byBound
};

CorrelativeSearch::CorrelativeSearch(const LikelihoodGrid& grid, Points2 scan,
                                     const Eigen::Vector3d& guess, const CorrelativeOptions& o)
    : impl_(std::make_unique<Impl>(grid, guess)) {
  Impl& m = *impl_;
  if (scan.size() == 0) return;
  const double res = grid.resolution();
  m.step = o.step_phi;
  if (!(m.step > 0)) {
    double far2 = 0;
    for (std::size_t i = 0; i < scan.size(); ++i)
      far2 = std::max(far2, double(scan.x[i]) * scan.x[i] + double(scan.y[i]) * scan.y[i]);
    const double far = std::max(std::sqrt(far2), res);
    m.step = std::acos(std::clamp(1 - res * res / (2 * far * far), -1.0, 1.0));
  }
  m.nk = static_cast<int>(std::ceil(o.window_phi / m.step));
  m.w = static_cast<int>(std::ceil(o.window_xy / res));
  const int top = grid.levels() - 1, block = 1 << top;
  for (int k = -m.nk; k <= m.nk; ++k) {
    m.cells.push_back(cellsAt(grid, scan, guess.z() + k * m.step, guess.x(), guess.y()));
    const int ki = k + m.nk;
    const std::size_t first = m.roots.size();
    for (int dx = -m.w; dx <= m.w; dx += block)
      for (int dy = -m.w; dy <= m.w; dy += block) m.roots.push_back({ki, dx, dy, top, 0.0});
    blockBounds(grid, top, m.cells.back(), m.roots.data() + first, m.roots.size() - first);
  }
  std::sort(m.roots.begin(), m.roots.end(), Search::byBound);
  m.lattice = static_cast<std::size_t>(2 * m.nk + 1) * (2 * m.w + 1) * (2 * m.w + 1);
}

CorrelativeSearch::~CorrelativeSearch() = default;

CorrelativeResult CorrelativeSearch::run(double min_score, const Eigen::Vector2d& exclude_xy,
                                         double exclude_radius) const {
  const Impl& m = *impl_;
  CorrelativeResult r;
  if (m.cells.empty()) return r;
  r.lattice = m.lattice;
  const Eigen::Vector2d ex = exclude_xy - m.guess.head<2>();  // in offsets from the guess
  Search search(m.grid, m.cells, m.w, ex, exclude_radius);
  search.run(m.roots, min_score);
  r.scored = search.scored();
  if (!search.found()) return r;
  const Node& b = search.best();
  const double res = m.grid.resolution();
  r.found = true;
  r.score = search.bestScore();
  r.pose = Eigen::Vector3d(m.guess.x() + b.dx * res, m.guess.y() + b.dy * res,
                           m.guess.z() + (b.k - m.nk) * m.step);
  return r;
}

CorrelativeResult correlativeMatch(const LikelihoodGrid& grid, Points2 scan,
                                   const Eigen::Vector3d& guess, const CorrelativeOptions& o,
                                   const Eigen::Vector2d& exclude_xy, double exclude_radius) {
  return CorrelativeSearch(grid, scan, guess, o).run(o.min_score, exclude_xy, exclude_radius);
}

}  // namespace asf::icp_graph
