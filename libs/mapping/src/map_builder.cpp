#include <asf/errors.h>
#include <asf/mapping/map_builder.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace asf::mapping {

namespace {
const KeySpec kMapKeys[] = {
    keyDouble("resolution", "0.05", "Occupancy grid cell size [m]", 0.005, 2.0),
    keyDouble("max_insertion_range", "15.0", "Laser returns farther than this are not inserted [m]",
              0.1, 1000.0),
    keyDouble("rebuild_threshold", "0.05",
              "Rebuild the map from all keyframes when an inserted keyframe moved more than "
              "this (translation [m], or rotation [rad] x 1 m) since insertion",
              1e-4, 100.0),
    keyBool("widen_beams", "false",
            "Widen each beam with its range (MRPT wideningBeamsWithDistance) so that far rays "
            "leave no unknown gaps between them: a corridor seen from afar becomes free space"),
    keyDouble("initial_half_size", "10.0",
              "Half side of the initial grid around the origin [m]; it grows as needed", 1.0,
              1000.0),
};
}  // namespace

const KeySpec* MapBuilder::keys(std::size_t& n) {
  n = std::size(kMapKeys);
  return kMapKeys;
}

struct MapBuilder::Impl {
  double resolution = 0.05, max_range = 15, rebuild_threshold = 0.05, half = 10;
  std::size_t rebuilds = 0;
  bool widen = false;
  /// The grid being built; also the published version's (map_.grid) until it changes.
  std::shared_ptr<mrpt::maps::COccupancyGridMap2D> grid =
      std::make_shared<mrpt::maps::COccupancyGridMap2D>();
  std::map<NodeId, mrpt::poses::CPose2D> inserted;  ///< node -> pose at insertion

  /// Copy on write: the grid is changed in place only when no one but the builder and its
  /// `published` map holds it (a consumer that kept a version keeps it unchanged). A full
  /// copy of a 23-million-cell grid per keyframe was half of a long log's run.
  bool heldElsewhere(const GridMap& published) const {
    return grid.use_count() > 1 + (published.grid == grid ? 1 : 0);
  }
  void writable(const GridMap& published) {
    if (heldElsewhere(published)) grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(*grid);
  }
  /// An empty grid of the initial size, or of the current one (`keep_extent`: a rebuild,
  /// whose scans cover about the same area; growing from the initial size again copied the
  /// whole grid at every growth, most of a long log's map stage).
  void reset(const GridMap& published, bool keep_extent = false) {
    float x0 = static_cast<float>(-half), x1 = static_cast<float>(half), y0 = x0, y1 = x1;
    if (keep_extent && grid->getSizeX() > 0) {
      x0 = std::min(x0, grid->getXMin()), x1 = std::max(x1, grid->getXMax());
      y0 = std::min(y0, grid->getYMin()), y1 = std::max(y1, grid->getYMax());
    }
    if (heldElsewhere(published)) grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>();
    grid->setSize(x0, x1, y0, y1, static_cast<float>(resolution), 0.5f);
    grid->insertionOptions.maxDistanceInsertion = static_cast<float>(max_range);
    grid->insertionOptions.wideningBeamsWithDistance = widen;
    inserted.clear();
  }
  /// Inserts one keyframe; returns the box its rays can have touched. Echoes reach at most
  /// min(maxRange, maxDistanceInsertion) from the sensor, but MRPT clears free space along
  /// no-echo rays to half of maxDistanceInsertion whatever the scan's maxRange (measured
  /// with MRPT 2.5: 7.5 m for maxRange 2, 4 or 6 m and 15 m; tests/test_coverage.cpp
  /// compares the box with every changed cell).
  Box2 insert(const PoseNode& n, const GridMap& published) {
    Box2 b;
    if (!n.scan) return b;
    const mrpt::poses::CPose3D robot(n.pose);
    writable(published);
    grid->insertObservation(*n.scan, robot);
    inserted[n.id] = n.pose;
    const mrpt::poses::CPose3D sensor = robot + n.scan->sensorPose;
    const double reach = std::max(std::min<double>(n.scan->maxRange, max_range), max_range / 2);
    const double r = reach + 2 * resolution;  // a cell either side of the last one touched
    b.extend(sensor.x() - r, sensor.y() - r);
    b.extend(sensor.x() + r, sensor.y() + r);
    return b;
  }
};

MapBuilder::MapBuilder() : impl_(std::make_unique<Impl>()) { impl_->reset(map_); }
MapBuilder::~MapBuilder() = default;

void MapBuilder::configure(const Params& p) {
  impl_->resolution = p.getDouble("resolution");
  impl_->max_range = p.getDouble("max_insertion_range");
  impl_->rebuild_threshold = p.getDouble("rebuild_threshold");
  impl_->half = p.getDouble("initial_half_size");
  impl_->widen = p.getBool("widen_beams");
  impl_->reset(map_);
  impl_->rebuilds = 0;
  map_ = GridMap{};
}

std::size_t MapBuilder::rebuilds() const { return impl_->rebuilds; }

bool MapBuilder::update(const PoseGraph& graph) {
  Impl& m = *impl_;
  bool moved = false, restart = false;
  for (const auto& [id, pose] : m.inserted) {
    if (id >= graph.nodes.size()) {
      moved = restart = true;  // the graph shrank: a new run; start over
      break;
    }
    const auto& now = graph.nodes[id].pose;
    const double dt = std::hypot(now.x() - pose.x(), now.y() - pose.y());
    const double dr = std::abs(mrpt::math::wrapToPi(now.phi() - pose.phi()));
    if (dt > m.rebuild_threshold || dr > m.rebuild_threshold) {
      moved = true;
      break;
    }
  }
  Box2 changed;
  bool any = false;
  if (moved) {
    ++m.rebuilds;
    m.reset(map_, !restart);
    for (const auto& n : graph.nodes) {
      const Box2 b = m.insert(n, map_);
      if (!b.empty()) changed.extend(b.min_x, b.min_y), changed.extend(b.max_x, b.max_y);
    }
    any = true;
  } else {
    for (const auto& n : graph.nodes) {
      if (m.inserted.count(n.id) || !n.scan) continue;
      const Box2 b = m.insert(n, map_);
      changed.extend(b.min_x, b.min_y), changed.extend(b.max_x, b.max_y);
      any = true;
    }
  }
  if (!any) return false;
  map_.grid = m.grid;
  ++map_.version;
  map_.changed = changed;
  map_.rebuilt = moved;
  return true;
}

std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> mergeOccupancy(
    const mrpt::maps::COccupancyGridMap2D& a, const mrpt::maps::COccupancyGridMap2D& b,
    double band) {
  const double res = a.getResolution();
  const double x0 = std::min(a.getXMin(), b.getXMin()), x1 = std::max(a.getXMax(), b.getXMax());
  const double y0 = std::min(a.getYMin(), b.getYMin()), y1 = std::max(a.getYMax(), b.getYMax());
  auto out = std::make_shared<mrpt::maps::COccupancyGridMap2D>(
      static_cast<float>(x0), static_cast<float>(x1), static_cast<float>(y0),
      static_cast<float>(y1), static_cast<float>(res));
  const unsigned w = out->getSizeX(), h = out->getSizeY();
  for (unsigned cy = 0; cy < h; ++cy) {
    const float y = out->idx2y(cy);
    for (unsigned cx = 0; cx < w; ++cx) {
      const float x = out->idx2x(cx);
      const float pa = a.getPos(x, y), pb = b.getPos(x, y);     // 0.5 outside a grid
      const bool oa = pa < 0.5f - band, ob = pb < 0.5f - band;  // occupied
      const bool fa = pa > 0.5f + band, fb = pb > 0.5f + band;  // free
      float p = 0.5f;
      if (oa || ob)
        p = std::min(oa ? pa : 1.0f, ob ? pb : 1.0f);
      else if (fa || fb)
        p = std::max(fa ? pa : 0.0f, fb ? pb : 0.0f);
      out->setCell(static_cast<int>(cx), static_cast<int>(cy), p);
    }
  }
  return out;
}

}  // namespace asf::mapping
