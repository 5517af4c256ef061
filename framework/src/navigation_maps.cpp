#include "navigation_maps.h"

#include <asf/text.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation.h>

#include <chrono>

namespace asf::framework {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

void NavigationMaps::configure(const Params& map_params, bool with_map3d,
                               const Params& map3d_params, const std::string& navigation_map) {
  scan2d_.configure(map_params);
  if (with_map3d) {
    map3d_ = std::make_unique<mapping::Map3d>();
    map3d_->configure(map3d_params);
  }
  nav_kind_ = navigation_map;
  counts_.navigation_map = navigation_map;
}

void NavigationMaps::addKeyframes3d(const SensorFrame& f, const PoseGraph& graph,
                                    std::size_t nodes_before, mrpt::system::COutputLogger& log) {
  if (!map3d_ || f.observations3d.empty()) return;
  if (graph.size() <= nodes_before) {
    counts_.not_keyframes += f.observations3d.size();
    return;
  }
  const auto t0 = Clock::now();
  const PoseNode& node = graph.nodes.back();  // the front-end's node for this frame
  mapping::Map3d::KeyframeId k = 0;
  for (const auto& o : f.observations3d) {
    if (!o) continue;
    ++counts_.observations;
    if (k == kObsPerNode) {
      ++counts_.over_cap;
      continue;
    }
    std::vector<Eigen::Vector3f> pts;
    mrpt::poses::CPose3D sensor;
    std::string why;
    if (!mapping::Map3d::observationPoints(*o, pts, sensor, &why)) {
      ++counts_.unsupported;
      if (warned_3d_.insert(why).second)
        log.logStr(mrpt::system::LVL_WARN, "map3d: observation '" + o->sensorLabel +
                                               "' not used: " + why + " (warned once)");
      continue;
    }
    const mapping::Map3d::KeyframeId id = node.id * kObsPerNode + k++;
    map3d_->addKeyframe(id, node.pose, sensor, std::move(pts));
    keyframes3d_.emplace_back(id, node.id);
    ++counts_.keyframes;
  }
  counts_.insert_ms += msSince(t0);
}

void NavigationMaps::followGraph(const PoseGraph& graph) {
  if (!map3d_ || map3d_->numKeyframes() == 0) return;
  std::map<mapping::Map3d::KeyframeId, mrpt::poses::CPose2D> poses;
  for (const auto& [id, node] : keyframes3d_)
    poses.emplace_hint(poses.end(), id, graph.nodes[node].pose);
  map3d_->updateKeyframePoses(poses);
}

bool NavigationMaps::update(const PoseGraph& graph, bool graph_changed) {
  bool map2d_changed = false;
  if (graph_changed) map2d_changed = scan2d_.update(graph);
  return updateNavigation(map2d_changed);
}

void NavigationMaps::completeRebuild() {
  if (!map3d_) return;
  while (map3d_->rebuilding()) map3d_->rebuildStep();
}

bool NavigationMaps::updateNavigation(bool map2d_changed) {
  if (!map3d_) return map2d_changed;
  if (map3d_->rebuilding()) {
    const auto t0 = Clock::now();
    map3d_->rebuildStep();
    counts_.rebuild_ms += msSince(t0);
  }
  bool projected_changed = false;
  if (map3d_->version() != projected_from_) {
    const auto t0 = Clock::now();
    GridMap p = map3d_->project();
    counts_.project_ms += msSince(t0);
    projected_from_ = map3d_->version();
    if (p.grid) {
      p.version = projected_.version + 1;
      p.rebuilt = p.rebuilt || projected_.version == 0;
      projected_ = std::move(p);
      projected_changed = true;
    }
  }
  if (nav_kind_ == "map3d") return projected_changed;
  if (nav_kind_ != "merged") return map2d_changed;
  return updateMerged();
}

bool NavigationMaps::updateMerged() {
  const GridMap& m2 = scan2d_.map();
  if (!m2.grid || !projected_.grid) {
    // One map alone: it is the merged one until the other exists.
    const GridMap& only = m2.grid ? m2 : projected_;
    if (!only.grid || (only.version == (m2.grid ? merged_2d_ : merged_3d_))) return false;
    (m2.grid ? merged_2d_ : merged_3d_) = only.version;
    const std::uint64_t v = merged_.version + 1;
    merged_ = only;
    merged_.version = v;
    merged_.rebuilt = true;
    return true;
  }
  if (m2.version == merged_2d_ && projected_.version == merged_3d_) return false;
  const bool whole = projected_.version != merged_3d_ || m2.rebuilt;
  GridMap g;
  g.grid = mapping::mergeOccupancy(*m2.grid, *projected_.grid);
  g.version = merged_.version + 1;
  g.rebuilt = whole;
  if (whole)
    g.changed = {g.grid->getXMin(), g.grid->getYMin(), g.grid->getXMax(), g.grid->getYMax()};
  else
    g.changed = m2.changed;
  merged_2d_ = m2.version;
  merged_3d_ = projected_.version;
  merged_ = std::move(g);
  return true;
}

Recorder::Map3dInfo NavigationMaps::map3dInfo() const { return counts_; }

}  // namespace asf::framework
