#include "correlative_matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>

namespace asf::icp_graph {

LikelihoodGrid::LikelihoodGrid(Points2 ref, double resolution, double sigma, int levels,
                               double margin)
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
  if (static_cast<double>(w_) * h_ > 64e6)
    throw std::invalid_argument("LikelihoodGrid: more than 64 million cells");
  level_.assign(static_cast<std::size_t>(levels),
                std::vector<float>(static_cast<std::size_t>(w_) * h_, 0.f));
  std::vector<float>& l0 = level_[0];
  const double inv2s2 = 1.0 / (2 * sigma * sigma), cut2 = 9 * sigma * sigma;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const int ci = cellX(ref.x[k]), cj = cellY(ref.y[k]);
    for (int j = cj - reach; j <= cj + reach; ++j) {
      for (int i = ci - reach; i <= ci + reach; ++i) {
        const double dx = x0_ + (i + 0.5) * res_ - ref.x[k], dy = y0_ + (j + 0.5) * res_ - ref.y[k];
        const double d2 = dx * dx + dy * dy;
        if (d2 > cut2) continue;
        float& v = l0[static_cast<std::size_t>(j) * w_ + i];
        v = std::max(v, static_cast<float>(std::exp(-d2 * inv2s2)));
      }
    }
  }
  // [i, i + 2^h) is [i, i + s) and [i + s, i + 2s) with s = 2^(h-1): each level from the last.
  for (int h = 1; h < levels; ++h) {
    const int s = 1 << (h - 1);
    const std::vector<float>& prev = level_[static_cast<std::size_t>(h - 1)];
    std::vector<float>& cur = level_[static_cast<std::size_t>(h)];
    auto prevAt = [&](int i, int j) {
      return i < w_ && j < h_ ? prev[static_cast<std::size_t>(j) * w_ + i] : 0.f;
    };
    for (int j = 0; j < h_; ++j)
      for (int i = 0; i < w_; ++i)
        cur[static_cast<std::size_t>(j) * w_ + i] =
            std::max({prevAt(i, j), prevAt(i + s, j), prevAt(i, j + s), prevAt(i + s, j + s)});
  }
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
        if (dx > w_ || dy > w_) continue;
        kids[nkids++] = {n.k, dx, dy, n.h - 1, meanAt(g_, n.h - 1, cells_[n.k], dx, dy)};
        if (n.h == 1) ++scored_;  // a leaf's bound is its exact score
      }
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
    for (int dx = -m.w; dx <= m.w; dx += block)
      for (int dy = -m.w; dy <= m.w; dy += block)
        m.roots.push_back({ki, dx, dy, top, meanAt(grid, top, m.cells.back(), dx, dy)});
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
