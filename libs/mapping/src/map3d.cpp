#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <octomap/OcTree.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <limits>

namespace asf::mapping {

namespace {

const KeySpec kMap3dKeys[] = {
    keyDouble("resolution", "0.05", "Octree voxel size [m]", 0.005, 5.0),
    keyDouble("max_range", "30.0",
              "Rays are cut here: a point farther than this is no hit, its ray marks free "
              "space up to max_range only [m]",
              0.1, 1000.0),
    keyDouble("min_range", "0.0",
              "Points closer to the sensor than this are dropped (robot body, dust) [m]", 0.0,
              100.0),
    keyDouble("prob_hit", "0.7", "Occupancy probability update of a voxel a point ends in",
              0.5001, 0.9999),
    keyDouble("prob_miss", "0.4", "Occupancy probability update of a voxel a ray traverses",
              0.0001, 0.4999),
    keyDouble("clamping_thres_min", "0.12",
              "Lower clamp of a voxel's occupancy probability (keeps the map updatable)", 0.0001,
              0.4999),
    keyDouble("clamping_thres_max", "0.97", "Upper clamp of a voxel's occupancy probability",
              0.5001, 0.9999),
    keyDouble("min_height", "0.05",
              "Bottom of the robot's body band, metres above the floor (z of the robot base); "
              "voxels with their centre strictly inside the band are projected to the 2D grid "
              "(keep resolution <= 2 min_height: the floor voxel stays out) [m]",
              -100.0, 100.0),
    keyDouble("max_height", "1.5", "Top of the robot's body band, metres above the floor [m]",
              -100.0, 100.0),
    keyDouble("project_resolution", "0.05", "Cell size of the projected 2D grid [m]", 0.005,
              5.0),
    keyDouble("unknown_band", "0.02",
              "Voxels with |occupancy - 0.5| below this count as unknown in the projection",
              0.0, 0.49),
    keyInt("max_keyframes_per_update", "10",
           "Rebuild cap: keyframes re-inserted per rebuildStep() after a loop closure", 1,
           1e9),
    keyDouble("rebuild_threshold", "0.05",
              "A keyframe moved more than this (translation [m], or rotation [rad] x 1 m) "
              "since its insertion starts a rebuild",
              1e-6, 100.0),
    keyBool("lazy_eval", "false",
            "Update the octree's inner nodes once per cloud (OctoMap's lazy_eval, then "
            "updateInnerOccupancy and prune over the whole tree) instead of per voxel: the same "
            "tree, faster while the map is room-sized, slower on large maps"),
    keyBool("discretize", "false",
            "OctoMap's discretized insertion: one ray per distinct end voxel (faster on dense "
            "clouds; rays then end at voxel centres)"),
};

constexpr double kEps = 1e-6;

struct Keyframe {
  mrpt::poses::CPose2D pose;          ///< latest pose from the back-end
  mrpt::poses::CPose3D sensor_on_robot;
  std::vector<Eigen::Vector3f> points;  ///< sensor frame
  mrpt::poses::CPose2D live_pose;     ///< pose it is inserted at in the current tree
  mrpt::poses::CPose2D shadow_pose;   ///< pose it is inserted at in the rebuild tree
  bool in_shadow = false;
};

bool movedMoreThan(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b, double thr) {
  return std::hypot(a.x() - b.x(), a.y() - b.y()) > thr ||
         std::abs(mrpt::math::wrapToPi(a.phi() - b.phi())) > thr;
}

void writeAtomically(const std::string& path, const std::string& what,
                     const std::function<bool(const std::string&)>& write) {
  writeFileVia(path, what, write);
}

}  // namespace

const KeySpec* Map3d::keys(std::size_t& n) {
  n = std::size(kMap3dKeys);
  return kMap3dKeys;
}

struct Map3d::Impl {
  double resolution = 0.05, max_range = 30, min_range = 0, prob_hit = 0.7, prob_miss = 0.4,
         clamp_min = 0.12, clamp_max = 0.97, min_height = 0.05, max_height = 1.5,
         project_resolution = 0.05, unknown_band = 0.02, rebuild_threshold = 0.05;
  std::size_t cap = 10;
  bool discretize = false, lazy_eval = false;

  std::unique_ptr<octomap::OcTree> tree, shadow;
  std::map<KeyframeId, Keyframe> keyframes;
  std::deque<KeyframeId> queue;  ///< keyframes still to re-insert into `shadow`
  std::uint64_t version = 0;
  bool rebuilt_since_project = false;
  std::size_t rebuilds = 0;
  // Counters of the current tree, and of the shadow (they replace the current on the swap).
  struct Counts {
    std::size_t clouds = 0, points = 0, dropped = 0;
  } counts, shadow_counts;
  octomap::Pointcloud cloud;  ///< reused buffer

  std::unique_ptr<octomap::OcTree> newTree() const {
    auto t = std::make_unique<octomap::OcTree>(resolution);
    t->setProbHit(prob_hit);
    t->setProbMiss(prob_miss);
    t->setClampingThresMin(clamp_min);
    t->setClampingThresMax(clamp_max);
    return t;
  }

  void reset() {
    tree = newTree();
    shadow.reset();
    keyframes.clear();
    queue.clear();
    counts = shadow_counts = Counts{};
    rebuilt_since_project = false;
    ++version;
  }

  std::size_t insert(octomap::OcTree& t, Counts& c, const std::vector<Eigen::Vector3f>& pts,
                     const mrpt::poses::CPose3D& sensor) {
    cloud.clear();
    cloud.reserve(pts.size());
    const double min2 = std::max(min_range, kEps) * std::max(min_range, kEps);
    const Eigen::Matrix3d R = sensor.getRotationMatrix().asEigen();
    const Eigen::Vector3d T(sensor.x(), sensor.y(), sensor.z());
    std::size_t dropped = 0;
    for (const auto& p : pts) {
      const Eigen::Vector3d q = p.cast<double>();
      if (!q.allFinite() || q.squaredNorm() < min2) {
        ++dropped;
        continue;
      }
      const Eigen::Vector3d w = R * q + T;
      cloud.push_back(static_cast<float>(w.x()), static_cast<float>(w.y()),
                      static_cast<float>(w.z()));
    }
    c.dropped += dropped;
    if (cloud.size() == 0) return 0;
    // OctoMap casts the rays: free voxels along each, the end voxel occupied, points beyond
    // max_range cut to free rays of length max_range.
    t.insertPointCloud(cloud, octomap::point3d(T.x(), T.y(), T.z()), max_range, lazy_eval,
                       discretize);
    if (lazy_eval) {  // what the per-voxel updates would have done: inner nodes, pruning
      t.updateInnerOccupancy();
      t.prune();
    }
    ++c.clouds;
    c.points += cloud.size();
    return cloud.size();
  }

  void insertKeyframe(octomap::OcTree& t, Counts& c, const Keyframe& k) {
    insert(t, c, k.points, mrpt::poses::CPose3D(k.pose) + k.sensor_on_robot);
  }

  void startRebuild() {
    shadow = newTree();
    shadow_counts = Counts{};
    queue.clear();
    for (auto& [id, k] : keyframes) {
      k.in_shadow = false;
      queue.push_back(id);
    }
  }
};

Map3d::Map3d() : impl_(std::make_unique<Impl>()) { impl_->reset(); }
Map3d::~Map3d() = default;

void Map3d::configure(const Params& p) {
  Impl& m = *impl_;
  m.resolution = p.getDouble("resolution");
  m.max_range = p.getDouble("max_range");
  m.min_range = p.getDouble("min_range");
  m.prob_hit = p.getDouble("prob_hit");
  m.prob_miss = p.getDouble("prob_miss");
  m.clamp_min = p.getDouble("clamping_thres_min");
  m.clamp_max = p.getDouble("clamping_thres_max");
  m.min_height = p.getDouble("min_height");
  m.max_height = p.getDouble("max_height");
  m.project_resolution = p.getDouble("project_resolution");
  m.unknown_band = p.getDouble("unknown_band");
  m.cap = static_cast<std::size_t>(p.getInt("max_keyframes_per_update"));
  m.rebuild_threshold = p.getDouble("rebuild_threshold");
  m.discretize = p.getBool("discretize");
  m.lazy_eval = p.getBool("lazy_eval");
  if (m.min_height >= m.max_height)
    p.fail("max_height", "must be above min_height (" + p.getString("min_height") + ")");
  if (m.min_range >= m.max_range)
    p.fail("min_range", "must be below max_range (" + p.getString("max_range") + ")");
  // OctoMap keys are 16 bits per axis: the map spans 65536 voxels per axis around 0.
  if (m.max_range > 0.45 * 65536 * m.resolution)
    p.fail("max_range", "too long for an octree of resolution " + p.getString("resolution") +
                            " (at most " + std::to_string(0.45 * 65536 * m.resolution) + " m)");
  m.reset();
}

std::size_t Map3d::insertPoints(const std::vector<Eigen::Vector3f>& points_in_sensor_frame,
                                const mrpt::poses::CPose3D& sensor_pose_in_map) {
  Impl& m = *impl_;
  const std::size_t n = m.insert(*m.tree, m.counts, points_in_sensor_frame, sensor_pose_in_map);
  if (n) ++m.version;
  return n;
}

std::size_t Map3d::insertObservation(const mrpt::obs::CObservation& obs,
                                     const mrpt::poses::CPose2D& robot_pose) {
  std::vector<Eigen::Vector3f> pts;
  mrpt::poses::CPose3D sensor;
  std::string why;
  if (!observationPoints(obs, pts, sensor, &why))
    throw InputError("[map3d] " + obs.sensorLabel + ": " + why);
  return insertPoints(pts, mrpt::poses::CPose3D(robot_pose) + sensor);
}

void Map3d::addKeyframe(KeyframeId id, const mrpt::poses::CPose2D& robot_pose,
                        const mrpt::poses::CPose3D& sensor_on_robot,
                        std::vector<Eigen::Vector3f> points) {
  Impl& m = *impl_;
  if (m.keyframes.count(id))
    throw Error("[map3d] keyframe " + std::to_string(id) + " was already added");
  Keyframe& k = m.keyframes[id];
  k.pose = k.live_pose = robot_pose;
  k.sensor_on_robot = sensor_on_robot;
  k.points = std::move(points);
  m.insertKeyframe(*m.tree, m.counts, k);
  ++m.version;
  if (m.shadow) m.queue.push_back(id);  // the rebuilt tree must hold it too
}

void Map3d::addKeyframe(KeyframeId id, const mrpt::poses::CPose2D& robot_pose,
                        const mrpt::obs::CObservation& obs) {
  std::vector<Eigen::Vector3f> pts;
  mrpt::poses::CPose3D sensor;
  std::string why;
  if (!observationPoints(obs, pts, sensor, &why))
    throw InputError("[map3d] keyframe " + std::to_string(id) + ": " + why);
  addKeyframe(id, robot_pose, sensor, std::move(pts));
}

std::size_t Map3d::updateKeyframePoses(
    const std::map<KeyframeId, mrpt::poses::CPose2D>& poses) {
  Impl& m = *impl_;
  std::size_t moved = 0;
  bool restart = false;
  for (const auto& [id, pose] : poses) {
    auto it = m.keyframes.find(id);
    if (it == m.keyframes.end()) continue;
    Keyframe& k = it->second;
    k.pose = pose;
    if (movedMoreThan(pose, k.live_pose, m.rebuild_threshold)) ++moved;
    // Already re-inserted into the rebuild tree at a pose that is now stale: start over.
    if (m.shadow && k.in_shadow && movedMoreThan(pose, k.shadow_pose, m.rebuild_threshold))
      restart = true;
  }
  if ((moved && !m.shadow) || restart) m.startRebuild();
  return moved;
}

std::size_t Map3d::rebuildStep() {
  Impl& m = *impl_;
  if (!m.shadow) return 0;
  std::size_t done = 0;
  while (done < m.cap && !m.queue.empty()) {
    Keyframe& k = m.keyframes.at(m.queue.front());
    m.queue.pop_front();
    m.insertKeyframe(*m.shadow, m.shadow_counts, k);
    k.shadow_pose = k.pose;
    k.in_shadow = true;
    ++done;
  }
  if (m.queue.empty()) {
    m.tree = std::move(m.shadow);
    m.counts = m.shadow_counts;
    for (auto& [id, k] : m.keyframes) {
      k.live_pose = k.shadow_pose;
      k.in_shadow = false;
    }
    ++m.rebuilds;
    ++m.version;
    m.rebuilt_since_project = true;
  }
  return done;
}

bool Map3d::rebuilding() const { return impl_->shadow != nullptr; }
std::size_t Map3d::rebuildPending() const { return impl_->shadow ? impl_->queue.size() : 0; }
std::size_t Map3d::numKeyframes() const { return impl_->keyframes.size(); }
std::uint64_t Map3d::version() const { return impl_->version; }
double Map3d::resolution() const { return impl_->resolution; }

GridMap Map3d::project() {
  Impl& m = *impl_;
  const octomap::OcTree& t = *m.tree;
  GridMap out;
  if (t.size() == 0) return out;
  double x0, y0, z0, x1, y1, z1;
  t.getMetricMin(x0, y0, z0);
  t.getMetricMax(x1, y1, z1);
  const double r = m.project_resolution;
  // Cell borders on multiples of r: with r = the octree resolution cells and voxel columns
  // coincide.
  const double gx0 = std::floor(x0 / r + kEps) * r, gy0 = std::floor(y0 / r + kEps) * r;
  const int W = std::max(1, static_cast<int>(std::ceil((x1 - gx0) / r - kEps)));
  const int H = std::max(1, static_cast<int>(std::ceil((y1 - gy0) / r - kEps)));
  // Per cell: the largest occupancy among occupied / free voxels of the band (-1: none).
  std::vector<float> occ(static_cast<std::size_t>(W) * H, -1.f), fre(occ.size(), -1.f);
  const double hi = 0.5 + m.unknown_band, lo = 0.5 - m.unknown_band;
  const octomap::point3d bmin(static_cast<float>(x0), static_cast<float>(y0),
                              static_cast<float>(m.min_height));
  const octomap::point3d bmax(static_cast<float>(x1), static_cast<float>(y1),
                              static_cast<float>(m.max_height));
  for (auto it = t.begin_leafs_bbx(bmin, bmax), end = t.end_leafs_bbx(); it != end; ++it) {
    const double half = 0.5 * it.getSize();
    const double zc = it.getZ();
    // In the band: a voxel whose centre is strictly inside (min_height, max_height), so the
    // floor voxel [0, res) is out as long as res <= 2 min_height; a pruned leaf when one of
    // its voxels is.
    const double top = zc + half - 0.5 * m.resolution, bottom = zc - half + 0.5 * m.resolution;
    if (!(top > m.min_height + kEps && bottom < m.max_height - kEps)) continue;
    const double p = it->getOccupancy();
    const bool is_occ = p >= hi, is_free = p <= lo;
    if (!is_occ && !is_free) continue;
    auto cellRange = [&](double c, double g0, int n, int& a, int& b) {
      a = static_cast<int>(std::floor((c - half - g0) / r + kEps));
      b = static_cast<int>(std::floor((c + half - g0) / r - kEps));
      if (b < a) b = a;  // a voxel smaller than a cell: the cell holding it
      a = std::clamp(a, 0, n - 1);
      b = std::clamp(b, 0, n - 1);
    };
    int ix0, ix1, iy0, iy1;
    cellRange(it.getX(), gx0, W, ix0, ix1);
    cellRange(it.getY(), gy0, H, iy0, iy1);
    auto& dst = is_occ ? occ : fre;
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix) {
        float& v = dst[static_cast<std::size_t>(iy) * W + ix];
        v = std::max(v, static_cast<float>(p));
      }
  }
  auto g = std::make_shared<mrpt::maps::COccupancyGridMap2D>();
  g->setSize(gx0, gx0 + W * r, gy0, gy0 + H * r, r, 0.5f);
  const int GW = static_cast<int>(g->getSizeX()), GH = static_cast<int>(g->getSizeY());
  for (int iy = 0; iy < H; ++iy)
    for (int ix = 0; ix < W; ++ix) {
      const std::size_t i = static_cast<std::size_t>(iy) * W + ix;
      const float p = occ[i] >= 0 ? occ[i] : fre[i];
      if (p < 0) continue;
      // MRPT may round the size: address cells by their centre.
      const int cx = g->x2idx(gx0 + (ix + 0.5) * r), cy = g->y2idx(gy0 + (iy + 0.5) * r);
      if (cx >= 0 && cy >= 0 && cx < GW && cy < GH) g->setCell(cx, cy, 1.0f - p);
    }
  out.grid = std::move(g);
  out.version = m.version;
  out.changed.extend(gx0, gy0);
  out.changed.extend(gx0 + W * r, gy0 + H * r);
  out.rebuilt = m.rebuilt_since_project;
  m.rebuilt_since_project = false;
  return out;
}

void Map3d::writeBt(const std::string& path) const {
  const octomap::OcTree& t = *impl_->tree;
  writeAtomically(path, "OctoMap binary tree (.bt)",
                  [&](const std::string& p) { return t.writeBinaryConst(p); });
}

void Map3d::writeOt(const std::string& path) const {
  const octomap::OcTree& t = *impl_->tree;
  writeAtomically(path, "OctoMap tree (.ot)", [&](const std::string& p) { return t.write(p); });
}

std::string Map3dStats::toJson() const {
  const nlohmann::json j = {
      {"occupied_leaves", occupied_leaves},
      {"free_leaves", free_leaves},
      {"occupied_voxels", occupied_voxels},
      {"free_voxels", free_voxels},
      {"memory_bytes", memory_bytes},
      {"known_volume_m3", known_volume_m3},
      {"bytes_per_known_m3", known_volume_m3 > 0 ? memory_bytes / known_volume_m3 : 0.0},
      {"resolution", resolution},
      {"keyframes", keyframes},
      {"clouds_inserted", clouds_inserted},
      {"points_inserted", points_inserted},
      {"points_dropped", points_dropped},
      {"rebuilds", rebuilds}};
  return j.dump();
}

Map3dStats Map3d::stats() const {
  const Impl& m = *impl_;
  const octomap::OcTree& t = *m.tree;
  Map3dStats s;
  s.resolution = m.resolution;
  const double res3 = m.resolution * m.resolution * m.resolution;
  for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) {
    const double size = it.getSize();
    const double vol = size * size * size;
    const auto voxels = static_cast<std::size_t>(std::llround(vol / res3));
    if (t.isNodeOccupied(*it)) {
      ++s.occupied_leaves;
      s.occupied_voxels += voxels;
    } else {
      ++s.free_leaves;
      s.free_voxels += voxels;
    }
    s.known_volume_m3 += vol;
  }
  s.memory_bytes = t.memoryUsage();
  s.keyframes = m.keyframes.size();
  s.clouds_inserted = m.counts.clouds;
  s.points_inserted = m.counts.points;
  s.points_dropped = m.counts.dropped;
  s.rebuilds = m.rebuilds;
  return s;
}

std::vector<std::uint64_t> Map3d::occupiedVoxelKeys() const {
  const octomap::OcTree& t = *impl_->tree;
  std::vector<std::uint64_t> keys;
  const unsigned max_depth = t.getTreeDepth();
  for (auto it = t.begin_leafs(), end = t.end_leafs(); it != end; ++it) {
    if (!t.isNodeOccupied(*it)) continue;
    const octomap::OcTreeKey k = it.getIndexKey();  // the leaf's smallest corner key
    const unsigned span = 1u << (max_depth - it.getDepth());
    for (unsigned dx = 0; dx < span; ++dx)
      for (unsigned dy = 0; dy < span; ++dy)
        for (unsigned dz = 0; dz < span; ++dz)
          keys.push_back((static_cast<std::uint64_t>(k[0] + dx) << 32) |
                         (static_cast<std::uint64_t>(k[1] + dy) << 16) |
                         static_cast<std::uint64_t>(k[2] + dz));
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

double Map3d::occupancyAt(double x, double y, double z) const {
  const octomap::OcTreeNode* n = impl_->tree->search(x, y, z);
  return n ? n->getOccupancy() : -1.0;
}

}  // namespace asf::mapping
