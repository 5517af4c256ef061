// Voronoi room segmentation on a raster, written from the published description (Thrun 1998;
// Bormann et al., ICRA 2016): opened free space -> distance transform -> skeleton by
// distance-ordered homotopic thinning (the raster generalized Voronoi graph) -> pruning ->
// clearance minima along the graph -> cut lines between their two basis points ->
// components -> wavefront fill of the remaining free cells -> merging of small regions.
#include "voronoi_segmentation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace asf::voronoi {
namespace {

// The 8-neighbourhood in ring order (E, NE, N, NW, W, SW, S, SE; image rows grow down):
// consecutive entries are 4-adjacent, even entries are the 4-neighbours.
constexpr int kRingDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
constexpr int kRingDy[8] = {0, -1, -1, -1, 0, 1, 1, 1};

/// simple[code]: removing the centre keeps the topology (8-connected foreground,
/// 4-connected background) for the neighbourhood `code` (bit k = ring cell k is foreground).
std::array<bool, 256> makeSimplePointTable() {
  std::array<bool, 256> table{};
  for (int code = 0; code < 256; ++code) {
    int parent[8];
    std::iota(parent, parent + 8, 0);
    auto find = [&](int a) {
      while (parent[a] != a) a = parent[a] = parent[parent[a]];
      return a;
    };
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) {
        const bool fa = code >> a & 1, fb = code >> b & 1;
        if (fa != fb) continue;
        const int dx = std::abs(kRingDx[a] - kRingDx[b]), dy = std::abs(kRingDy[a] - kRingDy[b]);
        const bool adjacent = fa ? std::max(dx, dy) == 1 : dx + dy == 1;
        if (adjacent) parent[find(a)] = find(b);
      }
    int fg_components = 0;
    bool bg_root_seen[8] = {};
    int bg_components = 0;  // only those touching the centre through a 4-neighbour
    for (int a = 0; a < 8; ++a) {
      if (code >> a & 1) {
        if (find(a) == a) ++fg_components;
      } else if (a % 2 == 0 && !bg_root_seen[find(a)]) {
        bg_root_seen[find(a)] = true;
        ++bg_components;
      }
    }
    table[code] = fg_components == 1 && bg_components == 1;
  }
  return table;
}

cv::Mat distanceToZero(const cv::Mat& mask) {
  cv::Mat d;
  cv::distanceTransform(mask, d, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  return d;
}

/// Morphological opening with a disc of radius r, exact, via two distance transforms:
/// removes passages narrower than 2r and free cells the robot's disc cannot cover.
cv::Mat openWithDisc(const cv::Mat& free255, double r) {
  if (r <= 0) return free255.clone();
  const cv::Mat not_core = distanceToZero(free255) <= r;
  if (cv::countNonZero(not_core) == static_cast<int>(not_core.total()))
    return cv::Mat::zeros(free255.size(), CV_8U);
  const cv::Mat near_core = distanceToZero(not_core) <= r;
  return near_core & free255;
}

struct Grid {
  int W, H;
  int offset[8];
  Grid(int w, int h) : W(w), H(h) {
    for (int k = 0; k < 8; ++k) offset[k] = kRingDy[k] * W + kRingDx[k];
  }
};

int degree(const std::vector<std::uint8_t>& s, const Grid& g, int i) {
  int n = 0;
  for (int k = 0; k < 8; ++k) n += s[i + g.offset[k]];
  return n;
}

/// Distance-ordered homotopic thinning: deletes simple cells in increasing clearance, keeping
/// the strict clearance maxima as anchors (room centres), so the result is a thin graph
/// on the ridge of the distance transform joining the anchors, with one loop per obstacle.
std::vector<std::uint8_t> skeletonize(const cv::Mat& open255, const cv::Mat& clearance,
                                      const Grid& g) {
  static const std::array<bool, 256> kSimple = makeSimplePointTable();
  const int N = g.W * g.H;
  const float* D = clearance.ptr<float>();
  std::vector<std::uint8_t> s(N), anchor(N), queued(N);
  for (int i = 0; i < N; ++i) s[i] = open255.data[i] ? 1 : 0;
  // Strict maxima of (clearance, index): plateaus give one anchor, not a thick blob.
  for (int i = 0; i < N; ++i) {
    if (!s[i]) continue;
    bool top = true;
    for (int k = 0; k < 8 && top; ++k) {
      const int j = i + g.offset[k];
      if (s[j] && (D[j] > D[i] || (D[j] == D[i] && j > i))) top = false;
    }
    anchor[i] = top;
  }
  // Exact EDT values are square roots of integers: bucket by the squared distance.
  auto key = [&](int i) { return static_cast<int>(std::lround(double(D[i]) * D[i])); };
  int max_key = 0;
  for (int i = 0; i < N; ++i)
    if (s[i]) max_key = std::max(max_key, key(i));
  std::vector<std::vector<int>> buckets(max_key + 1);
  for (int i = 0; i < N; ++i) {
    if (!s[i] || anchor[i]) continue;
    for (int k = 0; k < 8; k += 2)
      if (!s[i + g.offset[k]]) {
        queued[i] = 1;
        buckets[key(i)].push_back(i);
        break;
      }
  }
  for (int level = 0; level <= max_key; ++level) {
    auto& bucket = buckets[level];
    for (std::size_t b = 0; b < bucket.size(); ++b) {  // grows while we read it
      const int i = bucket[b];
      queued[i] = 0;
      if (!s[i]) continue;
      int code = 0;
      for (int k = 0; k < 8; ++k) code |= s[i + g.offset[k]] << k;
      if (!kSimple[code]) continue;  // re-queued if a neighbour's deletion changes that
      s[i] = 0;
      for (int k = 0; k < 8; ++k) {
        const int j = i + g.offset[k];
        if (s[j] && !anchor[j] && !queued[j]) {
          queued[j] = 1;
          buckets[std::max(key(j), level)].push_back(j);
        }
      }
    }
    std::vector<int>().swap(bucket);
  }
  return s;
}

/// Removes dead-end branches shorter than `length` (noise spurs), repeatedly, since removing
/// one spur can expose another.
void pruneSpurs(std::vector<std::uint8_t>& s, const Grid& g, double length) {
  if (length <= 0) return;
  std::vector<int> cells;
  for (int i = 0; i < g.W * g.H; ++i)
    if (s[i]) cells.push_back(i);
  for (int round = 0; round < 1000; ++round) {
    bool changed = false;
    for (int e : cells) {
      if (!s[e] || degree(s, g, e) != 1) continue;
      std::vector<int> path{e};
      double len = 0;
      int prev = -1, cur = e;
      bool at_junction = false;
      while (len < length) {
        int next = -1;
        for (int k = 0; k < 8; ++k) {
          const int j = cur + g.offset[k];
          if (s[j] && j != prev) {
            next = j;
            len += (k % 2) ? M_SQRT2 : 1.0;
            break;
          }
        }
        if (next < 0) break;
        const int d = degree(s, g, next);
        if (d >= 3) {
          at_junction = true;
          break;
        }
        if (d != 2) break;  // an isolated segment: the whole graph of its component
        path.push_back(next);
        prev = cur;
        cur = next;
      }
      if (at_junction && len < length) {
        for (int i : path) s[i] = 0;
        changed = true;
      }
    }
    if (!changed) break;
    cells.erase(std::remove_if(cells.begin(), cells.end(), [&](int i) { return !s[i]; }),
                cells.end());
  }
}

/// Chains of degree-2 cells between graph nodes (degree != 2). Non-cyclic chains start and
/// end with their node cells; cyclic chains (a loop without any node) hold only chain cells.
struct Chain {
  std::vector<int> cells;
  bool cyclic = false;
};

std::vector<Chain> traceChains(const std::vector<std::uint8_t>& s, const Grid& g) {
  const int N = g.W * g.H;
  std::vector<std::uint8_t> deg(N), visited(N);
  for (int i = 0; i < N; ++i)
    if (s[i]) deg[i] = static_cast<std::uint8_t>(degree(s, g, i));
  std::vector<Chain> chains;
  // A degree-2 cell has exactly one neighbour besides the one we came from.
  auto walk = [&](Chain& c, int prev, int cur) {
    while (true) {
      int next = -1;
      for (int k = 0; k < 8 && next < 0; ++k) {
        const int j = cur + g.offset[k];
        if (s[j] && j != prev) next = j;
      }
      if (next < 0) return;
      if (deg[next] != 2) {
        if (!c.cyclic) c.cells.push_back(next);
        return;
      }
      if (visited[next]) return;  // back at the start of a loop
      visited[next] = 1;
      c.cells.push_back(next);
      prev = cur;
      cur = next;
    }
  };
  for (int n = 0; n < N; ++n) {
    if (!s[n] || deg[n] == 2) continue;
    for (int k = 0; k < 8; ++k) {
      const int q = n + g.offset[k];
      if (!s[q] || deg[q] != 2 || visited[q]) continue;
      Chain c;
      c.cells = {n, q};
      visited[q] = 1;
      walk(c, n, q);
      chains.push_back(std::move(c));
    }
  }
  for (int i = 0; i < N; ++i) {
    if (!s[i] || deg[i] != 2 || visited[i]) continue;
    Chain c;
    c.cyclic = true;
    c.cells = {i};
    visited[i] = 1;
    walk(c, -1, i);
    chains.push_back(std::move(c));
  }
  return chains;
}

/// Critical points: chain cells whose clearance is the minimum within `half_window` cells
/// along the chain (ties broken by cell index) and rises within it on both sides by at least
/// a cell and by the factor 1 + min_rise (a door, not a dent in a corridor wall).
/// Windows stop at nodes: a door's minimum is compared with its own branch only.
std::vector<int> criticalPoints(const std::vector<Chain>& chains, const float* D, int half_window,
                                double min_rise) {
  std::vector<int> out;
  for (const Chain& c : chains) {
    const int m = static_cast<int>(c.cells.size());
    const int first = c.cyclic ? 0 : 1, last = c.cyclic ? m - 1 : m - 2;
    const int reach = c.cyclic ? std::min(half_window, (m - 1) / 2) : half_window;
    for (int k = first; k <= last; ++k) {
      const int ci = c.cells[k];
      const float d = D[ci];
      bool minimum = true;
      float rise[2] = {d, d};
      for (int side = 0; side < 2 && minimum; ++side)
        for (int t = 1; t <= reach; ++t) {
          int j = side ? k + t : k - t;
          if (c.cyclic)
            j = (j + m) % m;
          else if (j < 0 || j >= m)
            break;
          const int cj = c.cells[j];
          if (D[cj] < d || (D[cj] == d && cj < ci)) {
            minimum = false;
            break;
          }
          rise[side] = std::max(rise[side], D[cj]);
        }
      const float need = std::max(d + 1.0f, d * float(1 + min_rise));
      if (minimum && rise[0] >= need && rise[1] >= need) out.push_back(ci);
    }
  }
  return out;
}

/// Merges regions by the rules of Bormann et al. in spirit: small regions into the neighbour
/// with the longest shared border; mid-sized regions that share a large part of their
/// perimeter with one neighbour (a room split by a spurious cut) into that neighbour.
void mergeRegions(std::vector<int>& lab, const Grid& g, int n, const Options& o) {
  if (n <= 1) return;
  std::vector<double> area(n + 1, 0), perimeter(n + 1, 0);
  std::vector<std::map<int, double>> border(n + 1);
  for (int y = 0; y + 1 < g.H; ++y)
    for (int x = 0; x + 1 < g.W; ++x) {
      const int i = y * g.W + x, a = lab[i];
      if (a > 0) area[a] += 1;
      for (int j : {i + 1, i + g.W}) {
        const int b = lab[j];
        if (a == b) continue;
        if (a > 0) perimeter[a] += 1;
        if (b > 0) perimeter[b] += 1;
        if (a > 0 && b > 0) {
          border[a][b] += 1;
          border[b][a] += 1;
        }
      }
    }
  std::vector<int> target(n + 1);
  std::iota(target.begin(), target.end(), 0);
  std::vector<bool> alive(n + 1, true);
  alive[0] = false;
  while (true) {
    int pick = -1, into = -1;
    for (int r = 1; r <= n; ++r) {
      if (!alive[r] || border[r].empty()) continue;
      if (pick >= 0 && area[r] >= area[pick]) continue;  // smallest first
      int best = -1;
      for (const auto& [t, len] : border[r])
        if (best < 0 || len > border[r][best]) best = t;
      const bool small = area[r] < o.min_room_area;
      const bool split =
          area[r] < o.max_merge_area && border[r][best] >= o.merge_border_ratio * perimeter[r];
      if (small || split) {
        pick = r;
        into = best;
      }
    }
    if (pick < 0) break;
    const double shared = border[pick][into];
    area[into] += area[pick];
    perimeter[into] += perimeter[pick] - 2 * shared;
    for (const auto& [t, len] : border[pick]) {
      border[t].erase(pick);
      if (t == into) continue;
      border[into][t] += len;
      border[t][into] += len;
    }
    border[pick].clear();
    alive[pick] = false;
    target[pick] = into;
  }
  // Resolve chains of merges and renumber 1..k in order of first appearance.
  std::vector<int> final_id(n + 1, 0);
  int next_id = 0;
  for (int& l : lab) {
    if (l <= 0) continue;
    int r = l;
    while (target[r] != r) r = target[r];
    if (!final_id[r]) final_id[r] = ++next_id;
    l = final_id[r];
  }
}

/// Obstacles (8-connected, the padding joins all that touch the map border) smaller than
/// max_furniture_area are furniture: a gap between furniture and anything is no door.
class FurnitureTest {
 public:
  FurnitureTest(const cv::Mat& free255, const Options& o, const Grid& g)
      : obstacle255_(free255 == 0),
        max_area_(o.max_furniture_area),
        reach_(static_cast<int>(std::ceil(o.robot_radius)) + 2),
        g_(g) {
    if (max_area_ > 0)
      cv::connectedComponentsWithStats(obstacle255_, id_, stats_, centroids_, 8, CV_32S);
  }
  /// Whether the basis point (bx, by) stands for furniture. It lies on the opened space's
  /// border: the obstacle it stands for is the nearest original obstacle cell.
  bool operator()(int bx, int by) const {
    if (max_area_ <= 0) return false;
    int best = -1;
    double best_d2 = 1e18;
    for (int y = std::max(0, by - reach_); y <= std::min(g_.H - 1, by + reach_); ++y)
      for (int x = std::max(0, bx - reach_); x <= std::min(g_.W - 1, bx + reach_); ++x) {
        if (!obstacle255_.at<std::uint8_t>(y, x)) continue;
        const double d2 = double(x - bx) * (x - bx) + double(y - by) * (y - by);
        if (d2 < best_d2) {
          best_d2 = d2;
          best = id_.at<int>(y, x);
        }
      }
    return best > 0 && stats_.at<int>(best, cv::CC_STAT_AREA) < max_area_;
  }

 private:
  cv::Mat obstacle255_, id_, stats_, centroids_;
  double max_area_;
  int reach_;
  const Grid& g_;
};

/// Cut lines at the critical points: through the two nearest obstacle cells (basis points)
/// on opposite sides, drawn as obstacles into the opened space (the result).
cv::Mat drawCutLines(const cv::Mat& open255, const float* D, const std::vector<int>& critical,
                     const FurnitureTest& onFurniture, const Grid& g, const Options& o, Stats& st) {
  cv::Mat cut255 = open255.clone();
  const double cos_max = std::cos(o.min_cut_angle);
  for (int ci : critical) {
    const int px = ci % g.W, py = ci / g.W;
    const double d = D[ci], reach = d + 1.5;
    const int r = static_cast<int>(std::ceil(reach));
    struct Basis {
      int x, y;
      double dist;
    };
    std::vector<Basis> near;
    for (int y = std::max(0, py - r); y <= std::min(g.H - 1, py + r); ++y)
      for (int x = std::max(0, px - r); x <= std::min(g.W - 1, px + r); ++x) {
        if (open255.at<std::uint8_t>(y, x)) continue;
        const double dist = std::hypot(x - px, y - py);
        if (dist <= reach) near.push_back({x, y, dist});
      }
    if (near.size() < 2) continue;
    const Basis b1 = *std::min_element(
        near.begin(), near.end(), [](const Basis& a, const Basis& b) { return a.dist < b.dist; });
    const Basis* b2 = nullptr;
    double best_cos = 2;
    for (const Basis& b : near) {
      const double c = ((b1.x - px) * (b.x - px) + (b1.y - py) * (b.y - py)) / (b1.dist * b.dist);
      if (c < best_cos - 1e-12) {
        best_cos = c;
        b2 = &b;
      }
    }
    if (!b2 || best_cos > cos_max) continue;
    if (std::hypot(b2->x - b1.x, b2->y - b1.y) > o.max_cut_length) continue;
    if (onFurniture(b1.x, b1.y) || onFurniture(b2->x, b2->y)) continue;
    cv::line(cut255, {b1.x, b1.y}, {b2->x, b2->y}, cv::Scalar(0), 1, cv::LINE_8);
    st.cut_lines.emplace_back(b1.x - 1, b1.y - 1, b2->x - 1, b2->y - 1);
    ++st.cuts;
  }
  return cut255;
}

/// Wavefront fill: free cells outside the opened space and on cut lines join the region
/// that reaches them first; free pockets no region reaches become regions of their own.
/// Returns the number of labels.
int wavefrontFill(const cv::Mat& free255, const Grid& g, int n_components, std::vector<int>& lab) {
  const int N = g.W * g.H;
  std::vector<int> queue;
  queue.reserve(N);
  for (int i = 0; i < N; ++i)
    if (lab[i] > 0) queue.push_back(i);
  int n_labels = n_components, scan = 0;
  for (std::size_t head = 0;; ++head) {
    if (head == queue.size()) {
      while (scan < N && !(free255.data[scan] && lab[scan] == 0)) ++scan;
      if (scan == N) break;
      const int seed = scan;
      lab[seed] = ++n_labels;
      queue.push_back(seed);
    }
    const int i = queue[head];
    for (int k = 0; k < 8; k += 2) {
      const int j = i + g.offset[k];
      if (free255.data[j] && lab[j] == 0) {
        lab[j] = lab[i];
        queue.push_back(j);
      }
    }
  }
  return n_labels;
}

}  // namespace

cv::Mat segmentFreeSpace(const cv::Mat& free, const Options& o, Stats* stats) {
  CV_Assert(free.type() == CV_8U);
  Stats st;
  cv::Mat free255;
  // One obstacle cell of padding: neighbourhood reads below never leave the image.
  cv::copyMakeBorder(free != 0, free255, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  const Grid g(free255.cols, free255.rows);
  const int N = g.W * g.H;

  const cv::Mat open255 = openWithDisc(free255, o.robot_radius);
  const cv::Mat clearance = distanceToZero(open255);
  const float* D = clearance.ptr<float>();

  std::vector<std::uint8_t> skel = skeletonize(open255, clearance, g);
  pruneSpurs(skel, g, o.prune_length);
  st.skeleton_cells = static_cast<int>(std::count(skel.begin(), skel.end(), 1));
  const std::vector<int> critical =
      criticalPoints(traceChains(skel, g), D, o.neighborhood, o.min_rise);
  st.critical_points = static_cast<int>(critical.size());
  if (stats) {
    st.skeleton = cv::Mat(g.H, g.W, CV_8U, skel.data())(cv::Rect(1, 1, g.W - 2, g.H - 2)).clone();
    for (int ci : critical) st.critical.emplace_back(ci % g.W - 1, ci / g.W - 1);
  }

  const FurnitureTest onFurniture(free255, o, g);
  const cv::Mat cut255 = drawCutLines(open255, D, critical, onFurniture, g, o, st);
  // 8-connected cut lines separate 4-connected regions.
  cv::Mat components;
  const int n_components = cv::connectedComponents(cut255, components, 4, CV_32S) - 1;
  st.components = n_components;
  std::vector<int> lab(components.ptr<int>(), components.ptr<int>() + N);
  const int n_labels = wavefrontFill(free255, g, n_components, lab);

  mergeRegions(lab, g, n_labels, o);
  st.regions = lab.empty() ? 0 : *std::max_element(lab.begin(), lab.end());
  if (stats) *stats = st;

  cv::Mat out(free.size(), CV_32S);
  for (int y = 0; y < free.rows; ++y)
    std::copy_n(&lab[(y + 1) * g.W + 1], free.cols, out.ptr<int>(y));
  return out;
}

}  // namespace asf::voronoi
