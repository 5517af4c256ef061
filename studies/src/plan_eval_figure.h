#pragma once
// The pictures of `asf plan-eval`: a scenario as thesis Fig. 3.4 draws it (the pose graph
// with the feature-void zone as a blue square) and an error example as Fig. 3.5 draws it
// (a baseline's path through the zone beside the expected-uncertainty path around it).
#include <asf/pose_graph.h>
#include <asf/planning/unreliable_zone.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace asf::studies {

struct PathDrawing {
  std::string label;  ///< legend text
  std::string color;  ///< CSS colour
  std::vector<NodeId> nodes;
};

/// An SVG of `g`'s edges and nodes (zone nodes in blue) with `zone` shaded, `paths` drawn
/// over them (the first path's ends marked S and G) and `title` above. Node ids outside the
/// graph throw InputError.
std::string scenarioSvg(const PoseGraph& g, const planning::Zone& zone, const std::vector<PathDrawing>& paths,
                        const std::string& title);

/// The first pair of a scenario's record (plan_eval.json "pair_results", each planner with
/// its "path") where expected_uncertainty keeps out of the zone and `baseline` crosses it;
/// null when there is none.
nlohmann::json errorExample(const nlohmann::json& pair_results, const std::string& baseline);

/// Writes OUT_DIR/scenario_<name>.svg (Fig. 3.4) and, when mechanical_work (else sum_dopt)
/// crosses the zone on a pair where expected_uncertainty does not, error_example_<name>.svg
/// (Fig. 3.5). `scenario` is the scenario's record (name, zone_index, factor, pair_results).
/// Returns {"scenario": file, "error_example": {file, start, goal, baseline} or null}.
nlohmann::json writeScenarioFigures(const PoseGraph& g, const planning::Zone& zone,
                                    const nlohmann::json& scenario, const std::string& out_dir);

}  // namespace asf::studies
