#pragma once
// Writes a run's outputs. Private to the framework: stages never know about files.
#include <asf/pipeline.h>

#include <fstream>
#include <string>

namespace asf {

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
  void decision(long step, double time, const Decision& d, NavStatus previous);
  /// Final files: graph, map, regions, topology, summary. Never throws (logs instead):
  /// it also runs while an exception propagates.
  void finish(const PoseGraph& graph, const GridMap& map, const Segmentation& seg,
              const TopoGraph& topo, const std::vector<mrpt::poses::CPose2D>& path,
              const RunSummary& summary, std::string& error);

 private:
  std::string dir_;
  std::ofstream traj_, decisions_;
  std::map<std::string, std::string> slots_;
};

}  // namespace asf
