#pragma once
// Writes a run's outputs. Private to the framework: stages never know about files.
#include <asf/goal.h>
#include <asf/mapping/map3d.h>
#include <asf/framework/pipeline.h>
#include <asf/pose_graph.h>
#include <asf/segmentation.h>
#include <asf/topo_graph.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace asf::framework {

/// The run's segmentations: how many were incremental or full (Segmentation::Mode), their
/// times and changed cells; rows of timeseries.csv and the summary read it.
class SegmentationLog {
 public:
  std::size_t total = 0, incremental = 0, full = 0;
  void add(const Segmentation& s, double ms);
  /// Changed cells summed over the segmentations since the previous call; -1 if none knew.
  std::int64_t takeChangedSinceRow();
  void summarize(RunSummary& sum) const;

 private:
  std::vector<double> ms_incremental_, ms_full_, changed_;
  std::int64_t changed_since_row_ = -1;
};

class Recorder {
 public:
  Recorder(const std::string& out_dir, const ResolvedConfig& cfg);
  struct Step {
    long step;
    double time;
    mrpt::poses::CPose2D estimate;
    std::optional<mrpt::poses::CPose2D> truth;  ///< map frame
    std::size_t nodes, edges;
    double distance;
  };
  void step(const Step& s);
  /// One row of timeseries.csv (negative coverage / pose error: unknown, written empty).
  struct SeriesRow {
    long step = 0;
    double time = 0, distance = 0, coverage = -1, explored_area = 0, pose_error = -1;
    std::size_t loop_closures = 0, nodes = 0, edges = 0, regions = 0;
    int decisions = 0;
    std::array<double, 5> ms{};  ///< frontend, backend, map, segment, policy
    std::size_t segmentations = 0, incremental_segmentations = 0;  ///< so far
    std::int64_t changed_cells = -1;   ///< summed over the segmentations since the last row
    double map_information_bits = -1;  ///< of the navigation grid (mapInformationBits); -1: none
  };
  /// Also rewrites progress.json (status "running" and the row's figures) at the first row
  /// and then every 5 s of wall time: what a killed run leaves about itself. finish() sets
  /// it to "writing outputs", finalStatus() to the run's end once every output is in place.
  void series(const SeriesRow& r);
  void decision(long step, double time, const Decision& d, NavStatus previous);
  /// Final files: graph, map, regions, topology, summary. Never throws (logs instead):
  /// it also runs while an exception propagates.
  void finish(const PoseGraph& graph, const GridMap& map, const Segmentation& seg,
              const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
              const RunSummary& summary, std::string& error);
  /// progress.json's last status, "finished" or "stopped: <reason>": written after every other
  /// output, so a run killed while writing them never says it finished. Never throws.
  void finalStatus(const RunSummary& summary, std::string& error);
  /// snapshots/at_<d>m_{map.png, regions.png, topology.svg}: the run as it stands after d
  /// metres ([pipeline] snapshot_distances). Never throws: a failure is logged to stderr.
  void snapshot(double distance, const PoseGraph& graph, const GridMap& map,
                const Segmentation& seg, const TopoGraph& topo,
                const std::vector<mrpt::poses::CPose2D>& path);
  /// [pipeline] map3d: map3d.bt, map3d.ot, map3d_grid.png (the projection) and map3d.json
  /// (parameters, statistics, counts, timings). Never throws.
  struct Map3dInfo {
    std::size_t keyframes = 0, observations = 0, not_keyframes = 0, unsupported = 0, over_cap = 0;
    double insert_ms = 0, project_ms = 0, rebuild_ms = 0;
    std::string navigation_map;
  };
  void finishMap3d(const mapping::Map3d& map, const GridMap& projected, const Params& params,
                   const Map3dInfo& info, std::string& error);

 private:
  /// PREFIXmap.png (map, trajectory, keyframes), PREFIXregions.png and PREFIXtopology.svg
  /// (regions, graph, trajectory; only with a segmentation). Throws on a write failure.
  void writeMapViews(const std::string& prefix, const PoseGraph& graph, const GridMap& map,
                     const Segmentation& seg, const TopoGraph& topo,
                     const std::vector<mrpt::poses::CPose2D>& path);
  void writeProgress(const std::string& status, const SeriesRow& r);

 public:
  /// Rewrites progress.json with `status` and the last row's figures (e.g. "paused"). Never
  /// throws: a failure is reported on stderr, the run goes on.
  void status(const std::string& status);
  /// timeline/NNNN.png: the run at its n-th decision (asf::evaluation::writeTimelineFrame), for the
  /// report's timeline. Never throws: a failure is reported on stderr, the run goes on.
  void timelineFrame(int n, const GridMap& map, const Segmentation& seg, const TopoGraph& topo,
                     const std::vector<mrpt::poses::CPose2D>& path,
                     const mrpt::poses::CPose2D& robot, const Point2* goal, int max_side);

 private:
  std::string dir_;
  std::ofstream traj_, decisions_, series_;
  SeriesRow last_row_;
  std::chrono::steady_clock::time_point last_progress_{};
  bool progress_written_ = false;
  std::map<std::string, std::string> slots_;
};

}  // namespace asf::framework
