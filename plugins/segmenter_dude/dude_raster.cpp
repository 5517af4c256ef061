// Raster steps of segmenter_dude around the decomposition: label completion and the rooms
// variant's post-processing (small-region merging, room layer).
#include "dude_raster.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <set>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "dude.h"

namespace asf::dude::raster {

/// Every free cell gets a label: cells left out by the polygons (simplification, grown
/// obstacles, one-cell corridors) join the nearest labelled cell through free space;
/// free components with no labelled cell at all become regions of their own, when they
/// have at least `min_new_cells` cells (else they stay unlabelled).
void completeLabels(const cv::Mat& free, cv::Mat& labels, int* next_label, int min_new_cells) {
  const int W = free.cols, H = free.rows;
  std::deque<int> queue;
  for (int y = 0; y < H; ++y) {
    const unsigned char* fr = free.ptr<unsigned char>(y);
    int* lr = labels.ptr<int>(y);
    for (int x = 0; x < W; ++x)
      if (!fr[x]) lr[x] = 0;
  }
  int* L = labels.ptr<int>(0);
  const unsigned char* F = free.ptr<unsigned char>(0);
  // Seeds: labelled cells with an unlabelled free neighbour, in row-major order (the other
  // labelled cells would expand nothing: the result is that of seeding every one).
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int i = y * W + x;
      if (!F[i] || L[i] <= 0) continue;
      bool open = false;
      for (int dy = -1; dy <= 1 && !open; ++dy)
        for (int dx = -1; dx <= 1 && !open; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
          const int j = ny * W + nx;
          open = F[j] && L[j] == 0;
        }
      if (open) queue.push_back(i);
    }
  // Grows the queued cells' labels over unlabelled free cells; `visited` (if given) gets
  // every cell taken from the queue.
  auto bfs = [&](std::vector<int>* visited) {
    while (!queue.empty()) {
      const int i = queue.front();
      queue.pop_front();
      if (visited) visited->push_back(i);
      const int x = i % W, y = i / W;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
          const int j = ny * W + nx;
          if (F[j] && L[j] == 0) {
            L[j] = L[i];
            queue.push_back(j);
          }
        }
    }
  };
  bfs(nullptr);
  std::vector<int> component;
  for (int i = 0; i < W * H; ++i)
    if (F[i] && L[i] == 0) {
      L[i] = (*next_label)++;
      queue.push_back(i);
      component.clear();
      bfs(&component);
      if (static_cast<int>(component.size()) < min_new_cells)
        for (int c : component) L[c] = -1;  // too small: unlabelled (restored below)
    }
  for (int i = 0; i < W * H; ++i)
    if (L[i] < 0) L[i] = 0;
}

/// Regions below min_region_area join the neighbour they share the longest border with.
void mergeSmallRegions(cv::Mat& labels, int next_label, double res, int first_fresh,
                       double min_region_area) {
  if (min_region_area <= 0) return;
  const double cell = res * res;
  std::vector<long> count(next_label, 0);
  const int W = labels.cols, H = labels.rows;
  int* L = labels.ptr<int>(0);
  for (int i = 0; i < W * H; ++i) ++count[L[i]];
  std::vector<char> small(next_label, 0);
  bool any = false;
  for (int l = first_fresh; l < next_label; ++l)
    if (count[l] > 0 && count[l] * cell < min_region_area) small[l] = any = 1;
  if (!any) return;
  // Border lengths between a small region and its neighbours (4-neighbourhood).
  std::unordered_map<long long, long> border;
  auto touch = [&](int a, int b) {
    if (a == b || a == 0 || b == 0) return;
    if (small[a]) ++border[static_cast<long long>(a) * next_label + b];
    if (small[b]) ++border[static_cast<long long>(b) * next_label + a];
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int a = L[y * W + x];
      if (x + 1 < W) touch(a, L[y * W + x + 1]);
      if (y + 1 < H) touch(a, L[(y + 1) * W + x]);
    }
  std::vector<std::vector<std::pair<int, long>>> nb(next_label);
  for (const auto& [key, n] : border)
    nb[key / next_label].push_back({static_cast<int>(key % next_label), n});
  std::vector<int> parent(next_label);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::vector<int> order;
  for (int l = 1; l < next_label; ++l)
    if (small[l]) order.push_back(l);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return count[a] < count[b]; });
  std::vector<long> size(count.begin(), count.end());
  for (int l : order) {
    const int root = find(l);
    if (size[root] * cell >= min_region_area) continue;  // grew by earlier merges
    std::map<int, long> by_root;                         // ordered: deterministic ties
    for (const auto& [m, n] : nb[l]) {
      const int r = find(m);
      if (r != root) by_root[r] += n;
    }
    int best = -1;
    long best_n = 0;
    for (const auto& [r, n] : by_root)
      if (n > best_n) best = r, best_n = n;
    if (best < 0) continue;
    parent[root] = best;
    size[best] += size[root];
  }
  for (int i = 0; i < W * H; ++i)
    if (L[i] > 0) L[i] = find(L[i]);
}

namespace {

/// Concavity of the union of labels a and b within `box` (their bounding boxes' union):
/// the deepest reflex vertex of its simplified outline; infinity when it must stay apart (a
/// hole at least hole_px wide, or no outline).
double unionConcavity(const cv::Mat& labels, const cv::Rect& box, int a, int b, double res,
                      double eps_px, double hole_px) {
  const int W = labels.cols, H = labels.rows;
  const cv::Rect r = box + cv::Size(2, 2) - cv::Point(1, 1);
  cv::Mat m(r.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < r.height; ++y) {
    const int yy = y + r.y;
    if (yy < 0 || yy >= H) continue;
    const int* l = labels.ptr<int>(yy);
    unsigned char* o = m.ptr<unsigned char>(y);
    for (int x = 0; x < r.width; ++x) {
      const int xx = x + r.x;
      if (xx >= 0 && xx < W && (l[xx] == a || l[xx] == b)) o[x] = 1;
    }
  }
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(m, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  int outer = -1;
  double best = -1;
  for (int i = 0; i < static_cast<int>(contours.size()); ++i)
    if (hierarchy[i][3] < 0) {
      const double area = std::abs(cv::contourArea(contours[i]));
      if (area > best) best = area, outer = i;
    } else {
      const cv::Rect hb = cv::boundingRect(contours[i]);
      if (std::hypot(hb.width, hb.height) >= hole_px)
        return std::numeric_limits<double>::infinity();
    }
  if (outer < 0) return std::numeric_limits<double>::infinity();
  std::vector<cv::Point> poly;
  cv::approxPolyDP(contours[outer], poly, std::max(eps_px, 0.5), true);
  asf::dude::Ring ring;
  for (const cv::Point& p : poly) ring.push_back({p.x * res, p.y * res});
  ring = asf::dude::cleanRing(ring, true);
  if (ring.empty()) return std::numeric_limits<double>::infinity();
  return asf::dude::maxReflexConcavity(ring);
}

/// The bounding box of each label > 0 in `labels` (box and present indexed by label).
void labelBoxes(const cv::Mat& labels, std::vector<cv::Rect>& box, std::vector<char>& present) {
  const int W = labels.cols, H = labels.rows;
  for (int y = 0; y < H; ++y) {
    const int* l = labels.ptr<int>(y);
    for (int x = 0; x < W; ++x) {
      const int v = l[x];
      if (v <= 0) continue;
      if (!present[v])
        box[v] = cv::Rect(x, y, 1, 1), present[v] = 1;
      else
        box[v] |= cv::Rect(x, y, 1, 1);
    }
  }
}

/// Border lengths between the labels > 0 (4-neighbourhood): [a][b] cell sides a shares with b.
std::map<int, std::map<int, int>> labelBorders(const cv::Mat& labels) {
  const int W = labels.cols, H = labels.rows;
  std::map<int, std::map<int, int>> adj;
  for (int y = 0; y < H; ++y) {
    const int* l = labels.ptr<int>(y);
    const int* below = y + 1 < H ? labels.ptr<int>(y + 1) : nullptr;
    for (int x = 0; x < W; ++x) {
      const int a = l[x];
      if (a <= 0) continue;
      if (x + 1 < W && l[x + 1] > 0 && l[x + 1] != a) ++adj[a][l[x + 1]], ++adj[l[x + 1]][a];
      if (below && below[x] > 0 && below[x] != a) ++adj[a][below[x]], ++adj[below[x]][a];
    }
  }
  return adj;
}

}  // namespace

/// Room layer: neighbouring pieces whose union DuDe would not cut again (no reflex vertex
/// deeper than merge_concavity, no hole wider than min_hole_extent) are merged, cheapest
/// union first. Undoes cuts that were chosen for a pocket minimum resolved elsewhere
/// (furniture corners). Only labels >= first_fresh are considered: regions kept by an
/// incremental update keep their cells.
void mergeConvexNeighbours(cv::Mat& labels, int next_label, int first_fresh, double res,
                           const RoomLayerOptions& o) {
  if (o.merge_concavity <= 0) return;
  std::vector<cv::Rect> box(next_label);
  std::vector<char> present(next_label, 0);
  labelBoxes(labels, box, present);
  // Border lengths between labels, kept up to date through merges.
  std::map<int, std::map<int, int>> adj = labelBorders(labels);
  // Pieces meeting along less than this are joined by a doorway-sized opening: kept apart
  // without the (costly) union test.
  const int min_border_px = std::max(3, static_cast<int>(std::lround(o.merge_min_border / res)));
  const double eps_px = o.simplify_tolerance / res;
  const double hole_px = o.min_hole_extent / res;
  // Concavity of the union of a and b (infinity: must stay apart).
  // Candidate pairs, evaluated lazily and kept sorted by union concavity.
  std::set<std::tuple<double, int, int>> queue;
  std::map<std::pair<int, int>, double> score;
  auto evaluate = [&](int a) {
    for (const auto& [b, n] : adj[a]) {
      if (n < min_border_px || a < first_fresh || b < first_fresh) continue;
      const auto key = std::minmax(a, b);
      if (score.count(key)) continue;
      const double c = unionConcavity(labels, box[key.first] | box[key.second], key.first,
                                      key.second, res, eps_px, hole_px);
      score[key] = c;
      if (c <= o.merge_concavity) queue.insert({c, key.first, key.second});
    }
  };
  for (int a = 1; a < next_label; ++a)
    if (present[a]) evaluate(a);
  while (!queue.empty()) {
    const auto [c, a, b] = *queue.begin();
    queue.erase(queue.begin());
    if (!present[a] || !present[b]) continue;
    // a absorbs b (the smaller label stays: kept ids win over fresh ones).
    const cv::Rect r = box[b];
    for (int y = r.y; y < r.y + r.height; ++y) {
      int* l = labels.ptr<int>(y);
      for (int x = r.x; x < r.x + r.width; ++x)
        if (l[x] == b) l[x] = a;
    }
    box[a] |= box[b];
    present[b] = 0;
    for (const auto& [c, n] : adj[b]) {
      adj[c].erase(b);
      if (c == a) continue;
      adj[a][c] += n;
      adj[c][a] += n;
    }
    adj.erase(b);
    adj[a].erase(b);
    // Pairs involving a or b changed: drop their scores and evaluate a's again.
    for (auto it = score.begin(); it != score.end();)
      if (it->first.first == a || it->first.second == a || it->first.first == b ||
          it->first.second == b) {
        queue.erase({it->second, it->first.first, it->first.second});
        it = score.erase(it);
      } else {
        ++it;
      }
    evaluate(a);
  }
}

}  // namespace asf::dude::raster
